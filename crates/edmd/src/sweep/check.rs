//! Whether an epoch grid decoded from a checkpoint fits the config's.

use super::{CELL_ROOM, Filing, Span, SweepGrid};
use crate::cells::NONE;

impl SweepGrid {
    /// Errors unless a decoded grid has the geometry of `built` (the same config's) and
    /// holds particles `0..n` only: boxes inside the grid, rooms and overflow that
    /// agree with the counts, mid-epoch lists that end.
    pub fn check_restored(&self, built: &Self, n: usize) -> Result<(), String> {
        let geometry = |g: &Self| {
            let sizes = [g.count.len(), g.filed.len(), g.extra_head.len()];
            (g.lo, g.periodic, g.dims, g.inv_width, sizes)
        };
        if !crate::state::same_encoding(&geometry(self), &geometry(built))
            || self.spans.len() != n
            || self.seen.len() != n
        {
            return Err("another epoch grid than the config's".into());
        }
        let ok_span = |s: &Span, k: usize| {
            s.first < self.dims[k]
                && (1..=self.dims[k]).contains(&s.count)
                && (self.periodic[k] || s.first + s.count <= self.dims[k])
        };
        let cells = self.extra_head.len();
        let mut beyond = vec![0u32; cells];
        let ok_overflow = self.overflow.is_sorted_by_key(|&[c, _]| c)
            && self.overflow.iter().all(|&[c, e]| {
                let inside = (c as usize) < cells && (Filing::particle(e) as usize) < n;
                if inside {
                    beyond[c as usize] += 1;
                }
                inside
            });
        let ok_cells = (0..cells).all(|c| {
            let k = self.count[c] as usize;
            beyond[c] as usize == k.saturating_sub(CELL_ROOM)
                && self.filed[c].0[..k.min(CELL_ROOM)]
                    .iter()
                    .all(|&e| (Filing::particle(e) as usize) < n)
        });
        // A mid-epoch node links to one filed before it.
        let ok_extra = self
            .extra
            .iter()
            .enumerate()
            .all(|(m, &[j, next])| (j as usize) < n && (next == NONE || (next as usize) < m))
            && self
                .extra_head
                .iter()
                .all(|&h| h == NONE || (h as usize) < self.extra.len());
        let ok_spans = self.spans.iter().all(|s| (0..3).all(|k| ok_span(&s[k], k)));
        if ok_overflow
            && ok_cells
            && ok_extra
            && ok_spans
            && self.count[cells..].iter().all(|&k| k == 0)
        {
            Ok(())
        } else {
            Err("the epoch grid's filing is inconsistent".into())
        }
    }
}
