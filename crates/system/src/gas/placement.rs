//! Where a generated gas's spheres start (lattice, fcc, random placement) and their
//! Maxwell velocities.

use crate::error::{Result, invalid};
use crate::geometry::{SimBox, bounded_cell_width};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// The face-centred cubic lattice of `count` = 4n³ sites, n unit cells along each
/// axis, offset by a quarter cell from the box's lower corner.
pub(super) fn fcc(count: usize, radius: f64, b: &SimBox) -> Result<Vec<[f64; 3]>> {
    let n = ((count / 4) as f64).cbrt().round() as usize;
    if 4 * n * n * n != count {
        return invalid!(
            "arrangement = \"fcc\" needs gas.count = 4n³ (4, 32, 108, 256, 500, …), got {count}"
        );
    }
    let a: [f64; 3] = std::array::from_fn(|k| b.size[k] / n as f64);
    let nearest = a.iter().copied().fold(f64::INFINITY, f64::min) / std::f64::consts::SQRT_2;
    if nearest < 2.0 * radius {
        return invalid!(
            "an fcc lattice of {count} spheres of radius {radius} m does not fit in the box \
             (nearest-neighbour distance {nearest:.4e} m < diameter); use a bigger box"
        );
    }
    const BASIS: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    let mut sites = Vec::with_capacity(count);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let cell = [x as f64, y as f64, z as f64];
                for basis in &BASIS {
                    sites.push(std::array::from_fn(|k| {
                        b.lo[k] + (cell[k] + basis[k] + 0.25) * a[k]
                    }));
                }
            }
        }
    }
    Ok(sites)
}

/// The first `count` sites of the simple cubic lattice with the coarsest spacing that
/// holds them, each site in the middle of its lattice cell. The box's sides and volume
/// must be finite and positive: the search starts from a finite spacing no wider than
/// the longest side and ends once that side alone holds `count` sites, after at most
/// ln(count)/ln(1/0.999) + 1 narrowings.
pub(super) fn lattice(count: usize, radius: f64, b: &SimBox) -> Result<Vec<[f64; 3]>> {
    let mut a = (b.volume() / count as f64).cbrt();
    let dims = loop {
        let n: [usize; 3] = std::array::from_fn(|k| ((b.size[k] / a).floor() as usize).max(1));
        // Saturating: in a thin box two long axes can each hold usize::MAX sites.
        if n.iter().fold(1usize, |p, &m| p.saturating_mul(m)) >= count {
            break n;
        }
        a *= 0.999;
    };
    let spacing: [f64; 3] = std::array::from_fn(|k| b.size[k] / dims[k] as f64);
    let min_spacing = spacing.iter().copied().fold(f64::INFINITY, f64::min);
    if min_spacing < 2.0 * radius {
        return invalid!(
            "a simple cubic lattice of {count} spheres of radius {radius} m does not fit in the \
             box (spacing {min_spacing:.4e} m < diameter); use a bigger box or \
             arrangement = \"random\""
        );
    }
    Ok((0..count)
        .map(|i| {
            let idx = [
                i % dims[0],
                (i / dims[0]) % dims[1],
                i / dims[0].saturating_mul(dims[1]),
            ];
            std::array::from_fn(|k| b.lo[k] + (idx[k] as f64 + 0.5) * spacing[k])
        })
        .collect())
}

/// Cells per axis of a grid over a box of `size` whose cells are at least `d` wide,
/// `limit` cells at most (see [`bounded_cell_width`]).
pub(super) fn grid_dims(size: [f64; 3], d: f64, limit: f64) -> [usize; 3] {
    let width = bounded_cell_width(size, d, limit);
    std::array::from_fn(|k| (size[k] / width).floor().max(1.0) as usize)
}

/// Random sequential addition of spheres of `radii`, in that order: uniform trial
/// positions, rejected if they overlap a placed sphere (or leave the box along a closed
/// axis).
pub(super) fn random_placement(
    radii: &[f64],
    b: &SimBox,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<[f64; 3]>> {
    let count = radii.len();
    // Cells as wide as the largest contact: every overlap lies in the 27 cells around.
    let widest = 2.0 * radii.iter().copied().fold(0.0, f64::max);
    let dims = grid_dims(b.size, widest, 8.0 * count as f64 + 64.0);
    let cell: [f64; 3] = std::array::from_fn(|k| b.size[k] / dims[k] as f64);
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); dims.iter().product()];
    let mut placed: Vec<[f64; 3]> = Vec::with_capacity(count);
    let max_attempts = 1000 * count as u64 + 10_000;
    let mut attempts = 0u64;
    while placed.len() < count {
        attempts += 1;
        if attempts > max_attempts {
            return invalid!(
                "random placement stalled after {} of {count} spheres ({attempts} trials): the \
                 packing fraction is too high for random sequential addition (it jams near \
                 0.38); use arrangement = \"lattice\" or a bigger box",
                placed.len()
            );
        }
        let radius = radii[placed.len()];
        let x: [f64; 3] = std::array::from_fn(|k| {
            let u: f64 = rng.random();
            if b.periodic[k] {
                b.lo[k] + u * b.size[k]
            } else {
                b.lo[k] + radius + u * (b.size[k] - 2.0 * radius).max(0.0)
            }
        });
        let c: [usize; 3] =
            std::array::from_fn(|k| (((x[k] - b.lo[k]) / cell[k]) as usize).min(dims[k] - 1));
        let mut free = true;
        'search: for dz in -1i64..=1 {
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let off = [dx, dy, dz];
                    let mut cc = [0usize; 3];
                    for k in 0..3 {
                        let v = c[k] as i64 + off[k];
                        let n = dims[k] as i64;
                        if !b.periodic[k] && (v < 0 || v >= n) {
                            continue;
                        }
                        cc[k] = v.rem_euclid(n) as usize;
                    }
                    for &j in &cells[cc[0] + dims[0] * (cc[1] + dims[1] * cc[2])] {
                        let y = placed[j as usize];
                        let r = b.min_image(std::array::from_fn(|k| x[k] - y[k]));
                        let d = radius + radii[j as usize];
                        if r[0] * r[0] + r[1] * r[1] + r[2] * r[2] < d * d {
                            free = false;
                            break 'search;
                        }
                    }
                }
            }
        }
        if free {
            cells[c[0] + dims[0] * (c[1] + dims[1] * c[2])].push(placed.len() as u32);
            placed.push(x);
        }
    }
    Ok(placed)
}

/// Maxwell velocities of spheres of `masses` at one temperature: Gaussian components
/// (Box–Muller) of variance ∝ 1/m, shifted to zero total momentum and scaled to the
/// exact root-mean-square speed `rms` over all spheres. (For equal masses the weights
/// below are exactly 1, so the numbers are those of equal spheres.)
pub(super) fn maxwell_velocities(masses: &[f64], rms: f64, rng: &mut ChaCha8Rng) -> Vec<[f64; 3]> {
    let count = masses.len();
    let mut gauss = || {
        let u1: f64 = 1.0 - rng.random::<f64>(); // in (0, 1]
        let u2: f64 = rng.random();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    };
    let mut v: Vec<[f64; 3]> = (0..count).map(|_| [gauss(), gauss(), gauss()]).collect();
    // Weights m/m₀: equipartition scales each sphere by 1/√w, the momentum weighs by w.
    let weight: Vec<f64> = masses.iter().map(|m| m / masses[0]).collect();
    for (x, w) in v.iter_mut().zip(&weight) {
        let s = 1.0 / w.sqrt();
        for c in x.iter_mut() {
            *c *= s;
        }
    }
    let total: f64 = weight.iter().sum();
    let mean: [f64; 3] =
        std::array::from_fn(|k| v.iter().zip(&weight).map(|(x, w)| w * x[k]).sum::<f64>() / total);
    let mut sum_sq = 0.0;
    for x in &mut v {
        for k in 0..3 {
            x[k] -= mean[k];
            sum_sq += x[k] * x[k];
        }
    }
    let scale = if sum_sq > 0.0 {
        rms / (sum_sq / count as f64).sqrt()
    } else {
        0.0
    };
    for x in &mut v {
        for c in x.iter_mut() {
            *c *= scale;
        }
    }
    v
}
