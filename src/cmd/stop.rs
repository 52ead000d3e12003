//! Stopping a run cleanly on SIGINT (Ctrl-C) or SIGTERM (a batch scheduler's time
//! limit): the handlers only raise the stop request (`emdstar_system::stop`), which
//! every engine reads at each event or step; a second signal ends the process at once.

use anyhow::{Context, Result};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Installs the handlers (for the rest of the process).
pub fn install() -> Result<()> {
    emdstar_system::stop::clear();
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGINT, SIGTERM};
        use signal_hook::flag::{register, register_conditional_shutdown};
        for signal in [SIGINT, SIGTERM] {
            // A second signal ends the process at once (the run did not stop).
            let raised = Arc::new(AtomicBool::new(false));
            register_conditional_shutdown(signal, 1, Arc::clone(&raised))
                .and_then(|_| register(signal, raised))
                .context("installing the signal handlers")?;
            // SAFETY: the action is one atomic store, which is async-signal-safe.
            unsafe {
                signal_hook::low_level::register(signal, move || {
                    emdstar_system::stop::request(signal)
                })
            }
            .context("installing the signal handlers")?;
        }
    }
    Ok(())
}

/// The name of a signal that stops a run.
pub fn name(signal: i32) -> String {
    match signal {
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        other => format!("signal {other}"),
    }
}

/// The exit code a shell expects after `signal`: 128 + its number.
pub fn exit_code(signal: i32) -> u8 {
    u8::try_from(128 + signal).unwrap_or(1)
}
