//! A process-wide request to stop a run: raised by a signal handler (SIGINT, SIGTERM)
//! or by a host such as Python on Ctrl-C, and read by every engine at each event or
//! step, so that a run stops within an event or a step of the request, however long
//! its output intervals.
//!
//! An engine that sees the request returns from [`crate::Simulation::advance_to`]
//! early, between two events or steps, with its state whole (its time is then that of
//! its last event or step); the caller finds out with [`requested`]. Raising the
//! request is an atomic store, safe inside a signal handler.

use std::sync::atomic::{AtomicI32, Ordering};

/// The signal number that asked to stop, 0 while none did.
static REQUEST: AtomicI32 = AtomicI32::new(0);

/// Asks every running engine to stop; `signal` (not 0) says why. Async-signal-safe.
pub fn request(signal: i32) {
    REQUEST.store(signal, Ordering::Relaxed);
}

/// Whether a stop was asked for: one relaxed atomic load, for the engines' inner loops.
#[inline]
pub fn is_requested() -> bool {
    REQUEST.load(Ordering::Relaxed) != 0
}

/// The signal that asked to stop, if any.
pub fn requested() -> Option<i32> {
    match REQUEST.load(Ordering::Relaxed) {
        0 => None,
        signal => Some(signal),
    }
}

/// Withdraws the request (before a new run starts).
pub fn clear() {
    REQUEST.store(0, Ordering::Relaxed);
}
