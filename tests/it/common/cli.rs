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

/// Runs `hairlab ARGS` until `file` appears (a run writes its CSV after its first configuration), then sends it
/// SIGINT (Ctrl-C) and returns what it printed; fails the test when the run ends first or nothing comes within
/// 10 minutes.
pub fn interrupt_once_written<S: AsRef<std::ffi::OsStr>>(args: &[S], file: &std::path::Path) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .env("RUST_LOG", "warn")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run hairlab");
    let start = std::time::Instant::now();
    let mut child = child;
    while !file.exists() {
        assert!(
            child.try_wait().expect("poll hairlab").is_none(),
            "hairlab ended before writing {}",
            file.display()
        );
        assert!(
            start.elapsed().as_secs() < 600,
            "no {} after 10 minutes",
            file.display()
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(kill.success());
    child.wait_with_output().expect("wait for hairlab")
}
