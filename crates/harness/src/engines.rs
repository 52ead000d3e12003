//! Building systems and driving the three engines on them, with the default MoR tables.

use crate::plot::{PALETTE, RGBColor, Style};
use crate::{HarnessError, Result};
use emdstar_contact::ForceLaw;
use emdstar_dem::{DEFAULT_DT_FRACTION, Md, MdOptions, shortest_contact_time};
use emdstar_edmd::Engine;
use emdstar_engines::{EngineKind, EventChoice, MorChoice};
use emdstar_system::{
    Arrangement, Config, GasConfig, MaterialConfig, ParticleConfig, Simulation, System,
};
use rayon::prelude::*;
use serde::Serialize;

/// The event-driven engines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum EventKind {
    /// Classic eMD: instantaneous collisions with the central restitution ε(v_n).
    Emd,
    /// eMD* with the default table; impacts outside its box solved exactly (counted).
    EmdStarTable,
    /// eMD* with the exact solver for every collision.
    EmdStarExact,
}

impl EventKind {
    pub fn name(self) -> &'static str {
        match self {
            Self::Emd => "eMD",
            Self::EmdStarTable => "eMD* (table)",
            Self::EmdStarExact => "eMD* (exact)",
        }
    }
}

/// The `[material]` section of a force law with density `density` (kg/m³).
pub fn material(law: &ForceLaw, density: f64) -> MaterialConfig {
    let mut m = MaterialConfig {
        model: law.model().name().to_string(),
        density: Some(density),
        ..Default::default()
    };
    match law {
        ForceLaw::Linear(l) => {
            m.stiffness = Some(l.stiffness);
            m.damping = Some(l.damping);
        }
        ForceLaw::Hertz(h) => {
            m.young = Some(h.young);
            m.poisson = Some(h.poisson);
            m.dissipation = Some(h.dissipation);
        }
    }
    m
}

fn config(material: MaterialConfig, t_end: f64) -> Config {
    Config {
        t_end,
        material: Some(material),
        ..Config::default()
    }
}

/// Free spheres (radius, position, velocity) of one material in open space.
pub fn free_spheres(
    law: &ForceLaw,
    density: f64,
    spheres: &[(f64, [f64; 3], [f64; 3])],
) -> Result<System> {
    let mut c = config(material(law, density), 1.0);
    c.particles = spheres
        .iter()
        .map(|&(radius, position, velocity)| ParticleConfig {
            radius,
            position,
            velocity,
            ..Default::default()
        })
        .collect();
    Ok(c.build()?)
}

/// A gas of `count` equal spheres on a simple cubic lattice in a cubic periodic box at
/// packing fraction `eta`, with Maxwell velocities of rms speed `rms_speed` (m/s).
pub fn lattice_gas(
    law: &ForceLaw,
    density: f64,
    radius: f64,
    count: usize,
    eta: f64,
    rms_speed: f64,
    seed: u64,
) -> Result<System> {
    let mut c = config(material(law, density), 1.0);
    c.gas = Some(GasConfig {
        count,
        radius: Some(radius),
        arrangement: Arrangement::Lattice,
        packing_fraction: Some(eta),
        rms_speed,
        seed,
        ..GasConfig::default()
    });
    Ok(c.build()?)
}

/// An event engine of `kind` on `system`, built as `emdstar run` builds it (automatic
/// broad phase, exception (b) on the hit particle only; with friction, eMD's Walton
/// rule or eMD*'s exact frictional contact).
pub fn event_engine(system: &System, kind: EventKind) -> Result<Engine> {
    let (engine, mor) = match kind {
        EventKind::Emd => (EngineKind::Emd, MorChoice::default()),
        EventKind::EmdStarTable => (EngineKind::EmdStar, MorChoice::TableOrExact),
        EventKind::EmdStarExact => (EngineKind::EmdStar, MorChoice::Exact),
    };
    let choice = EventChoice {
        mor,
        ..Default::default()
    };
    emdstar_engines::event_engine(engine, system, &choice)
        .map_err(|e| HarnessError::Invalid(format!("{e:#}")))
}

/// Positions and velocities of an event engine at its current time, by particle number,
/// pending E^v velocities applied.
pub fn event_state(engine: &mut Engine) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    engine.sync();
    (engine.positions(), engine.settled_velocities())
}

/// MD (with its time step) or one of the event-driven engines, as the scenarios that
/// compare engines on one gas run them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyKind {
    Md { dt: f64 },
    Event(EventKind),
}

impl AnyKind {
    pub fn name(self) -> &'static str {
        match self {
            Self::Md { .. } => "MD",
            Self::Event(kind) => kind.name(),
        }
    }
}

/// An engine of a comparison: MD or an event engine.
pub enum AnyEngine {
    Md(Box<Md>),
    Event(Box<Engine>),
}

impl AnyEngine {
    /// The engine of `kind` on `system` up to `t_end`.
    pub fn new(system: &System, kind: AnyKind, t_end: f64) -> Result<Self> {
        Ok(match kind {
            AnyKind::Md { dt } => Self::Md(Box::new(md_engine(system.clone(), dt, t_end)?)),
            AnyKind::Event(kind) => Self::Event(Box::new(event_engine(system, kind)?)),
        })
    }

    /// The engine behind the simulation interface.
    pub fn sim(&mut self) -> &mut dyn Simulation {
        match self {
            Self::Md(e) => e.as_mut(),
            Self::Event(e) => e.as_mut(),
        }
    }

    /// Pair collisions executed (0 for MD, which has contacts instead).
    pub fn collisions(&self) -> u64 {
        match self {
            Self::Md(_) => 0,
            Self::Event(e) => e.stats().pair_collisions,
        }
    }

    /// The event engine's counters, if it is one.
    pub fn event_stats(&self) -> Option<&emdstar_edmd::Stats> {
        match self {
            Self::Md(_) => None,
            Self::Event(e) => Some(e.stats()),
        }
    }
}

/// Advances `sim` to each of `times` in turn and calls `observe(k, sim)` there, after
/// synchronising its stored state (as these scenarios have always sampled every
/// engine, so that their figures stay reproducible).
pub fn sample_at(
    sim: &mut dyn Simulation,
    times: impl IntoIterator<Item = f64>,
    mut observe: impl FnMut(usize, &dyn Simulation) -> Result<()>,
) -> Result<()> {
    for (k, t) in times.into_iter().enumerate() {
        sim.advance_to(t)
            .map_err(|e| HarnessError::Invalid(e.to_string()))?;
        sim.synchronise()
            .map_err(|e| HarnessError::Invalid(e.to_string()))?;
        observe(k, sim)?;
    }
    Ok(())
}

/// An MD engine with time step `dt` (s), contacts ending at F = 0, default skin.
pub fn md_engine(system: System, dt: f64, t_end: f64) -> Result<Md> {
    let opts = MdOptions {
        dt,
        contact_end: Default::default(),
        skin: None,
    };
    Ok(Md::new(system, opts, t_end)?)
}

/// MD's default time step on `system` up to `t_end`: [`DEFAULT_DT_FRACTION`] of the
/// shortest contact time expected (as `emdstar run` chooses it).
pub fn default_md_dt(system: &System, t_end: f64) -> Result<f64> {
    let tc = shortest_contact_time(system, t_end)?
        .ok_or_else(|| HarnessError::Invalid("the gas is at rest: no contact time".into()))?;
    Ok(DEFAULT_DT_FRACTION * tc)
}

/// Line colours and styles of MD, eMD and eMD* in the harness's plots: MD solid, the
/// event-driven engines dashed.
pub const ENGINE_STYLES: [(RGBColor, Style); 3] = [
    (PALETTE[0], Style::Line),
    (PALETTE[1], Style::Dashed),
    (PALETTE[2], Style::Dashed),
];

/// Positions and velocities of an MD engine, by particle number.
pub fn md_state(md: &Md) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let p = md.particles_in_config_order();
    (p.position, p.velocity)
}

/// `run(seed + r)` for r = 0 … `gases` − 1, in parallel, in seed order: independent
/// gases of one scenario (`what` names it in the error for zero gases).
pub fn on_independent_gases<T: Send>(
    what: &str,
    seed: u64,
    gases: usize,
    run: impl Fn(u64) -> Result<T> + Sync,
) -> Result<Vec<T>> {
    if gases == 0 {
        return Err(HarnessError::Invalid(format!(
            "{what}: need at least one gas"
        )));
    }
    (0..gases as u64)
        .into_par_iter()
        .map(|r| run(seed + r))
        .collect()
}
