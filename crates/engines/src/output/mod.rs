//! The outputs of a run as one mechanism, after lumol's `Output` with its
//! `OutputFrequency`: each output (the thermo log, the trajectory, checkpoints, the
//! hybrid's mode counts) says when it is next due, and the run loop
//! ([`crate::run`]) advances the engine to the earliest due time and lets every due
//! output write. Starting afresh or resuming from a checkpoint, and the last record
//! when a run ends between two due times, are each output's own business, so that they
//! work the same way for every output.
//!
//! An output is built around the files it claimed ([`emdstar_system::OutputFile`]:
//! checked and locked, nothing written yet); [`Output::open`] or [`Output::resume`]
//! starts writing them.

mod cadence;
mod checkpoint;
mod log;
mod memory;
mod modes;
mod trajectory;

pub use cadence::{Cadence, Schedule};
pub use checkpoint::CheckpointOutput;
pub use log::LogOutput;
pub use memory::Recorder;
pub use modes::{ModeCounts, ModePoint};
pub use trajectory::{TrajectoryFormat, TrajectoryOutput};

use crate::AnyEngine;
use anyhow::Result;
use emdstar_system::Cut;
use std::path::Path;

/// How a run ended, as its outputs see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// It reached the time it was asked to stop at.
    Complete,
    /// A stop was requested (a signal, Ctrl-C) before that.
    Stopped,
}

/// One output of a run (see the module documentation).
pub trait Output {
    /// What it is, in messages and in a run summary: "log", "trajectory", "checkpoint",
    /// "mode_counts".
    fn name(&self) -> &'static str;

    /// The file it writes, if any.
    fn path(&self) -> Option<&Path>;

    /// Starts the output of a fresh run, at the engine's time (which is due at once
    /// for a record of the start).
    fn open(&mut self, engine: &AnyEngine) -> Result<()>;

    /// Takes up the output of a run resumed at the engine's time: keeps what an earlier
    /// run wrote before that time (and at it, if the output is due then), cuts what it
    /// wrote after (whole records, and one left unfinished by a kill), and says what it
    /// cut.
    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut>;

    /// The time it is next due (infinite: only when the run ends). A step engine's
    /// time within half a step of it counts as it.
    fn next_due(&self) -> f64;

    /// Writes the record of the engine's time, and moves on to the next due time.
    fn write(&mut self, engine: &AnyEngine) -> Result<()>;

    /// The end of the run: writes a last record if the output wants one at the time
    /// the run ended and has none yet, and flushes.
    fn finish(&mut self, engine: &AnyEngine, end: End) -> Result<()>;

    /// Writes what the operating system buffers to the disk.
    fn sync(&mut self) -> Result<()> {
        Ok(())
    }

    /// Whether it saves the engine's state (a checkpoint): the loop writes and syncs
    /// the records of the same time first, so that a checkpoint never runs ahead of
    /// them.
    fn saves_state(&self) -> bool {
        false
    }
}
