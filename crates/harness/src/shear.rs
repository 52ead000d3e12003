//! Uniform shear flow of elastic hard spheres under Lees–Edwards boundaries (eMD): the
//! shear viscosity η = −P_xy/γ̇ from the log's pressure tensor against Enskog's.
//!
//! Enskog's viscosity of hard spheres (Chapman & Cowling, *The Mathematical Theory of
//! Non-uniform Gases*, 3rd ed. 1970, Sec. 16.41):
//! η_E = η₀ [1/χ + (4/5)·4φ + 0.7614·(4φ)²·χ], with the dilute (Boltzmann) value in
//! the first Sonine correction η₀ = 1.016·(5/(16σ²))·√(m k T/π), b ρ = 4φ at packing
//! fraction φ, and χ the contact value of the pair correlation, here Carnahan &
//! Starling's χ = (1 − φ/2)/(1 − φ)³.
//!
//! The gas is elastic, so the shear heats it: the viscosity is taken block by block at
//! each block's mean temperature (η ∝ √T at fixed density), as η/η_E.

use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::theory::{build, mean_and_error};
use crate::{HarnessError, Result};
use emdstar_engines::EngineKind;
use emdstar_engines::observe::{reading, since};
use serde::Serialize;
use std::path::Path;

/// Carnahan–Starling contact value χ = (1 − φ/2)/(1 − φ)³.
pub fn contact_value(phi: f64) -> f64 {
    (1.0 - 0.5 * phi) / (1.0 - phi).powi(3)
}

/// Enskog's shear viscosity (Pa s) of hard spheres of diameter `sigma` and mass `m`
/// at packing fraction `phi` and temperature `kt` (J); see the module docs.
pub fn enskog_viscosity(sigma: f64, m: f64, kt: f64, phi: f64) -> f64 {
    let eta0 = 1.016 * 5.0 / (16.0 * sigma * sigma) * (m * kt / std::f64::consts::PI).sqrt();
    let (chi, y) = (contact_value(phi), 4.0 * phi);
    eta0 * (1.0 / chi + 0.8 * y + 0.7614 * y * y * chi)
}

/// Settings of the sheared gas: unit spheres (σ = 1 m, m = 1 kg) at kT = 1 J.
#[derive(Debug, Clone, Serialize)]
pub struct ShearSettings {
    pub phi: f64,
    pub count: usize,
    /// γ̇ in 1/s (a collision takes about 1/3 s at φ = 0.15).
    pub rate: f64,
    /// Blocks and their length in s; the first block is the start's relaxation.
    pub blocks: usize,
    pub block: f64,
    pub seeds: Vec<u64>,
}

/// One block: its mean temperature, the viscosity measured and Enskog's.
#[derive(Debug, Clone, Serialize)]
pub struct ShearBlock {
    pub kt: f64,
    pub viscosity: f64,
    pub enskog: f64,
}

/// The sheared gas measured.
#[derive(Debug, Clone, Serialize)]
pub struct ShearViscosity {
    pub blocks: Vec<ShearBlock>,
    /// Mean of η/η_E over the blocks (all seeds but each first block) and its
    /// standard error.
    pub ratio: f64,
    pub ratio_error: f64,
    /// Pair collisions per particle over the measurement (mean over the seeds).
    pub collisions_per_particle: f64,
}

fn config(s: &ShearSettings, seed: u64) -> String {
    // A cube holding `count` unit spheres at packing fraction φ.
    let side = (s.count as f64 * std::f64::consts::PI / 6.0 / s.phi).cbrt();
    format!(
        "t_end = 1000.0\n[material]\nmodel = \"hertz\"\nyoung = 1e8\npoisson = 0.4\n\
         density = {rho}\n[gas]\ncount = {count}\nradius = 0.5\narrangement = \"random\"\n\
         rms_speed = {speed}\nseed = {seed}\n[box]\nsize = [{side}, {side}, {side}]\n\
         shear_rate = {rate}\n",
        rho = 6.0 / std::f64::consts::PI,
        count = s.count,
        speed = 3f64.sqrt(),
        rate = s.rate,
    )
}

/// Runs the sheared gas of `s` on eMD (one gas per seed, in parallel).
pub fn sheared_viscosity(s: &ShearSettings) -> Result<ShearViscosity> {
    use rayon::prelude::*;
    let runs: Vec<(Vec<ShearBlock>, f64)> = s
        .seeds
        .par_iter()
        .map(|&seed| {
            let mut e = build(&config(s, seed), EngineKind::Emd)?;
            let sim = e.sim_mut();
            let mut blocks = Vec::new();
            let mut collisions = 0.0;
            for k in 0..s.blocks {
                let start = reading(sim);
                let kt0 = sim.thermo().granular_temperature;
                emdstar_engines::drive::advance(sim, None, start.t + s.block)
                    .map_err(|e| HarnessError::Invalid(e.to_string()))?;
                let obs = since(sim, Some(&start));
                let kt = 0.5 * (kt0 + sim.thermo().granular_temperature);
                if k > 0 {
                    blocks.push(ShearBlock {
                        kt,
                        viscosity: -obs.tensor[3] / s.rate,
                        enskog: enskog_viscosity(1.0, 1.0, kt, s.phi),
                    });
                    collisions += obs.collision_rate * s.block;
                }
            }
            Ok((blocks, collisions))
        })
        .collect::<Result<_>>()?;
    let collisions_per_particle = runs.iter().map(|r| r.1).sum::<f64>() / runs.len() as f64;
    let blocks: Vec<ShearBlock> = runs.into_iter().flat_map(|r| r.0).collect();
    let ratios: Vec<f64> = blocks.iter().map(|b| b.viscosity / b.enskog).collect();
    let (ratio, ratio_error) = mean_and_error(&ratios);
    Ok(ShearViscosity {
        blocks,
        ratio,
        ratio_error,
        collisions_per_particle,
    })
}

/// η against kT: the blocks and Enskog's η_E(T).
pub fn plot_viscosity(
    s: &ShearSettings,
    r: &ShearViscosity,
    path: &Path,
) -> std::result::Result<(), String> {
    let (lo, hi) = r
        .blocks
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
            (lo.min(b.kt), hi.max(b.kt))
        });
    let curve: Vec<(f64, f64)> = (0..=40)
        .map(|k| {
            let kt = lo + (hi - lo) * k as f64 / 40.0;
            (kt, enskog_viscosity(1.0, 1.0, kt, s.phi))
        })
        .collect();
    let mut panel = Panel::new(
        format!(
            "Sheared elastic hard spheres (eMD, Lees–Edwards), φ = {}, shear rate {} /s",
            s.phi, s.rate
        ),
        Axis::linear("kT [J] (σ = 1 m, m = 1 kg)"),
        Axis::linear("shear viscosity η [Pa s]"),
    );
    panel.legend = LegendAt::UpperLeft;
    panel.series.push(Series::new(
        "Enskog (Chapman & Cowling 16.41), Carnahan–Starling χ",
        curve,
        PALETTE[0],
        Style::Line,
    ));
    panel.series.push(Series::new(
        format!(
            "eMD: −P_xy / shear rate, per block (η/η_E = {:.3} ± {:.3})",
            r.ratio, r.ratio_error
        ),
        r.blocks.iter().map(|b| (b.kt, b.viscosity)).collect(),
        PALETTE[1],
        Style::Points(4),
    ));
    write_png(path, (900, 600), 1, 1, &[panel])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enskog_viscosity_reduces_to_the_dilute_value_and_grows_with_density() {
        // φ → 0: η₀ = 1.016·5/16·√(1/π) = 0.17913 Pa s for σ = m = kT = 1.
        let dilute = enskog_viscosity(1.0, 1.0, 1.0, 1e-12);
        assert!((dilute - 0.179_130).abs() < 1e-5, "{dilute}");
        // φ = 0.15: χ = 1.5060, η_E/η₀ = 0.6640 + 0.48 + 0.4128 = 1.5568.
        let ratio = enskog_viscosity(1.0, 1.0, 1.0, 0.15) / dilute;
        assert!((ratio - 1.5568).abs() < 1e-3, "{ratio}");
    }
}
