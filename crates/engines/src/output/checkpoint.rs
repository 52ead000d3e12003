//! Checkpoints as an output: the engine's whole state, every restart interval (if one
//! is set), at the end of the run (if asked for), and always when a run is stopped.

use super::{Cadence, End, Output};
use crate::AnyEngine;
use anyhow::{Context, Result};
use emdstar_system::{Checkpoint, CheckpointFile, Cut};
use std::path::Path;
use std::time::Instant;

/// Checkpoints of a run ([`Checkpoint`]).
pub struct CheckpointOutput {
    file: CheckpointFile,
    /// Every restart interval, if one is set.
    cadence: Option<Cadence>,
    /// Whether a run that reaches its end writes one then.
    at_end: bool,
    config_digest: u64,
    /// The time of the last checkpoint written by this run.
    last: Option<f64>,
    written: u64,
    /// Wall-clock seconds spent writing them.
    seconds: f64,
}

impl CheckpointOutput {
    /// Checkpoints written to the claimed `file` at the ticks of `cadence` (if any),
    /// when the run reaches its end (if `at_end`) and when it is stopped; they record
    /// `config_digest`.
    pub fn new(
        file: CheckpointFile,
        cadence: Option<Cadence>,
        at_end: bool,
        config_digest: u64,
    ) -> Self {
        Self {
            file,
            cadence,
            at_end,
            config_digest,
            last: None,
            written: 0,
            seconds: 0.0,
        }
    }

    /// The path of the last checkpoint written, if one was.
    pub fn written(&self) -> Option<&Path> {
        (self.written > 0).then(|| self.file.path())
    }

    /// Checkpoints written so far and the wall-clock seconds they took.
    pub fn cost(&self) -> (u64, f64) {
        (self.written, self.seconds)
    }

    fn save(&mut self, engine: &AnyEngine, last: bool) -> Result<()> {
        let start = Instant::now();
        let sim = engine.sim();
        let checkpoint = Checkpoint {
            engine: sim.engine().to_string(),
            options: engine.options_tag(),
            config_digest: self.config_digest,
            time: sim.time(),
            state: sim.save_state(),
        };
        self.file.write(&checkpoint, last).with_context(|| {
            format!("stopped at t = {:e} s: writing the checkpoint", sim.time())
        })?;
        self.last = Some(sim.time());
        self.written += 1;
        self.seconds += start.elapsed().as_secs_f64();
        Ok(())
    }
}

impl Output for CheckpointOutput {
    fn name(&self) -> &'static str {
        "checkpoint"
    }

    fn path(&self) -> Option<&Path> {
        Some(self.file.path())
    }

    fn open(&mut self, engine: &AnyEngine) -> Result<()> {
        if let Some(c) = &mut self.cadence {
            // Not at the start: the config is that checkpoint.
            c.start_at(engine.sim().time(), false);
        }
        Ok(())
    }

    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        self.open(engine)?;
        Ok(Cut::default())
    }

    fn next_due(&self) -> f64 {
        self.cadence.as_ref().map_or(f64::INFINITY, Cadence::time)
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.save(engine, false)?;
        if let Some(c) = &mut self.cadence {
            c.pass(engine.sim().time());
        }
        Ok(())
    }

    fn finish(&mut self, engine: &AnyEngine, end: End) -> Result<()> {
        let wanted = end == End::Stopped || self.at_end || self.cadence.is_some();
        if wanted && self.last != Some(engine.sim().time()) {
            self.save(engine, true)?;
        }
        Ok(())
    }

    fn saves_state(&self) -> bool {
        true
    }
}
