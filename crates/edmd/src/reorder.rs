//! Spatial re-sorting: particles are renumbered cell by cell in Morton (Z) order so
//! that neighbours in space are mostly neighbours in memory. Pair tests are limited by memory latency, and a
//! gas stirs an initial ordering up within a few collisions per particle, so the
//! engine re-sorts periodically. Events and accessors report the original numbers.

use crate::engine::Engine;
use crate::queue::EventQueue;

/// Spreads the low 10 bits of `x` to every third bit.
fn spread(x: u32) -> u64 {
    let mut x = u64::from(x & 0x3ff);
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// The Morton (Z-order) key of cell coordinates below 1024: cells close in space are
/// mostly close in this order along all three axes, not only along x as in row order.
pub(crate) fn morton(c: [u32; 3]) -> u64 {
    spread(c[0]) | (spread(c[1]) << 1) | (spread(c[2]) << 2)
}

fn permute<T: Copy>(v: &mut [T], order: &[u32], scratch: &mut Vec<T>) {
    scratch.clear();
    scratch.extend(order.iter().map(|&i| v[i as usize]));
    v.copy_from_slice(scratch);
}

impl<Q: EventQueue> Engine<Q> {
    /// Renumbers the particles in cell order. Only the numbering changes: states,
    /// stamps and predicted events move with their particles, partners are renumbered
    /// and the queue is refiled, so nothing is predicted again.
    pub(crate) fn resort(&mut self) {
        let n = self.len();
        // Morton keys once per particle; (key, index) pairs are distinct, so the
        // unstable sort gives one order.
        let mut keyed: Vec<(u64, u32)> = (0..n)
            .map(|i| (morton(self.grid.coords[i]), i as u32))
            .collect();
        keyed.sort_unstable();
        let order: Vec<u32> = keyed.into_iter().map(|(_, i)| i).collect();
        let mut new_index = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        let mut s_slot = Vec::new();
        permute(&mut self.slot, &order, &mut s_slot);
        let mut s_f = Vec::new();
        permute(&mut self.mass, &order, &mut s_f);
        let mut s_u = Vec::new();
        permute(&mut self.species, &order, &mut s_u);
        permute(&mut self.id, &order, &mut s_u);
        let mut s_v = Vec::new();
        permute(&mut self.pending_vel, &order, &mut s_v);
        // Particles below n are renumbered; walls (n + w) and NONE keep their numbers.
        let renumber = |j: u32| new_index.get(j as usize).copied().unwrap_or(j);
        for e in self.slot.iter_mut().map(|s| &mut s.ev) {
            e.partner = renumber(e.partner);
            e.coll_partner = renumber(e.coll_partner);
        }
        let mut cells = Vec::new();
        permute(&mut self.grid.coords, &order, &mut cells);
        self.grid.clear();
        for i in (0..n).rev() {
            let c = self.grid.coords[i];
            self.grid.insert(i, c);
        }
        for i in 0..n {
            self.queue.set(i, f64::INFINITY);
        }
        for i in 0..n {
            self.schedule(i);
        }
        self.stats.resorts += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::morton;

    #[test]
    fn morton_interleaves_the_bits_of_the_three_axes() {
        assert_eq!(morton([1, 0, 0]), 0b001);
        assert_eq!(morton([0, 1, 0]), 0b010);
        assert_eq!(morton([0, 0, 1]), 0b100);
        assert_eq!(morton([3, 5, 6]), 0b110_101_011);
        assert_eq!(morton([1023, 1023, 1023]), (1 << 30) - 1);
        // Every cell of a 2×2×2 block comes before any cell of the next block.
        let mut keys: Vec<_> = (0..64u32)
            .map(|m| {
                (
                    [m % 4, m / 4 % 4, m / 16],
                    morton([m % 4, m / 4 % 4, m / 16]),
                )
            })
            .collect();
        keys.sort_by_key(|k| k.1);
        for (rank, (c, _)) in keys.iter().enumerate() {
            let block = (c[0] / 2) + 2 * (c[1] / 2) + 4 * (c[2] / 2);
            assert_eq!(block as usize, rank / 8, "{c:?}");
        }
    }
}
