//! Records kept in memory, for a caller that embeds a run (the Python package): the
//! thermo quantities and, if asked, the particles at every tick of a cadence, and at
//! the end of a run that ends between two.

use super::{Cadence, End, Output, Schedule};
use crate::AnyEngine;
use anyhow::Result;
use emdstar_system::{Cut, Particles, Thermo};
use std::path::Path;

/// The thermo quantities (and the particles, if asked) at each tick.
pub struct Recorder {
    schedule: Schedule,
    keep_particles: bool,
    /// One per record.
    pub thermo: Vec<Thermo>,
    /// One per record, if the particles are kept.
    pub particles: Vec<Particles>,
}

impl Recorder {
    /// Records at the ticks of `cadence`, with the particles if `keep_particles`.
    pub fn new(cadence: Cadence, keep_particles: bool) -> Self {
        Self {
            schedule: Schedule::new(cadence),
            keep_particles,
            thermo: Vec::new(),
            particles: Vec::new(),
        }
    }

    fn record(&mut self, engine: &AnyEngine, due: bool) {
        let sim = engine.sim();
        let th = sim.thermo();
        self.schedule.wrote(th.t, due);
        self.thermo.push(th);
        if self.keep_particles {
            self.particles.push(sim.particles());
        }
    }
}

impl Output for Recorder {
    fn name(&self) -> &'static str {
        "recorder"
    }

    fn path(&self) -> Option<&Path> {
        None
    }

    fn open(&mut self, engine: &AnyEngine) -> Result<()> {
        self.schedule.open(engine.sim().time());
        Ok(())
    }

    /// A resumed run records from its checkpoint on, the record of its time first if
    /// that is a tick (what came before is not in memory).
    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        self.schedule.open(engine.sim().time());
        Ok(Cut::default())
    }

    fn next_due(&self) -> f64 {
        self.schedule.next_due()
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.record(engine, true);
        Ok(())
    }

    fn finish(&mut self, engine: &AnyEngine, _end: End) -> Result<()> {
        if self.schedule.needs_last(engine.sim().time()) {
            self.record(engine, false);
        }
        Ok(())
    }
}
