//! A cell grid for neighbour searches: particles binned into cuboid cells.

/// Which neighbour cells [`CellGrid::for_each_neighbour`] visits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stencil {
    /// All 27 (fewer if the grid is small).
    Full,
    /// The cell and the 13 cells "after" it (dz > 0, or dz = 0 and dy > 0, or ...).
    Forward,
    /// The cell and the mirror images of the forward cells.
    Backward,
}

/// The width of cells for a grid of `n` particles over `extent`: `min_width`, widened
/// only where the particles are few and far apart (beyond 64 cells per particle plus
/// 4096, e.g. in free space), where a cell per contact size would take memory and
/// time without bound (binning visits every cell). Wider cells only add candidates.
/// Every engine's grid over user positions uses this bound.
pub fn sparse_cell_width(extent: [f64; 3], min_width: f64, n: usize) -> f64 {
    bounded_cell_width(extent, min_width, sparse_cell_limit(n))
}

/// The most cells a grid of `n` particles may have before [`sparse_cell_width`] widens
/// them: 64 per particle plus 4096.
pub fn sparse_cell_limit(n: usize) -> f64 {
    64.0 * n as f64 + 4096.0
}

/// The width of cells, at least `min_width`, with which a grid over `extent` has at
/// most `limit` cells: where particles are few and far apart the cells widen (a cell of
/// the contact size each would take memory without bound).
pub fn bounded_cell_width(extent: [f64; 3], min_width: f64, limit: f64) -> f64 {
    let mut width = min_width;
    for _ in 0..64 {
        let dims: [f64; 3] = std::array::from_fn(|k| {
            let n = (extent[k] / width).floor();
            if n.is_finite() { n.max(1.0) } else { f64::MAX }
        });
        let total = dims[0] * dims[1] * dims[2];
        if total <= limit {
            return width;
        }
        // Widen the cells of the axes that have more than one, so that their count
        // falls to the limit (floors and axes dropping to one cell only lower it).
        let split = dims.iter().filter(|&&n| n > 1.0).count().max(1) as f64;
        width *= (total / limit).powf(1.0 / split).min(1e300) * (1.0 + 1e-12);
    }
    f64::INFINITY
}

/// Particles binned into cuboid cells by a counting sort.
///
/// Along periodic axes the grid covers the box exactly and wraps; along closed axes it
/// covers the given extent and positions beyond it fall into the border cells.
///
/// Saved states hold the geometry and each particle's cell only ([`SavedGrid`]): the
/// per-cell index is rebuilt on loading, so a sparse grid costs a state no more than
/// its particles do.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
#[serde(into = "SavedGrid", try_from = "SavedGrid")]
pub struct CellGrid {
    pub lo: [f64; 3],
    pub dims: [usize; 3],
    pub cell_size: [f64; 3],
    pub periodic: [bool; 3],
    /// `cell_items[cell_start[c]..cell_start[c + 1]]` are the particles of cell c.
    pub cell_start: Vec<u32>,
    pub cell_items: Vec<u32>,
    cell_of: Vec<u32>,
}

/// Cells along each axis of `extent`, each at least `min_width` wide: at least one and at
/// most `cap` per axis (the rule of every cell grid of the workspace).
pub fn cells_per_axis(extent: [f64; 3], min_width: f64, cap: usize) -> [usize; 3] {
    std::array::from_fn(|k| {
        let n = (extent[k] / min_width).floor();
        if n.is_finite() && n >= 1.0 {
            (n as usize).min(cap)
        } else {
            1
        }
    })
}

/// The cell along one axis of a coordinate `x` in a grid of `dims` cells of `width` from
/// `lo`: below the grid it wraps to the top cell on a periodic axis and stays in the
/// first cell on a closed one; above it stays in the top cell.
#[inline]
pub fn cell_along(x: f64, lo: f64, width: f64, dims: usize, periodic: bool) -> usize {
    let c = ((x - lo) / width).floor();
    if c < 0.0 {
        if periodic { dims - 1 } else { 0 }
    } else {
        (c as usize).min(dims - 1)
    }
}

impl CellGrid {
    /// The grid of `n` particles over `extent` with cells at least `cell` wide, widened
    /// where the particles are few and far apart ([`sparse_cell_width`]), and with at least
    /// 3 cells along every periodic axis (the stencil must not meet a cell twice; the
    /// caller checks that cells of `cell` leave room for 3). Where widening would leave a
    /// periodic axis fewer, that axis gets 3 cells and the other axes share a third of the
    /// cell budget per such axis, so the grid stays within it.
    pub fn sparse(
        lo: [f64; 3],
        extent: [f64; 3],
        periodic: [bool; 3],
        cell: f64,
        n: usize,
    ) -> Self {
        let mut three = [false; 3];
        loop {
            let width = if three == [false; 3] {
                sparse_cell_width(extent, cell, n)
            } else {
                let rest = std::array::from_fn(|k| if three[k] { 0.0 } else { extent[k] });
                let forced = three.iter().filter(|&&t| t).count() as i32;
                bounded_cell_width(rest, cell, sparse_cell_limit(n) / 3f64.powi(forced))
            };
            let mut grid = Self::new(lo, extent, periodic, width);
            let short: Vec<usize> = (0..3)
                .filter(|&k| periodic[k] && !three[k] && grid.dims[k] < 3)
                .collect();
            if short.is_empty() {
                for k in (0..3).filter(|&k| three[k]) {
                    grid.dims[k] = 3;
                    grid.cell_size[k] = extent[k] / 3.0;
                }
                return grid;
            }
            for k in short {
                three[k] = true;
            }
        }
    }

    /// An empty grid over `[lo, lo + extent]` with cells at least `min_cell` wide.
    pub fn new(lo: [f64; 3], extent: [f64; 3], periodic: [bool; 3], min_cell: f64) -> Self {
        let dims = cells_per_axis(extent, min_cell, 1 << 20);
        let cell_size = std::array::from_fn(|k| extent[k] / dims[k] as f64);
        Self {
            lo,
            dims,
            cell_size,
            periodic,
            ..Default::default()
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// True if the grid has no cells (never, after [`CellGrid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Integer cell coordinates of a position.
    #[inline]
    pub fn coords(&self, p: [f64; 3]) -> [usize; 3] {
        std::array::from_fn(|k| {
            cell_along(
                p[k],
                self.lo[k],
                self.cell_size[k],
                self.dims[k],
                self.periodic[k],
            )
        })
    }

    /// Linear index of cell coordinates (x fastest).
    #[inline]
    pub fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    /// Bins `positions` (reusing the buffers).
    pub fn bin(&mut self, positions: &[[f64; 3]]) {
        self.cell_of.clear();
        for &p in positions {
            let c = self.index(self.coords(p)) as u32;
            self.cell_of.push(c);
        }
        self.index_cells();
    }

    /// Builds `cell_start` and `cell_items` from `cell_of` by a counting sort, each
    /// cell's particles in increasing index.
    fn index_cells(&mut self) {
        let n_cells = self.len();
        self.cell_start.clear();
        self.cell_start.resize(n_cells + 1, 0);
        for &c in &self.cell_of {
            self.cell_start[c as usize] += 1;
        }
        // Cell c's count becomes its end ...
        for c in 1..n_cells {
            self.cell_start[c] += self.cell_start[c - 1];
        }
        self.cell_start[n_cells] = self.cell_of.len() as u32;
        // ... and, filled from the last particle down, its start.
        self.cell_items.clear();
        self.cell_items.resize(self.cell_of.len(), 0);
        for (i, &c) in self.cell_of.iter().enumerate().rev() {
            self.cell_start[c as usize] -= 1;
            self.cell_items[self.cell_start[c as usize] as usize] = i as u32;
        }
    }

    /// The particles of cell `c`.
    #[inline]
    pub fn items(&self, c: usize) -> &[u32] {
        &self.cell_items[self.cell_start[c] as usize..self.cell_start[c + 1] as usize]
    }

    /// Calls `f(cell, shift)` for the cells next to `c` (`c` itself included), where the
    /// neighbour's particles appear at x + shift·size (periodic images). With
    /// [`Stencil::Forward`] or [`Stencil::Backward`] only `c` and 13 cells of one half
    /// of the stencil are visited, so that every pair of distinct cells is visited once;
    /// that needs at least 3 cells along every periodic axis. With [`Stencil::Full`], all
    /// distinct neighbour cells are visited once.
    pub fn for_each_neighbour(
        &self,
        c: [usize; 3],
        stencil: Stencil,
        mut f: impl FnMut(usize, [i8; 3]),
    ) {
        let half = stencil != Stencil::Full;
        let sign = if stencil == Stencil::Backward { -1 } else { 1 };
        // Duplicates only arise along periodic axes with fewer than 3 cells.
        let dedup = !half && (0..3).any(|k| self.periodic[k] && self.dims[k] < 3);
        let mut seen = [usize::MAX; 27];
        let mut n_seen = 0;
        for dz in -1i64..=1 {
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    if half && (dz < 0 || (dz == 0 && (dy < 0 || (dy == 0 && dx < 0)))) {
                        continue;
                    }
                    let d = [sign * dx, sign * dy, sign * dz];
                    let mut cc = [0usize; 3];
                    let mut shift = [0i8; 3];
                    let mut valid = true;
                    for k in 0..3 {
                        let n = self.dims[k] as i64;
                        let mut x = c[k] as i64 + d[k];
                        if x < 0 || x >= n {
                            if !self.periodic[k] {
                                valid = false;
                                break;
                            }
                            shift[k] = if x < 0 { -1 } else { 1 };
                            x = x.rem_euclid(n);
                        }
                        cc[k] = x as usize;
                    }
                    if !valid {
                        continue;
                    }
                    let idx = self.index(cc);
                    if dedup {
                        if seen[..n_seen].contains(&idx) {
                            continue;
                        }
                        seen[n_seen] = idx;
                        n_seen += 1;
                    }
                    f(idx, shift);
                }
            }
        }
    }
}

/// What a saved state holds of a [`CellGrid`]: its geometry and each particle's cell.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct SavedGrid {
    lo: [f64; 3],
    dims: [usize; 3],
    cell_size: [f64; 3],
    periodic: [bool; 3],
    cell_of: Vec<u32>,
}

impl From<CellGrid> for SavedGrid {
    fn from(g: CellGrid) -> Self {
        Self {
            lo: g.lo,
            dims: g.dims,
            cell_size: g.cell_size,
            periodic: g.periodic,
            cell_of: g.cell_of,
        }
    }
}

impl TryFrom<SavedGrid> for CellGrid {
    type Error = String;

    /// Refuses a grid larger than the sparse bound of its particles (no grid the
    /// engines build is) or a particle in a cell the grid does not have.
    fn try_from(s: SavedGrid) -> Result<Self, String> {
        let cells = s.dims.iter().try_fold(1usize, |acc, &d| acc.checked_mul(d));
        let fits = cells.is_some_and(|c| c as f64 <= sparse_cell_limit(s.cell_of.len()));
        if !fits {
            return Err(format!(
                "a cell grid of {:?} cells is larger than its particles need",
                s.dims
            ));
        }
        let cells = cells.unwrap_or(0);
        if s.cell_of.iter().any(|&c| c as usize >= cells) {
            return Err(format!(
                "a particle lies outside its cell grid of {cells} cells"
            ));
        }
        let mut grid = Self {
            lo: s.lo,
            dims: s.dims,
            cell_size: s.cell_size,
            periodic: s.periodic,
            cell_of: s.cell_of,
            ..Default::default()
        };
        if cells > 0 {
            grid.index_cells();
        }
        Ok(grid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Positions scattered over a 5 × 4 × 3 grid of unit cells, several per cell.
    fn binned_grid() -> (CellGrid, Vec<[f64; 3]>) {
        let positions: Vec<[f64; 3]> = (0..40)
            .map(|i| {
                let f = f64::from(i);
                [(f * 0.37) % 5.0, (f * 0.61) % 4.0, (f * 0.23) % 3.0]
            })
            .collect();
        let mut g = CellGrid::new([0.0; 3], [5.0, 4.0, 3.0], [true, false, true], 1.0);
        g.bin(&positions);
        (g, positions)
    }

    #[test]
    fn binning_lists_each_cells_particles_in_increasing_index() {
        let (g, positions) = binned_grid();
        for c in 0..g.len() {
            let expected: Vec<u32> = (0..positions.len() as u32)
                .filter(|&i| g.index(g.coords(positions[i as usize])) == c)
                .collect();
            assert_eq!(g.items(c), expected.as_slice(), "cell {c}");
        }
    }

    #[test]
    fn a_saved_grid_loads_with_the_same_cells() {
        let (g, _) = binned_grid();
        let bytes = postcard::to_allocvec(&g).unwrap();
        let back: CellGrid = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(back.cell_start, g.cell_start);
        assert_eq!(back.cell_items, g.cell_items);
        assert_eq!(
            (back.dims, back.lo, back.cell_size),
            (g.dims, g.lo, g.cell_size)
        );
        // The saved form holds no per-cell index: 40 particles, 60 cells.
        assert!(bytes.len() < 4 * 40 + 100, "{} bytes", bytes.len());
    }

    #[test]
    fn a_saved_grid_too_large_or_with_a_stray_cell_is_refused() {
        let (g, _) = binned_grid();
        let mut huge = SavedGrid::from(g.clone());
        huge.dims = [1 << 20, 1 << 20, 1 << 20];
        let err = CellGrid::try_from(huge).unwrap_err();
        assert!(err.contains("larger than its particles need"), "{err}");
        let mut stray = SavedGrid::from(g);
        stray.cell_of[3] = 60;
        let err = CellGrid::try_from(stray).unwrap_err();
        assert!(err.contains("outside its cell grid"), "{err}");
    }

    #[test]
    fn half_stencil_visits_each_cell_pair_once() {
        let g = CellGrid::new([0.0; 3], [4.0, 3.0, 5.0], [true, true, false], 1.0);
        let mut count = std::collections::HashMap::new();
        for z in 0..5 {
            for y in 0..3 {
                for x in 0..4 {
                    let a = g.index([x, y, z]);
                    g.for_each_neighbour([x, y, z], Stencil::Forward, |b, _| {
                        *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                    });
                }
            }
        }
        assert!(count.values().all(|&n| n == 1));
        let mut backward = std::collections::HashMap::new();
        for z in 0..5 {
            for y in 0..3 {
                for x in 0..4 {
                    let a = g.index([x, y, z]);
                    g.for_each_neighbour([x, y, z], Stencil::Backward, |b, _| {
                        *backward.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                    });
                }
            }
        }
        assert_eq!(backward, count);
        // Every full-stencil neighbour pair appears.
        let mut full = 0;
        for z in 0..5 {
            for y in 0..3 {
                for x in 0..4 {
                    let a = g.index([x, y, z]);
                    g.for_each_neighbour([x, y, z], Stencil::Full, |b, _| {
                        assert!(count.contains_key(&(a.min(b), a.max(b))));
                        full += 1;
                    });
                }
            }
        }
        assert!(full > count.len());
    }
}
