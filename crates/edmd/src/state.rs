//! The state an event engine keeps apart from its broad phase and its rules: each
//! particle's kinematics and own events, the queue, the clock and the counters, with
//! the operations both broad phases use on them (delayed updates, periodic images,
//! keeping the earliest prediction, queueing).

use crate::collision::{LastContact, NONE, RotationProbe};
use crate::queue::EventQueue;
use crate::stats::Stats;
use emdstar_contact::vec3::{dot, sub};
use emdstar_system::{
    Domain, LeesEdwards, SimBox, StressMark, Sym3, add_kinetic, add_scaled, sym_outer,
};
use serde::{Deserialize, Serialize};

/// A particle's kinematics (the line neighbour scans read) and own events in one
/// 128-byte block: an event's own particle costs one miss (adjacent-line prefetch).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
#[repr(C, align(128))]
pub(crate) struct Slot {
    pub kin: Kin,
    pub ev: EventRec,
}

/// A particle's position and velocity, valid at time `stamp` (delayed update), and
/// its radius: the data every pair test reads, packed into one cache line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[repr(C, align(64))]
pub(crate) struct Kin {
    pub pos: [f64; 3],
    pub stamp: f64,
    pub vel: [f64; 3],
    pub radius: f64,
}

/// A particle's own next events (the queue holds the earliest of them).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
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

/// A party's state before an E^φ: its kinematics and its cell (crossings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saved {
    pub(crate) kin: Kin,
    pub(crate) cell: [u32; 3],
    pub(crate) image: [i32; 3],
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

/// Particles from which [`State::is_large`] holds: 2 MiB of records.
const LARGE_GAS: usize = (2 << 20) / std::mem::size_of::<Slot>();

/// Asks for the cache line at `x`: a prediction asks for all its candidates' lines
/// first, so that it waits for memory about once rather than once per candidate.
#[inline(always)]
pub(crate) fn prefetch<T>(x: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch is a hint that never faults, whatever the address.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(x as *const i8) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// Whether `a` and `b` encode to the same bytes: for the parts of a decoded checkpoint
/// that the config determines, compared with those of the engine the config builds.
pub(crate) fn same_encoding<T: Serialize + ?Sized>(a: &T, b: &T) -> bool {
    postcard::to_allocvec(a).ok() == postcard::to_allocvec(b).ok()
}

/// Everything of an event engine but its broad phase: what a [`crate::BroadPhase`]
/// works on (opaque outside this crate).
#[derive(Serialize, Deserialize)]
pub struct State<Q: EventQueue> {
    /// Per-particle kinematics and own events, one 128-byte block each.
    pub(crate) slot: Vec<Slot>,
    pub(crate) mass: Vec<f64>,
    /// Original particle number of each slot (slots are re-sorted in space).
    pub(crate) id: Vec<u32>,
    pub(crate) species: Vec<u32>,
    /// eMD*: the velocity the pending E^v event applies.
    pub(crate) pending_vel: Vec<[f64; 3]>,
    /// eMD*: each particle's last pair collision (partners renumbered with the slots).
    pub(crate) last_contact: Vec<LastContact>,
    /// Angular velocities by original particle number (out of the slots, which
    /// frictionless runs never need them in): changed only by Walton's rule.
    pub(crate) spin: Vec<[f64; 3]>,
    /// Periodic crossings of each slot's particle: its unwrapped position is its
    /// position plus `image` box lengths (counted where positions wrap).
    pub(crate) image: Vec<[i32; 3]>,
    /// Events between spatial re-sorts (0: never), and events since the last.
    pub(crate) resort_every: u64,
    pub(crate) since_resort: u64,
    pub(crate) queue: Q,
    pub(crate) time: f64,
    /// The box, or in free space the particles' bounding box at the start.
    pub(crate) region: SimBox,
    /// The box's period along each axis, 0 along closed axes.
    pub(crate) period: [f64; 3],
    /// The walls (unit normals) and gravity; the box as given (`None`: free space).
    pub(crate) domain: Domain,
    pub(crate) has_gravity: bool,
    pub(crate) stats: Stats,
    /// ∫ Σ m v ⊗ v dt of every particle's motion up to its stamp (the kinetic part of
    /// the pressure tensor; see [`emdstar_system::StressSums`]).
    pub(crate) kinetic: Sym3,
    /// The stress sums at the last mark (see [`emdstar_system::StressMark`]).
    pub(crate) stress_mark: Option<StressMark>,
    /// Consecutive events with time advancing by round-off at most (an inelastic
    /// collapse never ends).
    pub(crate) zero_streak: u64,
    /// eMD*: exception (a) of the E^φ being executed, checked by the predictions
    /// (none between events).
    #[serde(skip)]
    pub(crate) probe: Option<RotationProbe<Saved>>,
    /// Whether frictional collisions are solved ahead, and the particles scheduled
    /// since the engine last handed their predictions on (see `collision::SolveAhead`).
    #[serde(skip)]
    pub(crate) anticipating: bool,
    #[serde(skip)]
    pub(crate) scheduled: Vec<u32>,
}

impl<Q: EventQueue> State<Q> {
    /// Errors unless `self`, decoded from a checkpoint, fits `built`, the state the same
    /// config builds: the same particles (each original number once, with its mass,
    /// species and radius), box, walls and gravity, one entry per particle in every
    /// array, every partner a particle, a wall or none, and a whole queue of
    /// `queue_len` ids.
    pub(crate) fn check_restored(&self, built: &Self, queue_len: usize) -> Result<(), String> {
        let n = built.len();
        let lengths = [
            self.slot.len(),
            self.mass.len(),
            self.id.len(),
            self.species.len(),
            self.pending_vel.len(),
            self.last_contact.len(),
            self.spin.len(),
            self.image.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(format!(
                "per-particle arrays of {lengths:?} entries for {n} particles"
            ));
        }
        if self.region != built.region
            || self.period.map(f64::to_bits) != built.period.map(f64::to_bits)
            || self.domain != built.domain
            || self.has_gravity != built.has_gravity
        {
            return Err("another box, walls or gravity than the config's".into());
        }
        // Where the built state keeps each original particle number.
        let mut built_at = vec![usize::MAX; n];
        for (k, &id) in built.id.iter().enumerate() {
            built_at[id as usize] = k;
        }
        let mut seen = vec![false; n];
        let parties = n + self.domain.walls.len();
        for k in 0..n {
            let id = self.id[k] as usize;
            if id >= n || std::mem::replace(&mut seen[id], true) {
                return Err(format!("particle number {id} is missing or repeated"));
            }
            let b = built_at[id];
            let same = self.mass[k].to_bits() == built.mass[b].to_bits()
                && self.species[k] == built.species[b]
                && self.slot[k].kin.radius.to_bits() == built.slot[b].kin.radius.to_bits();
            let ev = &self.slot[k].ev;
            let partners = [ev.coll_partner, ev.partner, self.last_contact[k].partner];
            if !same || partners.iter().any(|&j| j != NONE && j as usize >= parties) {
                return Err(format!("particle {id} differs from the config's"));
            }
        }
        self.queue.check(queue_len)
    }

    /// Number of particles.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.slot.len()
    }

    /// Whether the particles' records outgrow a core's L2 cache (2 MiB on current
    /// server cores), so that asking for them ahead of use pays: below, the extra
    /// instructions cost more than the waits they save (measured from N = 864 to 10⁶).
    #[inline(always)]
    pub(crate) fn is_large(&self) -> bool {
        self.len() >= LARGE_GAS
    }

    /// Asks for the records of the particles whose events come next (the queue's
    /// hint), and for what `also` asks for each: in a large gas each is a miss, which
    /// a whole event's work then hides.
    #[inline(always)]
    pub(crate) fn prefetch_upcoming(&self, also: impl Fn(usize)) {
        if !self.is_large() {
            return;
        }
        for &(_, id) in self.queue.upcoming() {
            self.prefetch_record(id as usize);
            also(id as usize);
        }
    }

    /// Asks for the line of particle `j`'s motion (what a pair test reads). Any `j`
    /// may be given: a prefetch never faults.
    #[inline(always)]
    pub(crate) fn prefetch_motion(&self, j: usize) {
        prefetch(self.slot.as_ptr().wrapping_add(j));
    }

    /// Asks for both lines of particle `j`'s record: its motion and its event record.
    #[inline(always)]
    pub(crate) fn prefetch_record(&self, j: usize) {
        let slot = self.slot.as_ptr().wrapping_add(j);
        prefetch(slot);
        prefetch((slot as *const u8).wrapping_add(std::mem::offset_of!(Slot, ev)));
    }

    /// Position and velocity of particle `j` at time `t` ≥ its stamp (no update).
    #[inline(always)]
    pub(crate) fn state_at(&self, j: usize, t: f64) -> ([f64; 3], [f64; 3]) {
        let dt = t - self.slot[j].kin.stamp;
        let (p, v) = (self.slot[j].kin.pos, self.slot[j].kin.vel);
        if self.has_gravity {
            let g = self.domain.gravity;
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
            self.integrate_kinetic(i, t);
            let (p, v) = self.state_at(i, t);
            self.slot[i].kin.pos = p;
            self.slot[i].kin.vel = v;
            self.slot[i].kin.stamp = t;
        }
    }

    /// Adds particle `i`'s m ∫ v ⊗ v dt from its stamp to `t` to `to`: with
    /// v(s) = v₀ + g·s over T, m·(v₀⊗v₀·T + sym(v₀⊗g)·T² + g⊗g·T³/3).
    #[inline(always)]
    fn add_motion_kinetic(&self, to: &mut Sym3, i: usize, t: f64) {
        let kin = &self.slot[i].kin;
        let (m, dt, v) = (self.mass[i], t - kin.stamp, kin.vel);
        if let Some(le) = self.lees_edwards() {
            // The peculiar velocity c = v − γ̇ (y − y_mid) e_x changes along the flight
            // as c₀ + b·s with b = (−γ̇ v_y, 0, g_z) (gravity only along z here).
            let c0 = [v[0] - le.streaming(kin.pos[1]), v[1], v[2]];
            let b = [-le.rate * v[1], 0.0, self.domain.gravity[2]];
            add_kinetic(to, m * dt, c0);
            add_scaled(to, sym_outer(c0, b), m * dt * dt);
            add_scaled(to, sym_outer(b, b), m * dt * dt * dt / 3.0);
            return;
        }
        add_kinetic(to, m * dt, v);
        if self.has_gravity {
            let g = self.domain.gravity;
            add_scaled(to, sym_outer(v, g), m * dt * dt);
            add_scaled(to, sym_outer(g, g), m * dt * dt * dt / 3.0);
        }
    }

    /// Adds particle `i`'s motion from its stamp to `t` to the kinetic integral.
    #[inline(always)]
    fn integrate_kinetic(&mut self, i: usize, t: f64) {
        let mut k = self.kinetic;
        self.add_motion_kinetic(&mut k, i, t);
        self.kinetic = k;
    }

    /// The kinetic integral up to `t` of the particles `members` accepts: the stored
    /// one plus each such particle's motion from its stamp to `t` (nothing is moved).
    pub(crate) fn kinetic_until(&self, t: f64, members: impl Fn(usize) -> bool) -> Sym3 {
        let mut k = self.kinetic;
        for i in (0..self.len()).filter(|&i| members(i)) {
            self.add_motion_kinetic(&mut k, i, t);
        }
        k
    }

    /// The sliding images of a sheared box, if sheared.
    #[inline(always)]
    pub(crate) fn lees_edwards(&self) -> Option<emdstar_system::LeesEdwards> {
        self.domain.lees_edwards()
    }

    /// Puts slot `i` (synced) at `x`, near its position, in a sheared box: through the
    /// sliding face it becomes its image (x by ∓Δ(t); v_x and a pending E^v velocity by
    /// ∓γ̇ L_y, Lees & Edwards 1972); x and z wrap as usual. Returns the stored position.
    pub(crate) fn place_sheared(
        &mut self,
        le: &LeesEdwards,
        i: usize,
        mut x: [f64; 3],
    ) -> [f64; 3] {
        let (lo, ly) = (le.lo[1], le.size[1]);
        let up = if x[1] >= lo + ly {
            1.0
        } else if x[1] < lo {
            -1.0
        } else {
            0.0
        };
        if up != 0.0 {
            // Inside [lo, lo + L_y) whatever the round-off of the shift.
            let top = lo + ly - f64::EPSILON * (lo + ly).abs().max(ly);
            x[1] = (x[1] - up * ly).clamp(lo, top);
            x[0] -= up * le.offset(self.time);
            let dv = up * le.image_speed();
            self.slot[i].kin.vel[0] -= dv;
            if self.slot[i].ev.pending_time.is_finite() {
                self.pending_vel[i][0] -= dv;
            }
            self.image[i][1] += up as i32;
        }
        let x = self.wrap_slot(i, x);
        self.slot[i].kin.pos = x;
        self.slot[i].kin.stamp = self.time;
        x
    }

    /// The minimum-image separation (valid for |d_k| < 1.5·size_k, which positions
    /// kept inside the box guarantee).
    #[inline]
    pub(crate) fn min_image(&self, d: [f64; 3]) -> [f64; 3] {
        min_image_in(d, self.period)
    }

    /// [`State::wrap`] of slot `i`'s position `p`, counting the crossings in its image
    /// flags.
    #[inline]
    pub(crate) fn wrap_slot(&mut self, i: usize, p: [f64; 3]) -> [f64; 3] {
        let w = self.wrap(p);
        if w != p {
            self.image[i] = self.image_of(i, p, w);
        }
        w
    }

    /// The image flags of slot `i` at position `p`, wrapped to `w`.
    #[inline]
    pub(crate) fn image_of(&self, i: usize, p: [f64; 3], w: [f64; 3]) -> [i32; 3] {
        let mut image = self.image[i];
        for k in 0..3 {
            if w[k] != p[k] {
                image[k] += ((p[k] - w[k]) / self.region.size[k]).round() as i32;
            }
        }
        image
    }

    /// Wraps a position into the box along periodic axes.
    #[inline]
    pub(crate) fn wrap(&self, mut p: [f64; 3]) -> [f64; 3] {
        for (k, x) in p.iter_mut().enumerate() {
            if self.region.periodic[k] {
                let (lo, l) = (self.region.lo[k], self.region.size[k]);
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

    /// Which party of the running exception-(a) probe `i` is, if any.
    #[inline]
    pub(crate) fn probe_slot(&self, i: usize) -> Option<(RotationProbe<Saved>, usize)> {
        let probe = self.probe?;
        let slot = probe.slot_of(i)?;
        Some((probe, slot))
    }

    /// Whether third particle `k`, at `xk` now and `r` = (new position of party
    /// `slot` of `probe`) − `xk` (its image), blocks the rotation.
    #[inline(always)]
    pub(crate) fn blocks_rotation(
        &self,
        probe: &RotationProbe<Saved>,
        slot: usize,
        k: usize,
        r: [f64; 3],
        xk: [f64; 3],
        contact: f64,
    ) -> bool {
        match self.lees_edwards() {
            Some(le) => probe.blocks(slot, k, r, xk, contact, |d| le.image(d, self.time).0),
            None => probe.blocks(slot, k, r, xk, contact, |d| self.min_image(d)),
        }
    }

    /// Marks the running probe blocked.
    #[inline]
    pub(crate) fn block_probe(&mut self) {
        if let Some(probe) = &mut self.probe {
            probe.blocked = true;
        }
    }

    /// Keeps the collision a broad phase found, if there is one: (time, partner or
    /// NONE, whether it is a stabilising collision now).
    #[inline(always)]
    pub(crate) fn keep_earliest(&mut self, i: usize, (time, j, now): (f64, u32, bool)) {
        if j != NONE {
            self.slot[i].ev.coll_time = time;
            self.slot[i].ev.coll_partner = j;
            self.slot[i].ev.coll_counter = self.slot[j as usize].ev.counter;
            self.slot[i].ev.coll_now = now;
        }
    }

    /// The earliest cell crossing (or, with epochs, horizon) of `i`: (time, axis,
    /// direction ±1).
    #[inline(always)]
    pub(crate) fn next_crossing(&self, i: usize) -> (f64, usize, i64) {
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
        if self.anticipating {
            self.scheduled.push(i as u32);
        }
    }

    /// The earliest wall collision of `i` (advanced to now), if before its prediction.
    pub(crate) fn predict_walls(&mut self, i: usize) {
        let now = self.time;
        let n = self.len();
        for w in 0..self.domain.walls.len() {
            if self.in_shared_transient(i, n + w) {
                continue;
            }
            let wall = self.domain.walls[w];
            let h = dot(wall.normal, sub(self.slot[i].kin.pos, wall.point));
            let (speed, accel) = (
                dot(wall.normal, self.slot[i].kin.vel),
                dot(wall.normal, self.domain.gravity),
            );
            let radius = self.slot[i].kin.radius;
            let dt = match &wall.vibration {
                None => crate::detect::sphere_wall(h, speed, accel, radius),
                Some(vib) => {
                    crate::vibrated::sphere_vibrated_wall(now, h, speed, accel, radius, vib)
                }
            };
            if now + dt < self.slot[i].ev.coll_time {
                self.slot[i].ev.coll_time = now + dt;
                self.slot[i].ev.coll_partner = (n + w) as u32;
                self.slot[i].ev.coll_now = false;
            }
        }
    }

    /// Renumbers the particles so that new slot k holds old slot `order[k]`. Only
    /// the numbering changes: states, stamps and predicted events move with their
    /// particles, partners are renumbered and the queue is refiled, so nothing is
    /// predicted again. The broad phase renumbers what it keeps per particle.
    pub(crate) fn permute(&mut self, order: &[u32]) {
        let n = self.len();
        let mut new_index = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        let mut s_slot = Vec::new();
        permute(&mut self.slot, order, &mut s_slot);
        let mut s_f = Vec::new();
        permute(&mut self.mass, order, &mut s_f);
        let mut s_u = Vec::new();
        permute(&mut self.species, order, &mut s_u);
        permute(&mut self.id, order, &mut s_u);
        let mut s_v = Vec::new();
        permute(&mut self.pending_vel, order, &mut s_v);
        let mut s_i = Vec::new();
        permute(&mut self.image, order, &mut s_i);
        let mut s_c = Vec::new();
        permute(&mut self.last_contact, order, &mut s_c);
        // Particles below n are renumbered; walls (n + w) and NONE keep their numbers.
        let renumber = |j: u32| new_index.get(j as usize).copied().unwrap_or(j);
        for e in self.slot.iter_mut().map(|s| &mut s.ev) {
            e.partner = renumber(e.partner);
            e.coll_partner = renumber(e.coll_partner);
        }
        for c in &mut self.last_contact {
            c.partner = renumber(c.partner);
        }
        self.scheduled.clear();
    }

    /// Refiles every particle's earliest event in the queue (after a renumbering).
    pub(crate) fn refile(&mut self) {
        let n = self.len();
        for i in 0..n {
            self.queue.set(i, f64::INFINITY);
        }
        for i in 0..n {
            self.schedule(i);
        }
    }
}

/// Reorders `v` so that new index k holds old element `order[k]`.
pub(crate) fn permute<T: Copy>(v: &mut [T], order: &[u32], scratch: &mut Vec<T>) {
    scratch.clear();
    scratch.extend(order.iter().map(|&i| v[i as usize]));
    v.copy_from_slice(scratch);
}

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

/// The order that sorts particles by the Morton keys of their cells. Pair tests are
/// limited by memory latency, and a gas stirs an initial ordering up within a few
/// collisions per particle, so engines re-sort periodically: neighbours in space are
/// then mostly neighbours in memory.
pub(crate) fn morton_order(cells: impl Iterator<Item = [u32; 3]>) -> Vec<u32> {
    // (key, index) pairs are distinct, so the unstable sort gives one order.
    let mut keyed: Vec<(u64, u32)> = cells
        .enumerate()
        .map(|(i, c)| (morton(c), i as u32))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
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
