//! Verlet neighbour lists built from a cell grid, with periodic image codes: every
//! pair once, under its higher index (MD's half list), and on demand the same pairs
//! under their lower index (its upper part), which completes it to every neighbour of
//! every particle (the hybrid engine's bookkeeping).

use crate::options::MdError;
use emdstar_system::{CellGrid, LeesEdwards, SimBox, Stencil, bounding_box};

/// Bits of a list entry that hold the neighbour's index; the rest hold its image code.
pub const INDEX_BITS: u32 = 27;
/// Mask of the index bits.
pub const INDEX_MASK: u32 = (1 << INDEX_BITS) - 1;

/// The image code of the opposite shift: code = Σ_k (s_k + 1)·3^k for s_k ∈ {−1, 0, 1}.
const MIRROR: u32 = 26;

/// A Verlet list: every pair closer than R_i + R_j + skin, as entries
/// `j | code << INDEX_BITS` under particle i, where `code` names the periodic image of
/// j that is close ([`NeighbourList::split`] gives j and the image's shift). Each pair
/// is listed once, under its higher index (a sweep in index order meets each pair after
/// both particles), for particles sorted by cell ([`NeighbourList::sort_order`]); under
/// each particle the neighbours come in the order of the cells of
/// [`CellGrid::for_each_neighbour`] (full stencil), by index within a cell.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct NeighbourList {
    /// The entries of particle i are `entries[start[i]..start[i + 1]]`.
    pub(crate) start: Vec<u32>,
    pub(crate) entries: Vec<u32>,
    pub(crate) shifts: [[f64; 3]; 27],
    /// The link cells of the last build, binned with the sorted order (cell c holds
    /// `cell_start[c]..cell_start[c + 1]`).
    pub grid: CellGrid,
    /// The upper part, once built ([`NeighbourList::build_upper`]): the neighbours of
    /// higher index of particle i are `upper_entries[upper_start[i]..upper_start[i +
    /// 1]]`. Derived from the entries, so not saved.
    #[serde(skip)]
    upper_start: Vec<u32>,
    #[serde(skip)]
    upper_entries: Vec<u32>,
    /// Under Lees–Edwards shear: γ̇ L_y, the x-velocity of the image one box up (set
    /// with the shifts by [`NeighbourList::slide`]; 0 without shear).
    #[serde(skip)]
    pub(crate) image_speed: f64,
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
pub(crate) fn within(xi: [f64; 3], xj: [f64; 3], shift: [f64; 3], cut: f64) -> bool {
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
            && self.start.windows(2).all(|w| w[0] <= w[1]);
        let entries = self
            .entries
            .iter()
            .all(|&e| ((e & INDEX_MASK) as usize) < n && ((e >> INDEX_BITS) as usize) < 27);
        (ranges && entries)
            .then_some(())
            .ok_or_else(|| "the neighbour list does not cover the config's particles".into())
    }

    /// Lays the grid over the box (or the particles' bounding box in free space) with
    /// cells at least `min_cell` wide and about `per_cell` particles each, bins
    /// `positions` and sets the image shifts. Errors if a periodic axis holds fewer than
    /// 3 cells of `min_cell`.
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
        let volume: f64 = extent.iter().map(|e| e.max(min_cell)).product();
        let cell = min_cell.max((per_cell * volume / positions.len().max(1) as f64).cbrt());
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
    #[inline]
    fn near(&self, c: [usize; 3], cells: &mut [Near; 27], sheared: bool) -> usize {
        let grid = &self.grid;
        let mut n = 0;
        grid.for_each_neighbour(c, Stencil::Full, |other, shift| {
            if sheared && shift[1] != 0 {
                // Across the sliding face: see `build_half_sheared`.
                return;
            }
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

    /// Lays a grid over the box (or the particles' bounding box in free space) with
    /// cells of about `per_cell` particles, never narrower than `min_cell`, and returns
    /// the particle order that sorts the particles by cell. Permute the particles with
    /// it, then call [`Self::build_half`]. Errors if a periodic axis holds fewer than 3
    /// cells of `min_cell` (a pair could then meet through two images).
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
        self.build_half_sheared(positions, radius, skin, None);
    }

    /// [`Self::build_half`] in a box sheared by `shear` = (its Lees–Edwards images, the
    /// time now): the cells that do not wrap in y as usual; across the sliding y face a
    /// cell in a border row takes the whole opposite row (within one cell in z), each
    /// pair under the image nearest now ([`Self::slide`] then moves the images on).
    pub fn build_half_sheared(
        &mut self,
        positions: &[[f64; 3]],
        radius: &[f64],
        skin: f64,
        shear: Option<(&LeesEdwards, f64)>,
    ) {
        if let Some((le, t)) = shear {
            self.slide_to(le, le.centred_offset(t));
        }
        self.start.clear();
        self.entries.clear();
        self.upper_start.clear();
        self.upper_entries.clear();
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
            let n_cells = self.near(c, &mut cells, shear.is_some());
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
                if let Some((le, _)) = shear {
                    self.push_across(le, c, (i, ri), positions, radius);
                }
                self.start.push(self.entries.len() as u32);
            }
        }
    }

    /// Builds the upper part from the half list (in O(pairs), no distance is
    /// computed): under each particle its neighbours of higher index, each pair's image
    /// code turned to the opposite shift.
    pub fn build_upper(&mut self) {
        let n = self.start.len().saturating_sub(1);
        self.upper_start.clear();
        self.upper_start.resize(n + 1, 0);
        for &e in &self.entries {
            self.upper_start[(e & INDEX_MASK) as usize + 1] += 1;
        }
        for i in 0..n {
            self.upper_start[i + 1] += self.upper_start[i];
        }
        self.upper_entries.clear();
        self.upper_entries.resize(self.entries.len(), 0);
        let mut fill: Vec<u32> = self.upper_start[..n].to_vec();
        for i in 0..n {
            for &e in &self.entries[self.start[i] as usize..self.start[i + 1] as usize] {
                let j = (e & INDEX_MASK) as usize;
                let code = MIRROR - (e >> INDEX_BITS);
                self.upper_entries[fill[j] as usize] = i as u32 | code << INDEX_BITS;
                fill[j] += 1;
            }
        }
    }

    /// Whether the upper part is built for the current list.
    pub fn has_upper(&self) -> bool {
        self.upper_start.len() == self.start.len()
    }

    /// The entries of particle i: its neighbours of lower index (each pair once).
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.entries[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The neighbours of higher index of particle i (empty until
    /// [`Self::build_upper`]).
    #[inline]
    pub fn upper(&self, i: usize) -> &[u32] {
        match self.upper_start.get(i + 1) {
            Some(&end) => &self.upper_entries[self.upper_start[i] as usize..end as usize],
            None => &[],
        }
    }

    /// Every neighbour of particle i, those of lower index first (the upper part must
    /// be built).
    #[inline]
    pub fn neighbours(&self, i: usize) -> impl Iterator<Item = u32> + '_ {
        debug_assert!(self.has_upper(), "the upper part is not built");
        self.of(i).iter().chain(self.upper(i)).copied()
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

    /// The list of `x` (wrapped into `b`) as MD builds it (with cells of about
    /// `per_cell` particles), with its upper part, and the order it sorted them in.
    fn sorted_list(
        x: &[[f64; 3]],
        r: &[f64],
        b: &SimBox,
        (min_cell, per_cell): (f64, f64),
        skin: f64,
    ) -> (NeighbourList, Vec<u32>) {
        let mut list = NeighbourList::default();
        let order = list.sort_order(x, Some(b), min_cell, per_cell).unwrap();
        let xs: Vec<[f64; 3]> = order.iter().map(|&k| x[k as usize]).collect();
        let rs: Vec<f64> = order.iter().map(|&k| r[k as usize]).collect();
        list.build_half(&xs, &rs, skin);
        list.build_upper();
        (list, order)
    }

    #[test]
    fn the_list_and_its_upper_part_hold_exactly_the_close_pairs_of_a_brute_force_search() {
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

            let (list, order) = sorted_list(&x, &r, &b, (min_cell, 2.0), skin);
            let xs: Vec<[f64; 3]> = order.iter().map(|&k| x[k as usize]).collect();
            let (mut lower, mut upper) = (Vec::new(), Vec::new());
            for i in 0..xs.len() {
                for (e, below) in list.neighbours(i).map(|e| (e, list.of(i).contains(&e))) {
                    let (j, s) = list.split(e);
                    // The image named is the close one, seen from either side.
                    assert!(within(
                        xs[i],
                        xs[j],
                        s,
                        r[order[i] as usize] + r[order[j] as usize] + skin
                    ));
                    assert_eq!(below, j < i, "{i} {j}");
                    let (a, b) = (order[i] as usize, order[j] as usize);
                    if below { &mut lower } else { &mut upper }.push((a.min(b), a.max(b)));
                }
            }
            lower.sort_unstable();
            upper.sort_unstable();
            assert_eq!(
                lower, want,
                "each pair under its higher index, periodic {periodic:?}"
            );
            assert_eq!(
                upper, want,
                "each pair under its lower index, periodic {periodic:?}"
            );
        }
    }

    #[test]
    fn a_sheared_list_holds_exactly_the_pairs_close_through_the_sliding_images() {
        // γ̇ L_y t = 2.6 m at t = 1.3 s in a 4 m box: the images above and below are slid
        // by ±2.6 m (−1.4 m centred). Every pair closer than the cut-off through its
        // Lees–Edwards image (brute force over all pairs), and the image named is it.
        let b = SimBox {
            lo: [0.0; 3],
            size: [4.0; 3],
            periodic: [true; 3],
        };
        let le = LeesEdwards::new(&b, 0.5);
        let t = 1.3;
        let x = cloud(1000, 4.0, 11);
        let r: Vec<f64> = (0..x.len()).map(|i| 0.1 + 0.02 * (i % 3) as f64).collect();
        let skin = 0.1;
        let mut want = Vec::new();
        for i in 0..x.len() {
            for j in 0..i {
                let d = std::array::from_fn(|k| x[i][k] - x[j][k]);
                let (d, _) = le.image(d, t);
                let cut = r[i] + r[j] + skin;
                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                    want.push((j, i));
                }
            }
        }
        let mut list = NeighbourList::default();
        let order = list
            .sort_order(&x, Some(&b), 2.0 * 0.14 + skin, 2.0)
            .unwrap();
        let xs: Vec<[f64; 3]> = order.iter().map(|&k| x[k as usize]).collect();
        let rs: Vec<f64> = order.iter().map(|&k| r[k as usize]).collect();
        list.build_half_sheared(&xs, &rs, skin, Some((&le, t)));
        let mut got = Vec::new();
        let mut across = 0;
        for i in 0..xs.len() {
            for &e in list.of(i) {
                let (j, s) = list.split(e);
                assert!(
                    within(xs[i], xs[j], s, rs[i] + rs[j] + skin),
                    "{i} {j} {s:?}"
                );
                if list.image_vx(e) != 0.0 {
                    across += 1;
                    assert_eq!(list.image_vx(e), s[1].signum() * 2.0, "{s:?}");
                }
                let (a, b) = (order[i] as usize, order[j] as usize);
                got.push((a.min(b), a.max(b)));
            }
        }
        got.sort_unstable();
        want.sort_unstable();
        assert!(across > 10, "{across} pairs across the sliding face");
        assert_eq!(got, want);
        // Slid on by 0.1 s the images move 0.2 m along x, continuously.
        let before = list.shifts[16][0];
        list.slide(&le, t + 0.1);
        assert!((list.shifts[16][0] - before - 0.2).abs() < 1e-12);
    }

    #[test]
    fn the_upper_part_names_the_image_across_a_periodic_face_from_the_other_side() {
        let b = SimBox {
            lo: [0.0; 3],
            size: [3.0, 3.0, 3.0],
            periodic: [true; 3],
        };
        let x = [[0.05, 1.5, 1.5], [2.95, 1.5, 1.5], [1.5, 1.5, 1.5]];
        let (list, order) = sorted_list(&x, &[0.1; 3], &b, (1.0, 2.0), 0.05);
        let at = |id: u32| order.iter().position(|&k| k == id).unwrap();
        let (p0, p1) = (at(0), at(1));
        let from = |i: usize| -> Vec<(usize, [f64; 3])> {
            list.neighbours(i).map(|e| list.split(e)).collect()
        };
        assert_eq!(from(p0), vec![(p1, [-3.0, 0.0, 0.0])]);
        assert_eq!(from(p1), vec![(p0, [3.0, 0.0, 0.0])]);
        assert!(from(at(2)).is_empty());
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
        // Cells as narrow as allowed (the budget, not the particles per cell, bounds them).
        let (list, order) = sorted_list(&x, &r, &b, (1.0, 1e-30), 0.05);
        let g = &list.grid;
        assert!(g.dims[0] == 3 && g.dims[2] == 3, "{:?}", g.dims);
        assert!(g.len() as f64 <= sparse_cell_limit(x.len()), "{:?}", g.dims);
        let mut got: Vec<(usize, usize)> = (0..x.len())
            .flat_map(|i| list.of(i).iter().map(move |&e| (i, e)))
            .map(|(i, e)| {
                let (a, b) = (order[i] as usize, order[list.split(e).0] as usize);
                (a.min(b), a.max(b))
            })
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
        list.sort_order(&[[971.0, 1.0, 1.0]], Some(&b), 1e-61, 1e-30)
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
            .sort_order(&[[1.0; 3]], Some(&b), 1.0, 2.0)
            .unwrap_err();
        assert!(
            matches!(err, MdError::BoxTooSmall { axis: "x", .. }),
            "{err}"
        );
    }
}
