//! The help pages (80 columns, the environment named), completions and man pages for every subcommand, the
//! adapter flag, and conflicting, ignored and old flags.

use crate::common::cli::{assert_fails, error_lines, hairlab, stderr};
use std::path::Path;

/// `hairlab ARGS` with `COLUMNS=80`: what a terminal 80 columns wide shows.
fn hairlab_80(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_hairlab"))
        .args(args)
        .env("COLUMNS", "80")
        .env("RUST_LOG", "warn")
        .output()
        .expect("run hairlab")
}

/// Every help page: `hairlab`'s and each subcommand's and mode's, as argument lists.
fn help_pages() -> Vec<Vec<String>> {
    use clap::CommandFactory;
    fn walk(cmd: &clap::Command, path: &[String], out: &mut Vec<Vec<String>>) {
        let mut page = path.to_vec();
        page.push("--help".to_string());
        out.push(page);
        for sub in cmd.get_subcommands().filter(|c| c.get_name() != "help") {
            let mut next = path.to_vec();
            next.push(sub.get_name().to_string());
            walk(sub, &next, out);
        }
    }
    let mut out = Vec::new();
    walk(&hairlab::cli::Cli::command(), &[], &mut out);
    out
}

/// The subcommands `hairlab --help` lists.
fn subcommands() -> Vec<String> {
    use clap::CommandFactory;
    hairlab::cli::Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .filter(|n| n != "help")
        .collect()
}

#[test]
fn every_help_page_fits_80_columns_and_names_the_environment() {
    let pages = help_pages();
    for mode in [
        ["measure", "shadows"],
        ["bench", "transparency"],
        ["bench", "scaling"],
    ] {
        assert!(pages.iter().any(|p| p.len() > 2 && p[..2] == mode), "{pages:?}");
    }
    for page in &pages {
        let args: Vec<&str> = page.iter().map(String::as_str).collect();
        let o = hairlab_80(&args);
        assert!(o.status.success(), "{page:?}: {}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout);
        for line in text.lines() {
            assert!(
                line.chars().count() < 80,
                "{page:?}: {} columns: {line:?}",
                line.chars().count()
            );
        }
    }
    let top = String::from_utf8_lossy(&hairlab_80(&["--help"]).stdout).into_owned();
    for var in [
        "HAIRLAB_ADAPTER",
        "WGPU_BACKEND",
        "HAIRLAB_SKIP_GPU_TESTS",
        "HAIRLAB_UPDATE_SNAPSHOTS",
        "HAIRLAB_FUZZ_CASES",
        "RUST_LOG",
        "--adapter",
        "HAIRLAB_SHADERS",
        "--shaders",
    ] {
        assert!(top.contains(var), "--help does not name {var}: {top}");
    }
}

#[test]
fn completions_and_man_pages_cover_every_subcommand() {
    let o = hairlab(&["completions", "bash"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bash = String::from_utf8_lossy(&o.stdout).into_owned();
    let o = hairlab(&["man"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(page.contains(".TH hairlab"), "{page}");
    let dir = tempfile::tempdir().unwrap();
    let o = hairlab(&["man", "--out", dir.path().to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("hairlab.1").is_file());
    for sub in subcommands() {
        assert!(
            bash.contains(&format!("hairlab__subcmd__{sub}")),
            "bash completion lacks {sub}"
        );
        let file = dir.path().join(format!("hairlab-{sub}.1"));
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert!(
            text.contains(".TH hairlab") && text.contains(&sub),
            "{}",
            file.display()
        );
    }
    let o = hairlab(&["completions", "tcsh"]);
    assert!(
        !o.status.success() && stderr(&o).contains("tcsh"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn adapter_flag_chooses_by_name_and_names_an_unknown_one() {
    if hairlab::gpu::Gpu::for_tests().is_none() {
        return;
    }
    let o = hairlab(&["adapters"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let list = String::from_utf8_lossy(&o.stdout).into_owned();
    let chosen: Vec<&str> = list.lines().filter(|l| l.starts_with("* ")).collect();
    assert_eq!(chosen.len(), 1, "{list}");
    // Every adapter can be chosen by its own name (its first word, which `describe` starts with).
    let adapters: Vec<&str> = list
        .lines()
        .filter(|l| l.starts_with("  ") || l.starts_with("* "))
        .collect();
    let unusable = |l: &str| l.contains("unusable");
    for line in adapters.iter().filter(|l| !unusable(l)) {
        let name = line[2..].split_whitespace().next().unwrap();
        let o = hairlab(&["--adapter", name, "adapters"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let again = String::from_utf8_lossy(&o.stdout).into_owned();
        let marked = again.lines().find(|l| l.starts_with("* ")).unwrap_or_default();
        assert!(
            marked.to_lowercase().contains(&name.to_lowercase()),
            "--adapter {name}: {again}"
        );
    }
    let o = hairlab(&["--adapter", "no-such-gpu-xyz", "measure", "--frames", "1"]);
    assert_fails(&o, &["no-such-gpu-xyz", "hairlab adapters"]);
}

#[test]
fn mode_help_pages_list_only_their_own_options() {
    let page = |args: &[&str]| String::from_utf8_lossy(&hairlab_80(args).stdout).into_owned();
    let shadows = page(&["measure", "shadows", "--help"]);
    assert!(
        shadows.contains("--config") && shadows.contains("--out"),
        "{shadows}"
    );
    for other in ["--technique", "--fur-config", "--transparency", "--fur "] {
        assert!(
            !shadows.contains(other),
            "measure shadows lists {other}: {shadows}"
        );
    }
    let eye = page(&["bench", "transparency", "--help"]);
    assert!(eye.contains("--out") && eye.contains("--frames"), "{eye}");
    for other in ["--metric", "--methods", "--max-segments", "--scaling"] {
        assert!(!eye.contains(other), "bench transparency lists {other}: {eye}");
    }
    let measure = page(&["measure", "--help"]);
    for mode in ["shadows", "transparency", "fur"] {
        assert!(measure.contains(mode), "{measure}");
    }
}

#[test]
fn conflicting_and_ignored_flags_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let out = out.to_str().unwrap();
    // A mode's page has no other mode's options.
    assert_fails(
        &hairlab(&["measure", "fur", "--technique", "wboit"]),
        &["--technique"],
    );
    assert_fails(
        &hairlab(&["bench", "transparency", "--metric", "flip", "--out", out]),
        &["--metric"],
    );
    // Today's flags: what the chosen mode would ignore is refused, naming both flags.
    assert_fails(
        &hairlab(&["bench", "--scaling", "--metric", "flip", "--out", out]),
        &["--metric", "--scaling"],
    );
    assert_fails(
        &hairlab(&["bench", "--transparency", "--methods", "osm", "--out", out]),
        &["--methods", "--transparency"],
    );
    assert_fails(
        &hairlab(&["bench", "--max-segments", "1000", "--out", out]),
        &["--max-segments", "--scaling"],
    );
    assert_fails(
        &hairlab(&["measure", "--fur", "--config", "osm:slices=16"]),
        &["--config", "--fur"],
    );
    assert_fails(
        &hairlab(&["measure", "--technique", "wboit"]),
        &["--technique", "--transparency"],
    );
    assert!(!Path::new(out).exists(), "nothing written");
}

#[test]
fn old_mode_flags_still_run_and_name_the_new_spelling() {
    // `default` has no fur: both spellings fail the same way, the old one after naming the new.
    let old = hairlab(&["measure", "--fur"]);
    let new = hairlab(&["measure", "fur"]);
    assert_eq!(error_lines(&old), error_lines(&new));
    assert_fails(&new, &["fur.mode is off"]);
    assert!(
        stderr(&old).contains("note: `hairlab measure --fur` is now `hairlab measure fur`"),
        "{}",
        stderr(&old)
    );
    assert!(!stderr(&new).contains("note:"), "{}", stderr(&new));
}
