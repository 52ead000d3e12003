//! The link cells and the full Verlet list of the hybrid engine, and the local volume
//! fraction that decides the modes.

use crate::options::HybridError;
use emdstar_dem::MdError;
use emdstar_system::{CellGrid, SimBox, bounding_box};

/// Bits of a list entry that hold the neighbour's index; the rest hold its image code.
pub(crate) const INDEX_BITS: u32 = 27;
pub(crate) const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// A full neighbour list (every pair closer than R_i + R_j + skin appears under both
/// particles) as `j | code << INDEX_BITS`; the neighbour's image sits at
/// x_j + `shifts[code]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct FullList {
    /// `entries[range[i].0..range[i].2]` are the neighbours of particle i, those with a
    /// higher index first (up to `range[i].1`), for the pair loop of the TD forces.
    pub range: Vec<(u32, u32, u32)>,
    pub entries: Vec<u32>,
    /// Scratch for the neighbours with a lower index during a build.
    lower: Vec<u32>,
    pub shifts: [[f64; 3]; 27],
    /// The binned link cells of the last build.
    pub grid: CellGrid,
}

/// The cells next to cell `c` (itself included) that hold particles, with the image
/// code of each (the neighbour's particles appear at x + shift, code = Σ 3^k (s_k + 1)).
/// Periodic axes need at least 3 cells (checked by [`FullList::build`]).
#[inline]
fn neighbour_cells(grid: &CellGrid, c: [usize; 3]) -> ([(u32, u32); 27], usize) {
    let mut out = [(0u32, 0u32); 27];
    let mut n = 0;
    let mut axis: [[(usize, usize); 3]; 3] = [[(0, 0); 3]; 3];
    let mut count = [0usize; 3];
    for k in 0..3 {
        let d = grid.dims[k];
        for step in [-1i64, 0, 1] {
            let x = c[k] as i64 + step;
            let (x, shift) = if x < 0 {
                (d as i64 - 1, 0)
            } else if x >= d as i64 {
                (0, 2)
            } else {
                (x, 1)
            };
            let wrapped = shift != 1;
            if wrapped && !(grid.periodic[k] && d >= 3) {
                continue;
            }
            if !wrapped && step != 0 && d == 1 {
                continue;
            }
            axis[k][count[k]] = (x as usize, shift);
            count[k] += 1;
        }
    }
    for &(z, sz) in &axis[2][..count[2]] {
        for &(y, sy) in &axis[1][..count[1]] {
            for &(x, sx) in &axis[0][..count[0]] {
                let index = grid.index([x, y, z]);
                if grid.cell_start[index] != grid.cell_start[index + 1] {
                    out[n] = (index as u32, (sx + 3 * sy + 9 * sz) as u32);
                    n += 1;
                }
            }
        }
    }
    (out, n)
}

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

impl FullList {
    /// Bins `positions` (already wrapped into the box) into cells at least `min_cell`
    /// wide and builds the list with cut-off R_i + R_j + `skin`.
    pub fn build(
        &mut self,
        positions: &[[f64; 3]],
        radius: &[f64],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        skin: f64,
    ) -> Result<(), HybridError> {
        let (lo, extent, periodic) = region(positions, sim_box);
        let grid_min = CellGrid::new(lo, extent, periodic, min_cell);
        if let Some(b) = sim_box {
            for k in 0..3 {
                // With fewer than 3 cells a pair could meet through two images.
                if periodic[k] && grid_min.dims[k] < 3 {
                    return Err(MdError::BoxTooSmall {
                        axis: ["x", "y", "z"][k],
                        length: b.size[k],
                        cell: min_cell,
                    }
                    .into());
                }
            }
            self.shifts = std::array::from_fn(|code| {
                let s = [code % 3, (code / 3) % 3, code / 9];
                std::array::from_fn(|k| (s[k] as f64 - 1.0) * b.size[k])
            });
        } else {
            self.shifts = [[0.0; 3]; 27];
        }
        let mut grid = grid_min;
        grid.bin(positions);
        self.range.clear();
        self.entries.clear();
        // In particle order: dilute grids have far more cells than particles.
        let mut last_cell = usize::MAX;
        let mut cells = ([(0u32, 0u32); 27], 0);
        for (i, &xi) in positions.iter().enumerate() {
            let c = grid.coords(xi);
            let index = grid.index(c);
            if index != last_cell {
                cells = neighbour_cells(&grid, c);
                last_cell = index;
            }
            let ri = radius[i] + skin;
            let begin = self.entries.len() as u32;
            self.lower.clear();
            for &(other, code) in &cells.0[..cells.1] {
                let s = self.shifts[code as usize];
                for &j in grid.items(other as usize) {
                    let j = j as usize;
                    if j == i {
                        continue;
                    }
                    let d: [f64; 3] = std::array::from_fn(|k| xi[k] - positions[j][k] - s[k]);
                    let cut = ri + radius[j];
                    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                        let entry = j as u32 | code << INDEX_BITS;
                        if j > i {
                            self.entries.push(entry);
                        } else {
                            self.lower.push(entry);
                        }
                    }
                }
            }
            let upper = self.entries.len() as u32;
            self.entries.extend_from_slice(&self.lower);
            self.range.push((begin, upper, self.entries.len() as u32));
        }
        self.grid = grid;
        Ok(())
    }

    /// The entries of particle i.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        let (a, _, b) = self.range[i];
        &self.entries[a as usize..b as usize]
    }

    /// The entries of particle i with a higher index: every pair once.
    #[inline]
    pub fn upper(&self, i: usize) -> &[u32] {
        let (a, b, _) = self.range[i];
        &self.entries[a as usize..b as usize]
    }

    /// Splits an entry into the neighbour and its image shift.
    #[inline]
    pub fn split(&self, entry: u32) -> (usize, [f64; 3]) {
        (
            (entry & INDEX_MASK) as usize,
            self.shifts[(entry >> INDEX_BITS) as usize],
        )
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
    (lo, extent, periodic): ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
) -> Vec<f64> {
    let mut grid = CellGrid::new(lo, extent, periodic, cell);
    grid.bin(positions);
    volume_fractions_on(&grid, positions, radius, cell)
}

/// [`local_volume_fractions`] on a grid binned with `positions`.
pub(crate) fn volume_fractions_on(
    grid: &CellGrid,
    positions: &[[f64; 3]],
    radius: &[f64],
    cell: f64,
) -> Vec<f64> {
    let periodic = grid.periodic;
    let mut solid = vec![0.0; grid.len()];
    for (x, r) in positions.iter().zip(radius) {
        solid[grid.index(grid.coords(*x))] += 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    }
    let cell_volume: f64 = grid
        .cell_size
        .iter()
        .map(|&c| if c > 0.0 { c } else { cell })
        .product();
    let mut phi_cell = vec![f64::NAN; grid.len()];
    positions
        .iter()
        .map(|x| {
            let c = grid.coords(*x);
            let index = grid.index(c);
            if phi_cell[index].is_nan() {
                // Every cell of the neighbourhood counts, empty or not.
                let cells: usize = (0..3)
                    .map(|k| {
                        let d = grid.dims[k];
                        if periodic[k] && d >= 3 {
                            3
                        } else {
                            1 + usize::from(c[k] > 0) + usize::from(c[k] + 1 < d)
                        }
                    })
                    .product();
                let (occupied, n) = neighbour_cells(grid, c);
                let v: f64 = occupied[..n].iter().map(|&(o, _)| solid[o as usize]).sum();
                phi_cell[index] = v / (cells as f64 * cell_volume);
            }
            phi_cell[index]
        })
        .collect()
}

/// The cells around cell `c` of a φ grid, as [`volume_fractions_on`] counts them
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

/// Scratch buffers of [`any_dense`] (kept between calls; `solid` stays zero).
#[derive(Debug, Clone, Default)]
pub(crate) struct DenseScratch {
    solid: Vec<f64>,
    cell_of: Vec<usize>,
}

/// Whether any particle's local volume fraction (as [`local_volume_fractions`] with
/// the same arguments; radius 0 leaves a particle out) reaches `phi`, without binning
/// the whole grid: φ of a neighbourhood is at most the largest φ of its cells, so only
/// the neighbourhoods of cells that alone reach `phi` are summed. O(N) per call.
pub(crate) fn any_dense(
    positions: &[[f64; 3]],
    radius: &[f64],
    (lo, extent, periodic): ([f64; 3], [f64; 3], [bool; 3]),
    cell: f64,
    phi: f64,
    scratch: &mut DenseScratch,
) -> bool {
    let grid = CellGrid::new(lo, extent, periodic, cell);
    let DenseScratch { solid, cell_of } = scratch;
    if solid.len() < grid.len() {
        solid.resize(grid.len(), 0.0);
    }
    cell_of.clear();
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
        cell_of.push(m);
        solid[m] += 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    }
    let volume: f64 = grid
        .cell_size
        .iter()
        .map(|&c| if c > 0.0 { c } else { cell })
        .product();
    // Slightly below the threshold, so that round-off in the sums cannot hide one.
    let hot = phi * volume * (1.0 - 1e-9);
    let (nx, ny) = (grid.dims[0], grid.dims[1]);
    let coords = |m: usize| [m % nx, (m / nx) % ny, m / (nx * ny)];
    let mut dense = false;
    'cells: for &m in cell_of.iter() {
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
    for &m in cell_of.iter() {
        solid[m] = 0.0;
    }
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
    fn the_full_list_holds_every_close_pair_twice_across_periodic_faces() {
        let b = SimBox {
            lo: [0.0; 3],
            size: [3.0, 3.0, 3.0],
            periodic: [true; 3],
        };
        let x = [[0.05, 1.5, 1.5], [2.95, 1.5, 1.5], [1.5, 1.5, 1.5]];
        let mut list = FullList::default();
        list.build(&x, &[0.1; 3], Some(&b), 1.0, 0.05).unwrap();
        assert_eq!(list.of(0).len(), 1);
        assert_eq!(list.of(1).len(), 1);
        assert!(list.of(2).is_empty());
        let (j, s) = list.split(list.of(0)[0]);
        assert_eq!(j, 1);
        assert_eq!(s, [-3.0, 0.0, 0.0]);
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
        let mut scratch = DenseScratch::default();
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
