//! The terminal's [`Progress`]: a bar on stderr, one line per stage (on a terminal the stage's line is redrawn in
//! place as it advances; off one, a stage also prints a line each tenth of the whole) that answers `false` once Ctrl-C was pressed ([`super::interrupt`]), so every long run of the CLI
//! reports and stops through the same parameter as the window's jobs.

use crate::progress::Progress;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// A progress bar on stderr that stops the run on Ctrl-C.
pub struct TerminalProgress {
    tty: bool,
    drawn: bool,
    last_label: String,
    /// The tenth of the whole the last printed line reached (off a terminal).
    last_tenth: u32,
    start: Instant,
    stop: Option<&'static AtomicBool>,
}

impl TerminalProgress {
    /// A bar that stops the run once Ctrl-C is pressed (the handler installed here).
    pub fn new() -> TerminalProgress {
        let mut bar = TerminalProgress::uninterruptible();
        bar.stop = Some(super::interrupt::flag());
        bar
    }

    /// A bar that never stops the run.
    pub fn uninterruptible() -> TerminalProgress {
        use std::io::IsTerminal;
        TerminalProgress {
            tty: std::io::stderr().is_terminal(),
            drawn: false,
            last_label: String::new(),
            last_tenth: 0,
            start: Instant::now(),
            stop: None,
        }
    }

    /// The line for `label` at `fraction` after `seconds`: a 24-cell bar, the percentage, the label cut to 40
    /// characters, the elapsed time.
    pub fn line(label: &str, fraction: f32, seconds: f64) -> String {
        const CELLS: usize = 24;
        let f = fraction.clamp(0.0, 1.0);
        let filled = ((f * CELLS as f32) as usize).min(CELLS);
        format!(
            "[{}{}] {:>3.0} % {:<40} {:>6.1} s",
            "#".repeat(filled),
            ".".repeat(CELLS - filled),
            f * 100.0,
            cut(label, 40),
            seconds
        )
    }
}

impl TerminalProgress {
    /// What a step writes to stderr: on a terminal the stage's line redrawn in place (a new stage first ends the
    /// last one's line, so the stages stay on screen as a log); off one, a line per stage and one each tenth of
    /// the whole within a long stage, or nothing.
    fn output(&mut self, label: &str, fraction: f32) -> Option<String> {
        let line = Self::line(label, fraction, self.start.elapsed().as_secs_f64());
        let new = label != self.last_label;
        if new {
            self.last_label = label.to_string();
        }
        if self.tty {
            let end = if new && self.drawn { "\n" } else { "" };
            self.drawn = true;
            return Some(format!("{end}\r{line}"));
        }
        let tenth = (fraction.clamp(0.0, 1.0) * 10.0) as u32;
        (new || tenth > self.last_tenth).then(|| {
            self.last_tenth = tenth;
            format!("{line}\n")
        })
    }
}

impl Progress for TerminalProgress {
    fn step(&mut self, label: &str, fraction: f32) -> bool {
        if let Some(text) = self.output(label, fraction) {
            eprint!("{text}");
        }
        !self.stop.is_some_and(|s| s.load(Ordering::SeqCst))
    }
}

impl Default for TerminalProgress {
    fn default() -> Self {
        TerminalProgress::new()
    }
}

impl Drop for TerminalProgress {
    /// Ends the redrawn line so what follows starts on its own.
    fn drop(&mut self) {
        if self.drawn {
            eprintln!();
        }
    }
}

/// `text` cut to `max` characters, ending in `...` when cut.
fn cut(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        return text.to_string();
    }
    let kept: String = text.chars().take(max.saturating_sub(3)).collect();
    format!("{kept}...")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_has_a_bar_a_percentage_and_a_cut_label() {
        let line = TerminalProgress::line(
            "a label much longer than the forty characters that fit",
            0.25,
            2.5,
        );
        assert!(
            line.starts_with("[######..................]  25 % a label much longer than the forty ch... "),
            "{line}"
        );
        assert!(line.ends_with("2.5 s"), "{line}");
    }

    /// Off a terminal: a line for each new stage and for each tenth crossed within one, nothing else; on a
    /// terminal every step redraws its stage's line, a new stage after the first starting a line of its own.
    #[test]
    fn off_a_terminal_a_line_per_stage_and_tenth_on_one_a_redrawn_line() {
        let mut bar = TerminalProgress::uninterruptible();
        bar.tty = false;
        let printed: Vec<bool> = [
            ("a", 0.0),
            ("a", 0.05),
            ("a", 0.1),
            ("a", 0.15),
            ("b", 0.15),
            ("b", 0.35),
        ]
        .iter()
        .map(|&(label, f)| bar.output(label, f).is_some())
        .collect();
        assert_eq!(printed, [true, false, true, false, true, true]);
        assert!(bar.output("b", 0.36).is_none());
        let mut bar = TerminalProgress::uninterruptible();
        bar.tty = true;
        let a = bar.output("a", 0.0).unwrap();
        assert!(a.starts_with("\r[") && a.contains(" a "), "{a:?}");
        assert!(bar.output("a", 0.5).unwrap().starts_with("\r[#"));
        assert!(bar.output("b", 0.6).unwrap().starts_with("\n\r["));
    }
}
