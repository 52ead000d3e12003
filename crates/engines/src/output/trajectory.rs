//! The trajectory as an output: a frame at every tick of its cadence, and one at the end
//! of a run that reaches its end between two; extended XYZ or GSD.

use super::{Cadence, End, Output, Schedule};
use crate::AnyEngine;
use anyhow::{Context, Result};
use emdstar_system::gsd::GsdWriter;
use emdstar_system::{Cut, OutputFile, Particles, XyzWriter};
use std::path::Path;

/// The file format of a trajectory; OVITO reads both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrajectoryFormat {
    /// Extended XYZ (text).
    Xyz,
    /// GSD (binary, a fifth of the size), for a name ending in `.gsd`.
    Gsd,
}

impl TrajectoryFormat {
    /// The format a path's extension chooses.
    pub fn of(path: &Path) -> Self {
        if path.extension().is_some_and(|e| e == "gsd") {
            Self::Gsd
        } else {
            Self::Xyz
        }
    }

    /// Bytes one frame of `n` particles of `species` kinds takes, about.
    pub fn frame_bytes(self, n: usize, species: usize) -> u64 {
        match self {
            Self::Gsd => GsdWriter::frame_bytes(n, species),
            // Fifteen columns in shortest round-trip notation.
            Self::Xyz => 220 * n as u64 + 300,
        }
    }
}

enum Writer {
    Xyz(XyzWriter),
    Gsd(GsdWriter),
}

/// The trajectory.
pub struct TrajectoryOutput {
    claim: Option<OutputFile>,
    path: std::path::PathBuf,
    format: TrajectoryFormat,
    writer: Option<Writer>,
    schedule: Schedule,
}

impl TrajectoryOutput {
    /// Frames written to the claimed file `file` at the ticks of `cadence`, in the
    /// format its name chooses.
    pub fn new(file: OutputFile, cadence: Cadence) -> Self {
        let path = file.path().to_path_buf();
        Self {
            format: TrajectoryFormat::of(&path),
            claim: Some(file),
            path,
            writer: None,
            schedule: Schedule::new(cadence),
        }
    }

    /// The file format.
    pub fn format(&self) -> TrajectoryFormat {
        self.format
    }

    fn frame(&mut self, engine: &AnyEngine, due: bool) -> Result<()> {
        let sim = engine.sim();
        let (t, p) = (sim.time(), sim.particles());
        let sim_box = sim.domain().sim_box.as_ref();
        match self.writer.as_mut().expect("the trajectory is open") {
            Writer::Xyz(w) => w.write_frame(t, &p, sim_box),
            Writer::Gsd(w) => w.write_frame(t, &p, species(&p), sim_box),
        }
        .with_context(|| format!("stopped at t = {t:e} s: writing the trajectory frame"))?;
        self.schedule.wrote(t, due);
        Ok(())
    }
}

/// The number of species of `p` (each species has particles).
fn species(p: &Particles) -> usize {
    p.species.iter().max().map_or(0, |&s| s as usize + 1)
}

impl Output for TrajectoryOutput {
    fn name(&self) -> &'static str {
        "trajectory"
    }

    fn path(&self) -> Option<&Path> {
        Some(&self.path)
    }

    fn open(&mut self, engine: &AnyEngine) -> Result<()> {
        let file = self.claim.take().expect("opened once");
        self.writer = Some(match self.format {
            TrajectoryFormat::Xyz => Writer::Xyz(XyzWriter::start(file)?),
            TrajectoryFormat::Gsd => Writer::Gsd(GsdWriter::start(file)?),
        });
        self.schedule.open(engine.sim().time());
        Ok(())
    }

    fn resume(&mut self, engine: &AnyEngine) -> Result<Cut> {
        let keep = self.schedule.resume(engine.sim().time());
        let p = engine.sim().particles();
        let file = self.claim.take().expect("opened once");
        let resumed = match self.format {
            TrajectoryFormat::Xyz => {
                XyzWriter::resume_in(file, keep, p.len()).map(|(w, cut)| (Writer::Xyz(w), cut))
            }
            TrajectoryFormat::Gsd => GsdWriter::resume_in(file, keep, p.len(), species(&p))
                .map(|(w, cut)| (Writer::Gsd(w), cut)),
        };
        let (writer, cut) =
            resumed.with_context(|| format!("resuming the trajectory {}", self.path.display()))?;
        self.writer = Some(writer);
        Ok(cut)
    }

    fn next_due(&self) -> f64 {
        self.schedule.next_due()
    }

    fn write(&mut self, engine: &AnyEngine) -> Result<()> {
        self.frame(engine, true)
    }

    /// The last frame of a run that reached its end; a stopped run writes none (its
    /// checkpoint holds the state).
    fn finish(&mut self, engine: &AnyEngine, end: End) -> Result<()> {
        if end == End::Complete && self.schedule.needs_last(engine.sim().time()) {
            self.frame(engine, false)?;
        }
        self.sync()
    }

    fn sync(&mut self) -> Result<()> {
        match &mut self.writer {
            Some(Writer::Xyz(w)) => w.flush()?,
            Some(Writer::Gsd(w)) => w.flush()?,
            None => {}
        }
        Ok(())
    }
}
