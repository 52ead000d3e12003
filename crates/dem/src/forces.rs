//! The force kernel: pair and wall contacts of one chunk of particles.

use crate::neighbour::{INDEX_BITS, INDEX_MASK, NeighbourList};
use crate::options::ContactEnd;
use emdstar_contact::PairLaw;
use emdstar_system::Wall;

/// A pair force found in phase 1, applied in phase 2: +f on `i`, −f on `j`.
#[derive(Debug, Clone, Copy)]
pub struct PairForce {
    pub i: u32,
    pub j: u32,
    pub f: [f64; 3],
}

/// What the kernel reads.
pub struct Kernel<'a> {
    pub position: &'a [[f64; 3]],
    /// Half-step velocities v(t − dt/2) … see [`Kernel::h`].
    pub velocity: &'a [[f64; 3]],
    /// Accelerations of the previous step.
    pub acc_old: &'a [[f64; 3]],
    pub radius: &'a [f64],
    pub inv_mass: &'a [f64],
    pub species: &'a [u32],
    pub list: &'a NeighbourList,
    /// `pair_laws[a * n_species + b]`.
    pub pair_laws: &'a [PairLaw],
    pub n_species: usize,
    pub wall_laws: &'a [PairLaw],
    pub walls: &'a [Wall],
    pub gravity: [f64; 3],
    /// The velocity at the force's time is predicted as v + h·a_old with h = dt/2
    /// (see the crate docs).
    pub h: f64,
    pub contact_end: ContactEnd,
}

/// The normal force of a law at overlap ξ > 0 and rate ξ̇ under a contact-end rule.
#[inline(always)]
pub fn normal_force(law: &PairLaw, overlap: f64, rate: f64, end: ContactEnd) -> f64 {
    match end {
        ContactEnd::ForceZero => law.normal_force(overlap, rate),
        ContactEnd::OverlapZero => unclipped_force(law, overlap, rate),
    }
}

/// The force laws of Müller & Pöschel 2013, Eqs. (40) and (51), without the clipping
/// F ≥ 0 (LAMMPS's convention; valid for ξ > 0 only).
#[inline]
pub fn unclipped_force(law: &PairLaw, overlap: f64, rate: f64) -> f64 {
    match *law {
        PairLaw::Linear { stiffness, damping } => stiffness * overlap + damping * rate,
        PairLaw::Hertz {
            rho_el,
            dissipation,
        } => rho_el * overlap.sqrt() * (overlap + 1.5 * dissipation * rate),
    }
}

impl Kernel<'_> {
    /// Sets `acc[k]` of particles `first..first + acc.len()` to gravity plus wall
    /// forces, and pushes their pair forces (pairs listed under them) onto `out`.
    pub fn chunk(&self, first: usize, acc: &mut [[f64; 3]], out: &mut Vec<PairForce>) {
        out.clear();
        for (local, a) in acc.iter_mut().enumerate() {
            let i = first + local;
            let xi = self.position[i];
            *a = self.gravity;
            for w in self.walls {
                let d = w.distance(xi);
                let overlap = self.radius[i] - d;
                if overlap > 0.0 {
                    let v = self.predicted_velocity(i);
                    let rate = -(w.normal[0] * v[0] + w.normal[1] * v[1] + w.normal[2] * v[2]);
                    let law = &self.wall_laws[self.species[i] as usize];
                    let f = normal_force(law, overlap, rate, self.contact_end) * self.inv_mass[i];
                    for k in 0..3 {
                        a[k] += f * w.normal[k];
                    }
                }
            }
            let ri = self.radius[i];
            let row = self.species[i] as usize * self.n_species;
            for &entry in self.list.of(i) {
                let j = (entry & INDEX_MASK) as usize;
                let s = &self.list.shifts[(entry >> INDEX_BITS) as usize];
                let xj = self.position[j];
                let d = [
                    xi[0] - xj[0] - s[0],
                    xi[1] - xj[1] - s[1],
                    xi[2] - xj[2] - s[2],
                ];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let l = ri + self.radius[j];
                if r2 >= l * l {
                    continue;
                }
                let r = r2.sqrt();
                let n = [d[0] / r, d[1] / r, d[2] / r];
                let (vi, vj) = (self.predicted_velocity(i), self.predicted_velocity(j));
                // ξ̇ = −ṙ = −n·(v_i − v_j).
                let rate =
                    -(n[0] * (vi[0] - vj[0]) + n[1] * (vi[1] - vj[1]) + n[2] * (vi[2] - vj[2]));
                let law = &self.pair_laws[row + self.species[j] as usize];
                let f = normal_force(law, l - r, rate, self.contact_end);
                if f != 0.0 {
                    out.push(PairForce {
                        i: i as u32,
                        j: j as u32,
                        f: [f * n[0], f * n[1], f * n[2]],
                    });
                }
            }
        }
    }

    #[inline(always)]
    fn predicted_velocity(&self, i: usize) -> [f64; 3] {
        let (v, a) = (self.velocity[i], self.acc_old[i]);
        [
            v[0] + self.h * a[0],
            v[1] + self.h * a[1],
            v[2] + self.h * a[2],
        ]
    }
}
