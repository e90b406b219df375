//! Running the `hairlab` binary from the integration tests.

use std::process::{Command, Output};

pub fn hairlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("run hairlab")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The `error:` lines hairlab printed (drivers may print their own noise on stderr).
pub fn error_lines(o: &Output) -> Vec<String> {
    stderr(o)
        .lines()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .map(String::from)
        .collect()
}

/// The run failed with exactly one error line that mentions every needle.
pub fn assert_fails(o: &Output, needles: &[&str]) {
    assert!(!o.status.success(), "expected failure, stderr: {}", stderr(o));
    let lines = error_lines(o);
    assert_eq!(lines.len(), 1, "exactly one error line expected: {lines:?}");
    for n in needles {
        assert!(lines[0].contains(n), "{:?} does not mention {n:?}", lines[0]);
    }
}
