//! The local volume fraction that decides the modes, on the link cells of the
//! neighbour list (emdstar-dem's [`emdstar_dem::NeighbourList`], full layout) or on a
//! grid of its own.

use emdstar_system::{CellGrid, SimBox, bounding_box};

/// The region a grid must cover: the box, or the particles' bounding box.
pub(crate) fn region(
    positions: &[[f64; 3]],
    sim_box: Option<&SimBox>,
) -> ([f64; 3], [f64; 3], [bool; 3]) {
    match sim_box {
        Some(b) => (b.lo, b.size, b.periodic),
        None => {
            let (lo, extent) = bounding_box(positions);
            (lo, extent, [false; 3])
        }
    }
}

/// The local volume fraction of every particle: the solid volume (4/3)πR³ of the
/// particles in its link cell and the neighbouring cells, over the volume of those
/// cells (HAET, Sec. 5–6: the link cell and its 26 neighbours in 3-D; fewer at closed
/// faces). The link cells are at least `cell` wide and cover `[lo, lo + extent]`
/// (positions beyond fall into the border cells); an axis thinner than `cell` (a
/// slab) has one cell as thick as the slab, or `cell` if it is flat.
pub fn local_volume_fractions(
    positions: &[[f64; 3]],
    radius: &[f64],
    region: ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
) -> Vec<f64> {
    let mut scratch = PhiScratch::default();
    volume_fractions(positions, radius, region, cell, &mut scratch).to_vec()
}

/// Scratch of the volume fractions, kept between calls (`solid` stays zero and
/// `phi_cell` NaN between them).
#[derive(Debug, Clone, Default)]
pub(crate) struct PhiScratch {
    solid: Vec<f64>,
    phi_cell: Vec<f64>,
    cell_of: Vec<usize>,
    phi: Vec<f64>,
}

/// The link cells of a φ computation: at least `cell` wide over the region, fewer
/// where particles are few and far apart.
fn phi_grid(
    (lo, extent, periodic): ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
    n: usize,
) -> CellGrid {
    CellGrid::sparse(lo, extent, periodic, cell, n)
}

/// The volume of a link cell of `grid` (`cell` along a flat axis).
fn cell_volume(grid: &CellGrid, cell: f64) -> f64 {
    grid.cell_size
        .iter()
        .map(|&c| if c > 0.0 { c } else { cell })
        .product()
}

/// Files the solid volume of each particle in its cell of `grid` (`solid`, sized) and
/// notes each particle's cell (`cell_of`).
fn file_solid(grid: &CellGrid, positions: &[[f64; 3]], radius: &[f64], s: &mut PhiScratch) {
    if s.solid.len() < grid.len() {
        s.solid.resize(grid.len(), 0.0);
        s.phi_cell.resize(grid.len(), f64::NAN);
    }
    s.cell_of.clear();
    // `grid.coords` without the floor call (a library call on baseline x86-64): for
    // non-negative c, truncation is the floor.
    let coords_of = |x: [f64; 3]| -> [usize; 3] {
        std::array::from_fn(|k| {
            let c = (x[k] - grid.lo[k]) / grid.cell_size[k];
            let top = grid.dims[k] - 1;
            if c < 0.0 {
                if grid.periodic[k] { top } else { 0 }
            } else {
                (c as usize).min(top)
            }
        })
    };
    for (x, r) in positions.iter().zip(radius) {
        let m = grid.index(coords_of(*x));
        s.cell_of.push(m);
        s.solid[m] += 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    }
}

/// Empties the cells `file_solid` filled.
fn clear_solid(s: &mut PhiScratch) {
    for &m in &s.cell_of {
        s.solid[m] = 0.0;
        s.phi_cell[m] = f64::NAN;
    }
}

/// [`local_volume_fractions`] into `scratch` (no allocation once it has grown).
pub(crate) fn volume_fractions<'a>(
    positions: &[[f64; 3]],
    radius: &[f64],
    region: ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
    scratch: &'a mut PhiScratch,
) -> &'a [f64] {
    let grid = phi_grid(region, cell, positions.len());
    file_solid(&grid, positions, radius, scratch);
    let volume = cell_volume(&grid, cell);
    let (nx, ny) = (grid.dims[0], grid.dims[1]);
    let PhiScratch {
        solid,
        phi_cell,
        cell_of,
        phi,
    } = scratch;
    phi.clear();
    for &m in cell_of.iter() {
        if phi_cell[m].is_nan() {
            // Every cell of the neighbourhood counts, empty or not.
            let (near, count) = around(&grid, [m % nx, (m / nx) % ny, m / (nx * ny)]);
            let sum: f64 = near[..count].iter().map(|&o| solid[o]).sum();
            phi_cell[m] = sum / (count as f64 * volume);
        }
        phi.push(phi_cell[m]);
    }
    clear_solid(scratch);
    &scratch.phi
}

/// The cells around cell `c` of a φ grid, as the volume fractions count them
/// (wrapping along a periodic axis of at least 3 cells, clipped otherwise).
fn around(grid: &CellGrid, c: [usize; 3]) -> ([usize; 27], usize) {
    let mut axis = [[0usize; 3]; 3];
    let mut count = [0usize; 3];
    for k in 0..3 {
        let d = grid.dims[k];
        let wraps = grid.periodic[k] && d >= 3;
        for step in [-1i64, 0, 1] {
            let x = c[k] as i64 + step;
            let x = if wraps {
                x.rem_euclid(d as i64)
            } else if (0..d as i64).contains(&x) {
                x
            } else {
                continue;
            };
            axis[k][count[k]] = x as usize;
            count[k] += 1;
        }
    }
    let mut out = [0usize; 27];
    let mut n = 0;
    for &z in &axis[2][..count[2]] {
        for &y in &axis[1][..count[1]] {
            for &x in &axis[0][..count[0]] {
                out[n] = grid.index([x, y, z]);
                n += 1;
            }
        }
    }
    (out, n)
}

/// Whether any particle's local volume fraction (as [`local_volume_fractions`] with
/// the same arguments; radius 0 leaves a particle out) reaches `phi`, without summing
/// every neighbourhood: φ of a neighbourhood is at most the largest φ of its cells, so
/// only the neighbourhoods of cells that alone reach `phi` are summed. O(N) per call.
pub(crate) fn any_dense(
    positions: &[[f64; 3]],
    radius: &[f64],
    region: ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
    phi: f64,
    scratch: &mut PhiScratch,
) -> bool {
    let grid = phi_grid(region, cell, positions.len());
    file_solid(&grid, positions, radius, scratch);
    let volume = cell_volume(&grid, cell);
    let solid = &scratch.solid;
    // Slightly below the threshold, so that round-off in the sums cannot hide one.
    let hot = phi * volume * (1.0 - 1e-9);
    let (nx, ny) = (grid.dims[0], grid.dims[1]);
    let coords = |m: usize| [m % nx, (m / nx) % ny, m / (nx * ny)];
    let mut dense = false;
    'cells: for &m in scratch.cell_of.iter() {
        if solid[m] == 0.0 || solid[m] < hot {
            continue;
        }
        let (near, len) = around(&grid, coords(m));
        for &o in &near[..len] {
            if solid[o] == 0.0 {
                continue; // no particle there (or only removed ones)
            }
            let (set, count) = around(&grid, coords(o));
            let sum: f64 = set[..count].iter().map(|&q| solid[q]).sum();
            if sum / (count as f64 * volume) >= phi {
                dense = true;
                break 'cells;
            }
        }
    }
    clear_solid(scratch);
    dense
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volume_fraction_counts_the_neighbour_cells() {
        // 4 × 1 × 1 cells of unit size; one sphere of volume 0.1 in the first cell.
        let r = (0.1 * 3.0 / (4.0 * std::f64::consts::PI)).cbrt();
        let x = [[0.5, 0.5, 0.5], [3.5, 0.5, 0.5], [2.5, 0.5, 0.5]];
        let region = ([0.0; 3], [4.0, 1.0, 1.0], [false; 3]);
        let phi = local_volume_fractions(&x, &[r; 3], region, 1.0);
        // First: cells 0 and 1, one sphere. Last: cells 2 and 3, two spheres. Third:
        // cells 1, 2, 3, two spheres.
        assert!((phi[0] - 0.05).abs() < 1e-12, "{phi:?}");
        assert!((phi[1] - 0.1).abs() < 1e-12);
        assert!((phi[2] - 0.2 / 3.0).abs() < 1e-12);
        // Periodic along x: every neighbourhood has three cells; the last sphere's
        // (cells 2, 3, 0) holds all three spheres, the others' two.
        let periodic = ([0.0; 3], [4.0, 1.0, 1.0], [true, false, false]);
        let phi = local_volume_fractions(&x, &[r; 3], periodic, 1.0);
        assert!((phi[0] - 0.2 / 3.0).abs() < 1e-12, "{phi:?}");
        assert!((phi[1] - 0.1).abs() < 1e-12);
        assert!((phi[2] - 0.2 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn far_apart_particles_get_a_small_grid() {
        // Two touching spheres and one 10⁴ m away along every axis (free space): one cell
        // of 0.3 m per contact size would be 3·10¹³ cells (found by fuzzing the hybrid).
        let x = [[0.0; 3], [0.2, 0.0, 0.0], [1e4; 3]];
        let region = ([0.0; 3], [1e4; 3], [false; 3]);
        let phi = local_volume_fractions(&x, &[0.1; 3], region, 0.3);
        assert!(
            phi.iter().all(|p| p.is_finite() && *p >= 0.0 && *p < 1e-6),
            "{phi:?}"
        );
        let mut scratch = PhiScratch::default();
        assert!(!any_dense(&x, &[0.1; 3], region, 0.3, 0.2, &mut scratch));
        assert!(scratch.solid.len() < 1 << 23);
    }

    #[test]
    fn the_dense_check_agrees_with_the_volume_fractions() {
        // Random clouds with a dense clump: `any_dense` must say whether the largest
        // φ of `local_volume_fractions` reaches the threshold, for thresholds on both
        // sides of it, periodic and closed.
        let mut seed = 12345u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut scratch = PhiScratch::default();
        for periodic in [[true; 3], [false; 3], [true, false, true]] {
            let mut x: Vec<[f64; 3]> = (0..300)
                .map(|_| [6.0 * uniform(), 5.0 * uniform(), 4.0 * uniform()])
                .collect();
            x.extend((0..40).map(|_| [1.0 + 0.5 * uniform(), 0.2 * uniform(), 3.0]));
            let r: Vec<f64> = (0..x.len()).map(|i| 0.1 + 0.02 * (i % 3) as f64).collect();
            let region = ([0.0; 3], [6.0, 5.0, 4.0], periodic);
            let phi = local_volume_fractions(&x, &r, region, 0.7);
            let max = phi.iter().copied().fold(0.0, f64::max);
            assert!(max > 0.01);
            for threshold in [0.5 * max, 0.999 * max, 1.001 * max, 2.0 * max] {
                let got = any_dense(&x, &r, region, 0.7, threshold, &mut scratch);
                assert_eq!(got, max >= threshold, "{periodic:?} {threshold} {max}");
            }
            // Particles with radius 0 do not count.
            let none = vec![0.0; x.len()];
            assert!(!any_dense(&x, &none, region, 0.7, 1e-12, &mut scratch));
        }
    }
}
