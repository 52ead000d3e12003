//! Contact forces: the one force kernel of velocity Verlet (walls, then a particle's
//! partners), generic over its tangential slot ([`TangentialSlot`], in the manner of
//! HOOMD-blue's `PotentialPair<evaluator>`): [`Smooth`] contacts give a normal force,
//! [`crate::Frictional`] ones add the tangential force and torques of their
//! [`emdstar_contact::Tangential`] law. Also where the contacts go ([`ContactRecord`],
//! [`apply_contacts`]) and the elastic energy of a contact.

use crate::neighbour::NeighbourList;
use crate::options::ContactEnd;
use emdstar_contact::PairLaw;
use emdstar_system::{Domain, Interaction, Interactions, Wall};

/// A frictionless contact force found by a sweep: +f on `i`, −f on `j` (unless `j` is
/// [`WALL`]).
#[derive(Debug, Clone, Copy)]
pub struct PairForce {
    pub i: u32,
    pub j: u32,
    pub f: [f64; 3],
}

/// The `j` of a contact that acts between particle `i` and a wall.
pub const WALL: u32 = u32::MAX;

/// A contact's key in [`crate::Springs`]: the two config ids, smaller first; a wall
/// contact has `WALL - w` for wall `w` as its second id.
pub type ContactKey = (u32, u32);

/// The accelerations a contact adds to: linear, and angular where contacts exert
/// torques (`None` without friction: spins are never touched).
pub struct Accelerations<'a> {
    pub inv_mass: &'a [f64],
    pub acc: &'a mut [[f64; 3]],
    /// 1/I of every particle and the angular accelerations.
    pub angular: Option<(&'a [f64], &'a mut [[f64; 3]])>,
}

/// What a sweep finds for one contact, and how it acts.
pub trait ContactRecord: Copy + Send + Sync {
    /// The particle and its partner (or [`WALL`]).
    fn parties(&self) -> (u32, u32);
    /// Adds the contact's force (and torques) to `to`.
    fn add_to(&self, to: &mut Accelerations<'_>);
    /// The contact's spring, to keep for the next step (none without one).
    fn spring(&self) -> Option<(ContactKey, [f64; 3])>;
    /// The force on the particle (and minus it on a partner particle), in N.
    fn force(&self) -> [f64; 3];
}

impl ContactRecord for PairForce {
    #[inline(always)]
    fn parties(&self) -> (u32, u32) {
        (self.i, self.j)
    }

    #[inline(always)]
    fn add_to(&self, to: &mut Accelerations<'_>) {
        let i = self.i as usize;
        let mi = to.inv_mass[i];
        for k in 0..3 {
            to.acc[i][k] += self.f[k] * mi;
        }
        if self.j != WALL {
            let j = self.j as usize;
            let mj = to.inv_mass[j];
            for k in 0..3 {
                to.acc[j][k] -= self.f[k] * mj;
            }
        }
    }

    #[inline(always)]
    fn spring(&self) -> Option<(ContactKey, [f64; 3])> {
        None
    }

    #[inline(always)]
    fn force(&self) -> [f64; 3] {
        self.f
    }
}

/// Adds `contacts` to the accelerations in their order (a fixed order, so the sums do
/// not depend on the number of threads), and records the particles they touch.
pub fn apply_contacts<'c, C: ContactRecord + 'c>(
    contacts: impl IntoIterator<Item = &'c C>,
    to: &mut Accelerations<'_>,
    mut touched: Option<&mut Vec<u32>>,
) {
    for c in contacts {
        c.add_to(to);
        if let Some(t) = touched.as_deref_mut() {
            let (i, j) = c.parties();
            t.push(i);
            if j != WALL {
                t.push(j);
            }
        }
    }
}

/// Where a sweep puts the contacts it finds.
pub trait ForceSink<C> {
    fn push(&mut self, contact: C);
}

/// Records the contacts, to be applied later in a fixed order.
impl<C> ForceSink<C> for Vec<C> {
    #[inline(always)]
    fn push(&mut self, contact: C) {
        Vec::push(self, contact);
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
/// contact models, walls, gravity and the contact-end rule.
#[derive(Clone, Copy)]
pub struct ForceModel<'a> {
    pub radius: &'a [f64],
    pub species: &'a [u32],
    pub interactions: &'a Interactions,
    pub walls: &'a [Wall],
    pub gravity: [f64; 3],
    pub contact_end: ContactEnd,
    /// The time of the forces: where vibrated walls are, and how fast they move.
    pub time: f64,
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
            time: 0.0,
        }
    }

    /// The model with the walls where they are at time `t`.
    pub fn at(self, t: f64) -> Self {
        Self { time: t, ..self }
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
                let law = self.interactions.pair(species[i], species[j]).law();
                *potential += elastic_energy(law, overlap);
            }
        }
        for (w, wall) in self.walls.iter().enumerate() {
            let overlap = radius[i] - wall.distance_at(xi, self.time);
            if overlap > 0.0 {
                *contacts += 1;
                *potential += elastic_energy(self.interactions.wall(species[i], w).law(), overlap);
            }
        }
    }
}

/// The normal part of one contact, as the kernel finds it: what a tangential slot
/// builds on.
pub struct Touch<'a> {
    /// The particle and its partner, or [`WALL`] and the wall's number.
    pub i: usize,
    pub j: u32,
    pub wall: usize,
    pub interaction: &'a Interaction,
    /// The unit normal towards i now.
    pub n: [f64; 3],
    /// For a pair: x_i − x_j now (minimum image), and one step ago (the drift was
    /// x += dt·v exactly); for a wall: zero.
    pub d: [f64; 3],
    pub d_prev: [f64; 3],
    /// The stored (mid-step) velocities of i and j (zero for a wall).
    pub v: [[f64; 3]; 2],
    /// The predicted (end-of-step) velocities of i and j.
    pub v_pred: [[f64; 3]; 2],
    /// The overlap now and one step ago.
    pub overlap: f64,
    pub overlap_prev: f64,
    /// ξ̇ = −n·(v_i − v_j), predicted.
    pub rate: f64,
    /// The normal force (the contact-end rule applied) and the touch correction.
    pub normal: f64,
    pub correction: f64,
}

/// The tangential slot of the force kernel: what a contact gives besides its normal
/// force. [`Smooth`] is the frictionless slot; [`crate::Frictional`] adds tangential
/// forces and torques.
pub trait TangentialSlot: Sync + Sized {
    /// What one contact gives.
    type Contact: ContactRecord;
    /// The contact of `touch`, if it exerts anything.
    fn contact(&self, kernel: &ForceKernel<'_, Self>, touch: &Touch<'_>) -> Option<Self::Contact>;
}

/// The slot of frictionless contacts: the normal force alone, which never turns a
/// spin. Zero-sized, so the kernel over it is the frictionless kernel.
#[derive(Debug, Clone, Copy, Default)]
pub struct Smooth;

impl TangentialSlot for Smooth {
    type Contact = PairForce;

    #[inline(always)]
    fn contact(&self, _: &ForceKernel<'_, Self>, t: &Touch<'_>) -> Option<PairForce> {
        let f = t.normal + t.correction;
        (f != 0.0).then(|| PairForce {
            i: t.i as u32,
            j: t.j,
            f: [f * t.n[0], f * t.n[1], f * t.n[2]],
        })
    }
}

/// The force kernel of one velocity-Verlet step: the model, the list whose entries the
/// sweep is given, the accelerations the velocity predictor needs, and the tangential
/// slot.
pub struct ForceKernel<'a, S = Smooth> {
    pub model: ForceModel<'a>,
    pub list: &'a NeighbourList,
    /// Contact accelerations of the previous step (zero for particles without contacts).
    pub contact_acc: &'a [[f64; 3]],
    /// The stored velocities lag by half a step; the velocity at the force's time is
    /// predicted as v + h·a_old with h = dt/2 (see the crate docs). With h = 0 the
    /// velocities are used as they are (the forces at t = 0, or of particles that
    /// start to be integrated).
    pub h: f64,
    pub slot: S,
}

impl<S: TangentialSlot> ForceKernel<'_, S> {
    /// Pushes the wall contacts of particle `i` and the contacts with the partners
    /// `entries` (of the list), in that order. Reads `position[j]`, `velocity[j]` of
    /// those partners only, and `xi`, `vi` for particle i itself, so a sweep may drift
    /// particle i just before.
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
        out: &mut impl ForceSink<S::Contact>,
    ) {
        let model = &self.model;
        let ri = model.radius[i];
        for (w, wall) in model.walls.iter().enumerate() {
            let overlap = ri - wall.distance_at(xi, model.time);
            if overlap > 0.0 {
                self.wall(i, w, wall, overlap, xi, vi, out);
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
                // Across a Lees–Edwards face j's image moves at v_j + image_vx e_x.
                let vx = list.image_vx(entry);
                let mut vj = velocity[j];
                if vx != 0.0 {
                    vj[0] += vx;
                }
                self.pair(i, j, d, r2.sqrt(), l, vi, vj, out);
            }
        }
    }

    /// The contact of a wall with particle i (at `xi`) at overlap ξ > 0. A vibrated
    /// wall is where it is at the force's time and moves: the overlap one step ago and
    /// the rate ξ̇ = −n·(v_i − u) take its velocity u.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn wall(
        &self,
        i: usize,
        w: usize,
        wall: &Wall,
        overlap: f64,
        xi: [f64; 3],
        vi: [f64; 3],
        out: &mut impl ForceSink<S::Contact>,
    ) {
        let dt = 2.0 * self.h;
        let n = wall.normal;
        let model = &self.model;
        let (overlap_prev, u_mid, u) = match wall.vibration {
            None => (
                overlap + dt * (n[0] * vi[0] + n[1] * vi[1] + n[2] * vi[2]),
                [0.0; 3],
                [0.0; 3],
            ),
            Some(_) => {
                // One step ago the particle was at x − dt·v and the wall where it was then.
                let x_prev = std::array::from_fn(|k| xi[k] - dt * vi[k]);
                let t = model.time;
                (
                    model.radius[i] - wall.distance_at(x_prev, t - dt),
                    wall.velocity_at(t - self.h),
                    wall.velocity_at(t),
                )
            }
        };
        let v = self.predict(i, vi);
        let rate = -(n[0] * (v[0] - u[0]) + n[1] * (v[1] - u[1]) + n[2] * (v[2] - u[2]));
        let interaction = model.interactions.wall(model.species[i], w);
        let law = interaction.law();
        let touch = Touch {
            i,
            j: WALL,
            wall: w,
            interaction,
            n,
            d: [0.0; 3],
            d_prev: [0.0; 3],
            v: [vi, u_mid],
            v_pred: [v, u],
            overlap,
            overlap_prev,
            rate,
            normal: normal_force(law, overlap, rate, model.contact_end),
            correction: touch_correction(law, overlap_prev, overlap, rate),
        };
        if let Some(c) = self.slot.contact(self, &touch) {
            out.push(c);
        }
    }

    /// The contact of a pair at separation `d` (|d| = r < l).
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
        out: &mut impl ForceSink<S::Contact>,
    ) {
        let n = [d[0] / r, d[1] / r, d[2] / r];
        // The separation one step ago: the drift was x += dt·v exactly.
        let dt = 2.0 * self.h;
        let d_prev: [f64; 3] = std::array::from_fn(|k| d[k] - dt * (vi[k] - vj[k]));
        let overlap_prev =
            l - (d_prev[0] * d_prev[0] + d_prev[1] * d_prev[1] + d_prev[2] * d_prev[2]).sqrt();
        let (pi, pj) = (self.predict(i, vi), self.predict(j, vj));
        // ξ̇ = −ṙ = −n·(v_i − v_j).
        let rate = -(n[0] * (pi[0] - pj[0]) + n[1] * (pi[1] - pj[1]) + n[2] * (pi[2] - pj[2]));
        let model = &self.model;
        let interaction = model.interactions.pair(model.species[i], model.species[j]);
        let law = interaction.law();
        let touch = Touch {
            i,
            j: j as u32,
            wall: 0,
            interaction,
            n,
            d,
            d_prev,
            v: [vi, vj],
            v_pred: [pi, pj],
            overlap: l - r,
            overlap_prev,
            rate,
            normal: normal_force(law, l - r, rate, model.contact_end),
            correction: touch_correction(law, overlap_prev, l - r, rate),
        };
        if let Some(c) = self.slot.contact(self, &touch) {
            out.push(c);
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
