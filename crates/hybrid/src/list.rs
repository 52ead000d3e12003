//! The link cells and the full Verlet list of the hybrid engine, and the local volume
//! fraction that decides the modes.

use crate::options::HybridError;
use emdstar_system::{CellGrid, SimBox, Stencil, bounding_box};

/// Bits of a list entry that hold the neighbour's index; the rest hold its image code.
pub(crate) const INDEX_BITS: u32 = 27;
pub(crate) const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// A full neighbour list (every pair closer than R_i + R_j + skin appears under both
/// particles) as `j | code << INDEX_BITS`; the neighbour's image sits at
/// x_j + `shifts[code]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct FullList {
    pub start: Vec<u32>,
    pub entries: Vec<u32>,
    pub shifts: [[f64; 3]; 27],
    pub grid: CellGrid,
}

impl FullList {
    /// Bins `positions` (already wrapped into the box) into link cells at least
    /// `min_cell` wide and builds the list with cut-off R_i + R_j + `skin`.
    pub fn build(
        &mut self,
        positions: &[[f64; 3]],
        radius: &[f64],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        skin: f64,
    ) -> Result<(), HybridError> {
        let (lo, extent, periodic) = match sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let (lo, extent) = bounding_box(positions);
                (lo, extent, [false; 3])
            }
        };
        let grid = CellGrid::new(lo, extent, periodic, min_cell);
        if let Some(b) = sim_box {
            for k in 0..3 {
                // With fewer than 3 cells a pair could meet through two images.
                if periodic[k] && grid.dims[k] < 3 {
                    return Err(HybridError::BoxTooSmall {
                        axis: ["x", "y", "z"][k],
                        length: b.size[k],
                        cell: min_cell,
                    });
                }
            }
            self.shifts = std::array::from_fn(|code| {
                let s = [code % 3, (code / 3) % 3, code / 9];
                std::array::from_fn(|k| (s[k] as f64 - 1.0) * b.size[k])
            });
        } else {
            self.shifts = [[0.0; 3]; 27];
        }
        self.grid = grid;
        self.grid.bin(positions);
        self.start.clear();
        self.entries.clear();
        self.start.push(0);
        let grid = &self.grid;
        for (i, &xi) in positions.iter().enumerate() {
            let c = grid.coords(xi);
            let ri = radius[i] + skin;
            let entries = &mut self.entries;
            let shifts = &self.shifts;
            grid.for_each_neighbour(c, Stencil::Full, |cell, shift| {
                let code = (shift[0] + 1) as usize
                    + 3 * (shift[1] + 1) as usize
                    + 9 * (shift[2] + 1) as usize;
                let s = shifts[code];
                for &j in grid.items(cell) {
                    let j = j as usize;
                    if j == i {
                        continue;
                    }
                    let d: [f64; 3] = std::array::from_fn(|k| xi[k] - positions[j][k] - s[k]);
                    let cut = ri + radius[j];
                    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                        entries.push(j as u32 | (code as u32) << INDEX_BITS);
                    }
                }
            });
            self.start.push(self.entries.len() as u32);
        }
        Ok(())
    }

    /// The entries of particle i.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.start[i] as usize..self.start[i + 1] as usize]
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
/// particles binned in its link cell and the neighbouring cells, over the volume of
/// those cells (HAET, Sec. 5–6: the link cell and its 26 neighbours in 3-D). `grid`
/// must have been binned with `positions`. Cells count at least `min_cell` wide
/// along every axis (in free space the grid may be flat along an axis).
pub fn local_volume_fractions(
    grid: &CellGrid,
    positions: &[[f64; 3]],
    radius: &[f64],
    min_cell: f64,
) -> Vec<f64> {
    let mut solid = vec![0.0; grid.len()];
    for (x, r) in positions.iter().zip(radius) {
        solid[grid.index(grid.coords(*x))] += 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    }
    let cell_volume: f64 = grid.cell_size.iter().map(|c| c.max(min_cell)).product();
    let mut phi_cell = vec![f64::NAN; grid.len()];
    positions
        .iter()
        .map(|x| {
            let c = grid.coords(*x);
            let index = grid.index(c);
            if phi_cell[index].is_nan() {
                let (mut v, mut cells) = (0.0, 0usize);
                grid.for_each_neighbour(c, Stencil::Full, |cell, _| {
                    v += solid[cell];
                    cells += 1;
                });
                phi_cell[index] = v / (cells as f64 * cell_volume);
            }
            phi_cell[index]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volume_fraction_counts_the_neighbour_cells() {
        // 4 × 1 × 1 cells of unit size; one sphere of volume 0.1 in the first cell.
        let mut grid = CellGrid::new([0.0; 3], [4.0, 1.0, 1.0], [false; 3], 1.0);
        let r = (0.1 * 3.0 / (4.0 * std::f64::consts::PI)).cbrt();
        let x = [[0.5, 0.5, 0.5], [3.5, 0.5, 0.5]];
        grid.bin(&x);
        let phi = local_volume_fractions(&grid, &x, &[r, r], 1.0);
        // First: cells 0 and 1 (2 cells), one sphere. Last: cells 2 and 3.
        assert!((phi[0] - 0.05).abs() < 1e-12, "{phi:?}");
        assert!((phi[1] - 0.05).abs() < 1e-12);
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
}
