//! Spatial re-sorting: particles are renumbered cell by cell so that neighbours in
//! space are neighbours in memory. Pair tests are limited by memory latency, and a
//! gas stirs an initial ordering up within a few collisions per particle, so the
//! engine re-sorts periodically. Events and accessors report the original numbers.

use crate::cells::NONE;
use crate::engine::Engine;
use crate::queue::EventQueue;

fn permute<T: Copy>(v: &mut [T], order: &[u32], scratch: &mut Vec<T>) {
    scratch.clear();
    scratch.extend(order.iter().map(|&i| v[i as usize]));
    v.copy_from_slice(scratch);
}

impl<Q: EventQueue> Engine<Q> {
    /// Renumbers the particles in cell order and predicts everything afresh. The
    /// physics is unchanged: predictions depend only on the current state.
    pub(crate) fn resort(&mut self) {
        let n = self.len();
        let now = self.time;
        for i in 0..n {
            self.advance(i, now);
        }
        let mut order: Vec<u32> = (0..n as u32).collect();
        let coords = &self.grid.coords;
        let dims = self.grid.dims;
        order.sort_by_key(|&i| {
            let c = coords[i as usize];
            (c[2] as usize * dims[1] + c[1] as usize) * dims[0] + c[0] as usize
        });
        let mut new_index = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        let mut s_kin = Vec::new();
        permute(&mut self.kin, &order, &mut s_kin);
        let mut s_f = Vec::new();
        permute(&mut self.mass, &order, &mut s_f);
        let mut s_e = Vec::new();
        permute(&mut self.ev, &order, &mut s_e);
        let mut s_u = Vec::new();
        permute(&mut self.species, &order, &mut s_u);
        permute(&mut self.id, &order, &mut s_u);

        let mut s_v = Vec::new();
        permute(&mut self.pending_vel, &order, &mut s_v);
        for e in &mut self.ev {
            if (e.partner as usize) < n {
                e.partner = new_index[e.partner as usize];
            }
            e.counter = 0;
            e.coll_partner = NONE;
            e.coll_time = f64::INFINITY;
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
            self.predict(i);
        }
        self.stats.resorts += 1;
    }
}
