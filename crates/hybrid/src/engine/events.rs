//! The event-driven part: eMD* among ED particles (Müller & Pöschel 2013, Sec. VI B)
//! with stable detection (Bannerman et al. 2014), lazily updated particles, a binary
//! queue holding each ED particle's earliest event (`emdstar_edmd`'s calendar queue,
//! ties to the smaller particle number), and the ED → TD switch. The collisions
//! themselves are `emdstar_edmd::collision`'s, with the hybrid as their host (host.rs).

use super::Hybrid;
use crate::options::{HybridError, Mode};
use emdstar_contact::vec3::{dot, norm, sub};
use emdstar_edmd::EventQueue;
use emdstar_edmd::collision::{self, NONE};
use emdstar_edmd::detect::{on_collision_course, sphere_sphere, sphere_wall};

impl Hybrid {
    /// Position and velocity of ED particle `j` at time `t` ≥ its stamp (parabolic
    /// flight under gravity, Bannerman 2014, Sec. 3).
    #[inline(always)]
    pub(crate) fn state_at(&self, j: usize, t: f64) -> ([f64; 3], [f64; 3]) {
        let dt = t - self.ed[j].stamp;
        let p = &self.system.particles;
        let (x, v, g) = (p.position[j], p.velocity[j], self.system.domain.gravity);
        (
            std::array::from_fn(|k| x[k] + v[k] * dt + 0.5 * g[k] * dt * dt),
            std::array::from_fn(|k| v[k] + g[k] * dt),
        )
    }

    /// State at `t` with a pending E^v velocity applied (for output and balances).
    pub(crate) fn settled_state(&self, j: usize, t: f64) -> ([f64; 3], [f64; 3]) {
        let (x, v) = self.state_at(j, t);
        let rec = &self.ed[j];
        if rec.pending_time.is_finite() {
            let early = rec.pending_time - t;
            let d = &self.system.domain;
            let g = collision::transient_gravity(d.gravity, &d.walls, self.mode.len(), rec.partner);
            (
                x,
                std::array::from_fn(|k| rec.pending_vel[k] - g[k] * early),
            )
        } else {
            (x, v)
        }
    }

    /// Moves ED particle `i` on to time `t` (the delayed update).
    #[inline]
    pub(crate) fn sync(&mut self, i: usize, t: f64) {
        if self.ed[i].stamp != t {
            let (x, v) = self.state_at(i, t);
            self.system.particles.position[i] = x;
            self.system.particles.velocity[i] = v;
            self.ed[i].stamp = t;
        }
    }

    pub(crate) fn in_shared_transient(&self, i: usize, j: usize) -> bool {
        let n = self.mode.len();
        self.ed[i].partner == j as u32 && (j >= n || self.ed[j].partner == i as u32)
    }

    /// The earliest of `found` (time, partner) and the collisions of ED particle `i`
    /// (synchronised at `now`) with the walls, but the one sharing its transient; a
    /// wall w is partner `n + w` (Bannerman et al. 2014, Algorithm 2).
    pub(crate) fn earliest_wall(&self, i: usize, now: f64, found: (f64, u32)) -> (f64, u32) {
        let (mut best, mut best_j) = found;
        let p = &self.system.particles;
        let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
        let n = self.mode.len();
        for (w, wall) in self.system.domain.walls.iter().enumerate() {
            if self.in_shared_transient(i, n + w) {
                continue;
            }
            let dt = sphere_wall(
                wall.distance(xi),
                dot(wall.normal, vi),
                dot(wall.normal, self.system.domain.gravity),
                ri,
            );
            if now + dt < best {
                best = now + dt;
                best_j = (n + w) as u32;
            }
        }
        (best, best_j)
    }

    /// Stores `i`'s predicted collision with `partner` (a particle, `n + w` for wall
    /// w, or NONE) at `time`, with the partner's counter for the staleness check.
    pub(crate) fn keep_collision(&mut self, i: usize, time: f64, partner: u32) {
        let n = self.mode.len();
        let coll_counter = if (partner as usize) < n {
            self.ed[partner as usize].counter
        } else {
            0
        };
        let rec = &mut self.ed[i];
        rec.coll_time = time;
        rec.coll_partner = partner;
        rec.coll_counter = coll_counter;
    }

    /// Predicts the earliest collision of ED particle `i` (synchronised at `now`) with
    /// an ED neighbour or a wall and queues its earliest event. While `i` is a party
    /// of an exception-(a) probe, every listed neighbour is shown to the probe: ED
    /// ones where they are now, TD ones extrapolated from the step start with a margin
    /// of one step's reach (see [`Hybrid::td_probe_margin`]).
    pub(crate) fn predict(&mut self, i: usize, now: f64) {
        if self.grid.is_some() {
            self.predict_in_cells(i, now);
            return;
        }
        self.sync(i, now);
        let p = &self.system.particles;
        let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
        let probe = self
            .probe
            .and_then(|probe| Some((probe, probe.slot_of(i)?)));
        let (t0, td_margin) = (self.time(), self.td_probe_margin());
        let mut blocked = false;
        let mut best = f64::INFINITY;
        let mut best_j = NONE;
        for &entry in self.list.of(i) {
            let (j, s) = self.list.split(entry);
            if let Some((probe, slot)) = &probe {
                let (xj, margin) = match self.mode[j] {
                    Mode::Removed => ([f64::NAN; 3], 0.0),
                    Mode::Event => (self.state_at(j, now).0, 0.0),
                    Mode::Time => (
                        std::array::from_fn(|k| p.position[j][k] + p.velocity[j][k] * (now - t0)),
                        td_margin,
                    ),
                };
                // The image of j next to i: r = x_i − (x_j + s).
                let image: [f64; 3] = std::array::from_fn(|k| xj[k] + s[k]);
                let contact = ri + p.radius[j] + margin;
                blocked |= self.mode[j] != Mode::Removed
                    && probe.blocks(*slot, j, sub(xi, image), image, contact, |d| d);
            }
            if self.mode[j] != Mode::Event || self.in_shared_transient(i, j) {
                continue;
            }
            let (xj, vj) = self.state_at(j, now);
            let r: [f64; 3] = std::array::from_fn(|k| xi[k] - xj[k] - s[k]);
            let (v, sigma) = (sub(vi, vj), ri + p.radius[j]);
            // Most candidates miss: one well-predicted test before the exact time.
            if !on_collision_course(r, v, sigma) {
                continue;
            }
            let dt = sphere_sphere(r, v, sigma);
            if now + dt < best {
                best = now + dt;
                best_j = j as u32;
            }
        }
        if blocked && let Some(probe) = &mut self.probe {
            probe.blocked = true;
        }
        let (best, best_j) = self.earliest_wall(i, now, (best, best_j));
        self.keep_collision(i, best, best_j);
        self.ed[i].cross_time = f64::INFINITY;
        self.schedule(i);
    }

    /// How close a jump may bring an ED particle to a TD one: within one step's reach,
    /// the guard (which runs at step boundaries) would find the pair in contact.
    pub(crate) fn td_probe_margin(&self) -> f64 {
        2.0 * (self.v_max_td + self.v_max_ed) * self.opts.dt
    }

    /// Queues the earliest event of `i` (a frozen particle's only event is its next
    /// cell crossing, on the cell path).
    pub(crate) fn schedule(&mut self, i: usize) {
        let rec = &self.ed[i];
        let time = if rec.frozen {
            rec.cross_time
        } else {
            rec.coll_time.min(rec.pending_time).min(rec.cross_time)
        };
        let time = if time.is_finite() {
            time
        } else {
            f64::INFINITY
        };
        self.heap.set(i, time);
    }

    /// Processes every ED event up to `t_end`, in time order.
    #[inline(never)]
    pub(crate) fn process_events(&mut self, t_end: f64) -> Result<(), HybridError> {
        // Every branch below queues the particle's next event (or +∞).
        loop {
            let (i, t) = self.heap.peek();
            // +∞ when no event is left (`schedule` never queues NaN).
            if t > t_end {
                break;
            }
            if self.mode[i] != Mode::Event {
                self.heap.set(i, f64::INFINITY);
                continue;
            }
            let rec = &self.ed[i];
            if rec.frozen || (rec.pending_time > t && rec.cross_time < rec.coll_time) {
                self.crossing(i, t);
                continue;
            }
            self.stats.ed.events += 1;
            if self.over_budget(i) {
                continue;
            }
            self.now = t;
            if self.ed[i].pending_time <= t {
                collision::velocity_event(self, i);
                continue;
            }
            let j = self.ed[i].coll_partner as usize;
            let n = self.mode.len();
            if j < n
                && (self.mode[j] != Mode::Event || self.ed[j].counter != self.ed[i].coll_counter)
            {
                self.stats.ed.stale += 1;
                self.predict(i, t);
                continue;
            }
            // The rules act on the rest of the engine, its host.
            let mut rules = std::mem::take(&mut self.rules);
            let done = if j >= n {
                collision::wall_collision(self, &mut rules, i, j - n)
            } else {
                collision::pair_collision(self, &mut rules, i, j).map(|_| ())
            };
            self.rules = rules;
            done?;
        }
        Ok(())
    }

    /// Counts an event of `i`; over the budget the particle is frozen and switched to
    /// TD at the end of the step.
    fn over_budget(&mut self, i: usize) -> bool {
        let step = self.steps;
        let rec = &mut self.ed[i];
        if rec.budget_step != step {
            rec.budget_step = step;
            rec.events = 0;
        }
        rec.events += 1;
        if rec.events > self.opts.max_events_per_step {
            rec.frozen = true;
            // Drops its queued event (on the cell path, queues its next crossing).
            self.schedule(i);
            self.deferred.push(i as u32);
            return true;
        }
        false
    }

    /// ED → TD at time `t` (a step boundary). A transient is ended first, for both
    /// partners, and the partner switches too (crate docs).
    pub(crate) fn switch_to_td(&mut self, i: usize, t: f64) {
        if self.mode[i] != Mode::Event {
            return;
        }
        self.sync(i, t);
        self.now = t;
        let partner = self.ed[i].partner as usize;
        if self.ed[i].pending_time.is_finite() {
            collision::finish_transient(self, i);
            self.stats.early_transient_ends += 1;
            if partner < self.mode.len()
                && self.mode[partner] == Mode::Event
                && self.ed[partner].partner == i as u32
            {
                collision::finish_transient(self, partner);
                self.set_time_driven(partner);
            }
        }
        self.set_time_driven(i);
    }

    fn set_time_driven(&mut self, i: usize) {
        self.mode[i] = Mode::Time;
        self.contact_acc[i] = [0.0; 3];
        let rec = &mut self.ed[i];
        rec.counter = rec.counter.wrapping_add(1);
        rec.partner = NONE;
        rec.pending_time = f64::INFINITY;
        rec.frozen = false;
        self.heap.set(i, f64::INFINITY);
        self.td_dirty = true;
        self.converted.push(i as u32);
        self.boundary.push(i as u32);
        self.stats.to_time += 1;
    }

    /// Records a jump of particle `p` by `dx` (it counts against the list's skin).
    pub(crate) fn record_jump(&mut self, p: usize, dx: [f64; 3]) {
        self.jump[p] += norm(dx);
        self.max_jump = self.max_jump.max(self.jump[p]);
    }

    pub(crate) fn note_speed(&mut self, v: [f64; 3]) {
        self.v_max_ed = self.v_max_ed.max(norm(v));
    }
}
