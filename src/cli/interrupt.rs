//! Ctrl-C in `bench`, `measure`, `report` and `render`: SIGINT sets a flag that the runs read after each
//! configuration (or pass of samples, or texel); they stop there, and the files they write hold each one finished,
//! written whole. The run then fails with [`Interrupted`], or [`InterruptedAt`] for a run stopped partway
//! through one long step (exit code 130 either way, as a shell reports a process stopped by SIGINT).

use crate::progress::Outcome;
use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of an interrupted run: 128 + SIGINT.
pub const EXIT_CODE: u8 = 130;

/// A run stopped by Ctrl-C after `done` finished configurations.
#[derive(Debug, thiserror::Error)]
#[error("interrupted (Ctrl-C) after {done} configurations; the files written hold those {done}")]
pub struct Interrupted {
    pub done: usize,
}

/// A run stopped by Ctrl-C partway through its one long step, after `done` `unit` (e.g. "of 64 samples per
/// pixel", "texels"), having written the file `wrote` of those `done` (if it writes one).
#[derive(Debug, thiserror::Error)]
#[error("interrupted (Ctrl-C) after {done} {unit}{}", holds(.wrote.as_deref(), *.done))]
pub struct InterruptedAt {
    pub done: u64,
    pub unit: String,
    pub wrote: Option<std::path::PathBuf>,
}

fn holds(wrote: Option<&std::path::Path>, done: u64) -> String {
    wrote.map_or(String::new(), |p| format!("; {} holds those {done}", p.display()))
}

/// The command's end of a run's [`Outcome`] (the one place a stopped run becomes exit code 130): complete, `Ok`;
/// stopped, [`Interrupted`] after the `done` configurations it kept.
pub fn finish<T>(outcome: &Outcome<T>, done: usize) -> anyhow::Result<()> {
    if outcome.is_stopped() {
        return Err(Interrupted { done }.into());
    }
    Ok(())
}

/// The end of a run that writes one CSV of rows: `rows` written whole as `name` in `dir` (when given) and said;
/// then `Ok`, or when `stopped` [`InterruptedAt`] after the `rows.len()` `unit` the file holds.
pub fn write_rows_and_finish<T: serde::Serialize>(
    dir: Option<&std::path::Path>,
    name: &str,
    rows: &[T],
    stopped: bool,
    unit: &str,
) -> anyhow::Result<()> {
    let wrote = match dir {
        Some(dir) => {
            let path = dir.join(name);
            crate::io::write_atomic(&path, crate::io::csv_text(name, rows)?.as_bytes())?;
            println!("wrote {}", path.display());
            Some(path)
        }
        None => None,
    };
    if stopped {
        return Err(InterruptedAt {
            done: rows.len() as u64,
            unit: unit.to_string(),
            wrote,
        }
        .into());
    }
    Ok(())
}

/// Whether `e` is a run stopped by Ctrl-C ([`Interrupted`] or [`InterruptedAt`]), whose exit code is [`EXIT_CODE`].
pub fn is_interrupted(e: &anyhow::Error) -> bool {
    e.is::<Interrupted>() || e.is::<InterruptedAt>()
}

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The flag SIGINT sets, with the handler installed on the first call (a second Ctrl-C changes nothing: the
/// configuration in progress still finishes and is written).
pub fn flag() -> &'static AtomicBool {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        let handler = || {
            if !INTERRUPTED.swap(true, Ordering::SeqCst) {
                eprintln!("\nCtrl-C: stopping after the configuration in progress");
            }
        };
        if let Err(e) = ctrlc::set_handler(handler) {
            log::warn!("Ctrl-C will stop the run at once, without writing the last files: {e}");
        }
    });
    &INTERRUPTED
}
