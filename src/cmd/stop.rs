//! Stopping a run cleanly on SIGINT (Ctrl-C) or SIGTERM (a batch scheduler's time
//! limit): the handlers only raise a flag, which the run loop reads between steps; a
//! second signal ends the process at once.

use anyhow::{Context, Result};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Which signal asked the run to stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    Interrupt,
    Terminate,
}

impl Stop {
    /// The exit code a shell expects after this signal: 128 + its number.
    pub fn exit_code(self) -> u8 {
        match self {
            Self::Interrupt => 130,
            Self::Terminate => 143,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Interrupt => "SIGINT",
            Self::Terminate => "SIGTERM",
        }
    }
}

/// The flags the signal handlers raise.
pub struct StopFlags {
    interrupt: Arc<AtomicBool>,
    terminate: Arc<AtomicBool>,
}

impl StopFlags {
    /// Installs the handlers (for the rest of the process).
    pub fn install() -> Result<Self> {
        let flags = Self {
            interrupt: Arc::new(AtomicBool::new(false)),
            terminate: Arc::new(AtomicBool::new(false)),
        };
        #[cfg(unix)]
        {
            use signal_hook::consts::{SIGINT, SIGTERM};
            use signal_hook::flag::{register, register_conditional_shutdown};
            for (signal, flag) in [(SIGINT, &flags.interrupt), (SIGTERM, &flags.terminate)] {
                // A second signal ends the process at once (the run did not stop).
                register_conditional_shutdown(signal, 1, Arc::clone(flag))
                    .and_then(|_| register(signal, Arc::clone(flag)))
                    .context("installing the signal handlers")?;
            }
        }
        Ok(flags)
    }

    /// The signal received, if any.
    pub fn requested(&self) -> Option<Stop> {
        if self.interrupt.load(Ordering::Relaxed) {
            Some(Stop::Interrupt)
        } else if self.terminate.load(Ordering::Relaxed) {
            Some(Stop::Terminate)
        } else {
            None
        }
    }
}
