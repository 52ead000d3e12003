//! Gases against kinetic theory, through the observables every engine reports
//! (pressure tensor, collision rate, Sonine a₂; see `emdstar_system::stress`):
//!
//! - elastic hard spheres (eMD at ε = 1): the compressibility factor Z = pV/(NkT)
//!   against Carnahan & Starling's equation of state;
//! - the homogeneous cooling state of inelastic hard spheres: a₂ against van Noije &
//!   Ernst's first Sonine approximation.
//!
//! Runs are measured in collisions per particle, so that a setting means the same at
//! any density or temperature.

use crate::plot::{Annotation, Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::{HarnessError, Result};
use emdstar_engines::observe::{reading, since};
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::{Config, Drive, Simulation, StressMark};
use serde::Serialize;
use std::path::Path;

/// Carnahan & Starling, J. Chem. Phys. 51, 635 (1969):
/// Z = (1 + η + η² − η³)/(1 − η)³.
pub fn carnahan_starling(eta: f64) -> f64 {
    (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3)
}

/// a₂ of the homogeneous cooling state of inelastic hard spheres at restitution ε, van
/// Noije & Ernst, Granular Matter 1, 57 (1998), first Sonine approximation in three
/// dimensions: a₂ = 16(1 − ε)(1 − 2ε²)/(81 − 17ε + 30ε²(1 − ε)).
pub fn cooling_a2(eps: f64) -> f64 {
    16.0 * (1.0 - eps) * (1.0 - 2.0 * eps * eps)
        / (81.0 - 17.0 * eps + 30.0 * eps * eps * (1.0 - eps))
}

/// A gas of `count` spheres of radius 1 cm and density 1000 kg/m³ at packing fraction
/// `eta`, Maxwell velocities of 1 m/s rms, with the `[material]` lines `material`.
pub fn gas_config(material: &str, count: usize, eta: f64, arrangement: &str, seed: u64) -> String {
    format!(
        "t_end = 100.0\n[material]\n{material}\ndensity = 1000.0\n[gas]\ncount = {count}\n\
         radius = 0.01\narrangement = \"{arrangement}\"\npacking_fraction = {eta}\n\
         rms_speed = 1.0\nseed = {seed}\n"
    )
}

/// Elastic hard spheres: Hertz with no dissipation, which eMD runs at ε = 1.
pub const ELASTIC: &str = "model = \"hertz\"\nyoung = 1e8\npoisson = 0.4";

/// The engine `kind` on the gas of the config `text`.
pub fn build(text: &str, kind: EngineKind) -> Result<AnyEngine> {
    let config = Config::from_toml(text)?;
    let system = config.build()?;
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    AnyEngine::build(&options, &config, system, 1.0 / 50.0)
        .map_err(|e| HarnessError::Invalid(format!("{e:#}")))
}

fn advance(sim: &mut dyn Simulation, drive: Option<&Drive>, t: f64) -> Result<()> {
    emdstar_engines::drive::advance(sim, drive, t).map_err(|e| HarnessError::Invalid(e.to_string()))
}

/// Advances `sim` (driven by `drive`, if any) by about `per_particle` collisions per
/// particle in slices of about `slice` each, calling `each` with the engine and the
/// mark at the slice's start.
pub fn by_collisions(
    sim: &mut dyn Simulation,
    drive: Option<&Drive>,
    per_particle: f64,
    slice: f64,
    mut each: impl FnMut(&dyn Simulation, &StressMark),
) -> Result<()> {
    let n = sim.particles().len() as f64;
    let target = sim.stress_sums().collisions as f64 + 0.5 * n * per_particle;
    // A first slice of a hundredth of a radius's flight at the rms speed, doubled until
    // it sees collisions; then slices of `slice` at the last rate.
    let mut dt = 1e-4;
    while (sim.stress_sums().collisions as f64) < target {
        let from = reading(sim);
        advance(sim, drive, from.t + dt)?;
        each(sim, &from);
        let done = (sim.stress_sums().collisions - from.sums.collisions) as f64;
        let rate = 2.0 * done / (n * dt);
        dt = if done > 0.0 { slice / rate } else { 2.0 * dt };
    }
    Ok(())
}

/// Z at one packing fraction.
#[derive(Debug, Clone, Serialize)]
pub struct EosPoint {
    pub eta: f64,
    pub z: f64,
    /// Standard error of Z from 10 blocks.
    pub z_error: f64,
    pub carnahan_starling: f64,
    pub collisions_per_particle: f64,
}

/// Settings of the equation-of-state sweep.
#[derive(Debug, Clone, Serialize)]
pub struct EosSettings {
    pub etas: Vec<f64>,
    /// fcc: 4n³ spheres.
    pub count: usize,
    /// Collisions per particle to melt the lattice, then to measure over.
    pub equilibrate: f64,
    pub measure: f64,
    pub seed: u64,
}

/// Z = pV/(NkT) of elastic hard spheres (eMD) at each packing fraction: from an fcc
/// lattice, melted, then measured in 10 blocks.
pub fn hard_sphere_eos(s: &EosSettings, tick: &(dyn Fn() + Sync)) -> Result<Vec<EosPoint>> {
    use rayon::prelude::*;
    s.etas
        .par_iter()
        .map(|&eta| {
            let text = gas_config(ELASTIC, s.count, eta, "fcc", s.seed);
            let mut e = build(&text, EngineKind::Emd)?;
            let sim = e.sim_mut();
            by_collisions(sim, None, s.equilibrate, s.equilibrate, |_, _| {})?;
            let volume = sim.domain().sim_box.map_or(f64::NAN, |b| b.volume());
            let mut blocks = Vec::new();
            let mut collisions = 0.0;
            for _ in 0..10 {
                let start = reading(sim);
                by_collisions(sim, None, s.measure / 10.0, s.measure / 10.0, |_, _| {})?;
                let obs = since(sim, Some(&start));
                let p = sim.particles();
                let kt = p.granular_temperature();
                blocks.push(obs.pressure * volume / (p.len() as f64 * kt));
                collisions += obs.collision_rate * (sim.time() - start.t);
            }
            tick();
            let (z, z_error) = mean_and_error(&blocks);
            Ok(EosPoint {
                eta,
                z,
                z_error,
                carnahan_starling: carnahan_starling(eta),
                collisions_per_particle: collisions,
            })
        })
        .collect()
}

/// Mean and standard error of the mean of independent samples.
pub fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// Z against η with Carnahan–Starling's curve, and the relative deviations.
pub fn plot_eos(points: &[EosPoint], path: &Path) -> std::result::Result<(), String> {
    let curve: Vec<(f64, f64)> = (0..=50)
        .map(|k| {
            let eta = 0.01 * k as f64 * 0.9;
            (eta, carnahan_starling(eta))
        })
        .collect();
    let mut z = Panel::new(
        "Elastic hard spheres (eMD): Z = pV/NkT",
        Axis::linear("packing fraction η"),
        Axis::linear("Z"),
    );
    z.legend = LegendAt::UpperLeft;
    z.series.push(Series::new(
        "Carnahan–Starling",
        curve,
        PALETTE[0],
        Style::Line,
    ));
    z.series.push(Series::new(
        "eMD: pressure from Σ r⊗Δp",
        points.iter().map(|p| (p.eta, p.z)).collect(),
        PALETTE[1],
        Style::Points(5),
    ));
    let mut dev = Panel::new(
        "Deviation from Carnahan–Starling (bars: 2 standard errors)",
        Axis::linear("packing fraction η"),
        Axis::linear("Z / Z_CS − 1 [%]").with_range(-2.0, 2.0),
    );
    dev.series.push(Series::new(
        "eMD",
        points
            .iter()
            .map(|p| (p.eta, 100.0 * (p.z / p.carnahan_starling - 1.0)))
            .collect(),
        PALETTE[1],
        Style::Points(5),
    ));
    for p in points {
        let (d, e) = (
            100.0 * (p.z / p.carnahan_starling - 1.0),
            200.0 * p.z_error / p.carnahan_starling,
        );
        dev.annotations.push(Annotation::ErrorBar {
            x: p.eta,
            lo: d - e,
            hi: d + e,
            color: PALETTE[1],
        });
    }
    for bound in [-1.0, 1.0] {
        dev.series.push(Series::new(
            if bound > 0.0 { "±1 %" } else { "" },
            vec![(0.0, bound), (0.45, bound)],
            PALETTE[3],
            Style::Dashed,
        ));
    }
    write_png(path, (1300, 550), 1, 2, &[z, dev])
}

/// The cooling-state a₂ of one gas.
#[derive(Debug, Clone, Serialize)]
pub struct CoolingA2 {
    pub restitution: f64,
    pub eta: f64,
    pub count: usize,
    /// (collisions per particle, a₂) at each sample.
    pub samples: Vec<(f64, f64)>,
    /// Mean over the samples after the transient, and its standard error from blocks.
    pub a2: f64,
    pub a2_error: f64,
    pub theory: f64,
}

/// Settings of the cooling-state a₂ measurement.
#[derive(Debug, Clone, Serialize)]
pub struct CoolingSettings {
    pub restitution: f64,
    pub eta: f64,
    pub count: usize,
    /// Collisions per particle before sampling (the cooling state forms in a few),
    /// and over which samples are taken, one every half collision per particle.
    pub transient: f64,
    pub measure: f64,
    pub seed: u64,
}

/// A freely cooling gas of inelastic hard spheres (eMD with a linear dashpot of
/// restitution ε, the same at every impact speed, stiff enough that the centrifugal
/// correction to ε stays below 10⁻³): a₂ sampled over the cooling state.
pub fn cooling_state_a2(s: &CoolingSettings) -> Result<CoolingA2> {
    let material = format!(
        "model = \"linear\"\nstiffness = 1e7\nrestitution = {}",
        s.restitution
    );
    let text = gas_config(&material, s.count, s.eta, "random", s.seed);
    let mut e = build(&text, EngineKind::Emd)?;
    let sim = e.sim_mut();
    let n = s.count as f64;
    let per = |sim: &dyn Simulation| 2.0 * sim.stress_sums().collisions as f64 / n;
    let mut samples = Vec::new();
    by_collisions(sim, None, s.transient + s.measure, 0.5, |sim, _| {
        samples.push((per(sim), emdstar_system::sonine_a2(&sim.particles())));
    })?;
    let kept: Vec<f64> = samples
        .iter()
        .filter(|(c, _)| *c >= s.transient)
        .map(|&(_, a)| a)
        .collect();
    let (a2, a2_error) = block_mean(&kept, 8);
    Ok(CoolingA2 {
        restitution: s.restitution,
        eta: s.eta,
        count: s.count,
        samples,
        a2,
        a2_error,
        theory: cooling_a2(s.restitution),
    })
}

/// Mean and the standard error of the means of `blocks` consecutive blocks (samples
/// closer than a block are correlated).
pub fn block_mean(x: &[f64], blocks: usize) -> (f64, f64) {
    let len = x.len() / blocks;
    if len == 0 {
        return (f64::NAN, f64::NAN);
    }
    let means: Vec<f64> = x
        .chunks(len)
        .take(blocks)
        .map(|c| c.iter().sum::<f64>() / c.len() as f64)
        .collect();
    let (_, error) = mean_and_error(&means);
    (x.iter().sum::<f64>() / x.len() as f64, error)
}

/// a₂ against collisions per particle, with the theory and the measured mean.
pub fn plot_a2(runs: &[(&str, &CoolingA2)], path: &Path) -> std::result::Result<(), String> {
    let mut panels = Vec::new();
    for (title, r) in runs {
        let mut p = Panel::new(
            format!(
                "{title}: N = {}, η = {}, ε = {}",
                r.count, r.eta, r.restitution
            ),
            Axis::linear("collisions per particle"),
            Axis::linear("Sonine a₂").with_range(-0.15, 0.15),
        );
        let end = r.samples.last().map_or(1.0, |s| s.0);
        p.series.push(Series::new(
            "a₂ of the velocities",
            r.samples.clone(),
            PALETTE[1],
            Style::LinePoints(2),
        ));
        p.series.push(Series::new(
            format!("van Noije & Ernst: {:.4}", r.theory),
            vec![(0.0, r.theory), (end, r.theory)],
            PALETTE[0],
            Style::Dashed,
        ));
        p.series.push(Series::new(
            format!("mean {:.4} ± {:.4}", r.a2, r.a2_error),
            vec![(0.0, r.a2), (end, r.a2)],
            PALETTE[3],
            Style::Line,
        ));
        panels.push(p);
    }
    write_png(
        path,
        (700 * panels.len() as u32, 550),
        1,
        panels.len(),
        &panels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_values() {
        // Z(0.3) = (1 + 0.3 + 0.09 − 0.027)/0.343 = 1.363/0.343.
        assert!((carnahan_starling(0.3) - 1.363 / 0.343).abs() < 1e-12);
        // Elastic: no deviation from a Maxwellian; ε = 1/√2 changes sign.
        assert_eq!(cooling_a2(1.0), 0.0);
        assert!(cooling_a2(0.5f64.sqrt()).abs() < 1e-15);
        // ε = 0.8: 16·0.2·(−0.28)/(81 − 13.6 + 3.84).
        assert!((cooling_a2(0.8) + 0.896 / 71.24).abs() < 1e-12);
    }
}
