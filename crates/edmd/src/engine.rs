//! The event loop: per-particle next events in a swappable queue, stale events found
//! by collision counters, cells with crossing events, and delayed (lazy) particle
//! updates — each particle's state is stored at the time of its last event and moved
//! on only when it is touched (Lubachevsky 1991; DynamO's delayed states).

use crate::calendar::CalendarQueue;
use crate::cells::{CellGrid, NONE};
use crate::detect::{on_collision_course, sphere_sphere, sphere_wall};
use crate::epoch::Epochs;
use crate::error::{EngineError, Result};
use crate::queue::EventQueue;
use crate::rules::HertzRestitution;
use crate::setup::{Physics, Wall};
use crate::stats::Stats;

/// What [`Engine::step`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A pair collision (for eMD*: its E^φ event, or the eMD fallback).
    Collision(u32, u32),
    /// A collision with wall `w`.
    Wall(u32, u32),
    /// An eMD* E^v event: the particle took its post-collision velocity.
    Velocity(u32),
    /// A particle moved into another cell (with epochs: renewed its swept box early).
    Crossing(u32),
    /// A new epoch of the epoch broad phase began (no particle changed).
    Epoch,
    /// A stale prediction was discarded and the particle re-predicted.
    Stale(u32),
    /// An interfering collision whose pair stopped approaching once the pending E^v
    /// events ran (eMD* exception b); nothing else happened.
    Resolved(u32, u32),
}

/// The event-driven engine for hard spheres, eMD and eMD*. The default queue is the
/// calendar queue (O(1) per event); [`crate::IndexedHeap`] gives the same event order.
pub struct Engine<Q: EventQueue = CalendarQueue> {
    /// Per-particle kinematics and own events, one 128-byte block each.
    pub(crate) slot: Vec<Slot>,
    pub(crate) mass: Vec<f64>,
    /// Original particle number of each slot (slots are re-sorted in space).
    pub(crate) id: Vec<u32>,
    /// Events between spatial re-sorts (0: never), and events since the last.
    pub(crate) resort_every: u64,
    pub(crate) since_resort: u64,
    pub(crate) species: Vec<u32>,
    /// eMD*: the velocity the pending E^v event applies.
    pub(crate) pending_vel: Vec<[f64; 3]>,
    pub(crate) grid: CellGrid,
    /// The epoch broad phase; `None` runs on cell crossings (the grid's lists).
    pub(crate) epochs: Option<Box<Epochs>>,
    pub(crate) queue: Q,
    pub(crate) time: f64,
    pub(crate) walls: Vec<Wall>,
    pub(crate) gravity: [f64; 3],
    pub(crate) has_gravity: bool,
    pub(crate) physics: Physics,
    pub(crate) hertz: HertzRestitution,
    pub(crate) stats: Stats,
    /// Consecutive events at one instant (an inelastic collapse never ends).
    pub(crate) zero_streak: u64,
    /// eMD*: exception (a) of the E^φ being executed, checked by the predictions.
    pub(crate) probe: Option<crate::collide::RotationProbe>,
}

/// A particle's kinematics (the line neighbour scans read) and own events in one
/// 128-byte block: an event's own particle costs one miss (adjacent-line prefetch).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(128))]
pub(crate) struct Slot {
    pub kin: Kin,
    pub ev: EventRec,
}

/// A particle's position and velocity, valid at time `stamp` (delayed update), and
/// its radius: the data every pair test reads, packed into one cache line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
pub(crate) struct Kin {
    pub pos: [f64; 3],
    pub stamp: f64,
    pub vel: [f64; 3],
    pub radius: f64,
}

/// A particle's own next events (the queue holds the earliest of them).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct EventRec {
    /// Earliest predicted collision, with a particle or (`n + w`) wall w.
    pub coll_time: f64,
    /// Next crossing of a face along each axis. The motion along one axis does not
    /// depend on the others, so a crossing only renews the time of its own axis. With
    /// epochs, `cross[0]` is the horizon of a swept box that ends before the epoch
    /// (+∞ otherwise), and reaching it renews the box.
    pub cross: [f64; 3],
    /// eMD*: time of the pending E^v event (+∞ if none).
    pub pending_time: f64,
    pub coll_partner: u32,
    /// The partner's `counter` when the collision was predicted.
    pub coll_counter: u32,
    /// Incremented whenever this particle's velocity or position jumps.
    pub counter: u32,
    /// eMD*: the particle (or `n + w` wall) sharing the transient, NONE otherwise.
    pub partner: u32,
    /// Bit k set: the next crossing along axis k is through the upper face.
    pub cross_up: u8,
    /// The collision was predicted for the moment of prediction: an overlapping,
    /// approaching pair (a stabilising collision, Bannerman 2014, Sec. 4.1).
    pub coll_now: bool,
}

impl Default for EventRec {
    fn default() -> Self {
        Self {
            coll_time: f64::INFINITY,
            cross: [f64::INFINITY; 3],
            pending_time: f64::INFINITY,
            coll_partner: NONE,
            coll_counter: 0,
            counter: 0,
            partner: NONE,
            cross_up: 0,
            coll_now: false,
        }
    }
}

/// The minimum image of `d` in a box of `period` (0 along closed axes), valid for
/// |d_k| < 1.5·period_k; selects rather than branches, as about one pair in five that
/// share an epoch cell straddles a periodic face.
#[inline(always)]
pub(crate) fn min_image_in(d: [f64; 3], period: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| {
        let l = period[k];
        let up = if d[k] > 0.5 * l { l } else { 0.0 };
        let down = if d[k] < -0.5 * l { l } else { 0.0 };
        d[k] - up + down
    })
}

#[inline]
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

impl<Q: EventQueue> Engine<Q> {
    const MAX_ZERO_TIME_EVENTS: u64 = 10_000_000;

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.slot.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.slot.is_empty()
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Event and exception counters.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Position and velocity of particle `j` at time `t` ≥ its stamp (no update).
    #[inline(always)]
    pub(crate) fn state_at(&self, j: usize, t: f64) -> ([f64; 3], [f64; 3]) {
        let dt = t - self.slot[j].kin.stamp;
        let (p, v) = (self.slot[j].kin.pos, self.slot[j].kin.vel);
        if self.has_gravity {
            let g = self.gravity;
            (
                std::array::from_fn(|k| p[k] + v[k] * dt + 0.5 * g[k] * dt * dt),
                std::array::from_fn(|k| v[k] + g[k] * dt),
            )
        } else {
            (std::array::from_fn(|k| p[k] + v[k] * dt), v)
        }
    }

    /// Moves particle `i` on to time `t` (the delayed update).
    #[inline]
    pub(crate) fn advance(&mut self, i: usize, t: f64) {
        if self.slot[i].kin.stamp != t {
            let (p, v) = self.state_at(i, t);
            self.slot[i].kin.pos = p;
            self.slot[i].kin.vel = v;
            self.slot[i].kin.stamp = t;
        }
    }

    /// The minimum-image separation (valid for |d_k| < 1.5·size_k, which positions
    /// kept inside the box guarantee).
    #[inline]
    pub(crate) fn min_image(&self, d: [f64; 3]) -> [f64; 3] {
        min_image_in(d, self.period())
    }

    /// The box's period along each axis, 0 along closed axes.
    #[inline]
    pub(crate) fn period(&self) -> [f64; 3] {
        std::array::from_fn(|k| {
            if self.grid.periodic[k] {
                self.grid.size[k]
            } else {
                0.0
            }
        })
    }

    /// Wraps a position into the box along periodic axes.
    #[inline]
    pub(crate) fn wrap(&self, mut p: [f64; 3]) -> [f64; 3] {
        for (k, x) in p.iter_mut().enumerate() {
            if self.grid.periodic[k] {
                let (lo, l) = (self.grid.lo[k], self.grid.size[k]);
                if *x < lo {
                    *x += l;
                } else if *x >= lo + l {
                    *x -= l;
                }
            }
        }
        p
    }

    /// Whether `i` and the particle or wall `j` (≥ n for walls) share an eMD*
    /// transient. Such partners move together at their centre-of-mass velocity
    /// between E^φ and E^v, overlapping by l(1 − ε_r), and are never tested against
    /// each other until one of them has taken its post-collision velocity: round-off
    /// in their common velocity must not trigger a spurious stabilising collision.
    #[inline]
    pub(crate) fn in_shared_transient(&self, i: usize, j: usize) -> bool {
        self.slot[i].ev.partner == j as u32
            && (j >= self.len() || self.slot[j].ev.partner == i as u32)
    }

    /// The earliest collision of `i` (at time `now`, already advanced) with the
    /// particles of `cells` (each with the shift of its periodic image) before `best`:
    /// (time, partner or NONE, whether it is a stabilising collision now), and whether
    /// a particle met blocks the rotation of a running exception-(a) probe.
    #[inline(always)]
    fn earliest_in(
        &self,
        i: usize,
        cells: impl Iterator<Item = (u32, [f64; 3])>,
        mut best: f64,
    ) -> ((f64, u32, bool), bool) {
        let now = self.time;
        let (pi, vi) = (self.slot[i].kin.pos, self.slot[i].kin.vel);
        let ri = self.slot[i].kin.radius;
        let mut best_j = NONE;
        let mut best_now = false;
        let probe = self.probe_slot(i);
        let mut blocked = false;
        for (cell, shift) in cells {
            // Centre i relative to the image of the neighbour cell: r = x_i − (x_j + s).
            let pi_rel = sub(pi, shift);
            let mut j = self.grid.first(cell);
            while j != NONE {
                let ju = j as usize;
                if ju != i && !self.in_shared_transient(i, ju) {
                    let (pj, vj) = self.state_at(ju, now);
                    let (r, v) = (sub(pi_rel, pj), sub(vi, vj));
                    let sigma = ri + self.slot[ju].kin.radius;
                    if let Some((probe, slot)) = &probe {
                        blocked |= self.blocks_rotation(probe, *slot, ju, r, pj, sigma);
                    }
                    if on_collision_course(r, v, sigma) {
                        let dt = sphere_sphere(r, v, sigma);
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

    /// Keeps the collision found by [`Engine::earliest_in`] (or a broad phase's own
    /// scan) if there is one: (time, partner or NONE, whether it is a stabilising
    /// collision now).
    #[inline(always)]
    pub(crate) fn keep_earliest(&mut self, i: usize, (time, j, now): (f64, u32, bool)) {
        if j != NONE {
            self.slot[i].ev.coll_time = time;
            self.slot[i].ev.coll_partner = j;
            self.slot[i].ev.coll_counter = self.slot[j as usize].ev.counter;
            self.slot[i].ev.coll_now = now;
        }
    }

    /// Tests `i` against every particle of its own and the neighbouring cells.
    #[inline]
    fn scan_neighbourhood(&mut self, i: usize) {
        let c = self.grid.coords[i];
        let best = self.slot[i].ev.coll_time;
        let (found, blocked) = if let Some(base) = self.grid.interior(c) {
            let cells = self.grid.interior_neighbours(base).map(|c| (c, [0.0; 3]));
            self.earliest_in(i, cells, best)
        } else {
            let set = self.grid.neighbourhood(c);
            self.earliest_in(i, set.iter(), best)
        };
        self.keep_earliest(i, found);
        if blocked && let Some(probe) = &mut self.probe {
            probe.blocked = true;
        }
    }

    /// Tests `i`, which has just entered cell `c` moving in direction `dir` along
    /// `axis`, against the layer of cells that became its neighbours.
    #[inline]
    fn scan_new_layer(&mut self, i: usize, c: [u32; 3], axis: usize, dir: i64) {
        let best = self.slot[i].ev.coll_time;
        let (found, _) = if let Some(base) = self.grid.interior(c) {
            let cells = self
                .grid
                .interior_layer(base, axis, dir)
                .map(|c| (c, [0.0; 3]));
            self.earliest_in(i, cells, best)
        } else {
            let set = self.grid.new_layer(c, axis, dir);
            self.earliest_in(i, set.iter(), best)
        };
        self.keep_earliest(i, found);
    }

    /// Next face crossing of `i` along `axis` (advanced to now).
    #[inline]
    fn predict_axis_crossing(&mut self, i: usize, axis: usize) {
        let (x, v) = (self.slot[i].kin.pos[axis], self.slot[i].kin.vel[axis]);
        let c = self.grid.coords[i][axis];
        let (dt, up) = self.grid.axis_crossing(axis, c, x, v, self.gravity[axis]);
        let ev = &mut self.slot[i].ev;
        ev.cross[axis] = self.time + dt;
        ev.cross_up = (ev.cross_up & !(1 << axis)) | (u8::from(up) << axis);
    }

    /// Next face crossings of `i` along all axes (advanced to now).
    #[inline]
    fn predict_crossing(&mut self, i: usize) {
        for axis in 0..3 {
            self.predict_axis_crossing(i, axis);
        }
    }

    /// The earliest cell crossing of `i`: (time, axis, direction ±1).
    #[inline(always)]
    fn next_crossing(&self, i: usize) -> (f64, usize, i64) {
        let ev = &self.slot[i].ev;
        let mut axis = 0;
        for k in 1..3 {
            if ev.cross[k] < ev.cross[axis] {
                axis = k;
            }
        }
        let dir = if ev.cross_up >> axis & 1 == 1 { 1 } else { -1 };
        (ev.cross[axis], axis, dir)
    }

    /// Pushes the particle's earliest own event to the queue.
    #[inline]
    pub(crate) fn schedule(&mut self, i: usize) {
        let t = self.slot[i]
            .ev
            .coll_time
            .min(self.next_crossing(i).0)
            .min(self.slot[i].ev.pending_time);
        self.queue.set(i, t);
    }

    /// Full prediction for particle `i` at the current time: all neighbours, walls and
    /// the next cell crossing.
    pub(crate) fn predict(&mut self, i: usize) {
        let now = self.time;
        self.advance(i, now);
        self.slot[i].ev.coll_time = f64::INFINITY;
        self.slot[i].ev.coll_partner = NONE;
        self.slot[i].ev.coll_now = false;
        if self.epochs.is_some() {
            self.predict_in_epoch(i);
        } else {
            self.scan_neighbourhood(i);
        }
        self.predict_walls(i);
        if self.epochs.is_none() {
            self.predict_crossing(i);
        }
        self.schedule(i);
    }

    /// The earliest wall collision of `i` (advanced to now), if before its prediction.
    pub(crate) fn predict_walls(&mut self, i: usize) {
        let now = self.time;
        let n = self.len();
        for w in 0..self.walls.len() {
            if self.in_shared_transient(i, n + w) {
                continue;
            }
            let wall = self.walls[w];
            let h = dot(wall.normal, sub(self.slot[i].kin.pos, wall.point));
            let dt = sphere_wall(
                h,
                dot(wall.normal, self.slot[i].kin.vel),
                dot(wall.normal, self.gravity),
                self.slot[i].kin.radius,
            );
            if now + dt < self.slot[i].ev.coll_time {
                self.slot[i].ev.coll_time = now + dt;
                self.slot[i].ev.coll_partner = (n + w) as u32;
                self.slot[i].ev.coll_now = false;
            }
        }
    }

    /// Processes the next event.
    pub fn step(&mut self) -> Result<Event> {
        let (i, t) = self.queue.peek();
        if !t.is_finite() {
            return Err(EngineError::Invalid(
                "no event is left: every particle flies freely for ever (an empty or \
                 fully separating system); run for a fixed time instead"
                    .into(),
            ));
        }
        if t == self.time {
            self.zero_streak += 1;
            if self.zero_streak > Self::MAX_ZERO_TIME_EVENTS {
                return Err(EngineError::Invalid(format!(
                    "more than {} events at time {t} without time advancing: an inelastic \
                     collapse (Bannerman et al. 2014, Sec. 5); event-driven dynamics cannot \
                     go on, use a force-based engine or less dissipation",
                    Self::MAX_ZERO_TIME_EVENTS
                )));
            }
        } else {
            self.zero_streak = 0;
        }
        self.time = t;
        self.stats.events += 1;
        self.since_resort += 1;
        if i == self.len() {
            self.rebuild_epoch();
            return Ok(Event::Epoch);
        }
        if self.epochs.is_none() && self.resort_every > 0 && self.since_resort >= self.resort_every
        {
            self.since_resort = 0;
            self.resort();
            self.stats.events -= 1;
            return self.step();
        }
        if self.slot[i].ev.pending_time <= t {
            self.velocity_event(i);
            return Ok(Event::Velocity(self.id[i]));
        }
        let (cross_time, axis, dir) = self.next_crossing(i);
        if cross_time < self.slot[i].ev.coll_time {
            self.crossing(i, axis, dir);
            return Ok(Event::Crossing(self.id[i]));
        }
        let j = self.slot[i].ev.coll_partner as usize;
        let n = self.len();
        if j >= n {
            self.wall_collision(i, j - n)?;
            return Ok(Event::Wall(self.id[i], (j - n) as u32));
        }
        if self.slot[j].ev.counter != self.slot[i].ev.coll_counter {
            self.stats.stale += 1;
            self.predict(i);
            return Ok(Event::Stale(self.id[i]));
        }
        if self.slot[i].ev.coll_now {
            self.stats.stabilising += 1;
        }
        if self.pair_collision(i, j)? {
            Ok(Event::Collision(self.id[i], self.id[j]))
        } else {
            Ok(Event::Resolved(self.id[i], self.id[j]))
        }
    }

    /// A cell crossing along `axis` in direction `dir`: move the particle to its new
    /// cell, test the new layer and renew the crossing time along that axis.
    fn crossing(&mut self, i: usize, axis: usize, dir: i64) {
        self.stats.crossings += 1;
        if self.epochs.is_some() {
            // The swept box reached its horizon before the epoch's end.
            self.predict(i);
            return;
        }
        let now = self.time;
        self.advance(i, now);
        let mut c = self.grid.coords[i];
        let (next, shift) = self.grid.step(axis, c[axis], dir);
        c[axis] = next;
        self.slot[i].kin.pos[axis] += shift;
        self.grid.relocate(i, c);
        self.scan_new_layer(i, c, axis, dir);
        self.predict_axis_crossing(i, axis);
        self.schedule(i);
    }

    /// An E^v event at its scheduled time.
    fn velocity_event(&mut self, i: usize) {
        self.stats.velocity_events += 1;
        self.finish_transient(i);
        self.predict(i);
    }

    /// Applies `i`'s pending post-collision velocity now (at its E^v time, or early
    /// for exception b), ending its transient.
    pub(crate) fn finish_transient(&mut self, i: usize) {
        let now = self.time;
        self.advance(i, now);
        // The stored velocity includes gravity up to the E^v time; undo the rest.
        let early = self.slot[i].ev.pending_time - now;
        let g = self.transient_gravity(self.slot[i].ev.partner);
        let v = self.pending_vel[i];
        self.slot[i].kin.vel = std::array::from_fn(|k| v[k] - g[k] * early);
        self.slot[i].ev.pending_time = f64::INFINITY;
        self.slot[i].ev.partner = NONE;
        self.slot[i].ev.counter = self.slot[i].ev.counter.wrapping_add(1);
    }

    /// The part of gravity that acts on a particle's velocity over an eMD* transient
    /// with `partner` (a particle, or `n + w` for wall w). A pair in free fall feels
    /// all of g through its centre of mass. A flat wall carries the normal part during
    /// the contact (an elastic sphere leaves a wall under gravity with its impact
    /// speed, by energy balance at ξ = 0), so only the part along the wall acts; the
    /// remaining effect of gravity on the contact is of second order in g·τ/v_n.
    pub(crate) fn transient_gravity(&self, partner: u32) -> [f64; 3] {
        let g = self.gravity;
        match (partner as usize).checked_sub(self.len()) {
            Some(w) if partner != NONE && w < self.walls.len() => {
                let n = self.walls[w].normal;
                let g_n = dot(g, n);
                std::array::from_fn(|k| g[k] - g_n * n[k])
            }
            _ => g,
        }
    }

    /// Runs until time `t_end` (all events before it), leaving every particle's
    /// stored state at its last event.
    pub fn run_until(&mut self, t_end: f64) -> Result<()> {
        while self.queue.peek().1 <= t_end {
            self.step()?;
        }
        self.time = self.time.max(t_end);
        Ok(())
    }

    /// Runs until `count` more pair and wall collisions have been executed.
    pub fn run_collisions(&mut self, count: u64) -> Result<()> {
        let target = self.stats.collisions() + count;
        while self.stats.collisions() < target {
            self.step()?;
        }
        Ok(())
    }

    /// Sets how many events pass between spatial re-sorts of the particle order
    /// (0 switches re-sorting off).
    pub fn set_resort_interval(&mut self, events: u64) {
        self.resort_every = events;
    }
}
