//! The thermo log as an output: a line at every tick of its cadence, and one at the
//! end of a run that ends between two.

use super::{Cadence, End, Output};
use crate::AnyEngine;
use anyhow::{Context, Result};
use emdstar_system::{Cut, KeepUntil, OutputFile, ThermoLog};
use std::path::{Path, PathBuf};

/// The thermo log ([`ThermoLog`]).
pub struct LogOutput {
    claim: Option<OutputFile>,
    path: PathBuf,
    log: Option<ThermoLog>,
    cadence: Cadence,
    /// The time of the last line written.
    last: Option<f64>,
}

impl LogOutput {
    /// A log written to the claimed file `file` at the ticks of `cadence`.
    pub fn new(file: OutputFile, cadence: Cadence) -> Self {
        Self {
            path: file.path().to_path_buf(),
            claim: Some(file),
            log: None,
            cadence,
            last: None,
        }
    }

    fn line(&mut self, engine: &AnyEngine) -> Result<()> {
        let th = engine.sim().thermo();
        self.log
            .as_mut()
            .expect("the log is open")
            .write(&th)
            .with_context(|| format!("stopped at t = {:e} s: writing the thermo log", th.t))?;
        self.last = Some(th.t);
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
        self.cadence.start_at(engine.sim().time(), true);
        Ok(())
    }

    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        let t = engine.sim().time();
        let keep = KeepUntil {
            t,
            at_t: self.cadence.is_tick(t),
        };
        let file = self.claim.take().expect("opened once");
        let (log, cut) = ThermoLog::resume_in(file, keep)
            .with_context(|| format!("resuming the log {}", self.path.display()))?;
        self.log = Some(log);
        // A line at a tick `t` is the earlier run's, kept: none is due again there.
        self.last = keep.at_t.then_some(t);
        self.cadence.start_at(t, false);
        Ok(cut)
    }

    fn next_due(&self) -> f64 {
        self.cadence.time()
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.line(engine)?;
        self.cadence.pass(engine.sim().time());
        Ok(())
    }

    fn finish(&mut self, engine: &AnyEngine, _end: End) -> Result<()> {
        if self.last != Some(engine.sim().time()) {
            self.line(engine)?;
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
