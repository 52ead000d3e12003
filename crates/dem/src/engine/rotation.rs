//! MD with friction: spins kicked by the contact torques like the velocities by the
//! forces (LAMMPS's `fix nve/sphere`: ω += (dt/2)·τ/I, I = (2/5) m R²), the frictional
//! force sweep, and the springs carried from step to step.

use super::{CHUNK, Md};
use crate::forces::WALL;
use crate::frictional::{ContactForce, FrictionKernel, Springs};
use crate::verlet::kick_contacts;
use emdstar_contact::Friction;
use emdstar_system::{Particles, permute};
use rayon::prelude::*;

/// What friction adds to MD's state.
pub(crate) struct Rotation {
    pub(crate) friction: Friction,
    pub(crate) inv_inertia: Vec<f64>,
    /// Angular accelerations of the contacts at the current time (non-zero only for
    /// particles in `Md::touched`).
    pub(crate) angular_acc: Vec<[f64; 3]>,
    pub(crate) springs: Springs,
    buffers: Vec<Vec<ContactForce>>,
}

/// 1/I of every particle, I = (2/5) m R².
fn inverse_inertia(p: &Particles) -> Vec<f64> {
    (0..p.len()).map(|i| 1.0 / p.inertia(i)).collect()
}

impl Rotation {
    pub(crate) fn new(friction: Friction, p: &Particles) -> Self {
        Self {
            friction,
            inv_inertia: inverse_inertia(p),
            angular_acc: vec![[0.0; 3]; p.len()],
            springs: Springs::default(),
            buffers: vec![Vec::new(); p.len().div_ceil(CHUNK)],
        }
    }

    /// After the particles were reordered by `order` (see [`Particles::permute`]).
    pub(crate) fn permute(&mut self, order: &[u32]) {
        permute(&mut self.inv_inertia, order);
        permute(&mut self.angular_acc, order);
    }

    /// After a restored state replaced the particles.
    pub(crate) fn reset_inertia(&mut self, p: &Particles) {
        self.inv_inertia = inverse_inertia(p);
    }

    /// The elastic energy of the tangential springs, Σ ½ k_t |ξ_t|².
    pub(crate) fn spring_energy(&self) -> f64 {
        self.springs.energy(&self.friction)
    }
}

impl Md {
    /// ω += α_contact·`by` for the particles in contact (nothing without friction).
    pub(super) fn kick_spins(&mut self, by: f64) {
        if let Some(rot) = &self.rotation {
            kick_contacts(
                &mut self.system.particles.angular_velocity,
                &rot.angular_acc,
                &self.touched,
                by,
            );
        }
    }

    /// The spins now, in the engine's order: the stored ones with the pending half
    /// kick applied.
    pub(super) fn spins_now(&self) -> Vec<[f64; 3]> {
        let mut w = self.system.particles.angular_velocity.clone();
        if let (Some(rot), true) = (&self.rotation, self.lagging) {
            kick_contacts(&mut w, &rot.angular_acc, &self.touched, 0.5 * self.opts.dt);
        }
        w
    }

    /// The frictional contacts at the current positions, with the velocity predictor
    /// of step `h` (0 at t = 0), in fixed chunks run in parallel.
    pub(super) fn frictional_sweep(&mut self, h: f64) {
        let Some(mut rot) = self.rotation.take() else {
            return;
        };
        let mut buffers = std::mem::take(&mut rot.buffers);
        {
            let p = &self.system.particles;
            let kernel = FrictionKernel {
                base: self.kernel(h),
                friction: rot.friction,
                id: &p.id,
                angular_velocity: &p.angular_velocity,
                angular_acc: &rot.angular_acc,
                springs: &rot.springs,
            };
            let n = p.len();
            let walls = !self.system.domain.walls.is_empty();
            let start = &self.list.start;
            buffers.par_iter_mut().enumerate().for_each(|(c, buf)| {
                buf.clear();
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    if walls || start[i] != start[i + 1] {
                        let entries = kernel.base.list.of(i).iter().copied();
                        let (x, v) = (p.position[i], p.velocity[i]);
                        kernel.particle(i, x, v, entries, &p.position, &p.velocity, buf);
                    }
                }
            });
        }
        rot.buffers = buffers;
        self.rotation = Some(rot);
    }

    /// Replaces the contact accelerations, angular accelerations and springs by those
    /// of the last frictional sweep, chunk by chunk and contact by contact.
    pub(super) fn apply_frictional_forces(&mut self) {
        let Some(rot) = self.rotation.as_mut() else {
            return;
        };
        for &i in &self.touched {
            self.contact_acc[i as usize] = [0.0; 3];
            rot.angular_acc[i as usize] = [0.0; 3];
        }
        self.touched.clear();
        for c in rot.buffers.iter().flatten() {
            let i = c.i as usize;
            let (mi, ii) = (self.inv_mass[i], rot.inv_inertia[i]);
            for k in 0..3 {
                self.contact_acc[i][k] += c.f[k] * mi;
                rot.angular_acc[i][k] += c.torque_i[k] * ii;
            }
            self.touched.push(c.i);
            if c.j != WALL {
                let j = c.j as usize;
                let (mj, ij) = (self.inv_mass[j], rot.inv_inertia[j]);
                for k in 0..3 {
                    self.contact_acc[j][k] -= c.f[k] * mj;
                    rot.angular_acc[j][k] += c.torque_j[k] * ij;
                }
                self.touched.push(c.j);
            }
        }
        self.touched.sort_unstable();
        self.touched.dedup();
        let records = rot.buffers.iter().flatten().map(|c| (c.key, c.spring));
        rot.springs.replace(records);
    }
}
