//! Reading the engine's state: positions, velocities, energy and momentum, by original
//! particle number (slots are re-sorted in space).

use super::EventEngine;
use crate::broad_phase::BroadPhase;
use crate::collision::transient_gravity;
use crate::queue::EventQueue;
use emdstar_contact::vec3::dot;
use emdstar_system::{Domain, Particles, StressMark, StressSums, Thermo};

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// Brings every particle to the current time (for output and measurements).
    pub fn sync(&mut self) {
        let now = self.state.time;
        for i in 0..self.len() {
            self.state.advance(i, now);
        }
    }

    /// Positions at the current time (call [`Engine::sync`] first), inside the box
    /// along periodic axes (the broad phases wrap stored positions at different times).
    pub fn positions(&self) -> Vec<[f64; 3]> {
        self.in_original_order(|i| self.state.wrap(self.state.slot[i].kin.pos))
    }

    /// `f(slot)` for every particle, listed by original particle number.
    pub(crate) fn in_original_order<T: Copy + Default>(&self, f: impl Fn(usize) -> T) -> Vec<T> {
        let mut out = vec![T::default(); self.len()];
        for (i, &id) in self.state.id.iter().enumerate() {
            out[id as usize] = f(i);
        }
        out
    }

    /// Velocities at the current time (call [`Engine::sync`] first). Particles in an
    /// eMD* transient show their centre-of-mass velocity.
    pub fn velocities(&self) -> Vec<[f64; 3]> {
        self.in_original_order(|i| self.state.slot[i].kin.vel)
    }

    /// Velocity of slot `i` now, counting a pending E^v as done (what the particle will
    /// have once its collision is over; use for energy and momentum balances).
    pub(crate) fn settled_velocity(&self, i: usize) -> [f64; 3] {
        let s = &self.state;
        let ev = &s.slot[i].ev;
        if ev.pending_time.is_finite() {
            let early = ev.pending_time - s.time;
            let v = s.pending_vel[i];
            let g = transient_gravity(s.domain.gravity, &s.domain.walls, s.len(), ev.partner);
            std::array::from_fn(|k| v[k] - g[k] * early)
        } else {
            s.state_at(i, s.time).1
        }
    }

    /// Velocities with pending E^v velocities applied, by original particle number.
    pub fn settled_velocities(&self) -> Vec<[f64; 3]> {
        self.in_original_order(|i| self.settled_velocity(i))
    }

    /// Kinetic energy Σ ½ m v² with pending E^v velocities applied.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| {
                let v = self.settled_velocity(i);
                0.5 * self.state.mass[i] * dot(v, v)
            })
            .sum()
    }

    /// Momentum Σ m v with pending E^v velocities applied.
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for i in 0..self.len() {
            let v = self.settled_velocity(i);
            for k in 0..3 {
                p[k] += self.state.mass[i] * v[k];
            }
        }
        p
    }

    /// Copies the current state (pending E^v velocities applied) into `particles`,
    /// which must be the particles the engine was built from (same order). Brings
    /// every particle to now first ([`Engine::sync`]).
    pub fn write_state(&mut self, particles: &mut Particles) {
        self.sync();
        particles.position = self.positions();
        particles.velocity = self.settled_velocities();
        particles.angular_velocity = self.state.spin.clone();
    }

    /// Angular velocities in rad/s, by original particle number.
    pub fn angular_velocities(&self) -> Vec<[f64; 3]> {
        self.state.spin.clone()
    }

    /// Radii and masses, in particle order.
    pub fn radii(&self) -> Vec<f64> {
        self.in_original_order(|i| self.state.slot[i].kin.radius)
    }

    pub fn masses(&self) -> Vec<f64> {
        self.in_original_order(|i| self.state.mass[i])
    }
}

/// The granular temperature of `p`, of the velocities relative to the streaming
/// profile in a sheared box.
pub(crate) fn peculiar_temperature(p: &Particles, domain: &Domain) -> f64 {
    match domain.lees_edwards() {
        Some(le) => {
            let mut q = p.clone();
            le.peculiar(&mut q);
            q.granular_temperature()
        }
        None => p.granular_temperature(),
    }
}

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// The particles now, by original particle number, without moving any stored
    /// state: positions where each particle is now (wrapped into the box), velocities
    /// with pending E^v velocities applied.
    pub fn particles_now(&self) -> Particles {
        let s = &self.state;
        let n = self.len();
        let position = self.in_original_order(|i| s.wrap(s.state_at(i, s.time).0));
        let velocity = self.in_original_order(|i| self.settled_velocity(i));
        let radius = self.in_original_order(|i| s.slot[i].kin.radius);
        let mass = self.in_original_order(|i| s.mass[i]);
        let species = self.in_original_order(|i| s.species[i]);
        let image = self.in_original_order(|i| self.image(i));
        Particles {
            position,
            velocity,
            // Kept by original particle number already.
            angular_velocity: s.spin.clone(),
            species,
            radius,
            mass,
            id: (0..n as u32).collect(),
            image,
        }
    }

    /// Energies, temperature and momentum now, pending E^v velocities applied (see
    /// [`EventEngine::particles_now`]). The potential energy is −Σ m g·x; contacts are
    /// instantaneous, so none is counted.
    pub fn thermo(&self) -> Thermo {
        let p = self.particles_now();
        let g = self.state.domain.gravity;
        let mut potential = 0.0;
        for (m, x) in p.mass.iter().zip(&p.position) {
            potential -= m * dot(g, *x);
        }
        Thermo {
            t: self.state.time,
            step: self.state.stats.events,
            kinetic_energy: p.kinetic_energy(),
            rotational_energy: p.rotational_energy(),
            potential_energy: potential,
            granular_temperature: peculiar_temperature(&p, &self.state.domain),
            rotational_temperature: p.rotational_temperature(),
            momentum: p.momentum(),
            contacts: 0,
        }
    }

    /// The sums behind the pressure tensor and the collision rate since the start
    /// (see [`StressSums`]), counting the motion of the particles `members` accepts
    /// (all but in the hybrid, whose time-driven particles the core does not move).
    pub fn stress_sums(&self, members: impl Fn(usize) -> bool) -> StressSums {
        let s = &self.state;
        StressSums {
            kinetic: s.kinetic_until(s.time, members),
            collisional: s.stats.collisional_virial,
            collisions: s.stats.pair_collisions,
        }
    }

    /// The sums and time of the last mark.
    pub fn stress_mark(&self) -> Option<StressMark> {
        self.state.stress_mark
    }

    /// Keeps `sums` (this engine's, or the hybrid's) at time `t` as the mark.
    pub fn mark_stress(&mut self, t: f64, sums: StressSums) {
        self.state.stress_mark = Some(StressMark { t, sums });
    }

    /// The box, walls (unit normals) and gravity.
    pub fn domain(&self) -> &Domain {
        &self.state.domain
    }
}
