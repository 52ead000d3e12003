//! The thermo log as an output: a line at every tick of its cadence, and one at the
//! end of a run that ends between two; each line ends with the observables of the
//! interval since the line before (see [`crate::observe`]).

use super::{Cadence, End, Output, Schedule};
use crate::AnyEngine;
use crate::observe;
use anyhow::{Context, Result};
use emdstar_system::{Cut, OutputFile, ThermoLog};
use std::path::{Path, PathBuf};

/// The thermo log ([`ThermoLog`]).
pub struct LogOutput {
    claim: Option<OutputFile>,
    path: PathBuf,
    log: Option<ThermoLog>,
    schedule: Schedule,
    /// Σ a₂ and the lines it sums (for the run mean).
    a2_sum: f64,
    a2_lines: u32,
}

impl LogOutput {
    /// A log written to the claimed file `file` at the ticks of `cadence`.
    pub fn new(file: OutputFile, cadence: Cadence) -> Self {
        Self {
            path: file.path().to_path_buf(),
            claim: Some(file),
            log: None,
            schedule: Schedule::new(cadence),
            a2_sum: 0.0,
            a2_lines: 0,
        }
    }

    /// The mean a₂ of the lines this run wrote (NaN before any).
    pub fn mean_sonine_a2(&self) -> f64 {
        self.a2_sum / self.a2_lines as f64
    }

    fn line(&mut self, engine: &AnyEngine, due: bool) -> Result<()> {
        let th = engine.sim().thermo();
        // The interval since the engine's mark, which the run loop sets after each
        // line (a checkpoint keeps it).
        let obs = observe::since(engine.sim(), engine.sim().stress_mark().as_ref());
        if obs.sonine_a2.is_finite() {
            self.a2_sum += obs.sonine_a2;
            self.a2_lines += 1;
        }
        self.log
            .as_mut()
            .expect("the log is open")
            .write(&th, &obs)
            .with_context(|| format!("stopped at t = {:e} s: writing the thermo log", th.t))?;
        self.schedule.wrote(th.t, due);
        Ok(())
    }
}

impl Output for LogOutput {
    fn name(&self) -> &'static str {
        "log"
    }

    fn path(&self) -> Option<&Path> {
        Some(&self.path)
    }

    fn open(&mut self, engine: &AnyEngine) -> Result<()> {
        let file = self.claim.take().expect("opened once");
        self.log = Some(ThermoLog::start(file)?);
        self.schedule.open(engine.sim().time());
        Ok(())
    }

    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        let keep = self.schedule.resume(engine.sim().time());
        let file = self.claim.take().expect("opened once");
        let (log, cut) = ThermoLog::resume_in(file, keep)
            .with_context(|| format!("resuming the log {}", self.path.display()))?;
        self.log = Some(log);
        Ok(cut)
    }

    fn next_due(&self) -> f64 {
        self.schedule.next_due()
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.line(engine, true)
    }

    fn finish(&mut self, engine: &AnyEngine, _end: End) -> Result<()> {
        if self.schedule.needs_last(engine.sim().time()) {
            self.line(engine, false)?;
        }
        self.sync()
    }

    fn sync(&mut self) -> Result<()> {
        if let Some(log) = &mut self.log {
            log.flush()?;
        }
        Ok(())
    }
}
