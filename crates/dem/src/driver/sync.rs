//! Velocities in step with the positions: the driver's pending half kick, applied
//! ([`Verlet::synchronise`]) or read ([`Verlet::velocities_now`]).

use super::{Members, Verlet};
use crate::options::MdError;
use crate::verlet::{kick_contacts, max_nan};
use emdstar_system::Particles;

/// v + g·dt/2, component by component (the gravity half kick of a synchronisation).
#[inline]
fn half_kick_gravity(v: [f64; 3], g: [f64; 3], dt: f64) -> [f64; 3] {
    [
        v[0] + g[0] * 0.5 * dt,
        v[1] + g[1] * 0.5 * dt,
        v[2] + g[2] * 0.5 * dt,
    ]
}

impl Verlet {
    /// Applies the pending half kick to the members, if their velocities lag (they are
    /// then in step with the positions), and reports a blow-up (of a member) at time
    /// `t`.
    pub fn synchronise<M: Members>(
        &mut self,
        p: &mut Particles,
        members: M,
        g: [f64; 3],
        t: f64,
    ) -> Result<(), MdError> {
        if !self.lagging {
            return Ok(());
        }
        self.lagging = false;
        let h = 0.5 * self.opts.dt;
        self.kick(p, h);
        let dt = self.opts.dt;
        let mut v2_max: f64 = 0.0;
        for (i, v) in p.velocity.iter_mut().enumerate() {
            if members.contains(i) {
                *v = half_kick_gravity(*v, g, dt);
                v2_max = max_nan(v2_max, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            }
        }
        self.v_max = v2_max.sqrt();
        if self.v_max.is_nan() {
            let bad = (0..p.len()).find(|&i| {
                members.contains(i)
                    && !p.velocity[i]
                        .iter()
                        .chain(&p.position[i])
                        .all(|c| c.is_finite())
            });
            return Err(MdError::BlewUp {
                id: bad.map_or(0, |i| p.id[i]),
                t,
            });
        }
        Ok(())
    }

    /// The members' velocities (in step) were changed from outside: their largest
    /// speed, which bounds the drift between list rebuilds, follows them.
    pub fn speeds_changed<M: Members>(&mut self, p: &Particles, members: M) {
        self.v_max = p
            .velocity
            .iter()
            .enumerate()
            .filter(|&(i, _)| members.contains(i))
            .map(|(_, v)| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            .fold(0.0, max_nan)
            .sqrt();
    }

    /// The members' velocities now (the others' as stored): with the pending half kick
    /// applied (the arithmetic of [`Verlet::synchronise`]).
    pub fn velocities_now<M: Members>(
        &self,
        p: &Particles,
        members: M,
        g: [f64; 3],
    ) -> Vec<[f64; 3]> {
        let mut v = p.velocity.clone();
        if self.lagging {
            let dt = self.opts.dt;
            kick_contacts(&mut v, &self.contact_acc, &self.touched, 0.5 * dt);
            for (i, w) in v.iter_mut().enumerate() {
                if members.contains(i) {
                    *w = half_kick_gravity(*w, g, dt);
                }
            }
        }
        v
    }

    /// The spins now: the stored ones with the pending half kick applied.
    pub fn spins_now(&self, p: &Particles) -> Vec<[f64; 3]> {
        let mut w = p.angular_velocity.clone();
        if let (Some(rot), true) = (&self.rotation, self.lagging) {
            kick_contacts(&mut w, &rot.angular_acc, &self.touched, 0.5 * self.opts.dt);
        }
        w
    }
}
