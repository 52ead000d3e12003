//! Executing collisions: hard spheres, eMD and the three events of eMD*
//! (Müller & Pöschel 2013, Sec. VI B), with the exceptions of Sec. VI B 5.

use crate::cells::NONE;
use crate::engine::{Engine, Kin, dot, sub};
use crate::error::Result;
use crate::queue::EventQueue;
use crate::rules::restitution_kick;
use crate::setup::{Interference, Physics};
use emdstar_contact::{Impact, Vec3, scale};
use emdstar_mor::rule::{Body, resolve, resolve_wall};

fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// eMD* exception (a) (Müller & Pöschel 2013, Sec. VI B 5) folded into the neighbour
/// scans of the predictions that follow an E^φ: the parties sit at their rotated
/// positions, and a scan that meets a third particle within contact of a party's new
/// position and closer to it than to the old one marks the rotation blocked; the
/// E^φ is then undone and the eMD rule applied. The scans visit every particle that
/// could be within contact, so no scan of its own is needed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RotationProbe {
    pub parties: [u32; 2],
    /// Each party's kinematics and cell before the rotation.
    pub before: [(Kin, [u32; 3]); 2],
    /// The eMD restitution to apply instead.
    pub fallback: f64,
    pub blocked: bool,
}

impl<Q: EventQueue> Engine<Q> {
    /// Whether third particle `k`, at `xk` now and `r` = (new position of party
    /// `slot` of `probe`) − `xk` (its image), blocks the rotation: within `contact`
    /// of the new position and closer to it than to the old one.
    #[inline(always)]
    pub(crate) fn blocks_rotation(
        &self,
        probe: &RotationProbe,
        slot: usize,
        k: usize,
        r: [f64; 3],
        xk: [f64; 3],
        contact: f64,
    ) -> bool {
        self.pushes_deeper(r, probe.before[slot].0.pos, xk, contact)
            && !probe.parties.contains(&(k as u32))
    }

    /// Whether a sphere moved from `old` to the point at `r` from `xk` (minimum image)
    /// ends within `contact` of `xk` and closer than it was.
    #[inline(always)]
    fn pushes_deeper(&self, r: [f64; 3], old: [f64; 3], xk: [f64; 3], contact: f64) -> bool {
        let d_new = dot(r, r);
        d_new < contact * contact && {
            let d_old = self.min_image(sub(old, xk));
            d_new < dot(d_old, d_old)
        }
    }

    /// Which party of the running exception-(a) probe `i` is, if any.
    #[inline]
    pub(crate) fn probe_slot(&self, i: usize) -> Option<(RotationProbe, usize)> {
        let probe = self.probe?;
        let slot = probe.parties.iter().position(|&p| p as usize == i)?;
        Some((probe, slot))
    }

    /// Runs the pending E^v of `i` early because a third party hits it (exception b),
    /// and with [`Interference::BothPartners`] that of its partner too.
    fn interrupt_transient(&mut self, i: usize, interference: Interference) {
        let partner = self.slot[i].ev.partner as usize;
        self.finish_transient(i);
        if interference == Interference::BothPartners
            && partner < self.len()
            && self.slot[partner].ev.pending_time.is_finite()
            && self.slot[partner].ev.partner == i as u32
        {
            self.finish_transient(partner);
            self.stats.early_partner_updates += 1;
            self.predict(partner);
        }
    }

    /// Handles exception (b) for the parties of a collision about to happen. Returns
    /// false if one of them was in a transient.
    fn settle_transients(&mut self, parties: &[usize]) -> bool {
        let interference = match &self.physics {
            Physics::EmdStar { interference, .. } => *interference,
            _ => return true,
        };
        let mut clean = true;
        for &p in parties {
            if self.slot[p].ev.pending_time.is_finite() {
                clean = false;
                self.interrupt_transient(p, interference);
            }
        }
        if !clean {
            self.stats.exception_interference += 1;
        }
        clean
    }

    /// Executes the predicted collision of `i` and `j` at the current time. Returns
    /// false if an eMD* transient had to end first and the pair then no longer
    /// approached.
    pub(crate) fn pair_collision(&mut self, i: usize, j: usize) -> Result<bool> {
        let now = self.time;
        self.advance(i, now);
        self.advance(j, now);
        if !self.settle_transients(&[i, j]) {
            let r = self.min_image(sub(self.slot[i].kin.pos, self.slot[j].kin.pos));
            if dot(r, sub(self.slot[i].kin.vel, self.slot[j].kin.vel)) >= 0.0 {
                self.stats.interference_resolved += 1;
                self.predict(i);
                self.predict(j);
                return Ok(false);
            }
        }
        let r = self.min_image(sub(self.slot[i].kin.pos, self.slot[j].kin.pos));
        let v = sub(self.slot[i].kin.vel, self.slot[j].kin.vel);
        let contact = self.slot[i].kin.radius + self.slot[j].kin.radius;
        let distance = dot(r, r).sqrt();
        self.stats.record_impact(distance, contact);
        self.stats.pair_collisions += 1;
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let eps = match &self.physics {
            Physics::HardSpheres { restitution } => Some(*restitution),
            Physics::Emd(m) => {
                let vn = -dot(r, v) / distance;
                let entry = m.pair(self.species[i], self.species[j]);
                Some(entry.central.at(vn, &mut self.hertz)?)
            }
            Physics::EmdStar { .. } => self.emdstar_pair(i, j, r, v)?,
        };
        if let Some(eps) = eps {
            let (di, dj) = restitution_kick(r, v, mi, mj, eps);
            for k in 0..3 {
                self.slot[i].kin.vel[k] += di[k];
                self.slot[j].kin.vel[k] += dj[k];
            }
        }
        self.slot[i].ev.counter = self.slot[i].ev.counter.wrapping_add(1);
        self.slot[j].ev.counter = self.slot[j].ev.counter.wrapping_add(1);
        self.predict(i);
        self.predict(j);
        if let Some(probe) = self.probe.take()
            && probe.blocked
        {
            // Exception (a): undo the rotation and apply the eMD rule instead.
            self.stats.exception_rotation += 1;
            for (slot, &p) in probe.parties.iter().enumerate() {
                let p = p as usize;
                let (kin, cell) = probe.before[slot];
                self.slot[p].kin = kin;
                self.slot[p].ev.pending_time = f64::INFINITY;
                self.slot[p].ev.partner = NONE;
                if self.epochs.is_none() {
                    self.grid.relocate(p, cell);
                }
            }
            let (di, dj) = restitution_kick(r, v, mi, mj, probe.fallback);
            for k in 0..3 {
                self.slot[i].kin.vel[k] += di[k];
                self.slot[j].kin.vel[k] += dj[k];
            }
            self.predict(i);
            self.predict(j);
        }
        Ok(true)
    }

    /// The E^φ event of eMD* for a pair (Sec. VI B 2). Returns the eMD restitution
    /// to use instead if the rotation is impossible (exception a).
    fn emdstar_pair(
        &mut self,
        i: usize,
        j: usize,
        r: [f64; 3],
        v: [f64; 3],
    ) -> Result<Option<f64>> {
        let Physics::EmdStar { materials, mor, .. } = &mut self.physics else {
            unreachable!("eMD* event without eMD* physics")
        };
        let entry = materials.pair(self.species[i], self.species[j]);
        let impact = Impact::from_relative(&vec3(r), &vec3(v))?;
        let scaled = scale(&entry.law, &entry.props, &impact)?;
        let (m, fallback) = mor.mor(entry.law.model(), &scaled.params)?;
        self.stats.mor_fallbacks += u64::from(fallback);
        let l = entry.props.l;
        // Unwrap i next to j so that the pair is contiguous.
        let pj = self.slot[j].kin.pos;
        let pi: [f64; 3] = std::array::from_fn(|k| pj[k] + r[k]);
        let bodies = [
            Body {
                position: vec3(pi),
                velocity: vec3(self.slot[i].kin.vel),
                mass: self.mass[i],
            },
            Body {
                position: vec3(pj),
                velocity: vec3(self.slot[j].kin.vel),
                mass: self.mass[j],
            },
        ];
        let out = resolve(&bodies, l, &m, scaled.time);
        let new = [
            arr(&out.rotated_positions[0]),
            arr(&out.rotated_positions[1]),
        ];
        if self.walls_block(&[i, j], &new, None) {
            self.stats.exception_rotation += 1;
            return Ok(Some(-m.eps_rdot));
        }
        // Third particles are checked by the predictions that follow (see
        // `RotationProbe`).
        self.probe = Some(RotationProbe {
            parties: [i as u32, j as u32],
            before: [i, j].map(|p| (self.slot[p].kin, self.grid.coords[p])),
            fallback: -m.eps_rdot,
            blocked: false,
        });
        let g = self.gravity;
        let end = self.time + out.duration;
        for (slot, &p) in [i, j].iter().enumerate() {
            self.place(p, new[slot]);
            self.slot[p].kin.vel = arr(&out.transient_velocity);
            let post = out.post_velocities[slot];
            self.pending_vel[p] = std::array::from_fn(|k| post[k] + g[k] * out.duration);
            self.slot[p].ev.pending_time = end;
        }
        self.slot[i].ev.partner = j as u32;
        self.slot[j].ev.partner = i as u32;
        Ok(None)
    }

    /// Puts particle `p` at position `x` now (wrapped, re-binned).
    fn place(&mut self, p: usize, x: [f64; 3]) {
        let x = self.wrap(x);
        self.slot[p].kin.pos = x;
        self.slot[p].kin.stamp = self.time;
        if self.epochs.is_none() {
            let c = self.grid.coords_of(x);
            self.grid.relocate(p, c);
        }
    }

    /// Exception (a) for a collision of `i` with wall `wall`: would moving `i` to `new`
    /// push it deeper into a third particle, or into another wall, than it is now? (A
    /// pair collision checks third particles with a [`RotationProbe`].)
    fn wall_rotation_blocked(&self, i: usize, new: [f64; 3], wall: usize) -> bool {
        let (now, old) = (self.time, self.slot[i].kin.pos);
        let blocked_by = |k: usize| {
            let (xk, _) = self.state_at(k, now);
            let contact = self.slot[i].kin.radius + self.slot[k].kin.radius;
            k != i && self.pushes_deeper(self.min_image(sub(new, xk)), old, xk, contact)
        };
        let third = if self.epochs.is_some() {
            // Filed boxes hold each sphere now: a third sphere within contact of the
            // new position is filed in a cell within the mover's radius of it.
            self.any_near_in_epoch(new, self.slot[i].kin.radius, blocked_by)
        } else {
            let c = self.grid.coords_of(self.wrap(new));
            let cells = self.grid.neighbourhood(c);
            cells
                .as_slice()
                .iter()
                .any(|&cell| self.grid.particles(cell).any(blocked_by))
        };
        third || self.walls_block(&[i], &[new], Some(wall))
    }

    /// Exception (a) for walls: would a party move deeper into a wall other than
    /// `own_wall` than it is now?
    fn walls_block(&self, parties: &[usize], new: &[[f64; 3]], own_wall: Option<usize>) -> bool {
        for (slot, &p) in parties.iter().enumerate() {
            let (x_new, x_old) = (new[slot], self.slot[p].kin.pos);
            for (w, wall) in self.walls.iter().enumerate() {
                if own_wall == Some(w) {
                    continue;
                }
                let h_new = dot(wall.normal, sub(x_new, wall.point));
                let h_old = dot(wall.normal, sub(x_old, wall.point));
                if h_new < self.slot[p].kin.radius && h_new < h_old {
                    return true;
                }
            }
        }
        false
    }

    /// Executes the predicted collision of `i` with wall `w` at the current time.
    pub(crate) fn wall_collision(&mut self, i: usize, w: usize) -> Result<()> {
        let now = self.time;
        self.advance(i, now);
        self.settle_transients(&[i]);
        let wall = self.walls[w];
        let n = wall.normal;
        let vn = dot(n, self.slot[i].kin.vel);
        self.stats.wall_collisions += 1;
        let height = dot(n, sub(self.slot[i].kin.pos, wall.point));
        if height < self.slot[i].kin.radius && vn >= 0.0 {
            self.stats.stabilising += 1;
        }
        let eps = if vn >= 0.0 {
            // A stabilising event at the top of a flight (Bannerman 2014, Alg. 2,
            // line 9): the sphere does not approach, so its velocity stays.
            None
        } else {
            match &self.physics {
                Physics::HardSpheres { restitution } => Some(*restitution),
                Physics::Emd(m) => Some(m.wall(self.species[i]).central.at(-vn, &mut self.hertz)?),
                Physics::EmdStar { .. } => self.emdstar_wall(i, w, -vn)?,
            }
        };
        if let Some(eps) = eps {
            let kick = (1.0 + eps) * vn;
            for (k, nk) in n.iter().enumerate() {
                self.slot[i].kin.vel[k] -= kick * nk;
            }
        }
        self.slot[i].ev.counter = self.slot[i].ev.counter.wrapping_add(1);
        self.predict(i);
        Ok(())
    }

    /// The E^φ event of eMD* against a flat wall: a central collision along the
    /// normal (Sec. IV applied with R₂, m₂ → ∞; see `emdstar_mor::rule::resolve_wall`).
    fn emdstar_wall(&mut self, i: usize, w: usize, v_n: f64) -> Result<Option<f64>> {
        let Physics::EmdStar { materials, mor, .. } = &mut self.physics else {
            unreachable!("eMD* event without eMD* physics")
        };
        let entry = materials.wall(self.species[i]);
        let impact = Impact {
            normal_speed: v_n,
            tangential_speed: 0.0,
        };
        let scaled = scale(&entry.law, &entry.props, &impact)?;
        let (m, fallback) = mor.mor(entry.law.model(), &scaled.params)?;
        self.stats.mor_fallbacks += u64::from(fallback);
        let wall = self.walls[w];
        let body = Body {
            position: vec3(sub(self.slot[i].kin.pos, wall.point)),
            velocity: vec3(self.slot[i].kin.vel),
            mass: self.mass[i],
        };
        let out = resolve_wall(&body, &vec3(wall.normal), entry.props.l, &m, scaled.time);
        let rel = out.rotated_positions[0];
        let new = std::array::from_fn(|k| rel[k] + wall.point[k]);
        if self.wall_rotation_blocked(i, new, w) {
            self.stats.exception_rotation += 1;
            return Ok(Some(-m.eps_rdot));
        }
        self.place(i, new);
        self.slot[i].kin.vel = arr(&out.transient_velocity);
        // The wall carries the normal part of gravity during the contact (an elastic
        // sphere leaves it with its impact speed), so only the tangential part acts
        // over τ; see `Engine::transient_gravity`.
        let post = out.post_velocities[0];
        let g = self.transient_gravity((self.len() + w) as u32);
        self.pending_vel[i] = std::array::from_fn(|k| post[k] + g[k] * out.duration);
        self.slot[i].ev.pending_time = self.time + out.duration;
        self.slot[i].ev.partner = (self.len() + w) as u32;
        Ok(None)
    }
}
