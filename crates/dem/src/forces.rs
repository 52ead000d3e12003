//! Contact forces: the per-pair and per-wall kernels, the sweep over one particle's
//! partners, where the forces go, and the elastic energy of a contact.

use crate::neighbour::NeighbourList;
use crate::options::ContactEnd;
use emdstar_contact::PairLaw;
use emdstar_system::{Domain, Interactions, Wall};

/// A contact force found by a sweep: +f on `i`, −f on `j` (unless `j` is [`WALL`]).
#[derive(Debug, Clone, Copy)]
pub struct PairForce {
    pub i: u32,
    pub j: u32,
    pub f: [f64; 3],
}

/// The `j` of a [`PairForce`] that acts between particle `i` and a wall.
pub const WALL: u32 = u32::MAX;

/// Where a sweep puts the forces it finds.
pub trait ForceSink {
    fn push(&mut self, force: PairForce);
}

/// Records the forces, to be applied later in a fixed order (MD's parallel sweep).
impl ForceSink for Vec<PairForce> {
    #[inline(always)]
    fn push(&mut self, force: PairForce) {
        Vec::push(self, force);
    }
}

/// Adds every force at once to the accelerations `acc` ([`add_force`]).
pub struct AddForces<'a> {
    pub acc: &'a mut [[f64; 3]],
    pub inv_mass: &'a [f64],
}

impl ForceSink for AddForces<'_> {
    #[inline(always)]
    fn push(&mut self, force: PairForce) {
        add_force(&force, self.inv_mass, self.acc);
    }
}

/// acc_i += f/m_i and, for a pair, acc_j −= f/m_j.
#[inline(always)]
pub fn add_force(pf: &PairForce, inv_mass: &[f64], acc: &mut [[f64; 3]]) {
    let i = pf.i as usize;
    let mi = inv_mass[i];
    for k in 0..3 {
        acc[i][k] += pf.f[k] * mi;
    }
    if pf.j != WALL {
        let j = pf.j as usize;
        let mj = inv_mass[j];
        for k in 0..3 {
            acc[j][k] -= pf.f[k] * mj;
        }
    }
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

/// The force correction at the first step of a contact, for laws whose force jumps on
/// at touch (the linear dashpot: F(0⁺) = γ·ξ̇).
///
/// Velocity Verlet weighs the force at a step with the whole step (the trapezoidal
/// rule). When the force switches on at a fraction θ of the step before, that puts
/// F(0⁺)·dt·(θ − ½) too much impulse into the pair: an O(dt) error per collision that
/// would make damped linear contacts first order. θ comes from the overlap one step
/// earlier, ξ_prev < 0 < ξ (linear interpolation, exact for straight approach), and
/// the returned ΔF = F(0⁺)·(½ − θ) enters the step's kicks with weight dt. Zero for
/// continuing contacts and for laws that start at F = 0 (Hertz), and at t = 0 (h = 0).
#[inline]
pub fn touch_correction(law: &PairLaw, overlap_prev: f64, overlap: f64, rate: f64) -> f64 {
    if overlap_prev >= 0.0 || !overlap_prev.is_finite() {
        return 0.0;
    }
    let theta = -overlap_prev / (overlap - overlap_prev);
    let jump = law.normal_force(f64::MIN_POSITIVE, rate);
    jump * (0.5 - theta)
}

/// Elastic energy stored at overlap ξ, ∫F_el dξ: ½kξ² (linear) or (2/5)ρ_el ξ^{5/2}
/// (Hertz; Müller & Pöschel 2013, Eqs. 40 and 51).
pub fn elastic_energy(law: &PairLaw, overlap: f64) -> f64 {
    match *law {
        PairLaw::Linear { stiffness, .. } => 0.5 * stiffness * overlap * overlap,
        PairLaw::Hertz { rho_el, .. } => 0.4 * rho_el * overlap * overlap * overlap.sqrt(),
    }
}

/// What the contact forces depend on besides the particles' motion: sizes, species,
/// laws, walls, gravity and the contact-end rule.
#[derive(Clone, Copy)]
pub struct ForceModel<'a> {
    pub radius: &'a [f64],
    pub species: &'a [u32],
    pub interactions: &'a Interactions,
    pub walls: &'a [Wall],
    pub gravity: [f64; 3],
    pub contact_end: ContactEnd,
}

impl<'a> ForceModel<'a> {
    /// The model of particles with `radius` and `species` in `domain` (its walls and
    /// gravity).
    pub fn new(
        radius: &'a [f64],
        species: &'a [u32],
        interactions: &'a Interactions,
        domain: &'a Domain,
        contact_end: ContactEnd,
    ) -> Self {
        Self {
            radius,
            species,
            interactions,
            walls: &domain.walls,
            gravity: domain.gravity,
            contact_end,
        }
    }

    /// Adds the contacts of particle `i` at `xi` with the walls and with the partners
    /// `entries` of `list` (positions `position`) to `contacts`, and their elastic
    /// energies ([`elastic_energy`]) to `potential`, pairs first, in list order.
    pub fn add_elastic(
        &self,
        i: usize,
        xi: [f64; 3],
        entries: impl IntoIterator<Item = u32>,
        list: &NeighbourList,
        position: &[[f64; 3]],
        (contacts, potential): (&mut usize, &mut f64),
    ) {
        let (radius, species) = (self.radius, self.species);
        for entry in entries {
            let (j, s) = list.split(entry);
            let d: [f64; 3] = std::array::from_fn(|k| xi[k] - position[j][k] - s[k]);
            let overlap = radius[i] + radius[j] - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if overlap > 0.0 {
                *contacts += 1;
                let law = &self.interactions.pair(species[i], species[j]).law;
                *potential += elastic_energy(law, overlap);
            }
        }
        for w in self.walls {
            let overlap = radius[i] - w.distance(xi);
            if overlap > 0.0 {
                *contacts += 1;
                *potential += elastic_energy(&self.interactions.wall(species[i]).law, overlap);
            }
        }
    }
}

/// The force kernel of one velocity-Verlet step: the model, the list whose entries the
/// sweep is given, and the accelerations the velocity predictor needs.
pub struct ForceKernel<'a> {
    pub model: ForceModel<'a>,
    pub list: &'a NeighbourList,
    /// Contact accelerations of the previous step (zero for particles without contacts).
    pub contact_acc: &'a [[f64; 3]],
    /// The stored velocities lag by half a step; the velocity at the force's time is
    /// predicted as v + h·a_old with h = dt/2 (see the crate docs). With h = 0 the
    /// velocities are used as they are (the forces at t = 0, or of particles that
    /// start to be integrated).
    pub h: f64,
}

impl ForceKernel<'_> {
    /// Pushes the wall forces of particle `i` and the forces of the pairs with the
    /// partners `entries` (of the list), in that order. Reads `position[j]`,
    /// `velocity[j]` of those partners only, and `xi`, `vi` for particle i itself, so a
    /// sweep may drift particle i just before.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub fn particle(
        &self,
        i: usize,
        xi: [f64; 3],
        vi: [f64; 3],
        entries: impl IntoIterator<Item = u32>,
        position: &[[f64; 3]],
        velocity: &[[f64; 3]],
        out: &mut impl ForceSink,
    ) {
        let model = &self.model;
        let ri = model.radius[i];
        for w in model.walls {
            let overlap = ri - w.distance(xi);
            if overlap > 0.0 {
                self.wall(i, w, overlap, vi, out);
            }
        }
        let list = self.list;
        for entry in entries {
            let (j, s) = list.split(entry);
            let xj = position[j];
            let d = [
                xi[0] - xj[0] - s[0],
                xi[1] - xj[1] - s[1],
                xi[2] - xj[2] - s[2],
            ];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let l = ri + model.radius[j];
            if r2 < l * l {
                self.pair(i, j, d, r2.sqrt(), l, vi, velocity[j], out);
            }
        }
    }

    /// The force of a wall on particle i at overlap ξ > 0.
    #[inline(never)]
    fn wall(&self, i: usize, w: &Wall, overlap: f64, vi: [f64; 3], out: &mut impl ForceSink) {
        let dt = 2.0 * self.h;
        let overlap_prev =
            overlap + dt * (w.normal[0] * vi[0] + w.normal[1] * vi[1] + w.normal[2] * vi[2]);
        let v = self.predict(i, vi);
        let rate = -(w.normal[0] * v[0] + w.normal[1] * v[1] + w.normal[2] * v[2]);
        let model = &self.model;
        let law = &model.interactions.wall(model.species[i]).law;
        let f = normal_force(law, overlap, rate, model.contact_end)
            + touch_correction(law, overlap_prev, overlap, rate);
        if f != 0.0 {
            let n = w.normal;
            out.push(PairForce {
                i: i as u32,
                j: WALL,
                f: [f * n[0], f * n[1], f * n[2]],
            });
        }
    }

    /// The force of a pair in contact at separation `d` (|d| = r < l).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn pair(
        &self,
        i: usize,
        j: usize,
        d: [f64; 3],
        r: f64,
        l: f64,
        vi: [f64; 3],
        vj: [f64; 3],
        out: &mut impl ForceSink,
    ) {
        let n = [d[0] / r, d[1] / r, d[2] / r];
        // The separation one step ago: the drift was x += dt·v exactly.
        let dt = 2.0 * self.h;
        let d_prev: [f64; 3] = std::array::from_fn(|k| d[k] - dt * (vi[k] - vj[k]));
        let overlap_prev =
            l - (d_prev[0] * d_prev[0] + d_prev[1] * d_prev[1] + d_prev[2] * d_prev[2]).sqrt();
        let (vi, vj) = (self.predict(i, vi), self.predict(j, vj));
        // ξ̇ = −ṙ = −n·(v_i − v_j).
        let rate = -(n[0] * (vi[0] - vj[0]) + n[1] * (vi[1] - vj[1]) + n[2] * (vi[2] - vj[2]));
        let model = &self.model;
        let law = &model
            .interactions
            .pair(model.species[i], model.species[j])
            .law;
        let f = normal_force(law, l - r, rate, model.contact_end)
            + touch_correction(law, overlap_prev, l - r, rate);
        if f != 0.0 {
            out.push(PairForce {
                i: i as u32,
                j: j as u32,
                f: [f * n[0], f * n[1], f * n[2]],
            });
        }
    }

    /// v + h·a with a = gravity + the contact acceleration of the previous step.
    #[inline(always)]
    pub(crate) fn predict(&self, i: usize, v: [f64; 3]) -> [f64; 3] {
        let (a, g, h) = (self.contact_acc[i], self.model.gravity, self.h);
        [
            v[0] + h * (g[0] + a[0]),
            v[1] + h * (g[1] + a[1]),
            v[2] + h * (g[2] + a[2]),
        ]
    }
}
