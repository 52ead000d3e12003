//! The engine of a `pair` or `run` command: built from the config and the command-line
//! options, driven through the one simulation interface, and reported with its own
//! counters.

use super::edmd_engine::{self, EdmdArgs};
use super::engine::{EngineKind, MdArgs, md_options, parse_engine};
use super::hybrid_engine::{self, HybridArgs};
use anyhow::{Result, bail};
use clap::Args;
use emdstar_dem::{ContactEnd, Md};
use emdstar_hybrid::{Hybrid, HybridOptions, Mode};
use emdstar_system::{Config, Simulation, System};
use serde_json::{Value, json};

/// Every engine's options, as `pair` and `run` take them.
#[derive(Args, Debug, Clone)]
pub struct EngineArgs {
    /// The engine: md, emd, emdstar or hybrid.
    #[arg(long, value_parser = parse_engine, default_value = "md")]
    pub engine: EngineKind,
    #[command(flatten)]
    pub md: MdArgs,
    #[command(flatten)]
    pub edmd: EdmdArgs,
    #[command(flatten)]
    pub hybrid: HybridArgs,
}

/// One of the engines.
pub enum AnyEngine {
    Md(Box<Md>),
    Event(Box<emdstar_edmd::Engine>),
    Hybrid(Box<Hybrid>),
}

impl AnyEngine {
    /// The engine `args` choose for `system` (built from `config`). Step engines take
    /// steps of `dt_fraction` × the shortest contact time unless told otherwise.
    pub fn build(
        args: &EngineArgs,
        config: &Config,
        system: System,
        dt_fraction: f64,
    ) -> Result<Self> {
        Ok(match args.engine {
            EngineKind::Md => {
                let opts = md_options(config, &system, &args.md, dt_fraction)?;
                Self::Md(Box::new(Md::new(system, opts, config.t_end)?))
            }
            EngineKind::Emd | EngineKind::EmdStar if system.friction.is_active() => bail!(
                "friction = {} cannot be run by the event-driven engines yet: their collision \
                 rules are frictionless; run it with --engine md, or set friction = 0",
                system.friction.friction
            ),
            EngineKind::Emd | EngineKind::EmdStar => Self::Event(Box::new(edmd_engine::build(
                args.engine,
                &system,
                &args.edmd,
            )?)),
            EngineKind::Hybrid => {
                let md = md_options(config, &system, &args.md, dt_fraction)?;
                if md.contact_end != ContactEnd::ForceZero {
                    bail!(
                        "the hybrid engine needs contact_end = \"force\" (F = max(0, …)): its \
                         mode switches rely on the force staying zero at the end of an eMD* \
                         contact"
                    );
                }
                let h = &args.hybrid;
                let opts = HybridOptions {
                    skin: md.skin,
                    phi_time: h.phi_time,
                    phi_event: h.phi_event,
                    max_events_per_step: h.max_events_per_step,
                    cells: !h.no_cells,
                    ..HybridOptions::with_dt(md.dt)
                };
                let mor = edmd_engine::mor_source(&system, &args.edmd)?;
                Self::Hybrid(Box::new(Hybrid::new(system, opts, mor, config.t_end)?))
            }
        })
    }

    pub fn sim(&self) -> &dyn Simulation {
        match self {
            Self::Md(e) => e.as_ref(),
            Self::Event(e) => e.as_ref(),
            Self::Hybrid(e) => e.as_ref(),
        }
    }

    pub fn sim_mut(&mut self) -> &mut dyn Simulation {
        match self {
            Self::Md(e) => e.as_mut(),
            Self::Event(e) => e.as_mut(),
            Self::Hybrid(e) => e.as_mut(),
        }
    }

    /// What a resumed run must share with the run that wrote its checkpoint, besides
    /// the config: the source of the matrix of restitution.
    pub fn options_tag(&self) -> String {
        match self {
            Self::Md(_) => String::new(),
            Self::Event(e) => edmd_engine::mor_name(e.physics()).to_string(),
            Self::Hybrid(e) => e.mor_name().to_string(),
        }
    }

    /// Impacts whose MoR came from the exact solver because the table did not cover
    /// them (eMD* and the hybrid).
    pub fn mor_fallbacks(&self) -> u64 {
        match self {
            Self::Md(_) => 0,
            Self::Event(e) => e.stats().mor_fallbacks,
            Self::Hybrid(e) => e.stats().ed.mor_fallbacks,
        }
    }

    /// The progress bar's note.
    pub fn status(&self) -> String {
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

    /// The hybrid's mode counts now (recorded at every log line), `None` for the other
    /// engines.
    pub fn mode_point(&self, wall_seconds: f64) -> Option<Value> {
        match self {
            Self::Hybrid(e) => Some(json!({
                "t": e.time(),
                "event_driven": e.count(Mode::Event),
                "time_driven": e.count(Mode::Time),
                "wall_time_s": wall_seconds,
            })),
            _ => None,
        }
    }

    /// The summary fields of this engine: its step, counters and rates over
    /// `wall_seconds` of work on `steps` steps.
    pub fn summary_fields(&self, wall_seconds: f64, steps: u64, threads: usize) -> Value {
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
                "threads": 1,
                "particle_steps_per_s": n * steps as f64 / wall_seconds,
                "collisions_per_s": e.stats().ed.pair_collisions as f64 / wall_seconds,
                "stats": hybrid_engine::stats_json(e.stats()),
            }),
        }
    }
}
