//! The hybrid's mode counts as an output: how many particles are event-driven and how
//! many time-driven, recorded in memory at the log's ticks (a run summary reports them).

use super::{Cadence, End, Output};
use crate::AnyEngine;
use anyhow::Result;
use emdstar_hybrid::Mode;
use emdstar_system::Cut;
use std::path::Path;
use std::time::Instant;

/// The modes at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModePoint {
    /// Simulated time in s.
    pub t: f64,
    pub event_driven: usize,
    pub time_driven: usize,
    /// Wall-clock seconds since this run started.
    pub wall_seconds: f64,
}

/// The hybrid's mode counts; records nothing for the other engines.
pub struct ModeCounts {
    cadence: Cadence,
    start: Instant,
    points: Vec<ModePoint>,
}

impl ModeCounts {
    /// Counts recorded at the ticks of `cadence`.
    pub fn new(cadence: Cadence) -> Self {
        Self {
            cadence,
            start: Instant::now(),
            points: Vec::new(),
        }
    }

    /// The counts recorded so far.
    pub fn points(&self) -> &[ModePoint] {
        &self.points
    }

    fn record(&mut self, engine: &AnyEngine) {
        if let AnyEngine::Hybrid(e) = engine {
            self.points.push(ModePoint {
                t: e.time(),
                event_driven: e.count(Mode::Event),
                time_driven: e.count(Mode::Time),
                wall_seconds: self.start.elapsed().as_secs_f64(),
            });
        }
    }
}

impl Output for ModeCounts {
    fn name(&self) -> &'static str {
        "mode_counts"
    }

    fn path(&self) -> Option<&Path> {
        None
    }

    fn open(&mut self, engine: &AnyEngine) -> Result<()> {
        self.start = Instant::now();
        self.cadence.start_at(engine.sim().time(), true);
        Ok(())
    }

    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        self.start = Instant::now();
        self.cadence.start_at(engine.sim().time(), false);
        Ok(Cut::default())
    }

    fn next_due(&self) -> f64 {
        self.cadence.time()
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.record(engine);
        self.cadence.pass(engine.sim().time());
        Ok(())
    }

    fn finish(&mut self, engine: &AnyEngine, _end: End) -> Result<()> {
        if self.points.last().map(|p| p.t) != Some(engine.sim().time()) {
            self.record(engine);
        }
        Ok(())
    }
}
