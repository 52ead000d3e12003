//! What the hybrid engine shows: the particles now and the thermo quantities, read
//! from both parts without moving either.

use super::Hybrid;
use crate::options::Mode;
use emdstar_dem::{ContactEnd, ForceModel};
use emdstar_system::{Particles, StressMark, StressSums, Thermo};

impl Hybrid {
    /// The particles now, in the engine's order: TD velocities and spins with their
    /// pending half kick (MD's readout), ED particles where the event core has them
    /// now with pending eMD* velocities applied (the velocity each particle will have
    /// once its collision is over), removed ones as they left.
    fn particles_now(&self) -> Particles {
        let p = &self.system.particles;
        let (mask, g) = (self.modes.time_driven(), self.system.domain.gravity);
        let mut now = Particles {
            velocity: self.td.velocities_now(p, mask, g),
            angular_velocity: self.td.spins_now(p),
            ..p.clone()
        };
        for i in 0..now.len() {
            if self.modes.of(i) == Mode::Event {
                (now.position[i], now.velocity[i]) = self.ed.settled(i);
                now.angular_velocity[i] = self.ed.spin(i);
                now.image[i] = self.ed.image(i);
            }
        }
        now
    }

    /// The sums behind the pressure tensor and the collision rate: the time-driven
    /// part's (its drift velocities, the forces between its particles) plus the event
    /// core's (its members' motion, the impulses of its collisions).
    pub fn stress_sums(&self) -> StressSums {
        let (td, ed) = (
            self.td.stress_sums(&self.system.particles),
            self.ed.stress_sums(|i| self.modes.of(i) == Mode::Event),
        );
        StressSums {
            kinetic: std::array::from_fn(|k| td.kinetic[k] + ed.kinetic[k]),
            collisional: std::array::from_fn(|k| td.collisional[k] + ed.collisional[k]),
            collisions: td.collisions + ed.collisions,
        }
    }

    /// The sums and time of the last mark (kept with the event core's state).
    pub fn ed_stress_mark(&self) -> Option<StressMark> {
        self.ed.stress_mark()
    }

    /// Keeps the hybrid's sums now as the mark.
    pub fn mark_stress(&mut self) {
        let sums = self.stress_sums();
        self.ed.mark_stress(self.time(), sums);
    }

    /// The particles now, in config order: time-driven ones with their pending half
    /// kick, event-driven ones with pending eMD* velocities applied.
    pub fn particles(&self) -> Particles {
        let mut p = self.particles_now();
        let mut order = vec![0u32; p.len()];
        for (k, &id) in p.id.iter().enumerate() {
            order[id as usize] = k as u32;
        }
        p.permute(&order);
        p
    }

    /// Energies, temperature, momentum and contacts now (pending eMD* velocities
    /// applied). The potential energy is the elastic energy of the TD contacts and of
    /// their tangential springs, plus −Σ m g·x. Removed particles are left out of the
    /// energies and the momentum (the granular temperature still counts them). With
    /// every particle TD, MD's thermo to the bit.
    pub fn thermo(&self) -> Thermo {
        let all = self.particles_now();
        let mut p = all.clone();
        for i in 0..p.len() {
            if self.modes.of(i) == Mode::Removed {
                p.velocity[i] = [0.0; 3];
                p.angular_velocity[i] = [0.0; 3];
            }
        }
        let model = ForceModel::new(
            &p.radius,
            &p.species,
            &self.system.interactions,
            &self.system.domain,
            ContactEnd::ForceZero,
        )
        .at(self.time());
        let mut potential = self
            .td
            .rotation()
            .map_or(0.0, |r| r.spring_energy(&self.system.interactions, &p));
        let mut contacts = 0;
        let list = self.td.list();
        let g = self.system.domain.gravity;
        for i in 0..p.len() {
            let xi = p.position[i];
            match self.modes.of(i) {
                Mode::Removed => continue,
                Mode::Time => {
                    let sums = (&mut contacts, &mut potential);
                    let time_driven = list
                        .of(i)
                        .iter()
                        .copied()
                        .filter(|&e| self.modes.of(list.split(e).0) == Mode::Time);
                    model.add_elastic(i, xi, time_driven, list, &p.position, sums);
                }
                Mode::Event => {}
            }
            potential -= p.mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: p.kinetic_energy(),
            rotational_energy: p.rotational_energy(),
            potential_energy: potential,
            granular_temperature: all.granular_temperature(),
            rotational_temperature: all.rotational_temperature(),
            momentum: p.momentum(),
            contacts,
        }
    }
}
