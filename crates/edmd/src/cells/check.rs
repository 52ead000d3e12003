//! Whether a linked-cell grid decoded from a checkpoint is whole.

use super::{LinkedCells, NONE};

impl LinkedCells {
    /// Errors unless a decoded grid is whole: the stencils of its own shape, one entry
    /// per particle `0..n` with cell coordinates inside the grid (or, unless
    /// `all_filed`, [`super::OUTSIDE`] for a particle filed in no cell), and lists that
    /// hold each particle filed at most once (every particle if `all_filed`), in its
    /// cell. (Whether the shape is the config's is the caller's to check.)
    pub fn check_restored(&self, n: usize, all_filed: bool) -> Result<(), String> {
        let dims = self.shape.dims;
        let cells = dims
            .iter()
            .try_fold(1usize, |p, &d| p.checked_mul(d).filter(|_| d > 0));
        if cells != Some(self.head.len()) {
            return Err("a cell grid whose cell count does not match its shape".into());
        }
        let reference = Self::from_shape(self.shape, 0);
        let stencils = |g: &Self| (g.offsets, g.layers, g.around.clone());
        if !crate::state::same_encoding(&stencils(self), &stencils(&reference))
            || [self.next.len(), self.prev.len(), self.coords.len()] != [n; 3]
        {
            return Err("a cell grid with other stencils or particles than its shape's".into());
        }
        let outside = |c: &[u32; 3]| !all_filed && *c == super::OUTSIDE;
        if self
            .coords
            .iter()
            .any(|c| !outside(c) && (0..3).any(|k| c[k] as usize >= dims[k]))
        {
            return Err("a particle's cell lies outside the grid".into());
        }
        let mut filed = vec![false; n];
        for (cell, &head) in self.head.iter().enumerate() {
            let (mut i, mut prev) = (head, NONE);
            while i != NONE {
                let k = i as usize;
                if k >= n || filed[k] || self.prev[k] != prev || self.index(self.coords[k]) != cell
                {
                    return Err(format!("cell {cell} lists particle {i} inconsistently"));
                }
                filed[k] = true;
                (prev, i) = (i, self.next[k]);
            }
        }
        if (0..n).any(|k| filed[k] == outside(&self.coords[k])) {
            return Err("a particle is in no cell, or listed while filed in none".into());
        }
        Ok(())
    }
}
