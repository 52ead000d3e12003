//! Simple starting states for tests and benchmarks: equal spheres on an FCC lattice
//! in a periodic cube with Maxwell–Boltzmann velocities.

use crate::setup::{Region, Setup};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// 4·cells³ spheres of diameter `sigma` and mass `mass` on an FCC lattice at number
/// density `density` (per σ³·… in the same units), with velocities drawn from a
/// Maxwell distribution, shifted to zero total momentum and scaled so that
/// Σ ½ m v² = (3/2) N kT exactly.
pub fn fcc(cells: usize, density: f64, sigma: f64, mass: f64, kt: f64, seed: u64) -> Setup {
    let n = 4 * cells * cells * cells;
    let side = (n as f64 / density).cbrt();
    let a = side / cells as f64;
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    let mut position = Vec::with_capacity(n);
    for z in 0..cells {
        for y in 0..cells {
            for x in 0..cells {
                for b in &basis {
                    position.push([
                        (x as f64 + b[0] + 0.25) * a,
                        (y as f64 + b[1] + 0.25) * a,
                        (z as f64 + b[2] + 0.25) * a,
                    ]);
                }
            }
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gauss = || {
        // Box–Muller.
        let u: f64 = 1.0 - rng.random::<f64>();
        let w: f64 = rng.random::<f64>();
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * w).cos()
    };
    let mut velocity: Vec<[f64; 3]> = (0..n).map(|_| [gauss(), gauss(), gauss()]).collect();
    let mean: [f64; 3] =
        std::array::from_fn(|k| velocity.iter().map(|v| v[k]).sum::<f64>() / n as f64);
    for v in &mut velocity {
        for k in 0..3 {
            v[k] -= mean[k];
        }
    }
    let ke: f64 = velocity
        .iter()
        .map(|v| 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
        .sum();
    let scale = (1.5 * n as f64 * kt / ke).sqrt();
    for v in &mut velocity {
        for x in v.iter_mut() {
            *x *= scale;
        }
    }
    Setup {
        position,
        velocity,
        radius: vec![0.5 * sigma; n],
        mass: vec![mass; n],
        species: vec![0; n],
        region: Some(Region {
            lo: [0.0; 3],
            size: [side; 3],
            periodic: [true; 3],
        }),
        walls: vec![],
        gravity: [0.0; 3],
    }
}
