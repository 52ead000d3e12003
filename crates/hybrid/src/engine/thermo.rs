//! Output of the hybrid engine: the particles now and the thermo quantities.

use super::Hybrid;
use super::time_driven::force_model;
use crate::options::Mode;
use emdstar_system::{Particles, Thermo};

impl Hybrid {
    /// The particles now, in config order: ED particles moved to the current time,
    /// pending eMD* velocities applied (the velocity each particle will have once its
    /// collision is over).
    pub fn particles(&self) -> Particles {
        let t = self.time();
        let mut p = self.system.particles.clone();
        for i in 0..p.len() {
            if self.mode[i] == Mode::Event {
                let (x, v) = self.settled_state(i, t);
                p.position[i] = x;
                p.velocity[i] = v;
            }
        }
        p
    }

    /// Energies, temperature, momentum and contacts now (pending eMD* velocities
    /// applied). The potential energy is the elastic energy of the TD contacts
    /// ([`emdstar_dem::elastic_energy`]) and of their tangential springs, plus −Σ m g·x.
    /// Removed particles are left out of the energies and the momentum (the granular
    /// temperature still counts them).
    pub fn thermo(&self) -> Thermo {
        let p = self.particles();
        let g = self.system.domain.gravity;
        let model = force_model(
            &p.radius,
            &p.species,
            &self.system.interactions,
            &self.system.domain,
        );
        let mut potential = self.spring_energy();
        let mut contacts = 0;
        let mut kinetic = 0.0;
        let mut momentum = [0.0; 3];
        for i in 0..p.len() {
            if self.mode[i] == Mode::Removed {
                continue;
            }
            let (xi, vi) = (p.position[i], p.velocity[i]);
            kinetic += 0.5 * p.mass[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
            for k in 0..3 {
                momentum[k] += p.mass[i] * vi[k];
            }
            potential -= p.mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
            if self.mode[i] != Mode::Time {
                continue;
            }
            // Each TD pair once, with its walls.
            let time_driven = self
                .list
                .upper(i)
                .iter()
                .copied()
                .filter(|&e| self.mode[self.list.split(e).0] == Mode::Time);
            let sums = (&mut contacts, &mut potential);
            model.add_elastic(i, xi, time_driven, &self.list, &p.position, sums);
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: kinetic,
            rotational_energy: p.rotational_energy(),
            potential_energy: potential,
            granular_temperature: p.granular_temperature(),
            rotational_temperature: p.rotational_temperature(),
            momentum,
            contacts,
        }
    }
}
