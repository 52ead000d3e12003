//! What the config and checkpoint targets share: building each engine from a parsed
//! config as `emdstar run` does (the default time step, the default MoR table with the
//! exact fallback), and running it a bounded amount.

use emdstar_dem::{ContactEnd, DEFAULT_DT_FRACTION, Md, MdOptions, shortest_contact_time};
use emdstar_edmd::rules::TableMorSource;
use emdstar_edmd::{BroadPhaseKind, Engine, Interference, Materials, Physics};
use emdstar_hybrid::{Hybrid, HybridOptions};
use emdstar_system::{Config, Simulation, System};

/// Particles above which an input is skipped, so that each input runs in well under a
/// second (a gas's `count` is checked before it is generated).
pub const MAX_PARTICLES: u64 = 64;

/// Whether the config describes few enough particles to be set up quickly.
pub fn small_enough(config: &Config) -> bool {
    config.particles.len() as u64 <= MAX_PARTICLES
        && config
            .gas
            .as_ref()
            .is_none_or(|g| (g.count as u64) <= MAX_PARTICLES)
}

/// The engines `emdstar run` builds.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    Md,
    EmdStar,
    Hybrid,
}

pub const KINDS: [Kind; 3] = [Kind::Md, Kind::EmdStar, Kind::Hybrid];

/// A built engine.
pub enum Built {
    Md(Box<Md>),
    Event(Box<Engine>),
    Hybrid(Box<Hybrid>),
}

/// The MD time step `emdstar run` takes by default.
fn default_dt(config: &Config, system: &System) -> Option<f64> {
    let dt = match shortest_contact_time(system, config.t_end).ok()? {
        Some(tc) => DEFAULT_DT_FRACTION * tc,
        None => config.t_end,
    };
    let steps = (config.t_end / dt).ceil().max(1.0);
    (steps <= 1e13).then_some(config.t_end / steps)
}

/// The engine of `kind` for the system of `config`, or `None` where set-up refuses it
/// (a refusal must be an error, never a panic).
pub fn build(kind: Kind, config: &Config, system: System) -> Option<Built> {
    let dt = default_dt(config, &system)?;
    let model = system.material.model();
    let table = || {
        emdstar_table::default_table(model)
            .ok()
            .map(|t| Box::new(TableMorSource::new(t, true)))
    };
    Some(match kind {
        Kind::Md => {
            let opts = MdOptions {
                dt,
                contact_end: ContactEnd::ForceZero,
                skin: None,
            };
            Built::Md(Box::new(Md::new(system, opts, config.t_end).ok()?))
        }
        Kind::EmdStar => {
            let physics = Physics::EmdStar {
                materials: Materials::from_system(&system).ok()?,
                mor: table()?,
                interference: Interference::HitOnly,
            };
            let engine = Engine::with_broad_phase(
                &system.particles,
                &system.domain,
                physics,
                BroadPhaseKind::Auto,
            )
            .ok()?;
            Built::Event(Box::new(engine))
        }
        Kind::Hybrid => {
            let opts = HybridOptions::with_dt(dt);
            Built::Hybrid(Box::new(
                Hybrid::new(system, opts, table()?, config.t_end).ok()?,
            ))
        }
    })
}

impl Built {
    pub fn sim(&mut self) -> &mut dyn Simulation {
        match self {
            Self::Md(e) => e.as_mut(),
            Self::Event(e) => e.as_mut(),
            Self::Hybrid(e) => e.as_mut(),
        }
    }

    /// Runs `n` time steps (MD, the hybrid) or events (the event engine), stopping at
    /// the first error, then reads the state out and saves it.
    pub fn run_bounded(&mut self, n: u32) {
        match self {
            Self::Md(e) => {
                let dt = e.options().dt;
                let _ = e.advance_to(e.time() + f64::from(n) * dt);
            }
            Self::Event(e) => {
                for _ in 0..n {
                    if e.step().is_err() {
                        break;
                    }
                }
            }
            Self::Hybrid(e) => {
                let _ = e.advance(u64::from(n));
            }
        }
        let sim = self.sim();
        let _ = sim.thermo();
        let _ = sim.particles();
        let _ = sim.save_state();
    }
}
