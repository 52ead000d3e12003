//! A cell grid with linked lists for the event engine: each particle lives in exactly
//! one cell and leaves it through a cell-crossing event (Alder & Wainwright 1959;
//! Rapaport 1980). Cells are at least as wide as the largest contact distance, so
//! colliding pairs are always in neighbouring cells.
//!
//! Along periodic axes the grid covers the box exactly and wraps. Along closed axes it
//! covers the given extent and the two border cells reach to ±∞, so nothing is ever
//! lost if a particle leaves the region.

use crate::detect::time_to_face;
use emdstar_system::cell_along;

mod check;

/// Sentinel for "no particle".
pub const NONE: u32 = u32::MAX;

/// The cell coordinates of a particle filed in no cell (see [`LinkedCells::take_out`]).
pub const OUTSIDE: [u32; 3] = [NONE; 3];

/// The automatic cell width for `n` particles in `volume` whose largest contact
/// distance is `max_contact`: at least that, and about half the mean spacing
/// (V/N)^(1/3) in a dilute gas, where a few more pair tests buy far fewer crossings
/// (measured optimum for η = 0.001 to 0.1).
pub fn auto_cell_width(max_contact: f64, volume: f64, n: usize) -> f64 {
    let spacing = (volume / n.max(1) as f64).cbrt();
    max_contact.max(0.55 * spacing)
}

/// Cells per axis of a grid over `size` with cells at least `min_width` wide: at least
/// one, at most 1024 (Morton keys and spans use 10 bits per axis).
pub fn cells_per_axis(size: [f64; 3], min_width: f64) -> [usize; 3] {
    emdstar_system::cells_per_axis(size, min_width, 1 << 10)
}

/// The geometry of a cell grid: cuboid cells over `[lo, lo + size]`, periodic or
/// closed along each axis.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CellShape {
    pub lo: [f64; 3],
    pub size: [f64; 3],
    pub periodic: [bool; 3],
    pub dims: [usize; 3],
    pub width: [f64; 3],
}

impl CellShape {
    /// Cells at least `min_width` wide over `[lo, lo + size]` (see [`cells_per_axis`]).
    pub fn new(lo: [f64; 3], size: [f64; 3], periodic: [bool; 3], min_width: f64) -> Self {
        let dims = cells_per_axis(size, min_width);
        let width = std::array::from_fn(|k| size[k] / dims[k] as f64);
        Self {
            lo,
            size,
            periodic,
            dims,
            width,
        }
    }

    /// Cell coordinates of a position (closed axes clamp to the border cells).
    #[inline]
    pub fn coords_of(&self, p: [f64; 3]) -> [u32; 3] {
        std::array::from_fn(|k| {
            cell_along(
                p[k],
                self.lo[k],
                self.width[k],
                self.dims[k],
                self.periodic[k],
            ) as u32
        })
    }
}

/// A cell grid with a linked list of particles per cell: O(1) insertion, removal and
/// moves, for particles that change cell one event at a time. (The static grids of
/// neighbour lists bin all particles at once instead: `emdstar_system::CellGrid`.)
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct LinkedCells {
    pub shape: CellShape,
    head: Vec<u32>,
    /// Index offsets of the 27 neighbours of an interior cell, and of the 9 cells of
    /// the new layer for each face (axis·2 + 1 if moving up).
    offsets: [isize; 27],
    layers: [[isize; 9]; 6],
    /// Per axis and coordinate c: the coordinates at c − 1, c, c + 1 (wrapped, NONE
    /// beyond a closed axis) and the image shift of each in units of the box size.
    pub(crate) around: [Vec<[(u32, i8); 3]>; 3],
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Cell coordinates of each particle.
    pub coords: Vec<[u32; 3]>,
}

/// Up to `N` neighbour cells (27 for a neighbourhood, 9 for a new layer), each with the
/// shift that brings its particles next to the centre cell (±size along a periodic
/// axis where the stencil wraps). A cell may appear more than once with different
/// shifts when an axis has fewer than three cells: every periodic image within reach
/// is then visited.
#[derive(Debug, Clone, Copy)]
pub struct CellSet<const N: usize = 27> {
    cells: [u32; N],
    shifts: [[f64; 3]; N],
    len: usize,
}

/// The up to 9 cells that become neighbours when a particle enters a cell (see
/// [`LinkedCells::new_layer`]).
pub type Layer = CellSet<9>;

impl<const N: usize> CellSet<N> {
    #[inline]
    pub fn as_slice(&self) -> &[u32] {
        &self.cells[..self.len]
    }

    /// Number of cells.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True without cells (a layer beyond a closed axis).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// (cell, shift) pairs.
    #[inline]
    pub fn iter(&self) -> impl Iterator<Item = (u32, [f64; 3])> + Clone + '_ {
        self.cells[..self.len]
            .iter()
            .copied()
            .zip(self.shifts[..self.len].iter().copied())
    }
}

impl LinkedCells {
    /// A grid over `[lo, lo + size]` with cells at least `min_width` wide, for `n`
    /// particles (all outside any cell until [`LinkedCells::insert`]).
    pub fn new(
        lo: [f64; 3],
        size: [f64; 3],
        periodic: [bool; 3],
        min_width: f64,
        n: usize,
    ) -> Self {
        // Where particles are few and far apart the cells widen.
        let min_width = emdstar_system::sparse_cell_width(size, min_width, n);
        Self::from_shape(CellShape::new(lo, size, periodic, min_width), n)
    }

    /// The grid of `shape` for `n` particles, all outside any cell (`shape`'s cells
    /// as they are, not widened for a sparse gas).
    pub(crate) fn from_shape(shape: CellShape, n: usize) -> Self {
        let (dims, periodic) = (shape.dims, shape.periodic);
        let stride = [1, dims[0] as isize, (dims[0] * dims[1]) as isize];
        let offset = |d: [isize; 3]| d[0] * stride[0] + d[1] * stride[1] + d[2] * stride[2];
        let mut offsets = [0; 27];
        let mut layers = [[0; 9]; 6];
        let mut counts = [0; 6];
        let mut m = 0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let d = [dx, dy, dz];
                    offsets[m] = offset(d);
                    m += 1;
                    for (face, layer) in layers.iter_mut().enumerate() {
                        let dir = if face % 2 == 1 { 1 } else { -1 };
                        if d[face / 2] == dir {
                            layer[counts[face]] = offset(d);
                            counts[face] += 1;
                        }
                    }
                }
            }
        }
        let around = std::array::from_fn(|k| {
            let n = dims[k] as i64;
            (0..n)
                .map(|c| {
                    std::array::from_fn(|m| {
                        let x = c + m as i64 - 1;
                        let image = if x < 0 {
                            -1
                        } else if x >= n {
                            1
                        } else {
                            0
                        };
                        if image != 0 && !periodic[k] {
                            (NONE, 0)
                        } else {
                            (x.rem_euclid(n) as u32, image)
                        }
                    })
                })
                .collect()
        });
        Self {
            shape,
            head: vec![NONE; dims.iter().product()],
            offsets,
            layers,
            around,
            next: vec![NONE; n],
            prev: vec![NONE; n],
            coords: vec![[0; 3]; n],
        }
    }

    /// Cell coordinates of a position (closed axes clamp to the border cells).
    #[inline]
    pub fn coords_of(&self, p: [f64; 3]) -> [u32; 3] {
        self.shape.coords_of(p)
    }

    #[inline]
    fn index(&self, c: [u32; 3]) -> usize {
        c[0] as usize + self.shape.dims[0] * (c[1] as usize + self.shape.dims[1] * c[2] as usize)
    }

    /// Puts particle `i` into the cell with coordinates `c`.
    #[inline]
    pub fn insert(&mut self, i: usize, c: [u32; 3]) {
        let cell = self.index(c);
        let h = self.head[cell];
        self.next[i] = h;
        self.prev[i] = NONE;
        if h != NONE {
            self.prev[h as usize] = i as u32;
        }
        self.head[cell] = i as u32;
        self.coords[i] = c;
    }

    /// Renumbers the particles so that new number k is old number `order[k]`, and
    /// lists every cell in increasing number (particles filed in no cell stay so).
    pub fn renumber(&mut self, order: &[u32]) {
        let mut coords = Vec::new();
        crate::state::permute(&mut self.coords, order, &mut coords);
        self.head.iter_mut().for_each(|h| *h = NONE);
        for i in (0..self.coords.len()).rev() {
            let c = self.coords[i];
            if c != OUTSIDE {
                self.insert(i, c);
            }
        }
    }

    /// Takes particle `i` out of its cell and files it in none (coordinates
    /// [`OUTSIDE`]) until it is inserted again.
    pub fn take_out(&mut self, i: usize) {
        if self.is_filed(i) {
            self.remove(i);
        }
        self.next[i] = NONE;
        self.prev[i] = NONE;
        self.coords[i] = OUTSIDE;
    }

    /// Whether particle `i` is filed in a cell.
    #[inline]
    pub fn is_filed(&self, i: usize) -> bool {
        self.coords[i] != OUTSIDE
    }

    /// Takes particle `i` out of its cell.
    #[inline]
    pub fn remove(&mut self, i: usize) {
        let (p, n) = (self.prev[i], self.next[i]);
        if p == NONE {
            let cell = self.index(self.coords[i]);
            self.head[cell] = n;
        } else {
            self.next[p as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
    }

    /// Moves particle `i` to the cell with coordinates `c`.
    #[inline]
    pub fn relocate(&mut self, i: usize, c: [u32; 3]) {
        if self.coords[i] != c {
            self.remove(i);
            self.insert(i, c);
        }
    }

    /// Asks for the records of `i` that moving it to another cell reads.
    #[inline(always)]
    pub(crate) fn prefetch(&self, i: usize) {
        crate::state::prefetch(self.coords.as_ptr().wrapping_add(i));
        self.prefetch_next(i);
        crate::state::prefetch(self.prev.as_ptr().wrapping_add(i));
    }

    /// Asks for the link from `i` to the next particle of its cell.
    #[inline(always)]
    pub(crate) fn prefetch_next(&self, i: usize) {
        crate::state::prefetch(self.next.as_ptr().wrapping_add(i));
    }

    /// First particle of a cell (follow with [`LinkedCells::next`]).
    #[inline]
    pub fn first(&self, cell: u32) -> u32 {
        self.head[cell as usize]
    }

    /// The particle after `i` in its cell.
    #[inline]
    pub fn next(&self, i: u32) -> u32 {
        self.next[i as usize]
    }

    /// The particles of a cell, in list order.
    pub fn particles(&self, cell: u32) -> impl Iterator<Item = usize> + '_ {
        let first = Some(self.first(cell)).filter(|&i| i != NONE);
        std::iter::successors(first, |&i| Some(self.next(i)).filter(|&j| j != NONE))
            .map(|i| i as usize)
    }

    /// Neighbour coordinates along axis `k` of coordinate `c` at the offsets
    /// `offsets` (each −1, 0 or 1), with their image shifts, dropping those beyond a
    /// closed axis.
    #[inline]
    fn axis_neighbours(&self, k: usize, c: u32, offsets: &[i64]) -> ([(u32, i8); 3], usize) {
        let row = &self.around[k][c as usize];
        let mut out = [(0u32, 0i8); 3];
        let mut len = 0;
        for &d in offsets {
            let entry = row[(d + 1) as usize];
            if entry.0 != NONE {
                out[len] = entry;
                len += 1;
            }
        }
        (out, len)
    }

    fn product(&self, axes: [([(u32, i8); 3], usize); 3]) -> CellSet {
        let mut set = CellSet {
            cells: [0; 27],
            shifts: [[0.0; 3]; 27],
            len: 0,
        };
        let stride = [
            1,
            self.shape.dims[0],
            self.shape.dims[0] * self.shape.dims[1],
        ];
        let shift = |k: usize, image: i8| f64::from(image) * self.shape.size[k];
        for &(z, sz) in &axes[2].0[..axes[2].1] {
            for &(y, sy) in &axes[1].0[..axes[1].1] {
                let row = y as usize * stride[1] + z as usize * stride[2];
                for &(x, sx) in &axes[0].0[..axes[0].1] {
                    set.cells[set.len] = (row + x as usize) as u32;
                    set.shifts[set.len] = [shift(0, sx), shift(1, sy), shift(2, sz)];
                    set.len += 1;
                }
            }
        }
        set
    }

    /// The index of cell `c` if it is an interior cell, whose neighbours are distinct
    /// and need no periodic shift.
    #[inline]
    pub fn interior(&self, c: [u32; 3]) -> Option<usize> {
        (0..3)
            .all(|k| c[k] >= 1 && (c[k] as usize) + 2 <= self.shape.dims[k])
            .then(|| self.index(c))
    }

    /// The 27 neighbour cells of the interior cell with index `base` (see
    /// [`LinkedCells::interior`]).
    #[inline]
    pub fn interior_neighbours(&self, base: usize) -> impl Iterator<Item = u32> + Clone + '_ {
        self.offsets
            .iter()
            .map(move |&o| (base as isize + o) as u32)
    }

    /// The 9 cells of the new layer of the interior cell with index `base` entered
    /// through the face on `axis` moving in direction `dir` (as [`LinkedCells::new_layer`]).
    #[inline]
    pub fn interior_layer(
        &self,
        base: usize,
        axis: usize,
        dir: i64,
    ) -> impl Iterator<Item = u32> + Clone + '_ {
        let face = 2 * axis + usize::from(dir > 0);
        self.layers[face]
            .iter()
            .map(move |&o| (base as isize + o) as u32)
    }

    /// The cell with coordinates `c` and its neighbours.
    #[inline]
    pub fn neighbourhood(&self, c: [u32; 3]) -> CellSet {
        if (0..3).all(|k| c[k] >= 1 && (c[k] as usize) + 2 <= self.shape.dims[k]) {
            // Interior cell: 27 distinct cells, no wrapping.
            let base = self.index(c) as i64;
            let (nx, nxy) = (
                self.shape.dims[0] as i64,
                (self.shape.dims[0] * self.shape.dims[1]) as i64,
            );
            let mut set = CellSet {
                cells: [0; 27],
                shifts: [[0.0; 3]; 27],
                len: 27,
            };
            let mut m = 0;
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        set.cells[m] = (base + dx + dy * nx + dz * nxy) as u32;
                        m += 1;
                    }
                }
            }
            return set;
        }
        let all = [-1, 0, 1];
        self.product(std::array::from_fn(|k| self.axis_neighbours(k, c[k], &all)))
    }

    /// The cells (with shifts) that became neighbours when a particle entered cell `c`
    /// through its face on `axis` moving in direction `dir` (±1): the layer at offset
    /// `dir` along `axis`. Along a periodic axis with few cells this is a cell seen
    /// before, but through another periodic image. Empty beyond a closed axis.
    #[inline]
    pub fn new_layer(&self, c: [u32; 3], axis: usize, dir: i64) -> Layer {
        // Built directly from the per-axis rows (measured faster than the general
        // product for the 25 % of crossings that enter border cells).
        let mut layer = Layer {
            cells: [0; 9],
            shifts: [[0.0; 3]; 9],
            len: 0,
        };
        let rows: [&[(u32, i8); 3]; 3] = std::array::from_fn(|k| &self.around[k][c[k] as usize]);
        let span = |k: usize| {
            if k == axis {
                let m = (dir + 1) as usize;
                m..m + 1
            } else {
                0..3
            }
        };
        let shift = |k: usize, image: i8| f64::from(image) * self.shape.size[k];
        for &(z, sz) in &rows[2][span(2)] {
            if z == NONE {
                continue;
            }
            for &(y, sy) in &rows[1][span(1)] {
                if y == NONE {
                    continue;
                }
                let row = self.shape.dims[0] * (y as usize + self.shape.dims[1] * z as usize);
                for &(x, sx) in &rows[0][span(0)] {
                    if x == NONE {
                        continue;
                    }
                    layer.cells[layer.len] = (row + x as usize) as u32;
                    layer.shifts[layer.len] = [shift(0, sx), shift(1, sy), shift(2, sz)];
                    layer.len += 1;
                }
            }
        }
        layer
    }

    /// The faces bounding cell coordinate `c` along axis `k`: (low, high), with ±∞
    /// for the outer faces of the border cells of a closed axis.
    #[inline]
    pub fn faces(&self, k: usize, c: u32) -> (f64, f64) {
        let low = self.shape.lo[k] + c as f64 * self.shape.width[k];
        let high = self.shape.lo[k] + (c + 1) as f64 * self.shape.width[k];
        if self.shape.periodic[k] {
            return (low, high);
        }
        let low = if c == 0 { f64::NEG_INFINITY } else { low };
        let high = if c as usize + 1 == self.shape.dims[k] {
            f64::INFINITY
        } else {
            high
        };
        (low, high)
    }

    /// The next crossing of a face of cell coordinate `c` along axis `k` by a particle
    /// at `x` with velocity `v` under gravity `g` (all along that axis): (time from
    /// now, whether through the upper face). Border cells of closed axes reach to ±∞
    /// and have no outer face.
    #[inline]
    pub fn axis_crossing(&self, k: usize, c: u32, x: f64, v: f64, g: f64) -> (f64, bool) {
        let (low, high) = self.faces(k, c);
        if g == 0.0 {
            // Straight flight: only the face ahead can be crossed.
            let (target, up) = if v > 0.0 { (high, true) } else { (low, false) };
            if v == 0.0 || !target.is_finite() {
                return (f64::INFINITY, up);
            }
            return (((target - x) / v).max(0.0), up);
        }
        let t_high = if high.is_finite() {
            time_to_face(x - high, v, g, 1.0)
        } else {
            f64::INFINITY
        };
        let t_low = if low.is_finite() {
            time_to_face(x - low, v, g, -1.0)
        } else {
            f64::INFINITY
        };
        if t_low < t_high {
            (t_low, false)
        } else {
            (t_high, true)
        }
    }

    /// The next crossing of a face of cell `c` by a particle at `x` with velocity `v`
    /// under gravity `g`: (time from now, face = axis·2 + 1 if moving up), the
    /// earliest of [`LinkedCells::axis_crossing`] over the axes.
    #[inline]
    pub fn next_crossing(&self, c: [u32; 3], x: [f64; 3], v: [f64; 3], g: [f64; 3]) -> (f64, u8) {
        let mut best = f64::INFINITY;
        let mut face = 0u8;
        for k in 0..3 {
            let (t, up) = self.axis_crossing(k, c[k], x[k], v[k], g[k]);
            if t < best {
                best = t;
                face = (2 * k + usize::from(up)) as u8;
            }
        }
        (best, face)
    }

    /// The neighbouring coordinate along axis `k` in direction `dir`, and the shift of
    /// the position (±size along a periodic axis when wrapping, else 0).
    #[inline]
    pub fn step(&self, k: usize, c: u32, dir: i64) -> (u32, f64) {
        let n = self.shape.dims[k] as i64;
        let x = c as i64 + dir;
        if x < 0 {
            ((n - 1) as u32, self.shape.size[k])
        } else if x >= n {
            (0, -self.shape.size[k])
        } else {
            (x as u32, 0.0)
        }
    }
}

#[cfg(test)]
mod tests;
