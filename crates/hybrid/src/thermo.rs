//! Output of the hybrid engine: the particles now and the thermo quantities.

use crate::engine::{Hybrid, norm};
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
    /// applied). The potential energy is the elastic energy of the TD contacts,
    /// ½kξ² or (2/5)ρ_el ξ^{5/2} (Müller & Pöschel 2013, Eqs. 40 and 51), plus −Σ m g·x.
    /// Removed particles are left out of the energies and the momentum (the granular
    /// temperature still counts them).
    pub fn thermo(&self) -> Thermo {
        let p = self.particles();
        let g = self.system.domain.gravity;
        let mut potential = 0.0;
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
            for &entry in self.list.of(i) {
                let (j, s) = self.list.split(entry);
                if j < i || self.mode[j] != Mode::Time {
                    continue;
                }
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
                let overlap = p.radius[i] + p.radius[j] - norm(d);
                if overlap > 0.0 {
                    contacts += 1;
                    let law = &self
                        .materials
                        .pair(p.species[i], p.species[j])
                        .interaction
                        .law;
                    potential += elastic_energy(law, overlap);
                }
            }
            for w in &self.system.domain.walls {
                let overlap = p.radius[i] - w.distance(xi);
                if overlap > 0.0 {
                    contacts += 1;
                    let law = &self.materials.wall(p.species[i]).interaction.law;
                    potential += elastic_energy(law, overlap);
                }
            }
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: kinetic,
            potential_energy: potential,
            granular_temperature: p.granular_temperature(),
            momentum,
            contacts,
        }
    }
}

/// Elastic energy stored at overlap ξ: ½kξ² or (2/5)ρ_el ξ^{5/2}.
fn elastic_energy(law: &emdstar_contact::PairLaw, overlap: f64) -> f64 {
    match *law {
        emdstar_contact::PairLaw::Linear { stiffness, .. } => 0.5 * stiffness * overlap * overlap,
        emdstar_contact::PairLaw::Hertz { rho_el, .. } => {
            0.4 * rho_el * overlap * overlap * overlap.sqrt()
        }
    }
}
