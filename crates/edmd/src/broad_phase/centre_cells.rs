//! The shell centres of the neighbour-list broad phase, filed in cells at least the list
//! range wide. Centres move only when a list is rebuilt, so each cell keeps its
//! members in a short array (index and centre side by side) rather than a linked
//! list: a rebuild reads the 27 cells around a centre as nine runs of memory.

use crate::cells::{CellShape, LinkedCells, NONE};

/// A filed centre.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Member {
    pub centre: [f64; 3],
    pub index: u32,
}

/// Cells of shell centres (see the module documentation).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct CentreCells {
    /// The grid's geometry and neighbour stencils (its linked lists stay empty).
    grid: LinkedCells,
    /// Capacity of each cell; `members[c * cap..][..len[c]]` holds cell c's centres.
    cap: usize,
    len: Vec<u32>,
    members: Vec<Member>,
    /// Each particle's cell index and place in it.
    cell: Vec<u32>,
    place: Vec<u32>,
    /// Each particle's cell coordinates.
    pub coords: Vec<[u32; 3]>,
}

impl CentreCells {
    /// Cells at least `width` wide over `region` for `n` particles, all unfiled; at
    /// most about two per particle, so that a sparse gas does not fill memory with
    /// empty cells (wider cells only add candidates: the range test decides).
    pub fn new(region: &emdstar_system::SimBox, width: f64, n: usize) -> Self {
        let limit = (2 * n).max(27) as f64;
        let width = emdstar_system::bounded_cell_width(region.size, width, limit);
        // Cells of `width` exactly: the grid holds no particles itself, and widening
        // its cells for a sparse gas of none (as `LinkedCells::new` would) would put
        // several times the centres needed into every rebuild's scan.
        let shape = CellShape::new(region.lo, region.size, region.periodic, width);
        let grid = LinkedCells::from_shape(shape, 0);
        let cells: usize = grid.shape.dims.iter().product();
        let cap = 2 * n.div_ceil(cells.max(1)) + 4;
        Self {
            grid,
            cap,
            len: vec![0; cells],
            members: vec![Member::default(); cells * cap],
            cell: vec![NONE; n],
            place: vec![0; n],
            coords: vec![[0; 3]; n],
        }
    }

    /// Errors unless a decoded set has the grid of `built` (the same config's) and
    /// holds particles `0..n` consistently: every member is the particle filed at its
    /// place, and every filed particle a member of the cell of its coordinates.
    pub fn check_restored(&self, built: &Self, n: usize) -> Result<(), String> {
        if !crate::state::same_encoding(&self.grid.shape, &built.grid.shape) {
            return Err("another grid of shell centres than the config's".into());
        }
        self.grid.check_restored(0, false)?;
        let cells = self.len.len();
        let sized = cells == built.len.len()
            && self.cap > 0
            && cells.checked_mul(self.cap) == Some(self.members.len())
            && [self.cell.len(), self.place.len(), self.coords.len()] == [n; 3];
        if !sized {
            return Err("another grid of shell centres than the config's".into());
        }
        for (c, &l) in self.len.iter().enumerate() {
            let Some(members) = self.members[c * self.cap..].get(..l as usize) else {
                return Err(format!("centre cell {c} holds more than it has room for"));
            };
            for (at, m) in members.iter().enumerate() {
                let i = m.index as usize;
                if i >= n || self.cell[i] as usize != c || self.place[i] as usize != at {
                    return Err(format!("centre cell {c} holds particle {i} inconsistently"));
                }
            }
        }
        let dims = self.grid.shape.dims;
        for i in 0..n {
            let c = self.coords[i];
            let filed = self.cell[i] == NONE
                || (0..3).all(|k| (c[k] as usize) < dims[k])
                    && self.index(c) == self.cell[i] as usize
                    && self.place[i] < self.len[self.cell[i] as usize];
            if !filed {
                return Err(format!(
                    "particle {i}'s shell centre is filed inconsistently"
                ));
            }
        }
        Ok(())
    }

    fn index(&self, c: [u32; 3]) -> usize {
        let d = self.grid.shape.dims;
        c[0] as usize + d[0] * (c[1] as usize + d[1] * c[2] as usize)
    }

    /// Files particle `i` (unfiled) with its centre `x`.
    pub fn insert(&mut self, i: usize, x: [f64; 3]) {
        let c = self.grid.coords_of(x);
        let cell = self.index(c);
        if self.len[cell] as usize == self.cap {
            self.grow();
        }
        let at = self.len[cell] as usize;
        self.members[cell * self.cap + at] = Member {
            centre: x,
            index: i as u32,
        };
        self.len[cell] += 1;
        self.cell[i] = cell as u32;
        self.place[i] = at as u32;
        self.coords[i] = c;
    }

    /// Takes particle `i` out of its cell.
    pub fn remove(&mut self, i: usize) {
        let cell = self.cell[i] as usize;
        let last = self.len[cell] as usize - 1;
        let at = self.place[i] as usize;
        let moved = self.members[cell * self.cap + last];
        self.members[cell * self.cap + at] = moved;
        self.place[moved.index as usize] = at as u32;
        self.len[cell] -= 1;
        self.cell[i] = NONE;
    }

    /// Doubles the capacity of every cell (a crowded cell).
    #[cold]
    fn grow(&mut self) {
        let (old, new) = (self.cap, 2 * self.cap);
        let mut members = vec![Member::default(); self.len.len() * new];
        for (c, &l) in self.len.iter().enumerate() {
            members[c * new..][..l as usize]
                .copy_from_slice(&self.members[c * old..][..l as usize]);
        }
        self.members = members;
        self.cap = new;
    }

    /// The members of the cells around particle `i`'s cell, each cell with the image
    /// code (see `neighbours::image_code`) and shift of its periodic image, to `visit`.
    #[inline(always)]
    pub fn around(&self, i: usize, mut visit: impl FnMut(&[Member], u32, [f64; 3])) {
        let c = self.coords[i];
        if let Some(base) = self.grid.interior(c) {
            for cell in self.grid.interior_neighbours(base) {
                visit(
                    self.members_of(cell as usize),
                    super::neighbours::NO_SHIFT,
                    [0.0; 3],
                );
            }
        } else {
            for (cell, shift) in self.grid.neighbourhood(c).iter() {
                let image = shift.map(|s| (s > 0.0) as i8 - (s < 0.0) as i8);
                let code = super::neighbours::image_code(image);
                visit(self.members_of(cell as usize), code, shift);
            }
        }
    }

    #[inline(always)]
    fn members_of(&self, cell: usize) -> &[Member] {
        &self.members[cell * self.cap..cell * self.cap + self.len[cell] as usize]
    }

    /// Renumbers the particles: new number k is old number `order[k]`.
    pub fn renumber(&mut self, order: &[u32], new_index: &[u32]) {
        for (c, &l) in self.len.iter().enumerate() {
            for m in &mut self.members[c * self.cap..][..l as usize] {
                m.index = new_index[m.index as usize];
            }
        }
        let mut scratch = Vec::new();
        crate::state::permute(&mut self.cell, order, &mut scratch);
        crate::state::permute(&mut self.place, order, &mut scratch);
        let mut c = Vec::new();
        crate::state::permute(&mut self.coords, order, &mut c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_as_narrow_as_the_list_range_allows() {
        // 32 000 spheres at η = 0.45 fill a cube 33.4 diameters wide: 22 cells of the
        // range 1.5 per axis, not the 16 of a grid widened as if it held no particles.
        let region = emdstar_system::SimBox {
            lo: [0.0; 3],
            size: [33.4; 3],
            periodic: [true; 3],
        };
        let cells = CentreCells::new(&region, 1.5, 32_000);
        assert_eq!(cells.grid.shape.dims, [22; 3]);
        let wide = CentreCells::new(&region, 1.5, 10);
        assert!(
            wide.grid.shape.dims.iter().all(|&d| d < 22),
            "a sparse gas widens them"
        );
    }
}
