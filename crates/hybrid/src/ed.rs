//! The event-driven part: eMD* among ED particles (Müller & Pöschel 2013, Sec. VI B)
//! with stable detection (Bannerman et al. 2014), lazily updated particles, a binary
//! queue holding each ED particle's earliest event (`emdstar_edmd`'s calendar queue,
//! ties to the smaller particle number), and the ED → TD switch.

use crate::engine::{Hybrid, norm};
use crate::options::{HybridError, Mode};
use emdstar_contact::{Impact, Vec3, scale};
use emdstar_edmd::EventQueue;
use emdstar_edmd::detect::{sphere_sphere, sphere_wall};
use emdstar_edmd::rules::restitution_kick;
use emdstar_mor::rule::{Body, resolve, resolve_wall};

/// No partner.
pub(crate) const NONE: u32 = u32::MAX;

/// The event state of one particle (meaningful while it is ED).
#[derive(Debug, Clone, Copy)]
pub(crate) struct EdRec {
    /// Time at which the stored position and velocity hold.
    pub stamp: f64,
    pub coll_time: f64,
    /// Partner particle, or `n + w` for wall w.
    pub coll_partner: u32,
    /// The partner's counter at the prediction.
    pub coll_counter: u32,
    /// eMD*: time of the pending E^v event (+∞ if none) and the velocity it applies.
    pub pending_time: f64,
    pub pending_vel: [f64; 3],
    /// eMD*: who shares the transient (particle, `n + w`, or NONE).
    pub partner: u32,
    /// Incremented whenever the particle's trajectory jumps.
    pub counter: u32,
    /// The step whose events `events` counts.
    pub budget_step: u64,
    pub events: u32,
    /// Over its event budget: no own events until the end of the step (on the cell
    /// path it still crosses cells).
    pub frozen: bool,
    /// Cell path: time of the next cell crossing (+∞ on the list path) and the face
    /// (axis·2 + 1 if moving up).
    pub cross_time: f64,
    pub cross_face: u8,
}

impl Default for EdRec {
    fn default() -> Self {
        Self {
            stamp: 0.0,
            coll_time: f64::INFINITY,
            coll_partner: NONE,
            coll_counter: 0,
            pending_time: f64::INFINITY,
            pending_vel: [0.0; 3],
            partner: NONE,
            counter: 0,
            budget_step: 0,
            events: 0,
            frozen: false,
            cross_time: f64::INFINITY,
            cross_face: 0,
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

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
            let g = self.system.domain.gravity;
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

    /// Time from `now` until a sphere at (x, v, R) = `a` hits ED particle `j` seen at
    /// its image shift `s` (Bannerman et al. 2014, Algorithm 1; +∞ if never).
    #[inline(always)]
    pub(crate) fn pair_time(
        &self,
        (xi, vi, ri): ([f64; 3], [f64; 3], f64),
        j: usize,
        s: [f64; 3],
        now: f64,
    ) -> f64 {
        let (xj, vj) = self.state_at(j, now);
        let r: [f64; 3] = std::array::from_fn(|k| xi[k] - xj[k] - s[k]);
        let v: [f64; 3] = std::array::from_fn(|k| vi[k] - vj[k]);
        sphere_sphere(r, v, ri + self.system.particles.radius[j])
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
    /// an ED neighbour or a wall and queues its earliest event.
    pub(crate) fn predict(&mut self, i: usize, now: f64) {
        if self.grid.is_some() {
            self.predict_in_cells(i, now);
            return;
        }
        self.sync(i, now);
        let p = &self.system.particles;
        let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
        let mut best = f64::INFINITY;
        let mut best_j = NONE;
        for &entry in self.list.of(i) {
            let (j, s) = self.list.split(entry);
            if self.mode[j] != Mode::Event || self.in_shared_transient(i, j) {
                continue;
            }
            let dt = self.pair_time((xi, vi, ri), j, s, now);
            if now + dt < best {
                best = now + dt;
                best_j = j as u32;
            }
        }
        let (best, best_j) = self.earliest_wall(i, now, (best, best_j));
        self.keep_collision(i, best, best_j);
        self.ed[i].cross_time = f64::INFINITY;
        self.schedule(i);
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
            self.stats.events += 1;
            if self.over_budget(i) {
                continue;
            }
            if self.ed[i].pending_time <= t {
                self.stats.velocity_events += 1;
                self.finish_transient(i, t);
                self.predict(i, t);
                continue;
            }
            let j = self.ed[i].coll_partner as usize;
            let n = self.mode.len();
            if j >= n {
                self.wall_collision(i, j - n, t)?;
            } else if self.mode[j] != Mode::Event || self.ed[j].counter != self.ed[i].coll_counter {
                self.predict(i, t);
            } else {
                self.pair_collision(i, j, t)?;
            }
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

    /// Applies `i`'s pending post-collision velocity at `t` (its E^v time, or early).
    pub(crate) fn finish_transient(&mut self, i: usize, t: f64) {
        self.sync(i, t);
        let rec = &mut self.ed[i];
        let early = rec.pending_time - t;
        let g = self.system.domain.gravity;
        self.system.particles.velocity[i] =
            std::array::from_fn(|k| rec.pending_vel[k] - g[k] * early);
        rec.pending_time = f64::INFINITY;
        rec.partner = NONE;
        rec.counter = rec.counter.wrapping_add(1);
    }

    /// ED → TD at time `t` (a step boundary). A transient is ended first, for both
    /// partners, and the partner switches too (crate docs).
    pub(crate) fn switch_to_td(&mut self, i: usize, t: f64) {
        if self.mode[i] != Mode::Event {
            return;
        }
        self.sync(i, t);
        let partner = self.ed[i].partner as usize;
        if self.ed[i].pending_time.is_finite() {
            self.finish_transient(i, t);
            self.stats.early_transient_ends += 1;
            if partner < self.mode.len()
                && self.mode[partner] == Mode::Event
                && self.ed[partner].partner == i as u32
            {
                self.sync(partner, t);
                self.finish_transient(partner, t);
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
    fn record_jump(&mut self, p: usize, dx: [f64; 3]) {
        self.jump[p] += norm(dx);
        self.max_jump = self.max_jump.max(self.jump[p]);
    }

    fn note_speed(&mut self, v: [f64; 3]) {
        self.v_max_ed = self.v_max_ed.max(norm(v));
    }

    /// A pair collision of ED particles at `t`: eMD*'s E^φ event with exceptions (a)
    /// and (b) (Müller & Pöschel 2013, Sec. VI B 2 and 5).
    fn pair_collision(&mut self, i: usize, j: usize, t: f64) -> Result<(), HybridError> {
        self.sync(i, t);
        self.sync(j, t);
        let mut interfered = false;
        for p in [i, j] {
            if self.ed[p].pending_time.is_finite() {
                interfered = true;
                self.finish_transient(p, t);
            }
        }
        let min_image = |d: [f64; 3]| self.system.domain.sim_box.map_or(d, |b| b.min_image(d));
        let p = &self.system.particles;
        let r = min_image(std::array::from_fn(|k| p.position[i][k] - p.position[j][k]));
        let v: [f64; 3] = std::array::from_fn(|k| p.velocity[i][k] - p.velocity[j][k]);
        if interfered {
            self.stats.exception_interference += 1;
            if dot(r, v) >= 0.0 {
                self.predict(i, t);
                self.predict(j, t);
                return Ok(());
            }
        }
        self.stats.pair_collisions += 1;
        let (mi, mj) = (p.mass[i], p.mass[j]);
        let entry = *self.materials.pair(p.species[i], p.species[j]).interaction;
        let impact = Impact::from_relative(&vec3(r), &vec3(v))?;
        let scaled = scale(&entry.law, &entry.props, &impact)?;
        let (mor, fallback) = self.mor.mor(entry.law.model(), &scaled.params)?;
        self.stats.mor_fallbacks += u64::from(fallback);
        let xj = p.position[j];
        let xi_unwrapped: [f64; 3] = std::array::from_fn(|k| xj[k] + r[k]);
        let bodies = [
            Body {
                position: vec3(xi_unwrapped),
                velocity: vec3(p.velocity[i]),
                mass: mi,
            },
            Body {
                position: vec3(xj),
                velocity: vec3(p.velocity[j]),
                mass: mj,
            },
        ];
        let out = resolve(&bodies, entry.props.l, &mor, scaled.time);
        // Displacements, applied to each particle's own (possibly wrapped) coordinates.
        let di: [f64; 3] = std::array::from_fn(|k| out.rotated_positions[0][k] - xi_unwrapped[k]);
        let dj: [f64; 3] = std::array::from_fn(|k| out.rotated_positions[1][k] - xj[k]);
        if self.rotation_blocked(&[(i, di), (j, dj)], None, t) {
            self.stats.exception_rotation += 1;
            let (ki, kj) = restitution_kick(r, v, mi, mj, -mor.eps_rdot);
            let p = &mut self.system.particles;
            for k in 0..3 {
                p.velocity[i][k] += ki[k];
                p.velocity[j][k] += kj[k];
            }
        } else {
            let g = self.system.domain.gravity;
            let end = t + out.duration;
            for (slot, (q, d)) in [(i, di), (j, dj)].into_iter().enumerate() {
                let x = self.system.particles.position[q];
                self.system.particles.position[q] = std::array::from_fn(|k| x[k] + d[k]);
                self.system.particles.velocity[q] = arr(&out.transient_velocity);
                let post = out.post_velocities[slot];
                let rec = &mut self.ed[q];
                rec.pending_vel = std::array::from_fn(|k| post[k] + g[k] * out.duration);
                rec.pending_time = end;
                self.record_jump(q, d);
                self.place(q);
                self.note_speed(self.ed[q].pending_vel);
            }
            self.ed[i].partner = j as u32;
            self.ed[j].partner = i as u32;
        }
        for q in [i, j] {
            self.ed[q].counter = self.ed[q].counter.wrapping_add(1);
            self.note_speed(self.system.particles.velocity[q]);
        }
        self.predict(i, t);
        self.predict(j, t);
        Ok(())
    }

    /// Whether a move of a sphere of `radius` from `x_old` to `x_new` pushes it deeper
    /// into a wall other than `own_wall` (the one it collides with, whose E^φ sets its
    /// distance to l·ε_r by design): part of exception (a).
    pub(crate) fn wall_blocks(
        &self,
        radius: f64,
        x_old: [f64; 3],
        x_new: [f64; 3],
        own_wall: Option<usize>,
    ) -> bool {
        self.system
            .domain
            .walls
            .iter()
            .enumerate()
            .any(|(index, w)| {
                let (h_new, h_old) = (w.distance(x_new), w.distance(x_old));
                own_wall != Some(index) && h_new < radius && h_new < h_old
            })
    }

    /// Exception (a): would displacing the parties push any of them deeper into a third
    /// particle (ED or TD) or a wall other than `own_wall` (the one being hit)? TD
    /// particles are extrapolated from the step start.
    fn rotation_blocked(
        &self,
        parties: &[(usize, [f64; 3])],
        own_wall: Option<usize>,
        t: f64,
    ) -> bool {
        if self.grid.is_some() {
            return self.rotation_blocked_in_cells(parties, own_wall, t);
        }
        let p = &self.system.particles;
        let t0 = self.time();
        let td_margin = 2.0 * (self.v_max_td + self.v_max_ed) * self.opts.dt;
        for &(q, d) in parties {
            let x_old = p.position[q];
            let x_new: [f64; 3] = std::array::from_fn(|k| x_old[k] + d[k]);
            for &entry in self.list.of(q) {
                let (k, s) = self.list.split(entry);
                if parties.iter().any(|&(o, _)| o == k) {
                    continue;
                }
                // A jump must not bring an ED particle within one step's reach of a TD
                // particle either: the guard, which runs at step boundaries, would then
                // find the pair already in contact.
                let (xk, margin) = match self.mode[k] {
                    Mode::Removed => continue,
                    Mode::Event => (self.state_at(k, t).0, 0.0),
                    Mode::Time => (
                        std::array::from_fn(|c| p.position[k][c] + p.velocity[k][c] * (t - t0)),
                        td_margin,
                    ),
                };
                let contact = p.radius[q] + p.radius[k] + margin;
                let d_new = norm(std::array::from_fn(|c| x_new[c] - xk[c] - s[c]));
                let d_old = norm(std::array::from_fn(|c| x_old[c] - xk[c] - s[c]));
                if d_new < contact && d_new < d_old {
                    return true;
                }
            }
            if self.wall_blocks(p.radius[q], x_old, x_new, own_wall) {
                return true;
            }
        }
        false
    }

    /// An ED wall collision at `t`: eMD*'s E^φ against a flat wall (a central
    /// collision along the normal, `emdstar_mor::rule::resolve_wall`), or at the top
    /// of a flight inside the wall a stabilising event without velocity change
    /// (Bannerman 2014, Algorithm 2).
    fn wall_collision(&mut self, i: usize, w: usize, t: f64) -> Result<(), HybridError> {
        self.sync(i, t);
        if self.ed[i].pending_time.is_finite() {
            self.stats.exception_interference += 1;
            self.finish_transient(i, t);
        }
        self.stats.wall_collisions += 1;
        let wall = self.system.domain.walls[w];
        let n = wall.normal;
        let p = &self.system.particles;
        let vi = p.velocity[i];
        let vn = dot(n, vi);
        if vn < 0.0 {
            let entry = *self.materials.wall(p.species[i]).interaction;
            let impact = Impact {
                normal_speed: -vn,
                tangential_speed: 0.0,
            };
            let scaled = scale(&entry.law, &entry.props, &impact)?;
            let (mor, fallback) = self.mor.mor(entry.law.model(), &scaled.params)?;
            self.stats.mor_fallbacks += u64::from(fallback);
            let x = p.position[i];
            let body = Body {
                position: vec3(std::array::from_fn(|k| x[k] - wall.point[k])),
                velocity: vec3(vi),
                mass: p.mass[i],
            };
            let out = resolve_wall(&body, &vec3(n), entry.props.l, &mor, scaled.time);
            let rel = out.rotated_positions[0];
            let d: [f64; 3] = std::array::from_fn(|k| rel[k] + wall.point[k] - x[k]);
            if self.rotation_blocked(&[(i, d)], Some(w), t) {
                self.stats.exception_rotation += 1;
                let kick = (1.0 - mor.eps_rdot) * vn;
                self.system.particles.velocity[i] = std::array::from_fn(|k| vi[k] - kick * n[k]);
            } else {
                self.system.particles.position[i] = std::array::from_fn(|k| x[k] + d[k]);
                self.system.particles.velocity[i] = arr(&out.transient_velocity);
                let post = out.post_velocities[0];
                // During the contact the wall carries the normal part of gravity: an
                // elastic sphere leaves a wall under gravity with its impact speed
                // (energy balance at ξ = 0), so only the tangential part of g acts
                // over τ. (Adding all of g·τ, as for a freely falling pair, would
                // take g_n·τ off every rebound.)
                let g = self.system.domain.gravity;
                let g_n = dot(g, n);
                let g_t: [f64; 3] = std::array::from_fn(|k| g[k] - g_n * n[k]);
                let rec = &mut self.ed[i];
                rec.pending_vel = std::array::from_fn(|k| post[k] + g_t[k] * out.duration);
                rec.pending_time = t + out.duration;
                rec.partner = (self.mode.len() + w) as u32;
                self.record_jump(i, d);
                self.place(i);
                self.note_speed(self.ed[i].pending_vel);
            }
        }
        self.ed[i].counter = self.ed[i].counter.wrapping_add(1);
        self.note_speed(self.system.particles.velocity[i]);
        self.predict(i, t);
        Ok(())
    }
}
