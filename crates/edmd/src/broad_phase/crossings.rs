//! The crossing broad phase: particles live in the linked-list cells of
//! [`LinkedCells`], at least one contact distance wide, and leave a cell through a
//! crossing event; a full prediction scans the 27 neighbour cells, a crossing only
//! the 9 cells of the new layer.

use super::BroadPhase;
use crate::cells::{LinkedCells, NONE};
use crate::queue::EventQueue;
use crate::state::{State, morton_order};
use emdstar_contact::vec3::sub;
use emdstar_system::SimBox;

/// Cell crossings on a linked-cell grid.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Crossings {
    pub(crate) grid: LinkedCells,
}

impl Crossings {
    /// A grid over `region` with cells at least `width` wide, for `n` particles.
    pub(crate) fn new(region: &SimBox, width: f64, n: usize) -> Self {
        Self {
            grid: LinkedCells::new(region.lo, region.size, region.periodic, width, n),
        }
    }

    /// The earliest collision of `i` (at time `now`, already advanced) with the
    /// particles of `cells` (each with the shift of its periodic image) before `best`:
    /// (time, partner or NONE, whether it is a stabilising collision now), and whether
    /// a particle met blocks the rotation of a running exception-(a) probe.
    #[inline(always)]
    pub(super) fn earliest_in<Q: EventQueue>(
        &self,
        s: &State<Q>,
        i: usize,
        cells: impl Iterator<Item = (u32, [f64; 3])> + Clone,
        mut best: f64,
    ) -> ((f64, u32, bool), bool) {
        // First ask for every cell's first particle, without a branch: in a large gas
        // the cells' heads and the particles' records are misses, and a branch on an
        // empty cell (most cells at η ≤ 0.1) taken before its head arrives would
        // serialise them.
        if s.is_large() {
            // An empty cell's head (NONE) asks for the last particle instead of a wild
            // address, whose translation would cost a page walk.
            let last = s.len() - 1;
            for (cell, _) in cells.clone() {
                let j = (self.grid.first(cell) as usize).min(last);
                s.prefetch_motion(j);
                self.grid.prefetch_next(j);
            }
        }
        let now = s.time;
        let (pi, vi) = (s.slot[i].kin.pos, s.slot[i].kin.vel);
        let ri = s.slot[i].kin.radius;
        let mut best_j = NONE;
        let mut best_now = false;
        let probe = s.probe_slot(i);
        let mut blocked = false;
        for (cell, shift) in cells {
            // Centre i relative to the image of the neighbour cell: r = x_i − (x_j + s).
            let pi_rel = sub(pi, shift);
            let mut j = self.grid.first(cell);
            while j != NONE {
                let ju = j as usize;
                if ju != i && !s.in_shared_transient(i, ju) {
                    let (pj, vj) = s.state_at(ju, now);
                    let (r, v) = (sub(pi_rel, pj), sub(vi, vj));
                    let sigma = ri + s.slot[ju].kin.radius;
                    if let Some((probe, slot)) = &probe {
                        blocked |= s.blocks_rotation(probe, *slot, ju, r, pj, sigma);
                    }
                    if crate::detect::on_collision_course(r, v, sigma) {
                        let dt = crate::detect::sphere_sphere(r, v, sigma);
                        if now + dt < best {
                            best = now + dt;
                            best_j = j;
                            best_now = dt == 0.0;
                        }
                    }
                }
                j = self.grid.next(j);
            }
        }
        ((best, best_j, best_now), blocked)
    }

    /// Tests `i`, which has just entered cell `c` moving in direction `dir` along
    /// `axis`, against the layer of cells that became its neighbours.
    #[inline]
    fn scan_new_layer<Q: EventQueue>(
        &self,
        s: &mut State<Q>,
        i: usize,
        c: [u32; 3],
        axis: usize,
        dir: i64,
    ) {
        let best = s.slot[i].ev.coll_time;
        if let Some(le) = s.lees_edwards()
            && self.grid.interior(c).is_none()
        {
            return self.scan_new_layer_sheared(s, &le, i, (c, axis, dir));
        }
        let (found, _) = if let Some(base) = self.grid.interior(c) {
            let cells = self
                .grid
                .interior_layer(base, axis, dir)
                .map(|c| (c, [0.0; 3]));
            self.earliest_in(s, i, cells, best)
        } else {
            let set = self.grid.new_layer(c, axis, dir);
            self.earliest_in(s, i, set.iter(), best)
        };
        s.keep_earliest(i, found);
    }

    /// Next face crossing of `i` along `axis` (advanced to now).
    #[inline]
    fn predict_axis_crossing<Q: EventQueue>(&self, s: &mut State<Q>, i: usize, axis: usize) {
        let (x, v) = (s.slot[i].kin.pos[axis], s.slot[i].kin.vel[axis]);
        let c = self.grid.coords[i][axis];
        let (dt, up) = self
            .grid
            .axis_crossing(axis, c, x, v, s.domain.gravity[axis]);
        let time = s.time;
        let ev = &mut s.slot[i].ev;
        ev.cross[axis] = time + dt;
        ev.cross_up = (ev.cross_up & !(1 << axis)) | (u8::from(up) << axis);
    }
}

impl BroadPhase for Crossings {
    const OWN_EVENTS: usize = 0;

    fn check_restored(&self, built: &Self, n: usize) -> Result<(), String> {
        if !crate::state::same_encoding(&self.grid.shape, &built.grid.shape) {
            return Err("another cell grid than the config's".into());
        }
        self.grid.check_restored(n, true)
    }

    fn fits(_: &SimBox, _: f64, _: usize) -> bool {
        true
    }

    fn file<Q: EventQueue>(&mut self, s: &State<Q>) {
        for i in 0..s.len() {
            let c = self.grid.coords_of(s.slot[i].kin.pos);
            self.grid.insert(i, c);
        }
    }

    fn start<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        for i in 0..s.len() {
            self.predict(s, i);
        }
    }

    /// Tests `i` against every particle of its own and the neighbouring cells.
    #[inline]
    fn predict_pairs<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize) {
        let c = self.grid.coords[i];
        let best = s.slot[i].ev.coll_time;
        if let Some(le) = s.lees_edwards()
            && self.grid.interior(c).is_none()
        {
            return self.predict_pairs_sheared(s, &le, i);
        }
        let (found, blocked) = if let Some(base) = self.grid.interior(c) {
            let cells = self.grid.interior_neighbours(base).map(|c| (c, [0.0; 3]));
            self.earliest_in(s, i, cells, best)
        } else {
            let set = self.grid.neighbourhood(c);
            self.earliest_in(s, i, set.iter(), best)
        };
        s.keep_earliest(i, found);
        if blocked {
            s.block_probe();
        }
    }

    /// Next face crossings of `i` along all axes (advanced to now).
    #[inline]
    fn predict_crossing<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize) {
        for axis in 0..3 {
            self.predict_axis_crossing(s, i, axis);
        }
    }

    /// A cell crossing along `axis` in direction `dir`: move the particle to its new
    /// cell, test the new layer and renew the crossing time along that axis.
    fn crossing<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize, axis: usize, dir: i64) {
        let now = s.time;
        s.advance(i, now);
        let mut c = self.grid.coords[i];
        let (next, shift) = self.grid.step(axis, c[axis], dir);
        if axis == 1
            && shift != 0.0
            && let Some(le) = s.lees_edwards()
        {
            return self.cross_sheared_face(s, &le, i, (next, shift, dir));
        }
        c[axis] = next;
        s.slot[i].kin.pos[axis] += shift;
        if shift != 0.0 {
            // Through a periodic face: one image along `axis`.
            s.image[i][axis] -= shift.signum() as i32;
        }
        self.grid.relocate(i, c);
        self.scan_new_layer(s, i, c, axis, dir);
        self.predict_axis_crossing(s, i, axis);
        s.schedule(i);
    }

    fn own_event<Q: EventQueue>(&mut self, _: &mut State<Q>) {
        unreachable!("cell crossings have no events of their own")
    }

    fn placed(&mut self, i: usize, x: [f64; 3]) {
        let c = self.grid.coords_of(x);
        self.grid.relocate(i, c);
    }

    fn cell_of(&self, i: usize) -> [u32; 3] {
        self.grid.coords[i]
    }

    fn return_to(&mut self, i: usize, cell: [u32; 3]) {
        self.grid.relocate(i, cell);
    }

    fn resorts_between_events(&self) -> bool {
        true
    }

    /// A crossing of `i` reads its cell and unlinks it from its list.
    #[inline(always)]
    fn prefetch(&self, i: usize) {
        self.grid.prefetch(i);
    }

    fn resort<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        let order = morton_order(self.grid.coords.iter().copied());
        s.permute(&order);
        self.grid.renumber(&order);
        s.refile();
        s.stats.resorts += 1;
    }
}
