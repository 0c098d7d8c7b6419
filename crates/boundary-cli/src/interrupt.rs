//! Ctrl-C and SIGTERM during a run over frames: the first signal asks the run to stop
//! starting frames (those in flight finish and are kept); a second one ends the process at
//! once, as the signal's default action would.

use crate::error::CliError;
use signal_hook::consts::{SIGINT, SIGTERM};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

/// The termination signals received so far, once installed.
pub(crate) struct Interrupt {
    /// Set by the first signal: arms the immediate exit of the second.
    armed: Arc<AtomicBool>,
    /// The number of the last signal received (0: none).
    signal: Arc<AtomicUsize>,
}

impl Interrupt {
    /// Catches SIGINT and SIGTERM from now on.
    pub(crate) fn install() -> Result<Self, CliError> {
        let armed = Arc::new(AtomicBool::new(false));
        let signal = Arc::new(AtomicUsize::new(0));
        for sig in [SIGINT, SIGTERM] {
            // The order matters: the default action is checked before the first signal arms it.
            signal_hook::flag::register_conditional_default(sig, Arc::clone(&armed))
                .and_then(|_| signal_hook::flag::register(sig, Arc::clone(&armed)))
                .and_then(|_| {
                    signal_hook::flag::register_usize(
                        sig,
                        Arc::clone(&signal),
                        usize::try_from(sig).unwrap_or(usize::MAX),
                    )
                })
                .map_err(CliError::Signals)?;
        }
        Ok(Interrupt { armed, signal })
    }

    /// The signal received, if any (`SIGINT` is 2, `SIGTERM` 15).
    pub(crate) fn received(&self) -> Option<i32> {
        if !self.armed.load(Ordering::SeqCst) {
            return None;
        }
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            s => Some(i32::try_from(s).unwrap_or(SIGTERM)),
        }
    }
}
