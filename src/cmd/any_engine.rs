//! How `pair` and `run` report an engine (emdstar_engines::AnyEngine): the progress
//! bar's note, the summary fields.

use super::{edmd_engine, hybrid_engine};
use emdstar_engines::AnyEngine;
use emdstar_hybrid::Mode;
use serde_json::{Value, json};

/// The command line's view of an engine.
pub trait EngineReport {
    /// The progress bar's note.
    fn status(&self) -> String;
    /// The summary fields of this engine: its step, counters and rates over
    /// `wall_seconds` of work on `steps` steps.
    fn summary_fields(&self, wall_seconds: f64, steps: u64, threads: usize) -> Value;
}

impl EngineReport for AnyEngine {
    fn status(&self) -> String {
        match self {
            Self::Md(e) => {
                let th = e.thermo();
                format!(
                    "T = {:.3e} J, contacts {}",
                    th.granular_temperature, th.contacts
                )
            }
            Self::Event(e) => format!("{} collisions", e.stats().collisions()),
            Self::Hybrid(e) => format!(
                "{} event-driven, {} time-driven",
                e.count(Mode::Event),
                e.count(Mode::Time)
            ),
        }
    }

    fn summary_fields(&self, wall_seconds: f64, steps: u64, threads: usize) -> Value {
        let n = self.sim().particles().len() as f64;
        match self {
            Self::Md(e) => json!({
                "steps": e.steps(),
                "dt": e.options().dt,
                "skin": e.skin(),
                "neighbour_rebuilds": e.rebuilds(),
                "threads": threads,
                "particle_steps_per_s": n * steps as f64 / wall_seconds,
            }),
            Self::Event(e) => json!({
                "collisions_per_s": e.stats().collisions() as f64 / wall_seconds,
                "stats": edmd_engine::stats_json(e.stats()),
            }),
            Self::Hybrid(e) => json!({
                "steps": e.steps(),
                "dt": e.options().dt,
                "skin": e.skin(),
                "neighbour_rebuilds": e.stats().rebuilds,
                "threads": threads,
                "particle_steps_per_s": n * steps as f64 / wall_seconds,
                "collisions_per_s": e.stats().ed.collisions() as f64 / wall_seconds,
                "stats": hybrid_engine::stats_json(e.stats(), e.options().events),
            }),
        }
    }
}
