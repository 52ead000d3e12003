//! The driver's part of the pressure tensor and the collision rate: the kinetic tensor
//! of each step's drift velocities and the force virial of its contacts.
//!
//! For velocity Verlet written as leapfrog (x_{n+1} = x_n + dt·v_{n+½},
//! v_{n+3/2} = v_{n+½} + dt·F_{n+1}/m), Σ x ⊗ p changes over a step by exactly
//! dt·[Σ m v_{n+½} ⊗ v_{n+½} + Σ x_{n+1} ⊗ F_{n+1}], so the half-step kinetic tensor and
//! the virial of the forces at the drifted positions, summed over steps, give the
//! discrete virial theorem without an O(dt²) mismatch.

use super::Verlet;
use super::slots::SlotKind;
use crate::forces::{ContactRecord, WALL};
use emdstar_system::{
    LeesEdwards, Particles, StressMark, StressSums, Sym3, System, add_kinetic, add_scaled,
    sym_outer,
};

/// The kinetic tensor of MD without gravity, kept by particle: a velocity changes only
/// in a contact kick, so each particle's m v ⊗ v·dt is added for the drifts it made
/// with a velocity when that velocity changes (as the event engines' delayed updates),
/// and not at every step.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct LazyKinetic {
    /// The drifts done so far.
    pub(crate) drifts: u64,
    /// For each particle, the drift from which its velocity has been what it is.
    pub(crate) since: Vec<u64>,
}

impl LazyKinetic {
    /// Adds m v ⊗ v·dt·(drifts since) of the particles `ids` (in their order) to `to`,
    /// before their velocities change, and restarts their count.
    pub(crate) fn flush(&mut self, ids: &[u32], p: &Particles, dt: f64, to: &mut Sym3) {
        for &i in ids {
            let i = i as usize;
            let count = self.drifts - self.since[i];
            if count > 0 {
                add_kinetic(to, p.mass[i] * dt * count as f64, p.velocity[i]);
                self.since[i] = self.drifts;
            }
        }
    }

    /// `to` plus what every particle has pending (nothing is restarted).
    fn pending(&self, p: &Particles, dt: f64, mut to: Sym3) -> Sym3 {
        for (i, &since) in self.since.iter().enumerate() {
            let count = self.drifts - since;
            if count > 0 {
                add_kinetic(&mut to, p.mass[i] * dt * count as f64, p.velocity[i]);
            }
        }
        to
    }
}

impl Verlet {
    /// Keeps the kinetic tensor by particle (MD over all particles without gravity:
    /// only contact kicks change velocities).
    pub fn keep_kinetic_by_particle(&mut self, n: usize) {
        self.lazy = Some(LazyKinetic {
            drifts: 0,
            since: vec![0; n],
        });
    }

    /// Adds what every particle has pending to the kinetic tensor before velocities
    /// change from outside (a thermostat's tick).
    pub fn flush_kinetic(&mut self, p: &Particles) {
        if let Some(lazy) = self.lazy.as_mut() {
            let all: Vec<u32> = (0..p.len() as u32).collect();
            lazy.flush(&all, p, self.opts.dt, &mut self.stress.kinetic);
        }
    }

    /// The sums since the run began: ∫ Σ m v ⊗ v dt over the steps' drift velocities,
    /// ∫ Σ r_ij ⊗ F_ij dt over the pair contacts (walls left out), and the pair
    /// contacts begun; `p` are the driver's particles.
    pub fn stress_sums(&self, p: &Particles) -> StressSums {
        match &self.lazy {
            Some(lazy) => StressSums {
                kinetic: lazy.pending(p, self.opts.dt, self.stress.kinetic),
                ..self.stress
            },
            None => self.stress,
        }
    }

    /// The sums and time of the last mark.
    pub fn stress_mark(&self) -> Option<StressMark> {
        self.stress_mark
    }

    /// Keeps the sums now (of the driver's particles `p`), at time `t`, as the mark.
    pub fn mark_stress(&mut self, t: f64, p: &Particles) {
        self.stress_mark = Some(StressMark {
            t,
            sums: self.stress_sums(p),
        });
    }

    /// Adds dt times the chunks' Σ m v ⊗ v, in chunk order.
    pub(super) fn add_chunk_kinetics(&mut self, chunks: &[Sym3], dt: f64) {
        for k in chunks {
            add_scaled(&mut self.stress.kinetic, *k, dt);
        }
    }

    /// Under Lees–Edwards shear the kinetic part is of the peculiar velocities
    /// c = v − u_x(y) e_x: adds dt·Σ m (c ⊗ c − v ⊗ v) of the drift just made to the
    /// Σ m v ⊗ v the sweep added, with u_x at the drift's mid-point.
    pub(super) fn add_streaming_kinetic(&mut self, p: &Particles, le: &LeesEdwards, dt: f64) {
        let mut k = [0.0; 6];
        for i in 0..p.len() {
            let (x, v, m) = (p.position[i], p.velocity[i], p.mass[i]);
            let u = le.streaming(x[1] - 0.5 * dt * v[1]);
            k[0] += m * u * (u - 2.0 * v[0]);
            k[3] -= m * u * v[1];
            k[4] -= m * u * v[2];
        }
        add_scaled(&mut self.stress.kinetic, k, dt);
    }

    /// Adds dt·Σ r_ij ⊗ F_ij of the pair contacts just applied, in their order, and
    /// counts those that began this step (apart one step ago: the drift was
    /// x += dt·v exactly).
    pub(super) fn add_virial<K: SlotKind>(&mut self, system: &System, dt: f64) {
        let p = &system.particles;
        let sim_box = system.domain.sim_box.as_ref();
        let shear = system.domain.lees_edwards();
        let mut w = [0.0; 6];
        let mut begun = 0;
        for c in K::chunks(&mut self.buffers).iter().flatten() {
            let (i, j) = c.parties();
            if j == WALL {
                continue;
            }
            let (i, j) = (i as usize, j as usize);
            let d: [f64; 3] = std::array::from_fn(|k| p.position[i][k] - p.position[j][k]);
            let (d, image_vx) = match &shear {
                Some(le) => self.list.sheared_image(le, d),
                None => (sim_box.map_or(d, |b| b.min_image(d)), 0.0),
            };
            add_scaled(&mut w, sym_outer(d, c.force()), 1.0);
            let (vi, mut vj) = (p.velocity[i], p.velocity[j]);
            if image_vx != 0.0 {
                vj[0] += image_vx;
            }
            let prev: [f64; 3] = std::array::from_fn(|k| d[k] - dt * (vi[k] - vj[k]));
            let l = p.radius[i] + p.radius[j];
            if prev[0] * prev[0] + prev[1] * prev[1] + prev[2] * prev[2] >= l * l {
                begun += 1;
            }
        }
        add_scaled(&mut self.stress.collisional, w, dt);
        self.stress.collisions += begun;
    }
}
