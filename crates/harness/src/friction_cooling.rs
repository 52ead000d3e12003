//! A freely cooling gas of frictional spheres: translational and rotational
//! temperatures by MD (the history spring integrated), by eMD* with the exact
//! frictional contact per collision, and by classic eMD with Walton's rule beside them.
//!
//! Linear dashpot (its contact time and central restitution do not depend on the
//! speed, so Walton's e and β₀ are one pair of numbers): e is the central restitution of
//! the law, β₀ = −cos(ω_t τ) of the sticking tangential oscillator over the contact
//! duration τ, ω_t² = k_t (1 + m_eff Σ R²/I)/m_eff (Schäfer, Dippel & Wolf, J. Phys. I
//! France 6, 5, 1996, Sec. 3). Spins start at zero.

use crate::engines::{
    AnyEngine, AnyKind, ENGINE_STYLES, EventKind, default_md_dt, event_engine, material,
    on_independent_gases, sample_at,
};
use crate::plot::{Axis, LegendAt, Panel, Series, write_png};
use crate::{HarnessError, Result};
use emdstar_contact::{ForceLaw, LinearDashpot, SOLID_SPHERE_INERTIA, Walton};
use emdstar_system::{Arrangement, Config, GasConfig, System};
use serde::Serialize;
use std::path::Path;

/// The gas and its friction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FrictionCoolingSettings {
    pub particles: usize,
    pub packing_fraction: f64,
    pub radius: f64,
    pub density: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub friction: f64,
    pub tangential_stiffness: f64,
    pub tangential_damping: f64,
    pub rms_speed: f64,
    pub t_end: f64,
    pub samples: usize,
    /// Independent gases (seeds seed, seed + 1, …) whose temperatures are averaged.
    pub gases: usize,
    pub seed: u64,
}

impl FrictionCoolingSettings {
    /// 16 gases of 512 spheres at η = 0.1, e ≈ 0.9, µ = 0.3, k_t = 2k/7 (the tangential
    /// oscillation as fast as the normal one): about 10⁴ collisions per gas.
    pub fn quick() -> Self {
        Self {
            particles: 512,
            packing_fraction: 0.1,
            radius: 0.01,
            density: 1000.0,
            stiffness: 1e4,
            damping: 0.3,
            friction: 0.3,
            tangential_stiffness: 2e4 / 7.0,
            tangential_damping: 0.0,
            rms_speed: 1.0,
            t_end: 1.0,
            samples: 21,
            gases: 16,
            seed: 5,
        }
    }
}

/// T(t) and T_rot(t) of one engine.
#[derive(Debug, Clone, Serialize)]
pub struct FrictionCurve {
    pub engine: String,
    pub temperature: Vec<f64>,
    pub rotational: Vec<f64>,
    pub collisions: u64,
    /// eMD*: exact frictional solves.
    pub frictional_solves: u64,
    /// eMD*: exceptions (a) (the frictionless eMD kick instead) and (b).
    pub exceptions: (u64, u64),
    pub wall_seconds: f64,
}

/// The three runs.
#[derive(Debug, Clone, Serialize)]
pub struct FrictionCooling {
    pub settings: FrictionCoolingSettings,
    pub times: Vec<f64>,
    pub md_dt: f64,
    /// Walton's e and β₀.
    pub walton: (f64, f64),
    /// MD, eMD*, eMD (Walton).
    pub curves: Vec<FrictionCurve>,
    /// Sample indices of t_end/4, t_end/2, t_end.
    pub picks: Vec<usize>,
    /// |T − T_MD|/T_MD and |T_rot − T_rot,MD|/T_rot,MD at the picks, per event engine.
    pub translational: Vec<Vec<f64>>,
    pub rotational: Vec<Vec<f64>>,
}

fn gas(s: &FrictionCoolingSettings) -> Result<System> {
    let law = ForceLaw::Linear(LinearDashpot::new(s.stiffness, s.damping)?);
    let mut m = material(&law, s.density);
    m.friction = Some(s.friction);
    m.tangential_stiffness = Some(s.tangential_stiffness);
    m.tangential_damping = Some(s.tangential_damping);
    let config = Config {
        t_end: s.t_end,
        material: Some(m),
        gas: Some(GasConfig {
            count: s.particles,
            radius: Some(s.radius),
            arrangement: Arrangement::Lattice,
            packing_fraction: Some(s.packing_fraction),
            rms_speed: s.rms_speed,
            seed: s.seed,
            ..GasConfig::default()
        }),
        ..Config::default()
    };
    Ok(config.build()?)
}

/// Walton's e and β₀ of the gas's contact (see the module documentation).
fn walton_parameters(s: &FrictionCoolingSettings, system: &System) -> Result<(f64, f64)> {
    let mass = system.particles.mass[0];
    let m_eff = 0.5 * mass;
    let omega = (s.stiffness / m_eff - (s.damping / (2.0 * m_eff)).powi(2)).sqrt();
    let tau = std::f64::consts::PI / omega;
    let e = (-s.damping / (2.0 * m_eff) * tau).exp();
    let inverse_inertia = 2.0 / (SOLID_SPHERE_INERTIA * mass);
    let omega_t = (s.tangential_stiffness * (1.0 + m_eff * inverse_inertia) / m_eff).sqrt();
    Ok((e, -(omega_t * tau).cos()))
}

const ENGINES: [&str; 3] = ["MD", "eMD* (exact, friction)", "eMD (Walton)"];

/// The curves of the three engines on one gas.
fn one_gas(
    s: &FrictionCoolingSettings,
    seed: u64,
    times: &[f64],
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(f64, Vec<FrictionCurve>)> {
    let system = gas(&FrictionCoolingSettings { seed, ..*s })?;
    let md_dt = default_md_dt(&system, s.t_end)?;
    let (e, beta) = walton_parameters(s, &system)?;
    let mut curves = Vec::new();
    for name in ENGINES {
        let start = std::time::Instant::now();
        let mut engine = match name {
            "MD" => AnyEngine::new(&system, AnyKind::Md { dt: md_dt }, s.t_end)?,
            "eMD (Walton)" => {
                let engine = emdstar_edmd::Engine::new(
                    &system.particles,
                    &system.domain,
                    emdstar_edmd::Physics::HardSpheres {
                        restitution: e,
                        walton: Some(Walton::new(s.friction, beta)?),
                    },
                )?;
                AnyEngine::Event(Box::new(engine))
            }
            _ => {
                let engine = event_engine(&system, EventKind::EmdStarExact)?;
                AnyEngine::Event(Box::new(engine))
            }
        };
        let (mut temps, mut rots) = (Vec::new(), Vec::new());
        sample_at(engine.sim(), times.iter().copied(), |_, sim| {
            let t = sim.thermo();
            temps.push(t.granular_temperature);
            rots.push(t.rotational_temperature);
            progress(name);
            Ok(())
        })?;
        curves.push(FrictionCurve {
            engine: name.into(),
            temperature: temps,
            rotational: rots,
            collisions: engine.collisions(),
            frictional_solves: engine.event_stats().map_or(0, |s| s.frictional_solves),
            exceptions: engine
                .event_stats()
                .map_or((0, 0), |s| (s.exception_rotation, s.exception_interference)),
            wall_seconds: start.elapsed().as_secs_f64(),
        });
    }
    Ok((md_dt, curves))
}

/// Runs MD, eMD* (exact frictional contacts) and eMD (Walton) from the same states,
/// `gases` of them in parallel, and averages their temperatures.
pub fn run(
    s: &FrictionCoolingSettings,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<FrictionCooling> {
    if s.samples < 5 {
        return Err(HarnessError::Invalid(
            "friction cooling needs at least 5 samples".into(),
        ));
    }
    let times: Vec<f64> = (0..s.samples)
        .map(|k| s.t_end * k as f64 / (s.samples - 1) as f64)
        .collect();
    let runs = on_independent_gases("friction cooling", s.seed, s.gases, |seed| {
        one_gas(s, seed, &times, progress)
    })?;
    let md_dt = runs[0].0;
    let walton = walton_parameters(s, &gas(s)?)?;
    let n = runs.len() as f64;
    let curves: Vec<FrictionCurve> = (0..ENGINES.len())
        .map(|k| {
            let mean = |of: &dyn Fn(&FrictionCurve) -> &Vec<f64>| -> Vec<f64> {
                (0..times.len())
                    .map(|t| runs.iter().map(|r| of(&r.1[k])[t]).sum::<f64>() / n)
                    .collect()
            };
            FrictionCurve {
                engine: ENGINES[k].into(),
                temperature: mean(&|c| &c.temperature),
                rotational: mean(&|c| &c.rotational),
                collisions: runs.iter().map(|r| r.1[k].collisions).sum(),
                frictional_solves: runs.iter().map(|r| r.1[k].frictional_solves).sum(),
                exceptions: runs.iter().fold((0, 0), |(a, b), r| {
                    (a + r.1[k].exceptions.0, b + r.1[k].exceptions.1)
                }),
                wall_seconds: runs.iter().map(|r| r.1[k].wall_seconds).sum(),
            }
        })
        .collect();
    let picks: Vec<usize> = [4, 2, 1].iter().map(|d| (s.samples - 1) / d).collect();
    let relative = |of: &dyn Fn(&FrictionCurve) -> &Vec<f64>| -> Vec<Vec<f64>> {
        let md = of(&curves[0]);
        curves[1..]
            .iter()
            .map(|c| {
                picks
                    .iter()
                    .map(|&k| ((of(c)[k] - md[k]) / md[k]).abs())
                    .collect()
            })
            .collect()
    };
    let translational = relative(&|c| &c.temperature);
    let rotational = relative(&|c| &c.rotational);
    Ok(FrictionCooling {
        settings: *s,
        times,
        md_dt,
        walton,
        picks,
        translational,
        rotational,
        curves,
    })
}

/// T(t) and T_rot(t) of the three engines.
pub fn plot(g: &FrictionCooling, path: &Path) -> std::result::Result<(), String> {
    let mut panels = Vec::new();
    for (title, rotational) in [("translational", false), ("rotational", true)] {
        let mut p = Panel::new(
            format!(
                "frictional gas (µ = {}), N = {}, η = {}: {title}",
                g.settings.friction, g.settings.particles, g.settings.packing_fraction
            ),
            Axis::linear("time t (s)"),
            Axis::log(format!("{title} temperature (J)")),
        );
        p.legend = LegendAt::UpperRight;
        for (c, (color, style)) in g.curves.iter().zip(ENGINE_STYLES) {
            let values = if rotational {
                &c.rotational
            } else {
                &c.temperature
            };
            let pts = g
                .times
                .iter()
                .copied()
                .zip(values.iter().copied())
                .filter(|(_, v)| *v > 0.0)
                .collect();
            p.series
                .push(Series::new(c.engine.clone(), pts, color, style));
        }
        panels.push(p);
    }
    write_png(path, (1500, 650), 1, 2, &panels)
}
