//! eMD* against MD in the steady uniform shear flow of an inelastic soft-sphere gas
//! under Lees–Edwards boundaries (see docs/physics.md, "Lees–Edwards shear"): the
//! shear heats the gas until the collisions dissipate what the boundaries' work feeds
//! in, −γ̇ V P_xy; both engines run the same contact law from the same start, and
//! their temperature, pressure tensor and a₂ must agree within the noise.
//!
//! The steady state's reduced shear rate γ̇/ν (ν the collision rate) depends on the
//! restitution alone, so its temperature grows as γ̇²: γ̇ sets the speeds, and the
//! runs are measured in seconds of that state.

use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::theory::{build, mean_and_error};
use crate::{HarnessError, Result};
use emdstar_engines::EngineKind;
use emdstar_engines::observe::{reading, since};
use emdstar_system::Simulation;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// A sheared inelastic gas of unit spheres (σ = 1 m, m = 1 kg) with a linear dashpot.
#[derive(Debug, Clone, Serialize)]
pub struct ShearPairSettings {
    pub restitution: f64,
    /// Spring constant in N/m: soft enough for MD's steps, stiff enough for a gas.
    pub stiffness: f64,
    pub phi: f64,
    pub count: usize,
    /// γ̇ in 1/s.
    pub rate: f64,
    /// kT at the start (J), near the steady state's to shorten the relaxation.
    pub start_kt: f64,
    /// Seconds from the start to the steady state, then blocks of `block` s.
    pub relax: f64,
    pub blocks: usize,
    pub block: f64,
    /// Samples of T and a₂ per block.
    pub samples: usize,
    /// One gas per seed (run in parallel); the errors are those of the seeds' means.
    pub seeds: Vec<u64>,
}

impl ShearPairSettings {
    /// The gas's config for `seed`.
    pub fn config(&self, seed: u64) -> String {
        // A cube holding `count` unit spheres at packing fraction φ.
        let side = (self.count as f64 * std::f64::consts::PI / 6.0 / self.phi).cbrt();
        format!(
            "t_end = 1000.0\n[material]\nmodel = \"linear\"\nstiffness = {k}\n\
             restitution = {e}\ndensity = {rho}\n[gas]\ncount = {count}\nradius = 0.5\n\
             arrangement = \"random\"\nrms_speed = {speed}\nseed = {seed}\n[box]\n\
             size = [{side}, {side}, {side}]\nshear_rate = {rate}\n",
            k = self.stiffness,
            e = self.restitution,
            rho = 6.0 / std::f64::consts::PI,
            count = self.count,
            speed = (3.0 * self.start_kt).sqrt(),
            rate = self.rate,
        )
    }
}

/// One engine's steady state: means over the seeds, with the standard errors of the
/// seeds' means (independent runs; in a box of 500 spheres the temperature wanders
/// over several seconds, so successive blocks of one run are not independent and their
/// scatter would understate the error by about half).
#[derive(Debug, Clone, Serialize)]
pub struct ShearPairRun {
    pub engine: String,
    /// Granular temperature kT of the peculiar velocities (J).
    pub temperature: f64,
    pub temperature_error: f64,
    /// P_xx, P_yy, P_zz, P_xy (Pa), kinetic plus collisional, over each block.
    pub tensor: [f64; 4],
    pub tensor_error: [f64; 4],
    pub a2: f64,
    pub a2_error: f64,
    /// (t, kT) at every sample of the first seed, the relaxation included.
    pub samples: Vec<(f64, f64)>,
    /// (block's mid-time, P_xy) of every block of every seed.
    pub shear_stress: Vec<(f64, f64)>,
    /// Over the measurement, per seed.
    pub collisions_per_particle: f64,
    /// Wall time per seed (one run each, in parallel), and simulated time per seed.
    pub wall_seconds: f64,
    pub time: f64,
}

/// One seed's run: its samples, and per block (kT, a₂, P_xx, P_yy, P_zz, P_xy, t_mid).
struct SeedRun {
    engine: String,
    samples: Vec<(f64, f64)>,
    blocks: Vec<[f64; 7]>,
    collisions: f64,
    wall_seconds: f64,
    time: f64,
}

impl ShearPairRun {
    /// (name, value, error) of each compared quantity.
    pub fn quantities(&self) -> [(&'static str, f64, f64); 6] {
        let (p, e) = (self.tensor, self.tensor_error);
        [
            ("kT", self.temperature, self.temperature_error),
            ("P_xx", p[0], e[0]),
            ("P_yy", p[1], e[1]),
            ("P_zz", p[2], e[2]),
            ("P_xy", p[3], e[3]),
            ("a₂", self.a2, self.a2_error),
        ]
    }
}

/// The largest |a − b| over the quantities of two runs, in standard errors of the
/// difference (independent runs: the errors add in quadrature), with its name.
pub fn largest_deviation(a: &ShearPairRun, b: &ShearPairRun) -> (&'static str, f64) {
    a.quantities()
        .iter()
        .zip(b.quantities())
        .map(|(&(name, x, ex), (_, y, ey))| (name, (x - y).abs() / ex.hypot(ey)))
        .fold(("", 0.0), |best, q| if q.1 > best.1 { q } else { best })
}

fn advance(sim: &mut dyn Simulation, t: f64) -> Result<()> {
    emdstar_engines::drive::advance(sim, None, t).map_err(|e| HarnessError::Invalid(e.to_string()))
}

/// The steady state of `s` run by `kind`, one gas per seed in parallel.
pub fn sheared_state(s: &ShearPairSettings, kind: EngineKind) -> Result<ShearPairRun> {
    use rayon::prelude::*;
    let runs: Vec<SeedRun> = s
        .seeds
        .par_iter()
        .map(|&seed| run_seed(s, kind, seed))
        .collect::<Result<_>>()?;
    let blocks: Vec<[f64; 7]> = runs.iter().flat_map(|r| r.blocks.clone()).collect();
    let seed_mean =
        |r: &SeedRun, k: usize| r.blocks.iter().map(|b| b[k]).sum::<f64>() / r.blocks.len() as f64;
    let column =
        |k: usize| mean_and_error(&runs.iter().map(|r| seed_mean(r, k)).collect::<Vec<_>>());
    let ((temperature, temperature_error), (a2, a2_error)) = (column(0), column(1));
    let tensor = [column(2), column(3), column(4), column(5)];
    let seeds = runs.len() as f64;
    Ok(ShearPairRun {
        engine: runs[0].engine.clone(),
        temperature,
        temperature_error,
        tensor: tensor.map(|c| c.0),
        tensor_error: tensor.map(|c| c.1),
        a2,
        a2_error,
        samples: runs[0].samples.clone(),
        shear_stress: blocks.iter().map(|b| (b[6], b[5])).collect(),
        collisions_per_particle: runs.iter().map(|r| r.collisions).sum::<f64>() / seeds,
        wall_seconds: runs.iter().map(|r| r.wall_seconds).sum::<f64>() / seeds,
        time: runs[0].time,
    })
}

fn run_seed(s: &ShearPairSettings, kind: EngineKind, seed: u64) -> Result<SeedRun> {
    let mut e = build(&s.config(seed), kind)?;
    let engine = e.sim().engine().to_string();
    let sim = e.sim_mut();
    let clock = Instant::now();
    let mut samples = vec![(0.0, sim.thermo().granular_temperature)];
    let relax_steps = 20;
    for k in 1..=relax_steps {
        advance(sim, s.relax * k as f64 / relax_steps as f64)?;
        samples.push((sim.time(), sim.thermo().granular_temperature));
    }
    let first = reading(sim);
    let mut blocks = Vec::new();
    for b in 0..s.blocks {
        let start = reading(sim);
        let (mut t_sum, mut a2_sum) = (0.0, 0.0);
        for k in 1..=s.samples {
            let until = s.relax + s.block * (b as f64 + k as f64 / s.samples as f64);
            advance(sim, until)?;
            let kt = sim.thermo().granular_temperature;
            samples.push((sim.time(), kt));
            t_sum += kt;
            a2_sum += since(sim, None).sonine_a2;
        }
        let p = since(sim, Some(&start)).tensor;
        let n = s.samples as f64;
        let mid = 0.5 * (start.t + sim.time());
        blocks.push([t_sum / n, a2_sum / n, p[0], p[1], p[2], p[3], mid]);
    }
    let collisions = (sim.stress_sums().collisions - first.sums.collisions) as f64;
    Ok(SeedRun {
        engine,
        samples,
        blocks,
        collisions: 2.0 * collisions / s.count as f64,
        wall_seconds: clock.elapsed().as_secs_f64(),
        time: sim.time(),
    })
}

/// Temperature against time and the shear stress of each block, for each run.
pub fn plot(
    s: &ShearPairSettings,
    runs: &[&ShearPairRun],
    path: &Path,
) -> std::result::Result<(), String> {
    let mut temperature = Panel::new(
        format!(
            "Sheared inelastic gas (ε = {}, φ = {}, shear rate {} /s, N = {}): kT",
            s.restitution, s.phi, s.rate, s.count
        ),
        Axis::linear("t [s]"),
        Axis::linear("kT [J] (σ = 1 m, m = 1 kg)"),
    );
    let mut stress = Panel::new(
        "Shear stress per block",
        Axis::linear("t [s]"),
        Axis::linear("P_xy [Pa]"),
    );
    stress.legend = LegendAt::LowerRight;
    for (k, r) in runs.iter().enumerate() {
        temperature.series.push(Series::new(
            format!(
                "{}: kT = {:.4} ± {:.4} J, a₂ = {:.4} ± {:.4}",
                r.engine, r.temperature, r.temperature_error, r.a2, r.a2_error
            ),
            r.samples.clone(),
            PALETTE[1 + k],
            Style::Line,
        ));
        let [pxx, pyy, pzz, pxy] = r.tensor;
        let e = r.tensor_error;
        stress.series.push(Series::new(
            format!(
                "{}: P_xy = {pxy:.4} ± {:.4}; P_xx, P_yy, P_zz = {pxx:.3}, {pyy:.3}, {pzz:.3} \
                 (± {:.3}, {:.3}, {:.3}) Pa",
                r.engine, e[3], e[0], e[1], e[2]
            ),
            r.shear_stress.clone(),
            PALETTE[1 + k],
            Style::Points(4),
        ));
    }
    write_png(path, (900, 900), 2, 1, &[temperature, stress])
}
