//! The Bench window's **Export report…**: `hairlab report` of the current scene and selection (the window's
//! settings, its shadow method and transparency technique, the motion when the scene has one, the Bench
//! window's timed frames) as a job ([`super::jobs`]) with its progress, written into `hairlab-report/` of the
//! chosen folder with the window's settings beside the page (`settings.toml`) and the command that reproduces it
//! from them. The job bar's Stop writes the page of what finished, as Ctrl-C does; Cancel writes none (an
//! earlier report there stays).

use super::HairlabApp;
use super::jobs::{Job, Poll};
use crate::measure::MethodConfig;
use crate::measure::transparency::TechniqueConfig;
use crate::progress::Outcome;
use crate::report::run::Plan;
use std::path::{Path, PathBuf};

/// The folder the report is written to inside the chosen one.
pub const REPORT_DIR: &str = "hairlab-report";

/// What the export job gives back: the page and the configurations on it (stopped: those finished).
pub type ReportDone = Result<Outcome<(PathBuf, usize)>, String>;

/// The report's folder for the chosen folder `dir`.
fn out_shown(dir: &Path) -> PathBuf {
    dir.join(REPORT_DIR)
}

/// The command that reproduces a report of `plan` from `settings.toml` in `out`, quoted for a POSIX shell as
/// `hairlab report` quotes its own ([`crate::cli::report::shell_command`]).
fn command(plan: &Plan, out: &Path) -> String {
    let mut words = vec![
        "hairlab".to_string(),
        "report".to_string(),
        "--preset".to_string(),
        out.join("settings.toml").display().to_string(),
    ];
    for c in &plan.configs {
        words.extend(["--config".to_string(), c.clone()]);
    }
    for t in &plan.techniques {
        words.extend(["--technique".to_string(), t.clone()]);
    }
    if plan.motion {
        words.push("--motion".to_string());
    }
    words.extend([
        "--frames".to_string(),
        plan.frames.to_string(),
        "--out".to_string(),
        out.display().to_string(),
    ]);
    crate::cli::report::shell_command(words)
}

impl HairlabApp {
    /// Starts the report of the current scene and selection into `dir/hairlab-report` (replacing an earlier
    /// report there).
    pub(super) fn start_report_export(&mut self, dir: &Path) {
        let settings = self.settings.clone();
        let out = dir.join(REPORT_DIR);
        let method = MethodConfig::new(settings.method.name.clone(), settings.method.params.clone());
        let technique = TechniqueConfig::new(
            settings.transparency.name.clone(),
            settings.transparency.params.clone(),
        );
        let plan = Plan {
            preset: "the window's settings".to_string(),
            configs: vec![method.label()],
            techniques: vec![technique.label()],
            motion: settings.motion.source != crate::motion::MotionSource::None,
            frames: self.bench.frames,
            truth: false,
        };
        let command = command(&plan, &out);
        let toml = settings.to_toml().into_bytes();
        let job = Job::spawn("report", &self.egui_ctx, self.job_gate.clone(), move |ctl| {
            let extra = [("settings.toml", toml)];
            let study = crate::report::study_fresh(&out, &plan, &settings, &extra, &mut ctl.clone());
            // Cancelled, the draft is dropped unwritten; stopped, the page holds what finished.
            if ctl.cancelled() {
                return None;
            }
            let page = study.and_then(|study| {
                study.try_map(|study| {
                    let configurations = study.configurations();
                    Ok((study.finish(command)?, configurations))
                })
            });
            Some(page.map_err(|e| format!("{e:#}")))
        })
        .stoppable();
        self.info(format!("report: writing {}", out_shown(dir).display()));
        self.bench.report = Some((job, out_shown(dir)));
    }

    /// Takes the export's result once it finished.
    pub(super) fn poll_report_export(&mut self) {
        let Some((job, out)) = &self.bench.report else {
            return;
        };
        let done = match job.poll() {
            Poll::Running => return,
            Poll::Gone if job.cancelled() => Ok(None),
            Poll::Gone => Err("the report stopped without a page".to_string()),
            Poll::Done(done) => done.map(Some),
        };
        let out = out.clone();
        self.bench.report = None;
        match done {
            Ok(None) => self.info(format!(
                "report cancelled: nothing written ({} as it was)",
                out.display()
            )),
            Ok(Some(Outcome::Complete((page, _)))) => self.info(format!("report: wrote {}", page.display())),
            Ok(Some(Outcome::Stopped((page, n)))) => self.info(format!(
                "report stopped: kept {n} configurations in {}",
                page.display()
            )),
            Err(e) => self.error(format!("report: {e}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The command read back by `sh -c` (with `hairlab` a shell function that prints its arguments) gives back
    /// every word: a folder with a space, a `$(…)`, a `'`, a `"` and a backquote in its name, and a configuration
    /// with a space and a `;`.
    #[test]
    fn the_reproducing_command_survives_a_shell() {
        let out = Path::new("/tmp/my reports/$(echo injected)/it's \"here\" `x`/hairlab-report");
        let technique = crate::render::transparency::registry::reference().name();
        let plan = Plan {
            preset: String::new(),
            configs: vec!["dom:slices=8".to_string(), "a b;c".to_string()],
            techniques: vec![technique.to_string()],
            motion: true,
            frames: 12,
            truth: false,
        };
        let command = command(&plan, out);
        let script = format!("hairlab() {{ printf '%s\\0' \"$@\"; }}; {command}");
        let o = std::process::Command::new("sh")
            .args(["-c", &script])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let words: Vec<String> = String::from_utf8(o.stdout)
            .unwrap()
            .split_terminator('\0')
            .map(str::to_string)
            .collect();
        let settings = out.join("settings.toml").display().to_string();
        let want = [
            "report",
            "--preset",
            &settings,
            "--config",
            "dom:slices=8",
            "--config",
            "a b;c",
            "--technique",
            technique,
            "--motion",
            "--frames",
            "12",
            "--out",
            out.to_str().unwrap(),
        ];
        assert_eq!(words, want, "{command}");
    }
}
