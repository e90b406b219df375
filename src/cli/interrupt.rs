//! Ctrl-C in `bench` and `measure`: SIGINT sets a flag that the runs read after each configuration; they stop
//! there, and the files they write after every configuration hold each one finished, written whole. The run
//! then fails with [`Interrupted`] (exit code 130, as a shell reports a process stopped by SIGINT).

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
