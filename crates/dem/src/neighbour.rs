//! Verlet neighbour lists built from a cell grid, with periodic image codes, in the two
//! layouts the engines need: half (MD) and full with an upper part (the hybrid).

use crate::options::MdError;
use emdstar_system::{CellGrid, SimBox, Stencil, bounding_box};

/// Bits of a list entry that hold the neighbour's index; the rest hold its image code.
pub const INDEX_BITS: u32 = 27;
/// Mask of the index bits.
pub const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// Which pairs a list holds under which particle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Layout {
    /// Every pair once, under its higher index, so that a single sweep in index order
    /// meets each pair after both particles. Needs particles sorted by cell.
    #[default]
    Half,
    /// Every pair under both particles, the neighbours of higher index first (the
    /// upper part, [`NeighbourList::upper`]), for particles in any order.
    Full,
}

/// A Verlet list: every pair closer than R_i + R_j + skin, as entries
/// `j | code << INDEX_BITS` under particle i, where `code` names the periodic image of
/// j that is close ([`NeighbourList::split`] gives j and the image's shift). Under each
/// particle the neighbours come in the order of the cells of
/// [`CellGrid::for_each_neighbour`] (full stencil), by index within a cell.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct NeighbourList {
    layout: Layout,
    /// The entries of particle i are `entries[start[i]..start[i + 1]]`.
    pub(crate) start: Vec<u32>,
    /// Full layout: the upper part of particle i ends at `upper_end[i]`.
    upper_end: Vec<u32>,
    pub(crate) entries: Vec<u32>,
    /// Scratch of a full build: the neighbours of lower index of one particle.
    #[serde(skip)]
    lower: Vec<u32>,
    pub(crate) shifts: [[f64; 3]; 27],
    /// The link cells of the last build, binned with the positions it was given (for
    /// the half layout: with the sorted order, so cell c holds `start..end` of
    /// `cell_start`).
    pub grid: CellGrid,
}

/// A non-empty cell next to the one being scanned: its particles
/// `cell_items[first..end]` appear at x + `shift`; `code` is the image code, already
/// shifted into place for an entry.
#[derive(Debug, Clone, Copy, Default)]
struct Near {
    first: usize,
    end: usize,
    shift: [f64; 3],
    code: u32,
}

/// Whether the image of x_j at `shift` lies within `cut` of x_i.
#[inline(always)]
fn within(xi: [f64; 3], xj: [f64; 3], shift: [f64; 3], cut: f64) -> bool {
    let d = [
        xi[0] - xj[0] - shift[0],
        xi[1] - xj[1] - shift[1],
        xi[2] - xj[2] - shift[2],
    ];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut
}

impl NeighbourList {
    /// Errors unless a decoded list (a checkpoint's) covers particles `0..n`: ranges
    /// that follow each other through the entries, and entries that name particles
    /// `0..n` and one of the 27 images.
    pub fn check_restored(&self, n: usize) -> Result<(), String> {
        let ranges = self.start.len() == n + 1
            && self.start.first() == Some(&0)
            && self.start.last().map(|&e| e as usize) == Some(self.entries.len())
            && self.start.windows(2).all(|w| w[0] <= w[1])
            && (self.upper_end.is_empty()
                || self.upper_end.len() == n
                    && (0..n)
                        .all(|i| (self.start[i]..=self.start[i + 1]).contains(&self.upper_end[i])));
        let entries = self
            .entries
            .iter()
            .all(|&e| ((e & INDEX_MASK) as usize) < n && ((e >> INDEX_BITS) as usize) < 27);
        (ranges && entries)
            .then_some(())
            .ok_or_else(|| "the neighbour list does not cover the config's particles".into())
    }

    /// The layout of the last build.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Lays the grid over the box (or the particles' bounding box in free space) with
    /// cells at least `min_cell` wide and, if `per_cell` > 0, about `per_cell`
    /// particles each, bins `positions` and sets the image shifts. Errors if a periodic
    /// axis holds fewer than 3 cells of `min_cell` (a pair could then meet through two
    /// images).
    fn lay_grid(
        &mut self,
        positions: &[[f64; 3]],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        per_cell: f64,
    ) -> Result<(), MdError> {
        let (lo, extent, periodic) = match sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let (lo, extent) = bounding_box(positions);
                (lo, extent, [false; 3])
            }
        };
        let cell = if per_cell > 0.0 {
            let volume: f64 = extent.iter().map(|e| e.max(min_cell)).product();
            min_cell.max((per_cell * volume / positions.len().max(1) as f64).cbrt())
        } else {
            min_cell
        };
        let mut grid = CellGrid::sparse(lo, extent, periodic, cell, positions.len());
        if let Some(b) = sim_box {
            let grid_min = CellGrid::new(lo, extent, periodic, min_cell);
            for k in 0..3 {
                if periodic[k] && grid_min.dims[k] < 3 {
                    return Err(MdError::BoxTooSmall {
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
        grid.bin(positions);
        self.grid = grid;
        Ok(())
    }

    /// Writes the non-empty cells next to cell `c` (itself included) to `cells`, in the
    /// order of [`CellGrid::for_each_neighbour`], and returns their number.
    ///
    /// `HALF` names the build that asks. It changes nothing but gives each build its
    /// own copy of the stencil walk, which the compiler then inlines into it; a copy
    /// shared by both builds is not inlined and costs MD's rebuilds about 1 % more
    /// instructions.
    #[inline]
    fn near<const HALF: bool>(&self, c: [usize; 3], cells: &mut [Near; 27]) -> usize {
        let grid = &self.grid;
        let mut n = 0;
        grid.for_each_neighbour(c, Stencil::Full, |other, shift| {
            let code =
                (shift[0] + 1) as usize + 3 * (shift[1] + 1) as usize + 9 * (shift[2] + 1) as usize;
            let (first, end) = (
                grid.cell_start[other] as usize,
                grid.cell_start[other + 1] as usize,
            );
            if first < end {
                cells[n] = Near {
                    first,
                    end,
                    shift: self.shifts[code],
                    code: (code as u32) << INDEX_BITS,
                };
                n += 1;
            }
        });
        n
    }

    /// Lays a grid as [`Self::build_full`] does, with cells of about `per_cell`
    /// particles (never narrower than `min_cell`), and returns the particle order that
    /// sorts the particles by cell. Permute the particles with it, then call
    /// [`Self::build_half`].
    pub fn sort_order(
        &mut self,
        positions: &[[f64; 3]],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        per_cell: f64,
    ) -> Result<Vec<u32>, MdError> {
        self.lay_grid(positions, sim_box, min_cell, per_cell)?;
        let order = self.grid.cell_items.clone();
        // After the caller's permutation, cell c holds particles cell_start[c]..
        for (k, item) in self.grid.cell_items.iter_mut().enumerate() {
            *item = k as u32;
        }
        Ok(order)
    }

    /// Builds the half layout with cut-off R_i + R_j + `skin` for particles sorted by
    /// [`Self::sort_order`] (`positions` in that order).
    pub fn build_half(&mut self, positions: &[[f64; 3]], radius: &[f64], skin: f64) {
        self.layout = Layout::Half;
        self.start.clear();
        self.entries.clear();
        self.upper_end.clear();
        self.start.push(0);
        let dims = self.grid.dims;
        for c_index in 0..self.grid.len() {
            let (a, b) = (
                self.grid.cell_start[c_index] as usize,
                self.grid.cell_start[c_index + 1] as usize,
            );
            if a == b {
                continue;
            }
            let c = [
                c_index % dims[0],
                (c_index / dims[0]) % dims[1],
                c_index / (dims[0] * dims[1]),
            ];
            // The full stencil, keeping j < i: a half stencil would list some pairs
            // that meet through a periodic wrap under their lower index.
            let mut cells = [Near::default(); 27];
            let n_cells = self.near::<true>(c, &mut cells);
            for i in a..b {
                let (xi, ri) = (positions[i], radius[i] + skin);
                for near in &cells[..n_cells] {
                    // Sorted: the particles of a cell are a range of indices.
                    for j in near.first..near.end.min(i) {
                        if within(xi, positions[j], near.shift, ri + radius[j]) {
                            self.entries.push(j as u32 | near.code);
                        }
                    }
                }
                self.start.push(self.entries.len() as u32);
            }
        }
    }

    /// Bins `positions` (already wrapped into the box, in any order) into cells at
    /// least `min_cell` wide and builds the full layout with cut-off R_i + R_j +
    /// `skin`. Errors as [`Self::sort_order`].
    pub fn build_full(
        &mut self,
        positions: &[[f64; 3]],
        radius: &[f64],
        sim_box: Option<&SimBox>,
        min_cell: f64,
        skin: f64,
    ) -> Result<(), MdError> {
        self.lay_grid(positions, sim_box, min_cell, 0.0)?;
        self.layout = Layout::Full;
        self.start.clear();
        self.entries.clear();
        self.upper_end.clear();
        self.start.push(0);
        // In particle order: dilute grids have far more cells than particles.
        let mut last_cell = usize::MAX;
        let (mut cells, mut n_cells) = ([Near::default(); 27], 0);
        for (i, &xi) in positions.iter().enumerate() {
            let c = self.grid.coords(xi);
            let index = self.grid.index(c);
            if index != last_cell {
                n_cells = self.near::<false>(c, &mut cells);
                last_cell = index;
            }
            let ri = radius[i] + skin;
            self.lower.clear();
            for near in &cells[..n_cells] {
                for &j in &self.grid.cell_items[near.first..near.end] {
                    let j = j as usize;
                    if j != i && within(xi, positions[j], near.shift, ri + radius[j]) {
                        let entry = j as u32 | near.code;
                        if j > i {
                            self.entries.push(entry);
                        } else {
                            self.lower.push(entry);
                        }
                    }
                }
            }
            self.upper_end.push(self.entries.len() as u32);
            self.entries.extend_from_slice(&self.lower);
            self.start.push(self.entries.len() as u32);
        }
        Ok(())
    }

    /// The entries of particle i: its neighbours of lower index (half layout) or all
    /// its neighbours, those of higher index first (full layout).
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The entries of particle i with a higher index (none in the half layout).
    #[inline]
    pub fn upper(&self, i: usize) -> &[u32] {
        let a = self.start[i] as usize;
        let b = match self.layout {
            Layout::Half => a,
            Layout::Full => self.upper_end[i] as usize,
        };
        &self.entries[a..b]
    }

    /// The entries of particle i such that every pair is listed under one of its two
    /// particles only: [`Self::of`] in the half layout, [`Self::upper`] in the full.
    #[inline]
    pub fn once(&self, i: usize) -> &[u32] {
        match self.layout {
            Layout::Half => self.of(i),
            Layout::Full => self.upper(i),
        }
    }

    /// Splits an entry into the neighbour and its image shift.
    #[inline(always)]
    pub fn split(&self, entry: u32) -> (usize, [f64; 3]) {
        (
            (entry & INDEX_MASK) as usize,
            self.shifts[(entry >> INDEX_BITS) as usize],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use emdstar_system::sparse_cell_limit;

    /// Every pair (j < i) closer than the cut-off through any of the 27 images, by
    /// brute force.
    fn brute_force(x: &[[f64; 3]], r: &[f64], b: &SimBox, skin: f64) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        for i in 0..x.len() {
            for j in 0..i {
                let close = (0..27).any(|code| {
                    let s: [f64; 3] = std::array::from_fn(|k| {
                        let step = [code % 3, (code / 3) % 3, code / 9][k] as f64 - 1.0;
                        if b.periodic[k] { step * b.size[k] } else { 0.0 }
                    });
                    within(x[i], x[j], s, r[i] + r[j] + skin)
                });
                if close {
                    pairs.push((j, i));
                }
            }
        }
        pairs
    }

    fn cloud(n: usize, size: f64, seed: u64) -> Vec<[f64; 3]> {
        let mut s = seed;
        let mut uniform = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| [size * uniform(), size * uniform(), size * uniform()])
            .collect()
    }

    #[test]
    fn both_layouts_hold_exactly_the_close_pairs_of_a_brute_force_search() {
        for periodic in [[true; 3], [false; 3], [true, false, true]] {
            let b = SimBox {
                lo: [0.0; 3],
                size: [4.0; 3],
                periodic,
            };
            let x = cloud(400, 4.0, 7);
            let r: Vec<f64> = (0..x.len()).map(|i| 0.1 + 0.02 * (i % 3) as f64).collect();
            let skin = 0.1;
            let min_cell = 2.0 * 0.14 + skin;
            let mut want = brute_force(&x, &r, &b, skin);
            want.sort_unstable();
            assert!(want.len() > 100, "{}", want.len());

            let mut full = NeighbourList::default();
            full.build_full(&x, &r, Some(&b), min_cell, skin).unwrap();
            let mut got = Vec::new();
            for i in 0..x.len() {
                for &e in full.upper(i) {
                    let (j, _) = full.split(e);
                    assert!(j > i);
                    assert!(full.of(j).iter().any(|&f| full.split(f).0 == i));
                    got.push((i, j));
                }
                assert_eq!(full.once(i), full.upper(i));
                assert!(
                    full.of(i)[full.upper(i).len()..]
                        .iter()
                        .all(|&e| full.split(e).0 < i)
                );
            }
            got.sort_unstable();
            assert_eq!(got, want, "full, periodic {periodic:?}");

            let mut half = NeighbourList::default();
            let order = half.sort_order(&x, Some(&b), min_cell, 2.0).unwrap();
            let xs: Vec<[f64; 3]> = order.iter().map(|&k| x[k as usize]).collect();
            let rs: Vec<f64> = order.iter().map(|&k| r[k as usize]).collect();
            half.build_half(&xs, &rs, skin);
            let mut got = Vec::new();
            for i in 0..xs.len() {
                assert!(half.upper(i).is_empty());
                for &e in half.once(i) {
                    let (j, _) = half.split(e);
                    assert!(j < i);
                    let (a, b) = (order[i] as usize, order[j] as usize);
                    got.push((a.min(b), a.max(b)));
                }
            }
            got.sort_unstable();
            assert_eq!(got, want, "half, periodic {periodic:?}");
        }
    }

    #[test]
    fn the_full_list_holds_every_close_pair_twice_across_periodic_faces() {
        let b = SimBox {
            lo: [0.0; 3],
            size: [3.0, 3.0, 3.0],
            periodic: [true; 3],
        };
        let x = [[0.05, 1.5, 1.5], [2.95, 1.5, 1.5], [1.5, 1.5, 1.5]];
        let mut list = NeighbourList::default();
        list.build_full(&x, &[0.1; 3], Some(&b), 1.0, 0.05).unwrap();
        assert_eq!(list.of(0).len(), 1);
        assert_eq!(list.of(1).len(), 1);
        assert!(list.of(2).is_empty());
        let (j, s) = list.split(list.of(0)[0]);
        assert_eq!(j, 1);
        assert_eq!(s, [-3.0, 0.0, 0.0]);
        let (i, s) = list.split(list.of(1)[0]);
        assert_eq!(i, 0);
        assert_eq!(s, [3.0, 0.0, 0.0]);
    }

    #[test]
    fn a_long_periodic_channel_keeps_three_cells_across_within_the_cell_budget() {
        // 1e9 m long, 3 m across: cells of 1 m would be 9.4e6; widened to the budget, the
        // thin axes would hold fewer than 3 cells. They keep 3, the long axis shares the
        // rest, and the pairs across every periodic face are found.
        let b = SimBox {
            lo: [0.0; 3],
            size: [3.0, 1e9, 3.0],
            periodic: [true; 3],
        };
        let x = [
            [0.05, 5e8, 1.5],
            [2.95, 5e8, 1.5],
            [1.5, 5e8 + 0.5, 0.05],
            [1.5, 5e8 + 0.5, 2.95],
            [1.5, 0.05, 1.5],
            [1.5, 1e9 - 0.05, 1.5],
            [1.4, 2e8, 1.5],
        ];
        let r = [0.1; 7];
        let mut list = NeighbourList::default();
        list.build_full(&x, &r, Some(&b), 1.0, 0.05).unwrap();
        let g = &list.grid;
        assert!(g.dims[0] == 3 && g.dims[2] == 3, "{:?}", g.dims);
        assert!(g.len() as f64 <= sparse_cell_limit(x.len()), "{:?}", g.dims);
        let mut got: Vec<(usize, usize)> = (0..x.len())
            .flat_map(|i| list.upper(i).iter().map(move |&e| (i, e)))
            .map(|(i, e)| (i, list.split(e).0))
            .collect();
        got.sort_unstable();
        let mut want = brute_force(&x, &r, &b, 0.05);
        want.sort_unstable();
        assert_eq!(want, vec![(0, 1), (2, 3), (4, 5)]);
        assert_eq!(got, want);
        // Found by fuzzing: one sphere of 5e-62 m in a periodic box of 123 × 5.5e8 × 5.9
        // m; the list fell back to cells of the contact size on every axis (2⁶⁰ cells).
        let b = SimBox {
            lo: [970.0, 0.0, 0.0],
            size: [123.0, 5.5e8, 5.9],
            periodic: [true; 3],
        };
        let mut list = NeighbourList::default();
        list.build_full(&[[971.0, 1.0, 1.0]], &[4.8e-62], Some(&b), 1e-61, 1e-62)
            .unwrap();
        assert!(
            list.grid.len() as f64 <= sparse_cell_limit(1),
            "{:?}",
            list.grid.dims
        );
    }

    #[test]
    fn a_periodic_axis_of_fewer_than_three_cells_is_refused() {
        let b = SimBox {
            lo: [0.0; 3],
            size: [2.5, 3.0, 3.0],
            periodic: [true; 3],
        };
        let mut list = NeighbourList::default();
        let err = list
            .build_full(&[[1.0; 3]], &[0.1], Some(&b), 1.0, 0.05)
            .unwrap_err();
        assert!(
            matches!(err, MdError::BoxTooSmall { axis: "x", .. }),
            "{err}"
        );
    }
}
