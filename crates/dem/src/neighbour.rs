//! Half Verlet lists built from a cell grid, with periodic image codes.

use emdstar_system::{CellGrid, SimBox, Stencil, bounding_box};

/// Bits of a list entry that hold the neighbour's index; the rest hold its image code.
pub const INDEX_BITS: u32 = 27;
/// Mask of the index bits.
pub const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// A half neighbour list: every pair closer than R_i + R_j + skin appears once, under
/// its higher index (so that a single sweep in index order meets each pair after both
/// particles), as `j | code << INDEX_BITS`; the neighbour's image sits at
/// x_j + `shifts[code]`.
#[derive(Debug, Clone, Default)]
pub struct NeighbourList {
    pub start: Vec<u32>,
    pub entries: Vec<u32>,
    pub shifts: [[f64; 3]; 27],
    pub grid: CellGrid,
}

/// Why a neighbour list cannot be built.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxTooSmall {
    pub axis: usize,
    pub length: f64,
    pub cell: f64,
}

impl NeighbourList {
    /// Lays a grid over the box (or the particles' bounding box in free space) with
    /// cells at least `min_cell` wide and about `target_per_cell` particles each, and
    /// returns the particle order that sorts them by cell.
    pub fn sort_order(
        &mut self,
        positions: &[[f64; 3]],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        target_per_cell: f64,
    ) -> Result<Vec<u32>, BoxTooSmall> {
        let (lo, extent, periodic) = match sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let (lo, extent) = bounding_box(positions);
                (lo, extent, [false; 3])
            }
        };
        let volume: f64 = extent.iter().map(|e| e.max(min_cell)).product();
        let cell = min_cell.max((target_per_cell * volume / positions.len().max(1) as f64).cbrt());
        let mut grid = CellGrid::new(lo, extent, periodic, cell);
        if let Some(b) = sim_box {
            // With fewer than 3 cells a pair could meet through two images.
            let grid_min = CellGrid::new(lo, extent, periodic, min_cell);
            for k in 0..3 {
                if periodic[k] && grid_min.dims[k] < 3 {
                    return Err(BoxTooSmall {
                        axis: k,
                        length: b.size[k],
                        cell: min_cell,
                    });
                }
                if periodic[k] && grid.dims[k] < 3 {
                    grid = CellGrid::new(lo, extent, periodic, min_cell);
                }
            }
            self.shifts = std::array::from_fn(|code| {
                let s = [code % 3, (code / 3) % 3, code / 9];
                std::array::from_fn(|k| (s[k] as f64 - 1.0) * b.size[k])
            });
        } else {
            self.shifts = [[0.0; 3]; 27];
        }
        grid.bin(positions);
        let order = grid.cell_items.clone();
        self.grid = grid;
        Ok(order)
    }

    /// Builds the list for particles already sorted by [`Self::sort_order`] (so that
    /// cell c holds the contiguous range `cell_start[c]..cell_start[c+1]`).
    pub fn build(&mut self, positions: &[[f64; 3]], radius: &[f64], skin: f64) {
        let grid = &self.grid;
        self.start.clear();
        self.entries.clear();
        self.start.push(0);
        for c_index in 0..grid.len() {
            let (a, b) = (
                grid.cell_start[c_index] as usize,
                grid.cell_start[c_index + 1] as usize,
            );
            if a == b {
                continue;
            }
            let c = [
                c_index % grid.dims[0],
                (c_index / grid.dims[0]) % grid.dims[1],
                c_index / (grid.dims[0] * grid.dims[1]),
            ];
            // The full stencil, keeping j < i: a half stencil would list some pairs
            // that meet through a periodic wrap under their lower index.
            let mut cells = [(0usize, 0usize, [0.0; 3], 0u32); 27];
            let mut n_cells = 0;
            grid.for_each_neighbour(c, Stencil::Full, |other, shift| {
                let code = (shift[0] + 1) as usize
                    + 3 * (shift[1] + 1) as usize
                    + 9 * (shift[2] + 1) as usize;
                let (oa, ob) = (
                    grid.cell_start[other] as usize,
                    grid.cell_start[other + 1] as usize,
                );
                if oa < ob {
                    cells[n_cells] = (oa, ob, self.shifts[code], (code as u32) << INDEX_BITS);
                    n_cells += 1;
                }
            });
            for i in a..b {
                let xi = positions[i];
                let ri = radius[i] + skin;
                for &(oa, ob, s, code) in &cells[..n_cells] {
                    for j in oa..ob.min(i) {
                        let d = [
                            xi[0] - positions[j][0] - s[0],
                            xi[1] - positions[j][1] - s[1],
                            xi[2] - positions[j][2] - s[2],
                        ];
                        let cut = ri + radius[j];
                        if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                            self.entries.push(j as u32 | code);
                        }
                    }
                }
                self.start.push(self.entries.len() as u32);
            }
        }
    }

    /// The entries of particle i.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.start[i] as usize..self.start[i + 1] as usize]
    }
}
