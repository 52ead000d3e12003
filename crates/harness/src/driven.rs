//! The white-noise driven steady state (see docs/physics.md, "Driving"): its
//! temperature against the energy balance with Enskog's collision rate, its a₂ against
//! van Noije & Ernst's driven formula, and eMD* against MD on the same gas and kicks.

use crate::plot::{Axis, PALETTE, Panel, Series, Style, write_png};
use crate::theory::{block_mean, build, by_collisions, gas_config};
use crate::{HarnessError, Result};
use emdstar_engines::observe::since;
use emdstar_engines::{AnyEngine, EngineKind};
use emdstar_system::{Config, sonine_a2};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

/// a₂ of the white-noise driven state of inelastic hard spheres in d = 3, van Noije &
/// Ernst (1998), first Sonine approximation:
/// 16(1 − ε)(1 − 2ε²)/(73 + 56d − 24dε − 105ε + 30(1 − ε)ε²).
pub fn driven_a2(eps: f64) -> f64 {
    let d = 3.0;
    16.0 * (1.0 - eps) * (1.0 - 2.0 * eps * eps)
        / (73.0 + 56.0 * d - 24.0 * d * eps - 105.0 * eps + 30.0 * (1.0 - eps) * eps * eps)
}

/// The steady temperature kT (J) of `count` spheres of `mass` and diameter `sigma` at
/// packing fraction `eta` driven by white noise of strength ξ₀² = `strength`: the power
/// fed, m ξ₀²(1 − 1/N), against the collisional loss (1 − ε²) ω T (1 + 3a₂/16)/3 with
/// Enskog's ω = 4nσ²g(σ)√(πT/m) and Carnahan–Starling's g(σ) = (1 − η/2)/(1 − η)³.
pub fn steady_temperature(
    eps: f64,
    eta: f64,
    sigma: f64,
    mass: f64,
    count: usize,
    strength: f64,
) -> f64 {
    let n = eta / (PI * sigma.powi(3) / 6.0);
    let g = (1.0 - 0.5 * eta) / (1.0 - eta).powi(3);
    let fed = mass * strength * (1.0 - 1.0 / count as f64);
    let loss = (1.0 - eps * eps)
        * 4.0
        * n
        * sigma
        * sigma
        * g
        * (PI / mass).sqrt()
        * (1.0 + 3.0 * driven_a2(eps) / 16.0)
        / 3.0;
    (fed / loss).powf(2.0 / 3.0)
}

/// A driven gas.
#[derive(Debug, Clone, Serialize)]
pub struct DrivenSettings {
    pub restitution: f64,
    pub eta: f64,
    pub count: usize,
    /// Linear spring constant in N/m (soft enough for MD's steps, stiff enough that
    /// the gas is one of hard spheres to eMD's rule).
    pub stiffness: f64,
    /// ξ₀² in m²/s³ and ticks per second.
    pub strength: f64,
    pub rate: f64,
    /// Collisions per particle to reach the steady state, then to measure over (in 8
    /// blocks).
    pub relax: f64,
    pub measure: f64,
    pub seed: u64,
}

/// One engine's steady state.
#[derive(Debug, Clone, Serialize)]
pub struct DrivenRun {
    pub engine: String,
    /// Means over the measurement and their standard errors from 8 blocks.
    pub temperature: f64,
    pub temperature_error: f64,
    pub pressure: f64,
    pub pressure_error: f64,
    pub a2: f64,
    pub a2_error: f64,
    pub collision_rate: f64,
    /// (t, kT) at every sample, the relaxation included.
    pub samples: Vec<(f64, f64)>,
    pub wall_seconds: f64,
    pub time: f64,
    /// The hybrid: the mean fraction of its particles that were time-driven, over its
    /// steps (None for the other engines).
    pub time_driven_fraction: Option<f64>,
}

impl DrivenSettings {
    /// The gas's config: spheres of radius 1 cm, density 1000 kg/m³.
    pub fn config(&self) -> String {
        let material = format!(
            "model = \"linear\"\nstiffness = {}\nrestitution = {}",
            self.stiffness, self.restitution
        );
        gas_config(&material, self.count, self.eta, "random", self.seed)
            + &format!(
                "[driving]\nkind = \"white_noise\"\nstrength = {}\nrate = {}\nseed = {}\n",
                self.strength, self.rate, self.seed
            )
    }

    /// The mass of a sphere (radius 1 cm, 1000 kg/m³).
    pub fn mass(&self) -> f64 {
        1000.0 * 4.0 / 3.0 * PI * 1e-6
    }

    /// The energy balance's steady temperature.
    pub fn theory_temperature(&self) -> f64 {
        steady_temperature(
            self.restitution,
            self.eta,
            0.02,
            self.mass(),
            self.count,
            self.strength,
        )
    }
}

/// The steady state of `s` run by `kind`.
pub fn driven_state(s: &DrivenSettings, kind: EngineKind) -> Result<DrivenRun> {
    let text = s.config();
    let drive = Config::from_toml(&text)?
        .driving
        .map(|d| d.drive())
        .transpose()?
        .ok_or_else(|| HarnessError::Invalid("no [driving]".into()))?;
    let mut e = build(&text, kind)?;
    let name = e.sim().engine().to_string();
    let sim = e.sim_mut();
    let clock = Instant::now();
    let mut samples = Vec::new();
    let mut record = |sim: &dyn emdstar_system::Simulation| {
        samples.push((sim.time(), sim.thermo().granular_temperature));
    };
    by_collisions(sim, Some(&drive), s.relax, 0.5, |sim, _| record(sim))?;
    let (mut t, mut p, mut a2, mut rate) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    by_collisions(sim, Some(&drive), s.measure, 0.5, |sim, from| {
        record(sim);
        let obs = since(sim, Some(from));
        t.push(sim.thermo().granular_temperature);
        p.push(obs.pressure);
        a2.push(sonine_a2(&sim.particles()));
        rate.push(obs.collision_rate);
    })?;
    let wall_seconds = clock.elapsed().as_secs_f64();
    let time = sim.time();
    let time_driven_fraction = match &e {
        AnyEngine::Hybrid(h) => {
            let stats = h.stats();
            Some(stats.td_particle_steps as f64 / (stats.steps as f64 * s.count as f64))
        }
        _ => None,
    };
    let (temperature, temperature_error) = block_mean(&t, 8);
    let (pressure, pressure_error) = block_mean(&p, 8);
    let (a2, a2_error) = block_mean(&a2, 8);
    Ok(DrivenRun {
        engine: name,
        temperature,
        temperature_error,
        pressure,
        pressure_error,
        a2,
        a2_error,
        collision_rate: rate.iter().sum::<f64>() / rate.len() as f64,
        samples,
        wall_seconds,
        time,
        time_driven_fraction,
    })
}

/// How far two independent runs of the same driven gas lie apart, in T, pressure and
/// a₂: each |difference| with three standard errors of the difference (from the two
/// runs' block errors).
pub fn apart(a: &DrivenRun, b: &DrivenRun) -> [(f64, f64); 3] {
    let one = |x: f64, ex: f64, y: f64, ey: f64| ((x - y).abs(), 3.0 * ex.hypot(ey));
    [
        one(
            a.temperature,
            a.temperature_error,
            b.temperature,
            b.temperature_error,
        ),
        one(a.pressure, a.pressure_error, b.pressure, b.pressure_error),
        one(a.a2, a.a2_error, b.a2, b.a2_error),
    ]
}

/// Temperature against time for each run, with the energy balance's steady value.
pub fn plot(runs: &[&DrivenRun], theory: f64, path: &Path) -> std::result::Result<(), String> {
    let mut p = Panel::new(
        "White-noise driven gas: granular temperature",
        Axis::linear("t [s]"),
        Axis::linear("kT [J]"),
    );
    let end = runs
        .iter()
        .filter_map(|r| r.samples.last().map(|s| s.0))
        .fold(0.0, f64::max);
    for (k, r) in runs.iter().enumerate() {
        p.series.push(Series::new(
            format!(
                "{}: {:.4e} ± {:.1e} J, a₂ = {:.4} ± {:.4}",
                r.engine, r.temperature, r.temperature_error, r.a2, r.a2_error
            ),
            r.samples.clone(),
            PALETTE[1 + k],
            Style::Line,
        ));
    }
    p.series.push(Series::new(
        format!("energy balance (Enskog): {theory:.4e} J"),
        vec![(0.0, theory), (end, theory)],
        PALETTE[0],
        Style::Dashed,
    ));
    write_png(path, (900, 600), 1, 1, &[p])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn driven_reference_values() {
        // Elastic and ε = 1/√2: no deviation from a Maxwellian in this approximation.
        assert_eq!(driven_a2(1.0), 0.0);
        assert!(driven_a2(0.5f64.sqrt()).abs() < 1e-15);
        // ε = 0.5: 16·0.5·0.5/(241 − 88.5 + 3.75).
        assert!((driven_a2(0.5) - 4.0 / 156.25).abs() < 1e-15);
        // The balance: fed = lost at the steady temperature.
        let (eps, eta, sigma, m, n, xi) = (0.8, 0.05, 0.02, 4.0e-3, 1000, 2.0);
        let t = steady_temperature(eps, eta, sigma, m, n, xi);
        let density = eta / (PI * sigma.powi(3) / 6.0);
        let g = (1.0 - 0.5 * eta) / (1.0 - eta).powi(3);
        let omega = 4.0 * density * sigma * sigma * g * (PI * t / m).sqrt();
        let lost = (1.0 - eps * eps) * omega * t * (1.0 + 3.0 * driven_a2(eps) / 16.0) / 3.0;
        assert!((lost / (m * xi * (1.0 - 1e-3)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_hybrid_with_both_modes_reaches_mds_driven_state() {
        // A driven gas at η = 0.1 clusters: its dense spots run time-driven, the rest
        // event-driven. The same gas and kicks in MD: T, pressure and a₂ within noise.
        let s = DrivenSettings {
            restitution: 0.8,
            eta: 0.1,
            count: 1000,
            stiffness: 1e4,
            strength: 2.0,
            rate: 400.0,
            relax: 10.0,
            measure: 60.0,
            seed: 3,
        };
        let hybrid = driven_state(&s, EngineKind::Hybrid).unwrap();
        let md = driven_state(&s, EngineKind::Md).unwrap();
        let fraction = hybrid.time_driven_fraction.unwrap();
        eprintln!(
            "hybrid T {:e} ± {:e}, p {} ± {}, a2 {} ± {}, TD fraction {fraction}, {} s",
            hybrid.temperature,
            hybrid.temperature_error,
            hybrid.pressure,
            hybrid.pressure_error,
            hybrid.a2,
            hybrid.a2_error,
            hybrid.wall_seconds
        );
        eprintln!(
            "MD     T {:e} ± {:e}, p {} ± {}, a2 {} ± {}, {} s",
            md.temperature,
            md.temperature_error,
            md.pressure,
            md.pressure_error,
            md.a2,
            md.a2_error,
            md.wall_seconds
        );
        assert!(
            (0.1..0.9).contains(&fraction),
            "both modes: TD fraction {fraction}"
        );
        for ((off, bar), what) in apart(&hybrid, &md).into_iter().zip(["T", "p", "a2"]) {
            assert!(
                off < bar,
                "{what}: hybrid and MD {off:e} apart (3σ = {bar:e})"
            );
        }
    }
}
