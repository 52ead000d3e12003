//! Friction of soft spheres: the tangential force of a contact, in the conventions of
//! Cundall & Strack's history spring as LAMMPS implements it (`pair granular …
//! tangential linear_history` with `limit_damping`), or HAET's pure Coulomb sliding
//! (Huang & Nydal, Sec. 2). The equations are those of docs/physics.md, section
//! "Friction and rotation".
//!
//! Conventions, for particle i against partner j (a wall is a partner of infinite mass
//! that does not rotate):
//! - **n** = (**x**_i − **x**_j)/|**x**_i − **x**_j| (for a wall, its normal);
//! - the slip velocity **v**_t = **v**_ij − (**v**_ij·**n**)**n** − (R_i **ω**_i + R_j **ω**_j) × **n**
//!   with **v**_ij = **v**_i − **v**_j ([`slip_velocity`]);
//! - the spring **ξ**_t lives in the tangent plane: each step it is projected onto the
//!   plane of the new normal by the rotation that turns the normal ([`turn_spring`];
//!   LAMMPS projects and rescales, which is the same for a normal turning in one plane),
//!   and grows by **v**_t·dt;
//! - **F**_t = −k_t **ξ**_t − γ_t **v**_t on i (−**F**_t on j), capped at µF_n with F_n
//!   the clipped total normal force; at the cap **ξ**_t = −(**F**_t + γ_t **v**_t)/k_t
//!   ([`HistorySpring::force`]);
//! - torques **τ**_i = −(R_i − ξ/2) **n** × **F**_t and **τ**_j = −(R_j − ξ/2) **n** × **F**_t,
//!   ξ the normal overlap ([`lever_arm`]): the orbital and spin torques cancel exactly,
//!   so the total angular momentum is conserved.

use crate::error::{ContactError, Result, non_negative};
use crate::vec3::{add, add_scaled, cross, dot, norm, scale, sub};

/// The moment of inertia of a solid sphere in units of m R²: I = (2/5) m R².
pub const SOLID_SPHERE_INERTIA: f64 = 0.4;

/// The Cundall–Strack history spring with a dashpot, capped by Coulomb's law
/// (Cundall & Strack 1979; LAMMPS's `tangential linear_history` with `limit_damping`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HistorySpring {
    /// Coulomb's coefficient µ > 0.
    pub friction: f64,
    /// k_t in N/m (> 0: the cap resets the spring through 1/k_t).
    pub stiffness: f64,
    /// γ_t in kg/s.
    pub damping: f64,
}

impl HistorySpring {
    /// Checks µ, k_t and γ_t finite and not negative, and k_t > 0.
    pub fn new(friction: f64, stiffness: f64, damping: f64) -> Result<Self> {
        let spring = Self {
            friction: non_negative("friction", friction)?,
            stiffness: non_negative("tangential_stiffness", stiffness)?,
            damping: non_negative("tangential_damping", damping)?,
        };
        if spring.stiffness == 0.0 {
            return Err(ContactError::OutOfRange {
                name: "tangential_stiffness",
                value: 0.0,
                allowed: "(0, ∞) when friction > 0 with the history model (give \
                          tangential_stiffness, or tangential = \"coulomb\", for MD; or \
                          tangential_restitution for Walton's rule of the event engines)",
            });
        }
        Ok(spring)
    }

    /// The tangential force on i and the spring afterwards, given the spring `spring`
    /// already turned and grown for this step, the slip velocity `slip` and the clipped
    /// total normal force `normal_force` ≥ 0: F_t = −k_t ξ_t − γ_t v_t while
    /// |F_t| ≤ µF_n, else scaled onto the cap with ξ_t = −(F_t + γ_t v_t)/k_t.
    #[inline]
    pub fn force(&self, normal_force: f64, slip: [f64; 3], spring: [f64; 3]) -> TangentialForce {
        let cap = self.friction * normal_force.max(0.0);
        let (k, g) = (self.stiffness, self.damping);
        let force = add_scaled(scale(-k, spring), -g, slip);
        let f = norm(force);
        if f <= cap {
            return TangentialForce {
                force,
                spring,
                sliding: false,
            };
        }
        let force = scale(cap / f, force);
        TangentialForce {
            force,
            spring: scale(-1.0 / k, add_scaled(force, g, slip)),
            sliding: true,
        }
    }
}

/// The tangential sub-model of a contact: the slot of [`crate::ContactModel`] that
/// LAMMPS's `GranularModel` calls `tangential`. Frictionless contacts have
/// [`Tangential::None`], never a variant with µ = 0 ([`Tangential::normalised`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub enum Tangential {
    /// Smooth spheres: no tangential force, spins never change.
    #[default]
    None,
    /// The history spring (MD; eMD* solves it exactly per collision).
    History(HistorySpring),
    /// Pure Coulomb sliding, |F_t| = µF_n against the slip (Huang & Nydal, Sec. 2; MD).
    Coulomb {
        /// µ > 0.
        friction: f64,
    },
    /// Walton's instantaneous rule (µ, β₀) of the event-driven engines.
    Walton(crate::Walton),
}

impl Tangential {
    /// Coulomb's µ (0 without friction).
    pub fn friction(&self) -> f64 {
        match self {
            Self::None => 0.0,
            Self::History(h) => h.friction,
            Self::Coulomb { friction } => *friction,
            Self::Walton(w) => w.friction,
        }
    }

    /// True if contacts exchange tangential forces (µ > 0).
    pub fn is_frictional(&self) -> bool {
        self.friction() > 0.0
    }

    /// The same law, or [`Tangential::None`] where µ = 0 (a frictionless contact is run
    /// by the frictionless code, bit for bit).
    pub fn normalised(self) -> Self {
        if self.is_frictional() {
            self
        } else {
            Self::None
        }
    }

    /// The name of the sub-model, as the config and the messages give it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::None => "none",
            Self::History(_) => "history",
            Self::Coulomb { .. } => "coulomb",
            Self::Walton(_) => "walton",
        }
    }

    /// The tangential force of MD's laws ([`HistorySpring::force`]; for
    /// [`Tangential::Coulomb`] −µF_n v̂_t with the spring kept at zero). Zero for
    /// smooth contacts and for Walton's rule, which is instantaneous and has no force.
    #[inline]
    pub fn force(&self, normal_force: f64, slip: [f64; 3], spring: [f64; 3]) -> TangentialForce {
        match self {
            Self::History(h) => h.force(normal_force, slip, spring),
            Self::Coulomb { friction } => {
                let cap = friction * normal_force.max(0.0);
                let s = norm(slip);
                let force = if s > 0.0 {
                    scale(-cap / s, slip)
                } else {
                    [0.0; 3]
                };
                TangentialForce {
                    force,
                    spring: [0.0; 3],
                    sliding: s > 0.0,
                }
            }
            Self::None | Self::Walton(_) => TangentialForce {
                force: [0.0; 3],
                spring: [0.0; 3],
                sliding: false,
            },
        }
    }

    /// The elastic energy ½ k_t |ξ_t|² of a contact's spring (zero without one).
    pub fn spring_energy(&self, spring: [f64; 3]) -> f64 {
        match self {
            Self::History(h) => 0.5 * h.stiffness * dot(spring, spring),
            _ => 0.0,
        }
    }
}

/// What [`Tangential::force`] gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialForce {
    /// F_t on i in N.
    pub force: [f64; 3],
    /// The spring ξ_t after the step, in m.
    pub spring: [f64; 3],
    /// True if the force sits on the Coulomb cap.
    pub sliding: bool,
}

/// The slip velocity at the contact, v_t = v_ij − (v_ij·n)n − (R_i ω_i + R_j ω_j) × n,
/// with v_ij = v_i − v_j (LAMMPS's `pair granular`; a wall has v_j = 0, ω_j = 0).
#[inline]
pub fn slip_velocity(
    n: [f64; 3],
    v_ij: [f64; 3],
    (r_i, w_i): (f64, [f64; 3]),
    (r_j, w_j): (f64, [f64; 3]),
) -> [f64; 3] {
    let vn = dot(v_ij, n);
    let w = add_scaled(scale(r_i, w_i), r_j, w_j);
    sub(add_scaled(v_ij, -vn, n), cross(w, n))
}

/// The spring carried from the tangent plane of the normal `n_old` into that of `n`:
/// turned by the smallest rotation that takes `n_old` to `n` (the parallel transport of
/// dξ_t/dt = −(ξ_t·ṅ)n over a step, to second order), then projected onto the plane to
/// remove round-off. For a normal turning in one plane this is LAMMPS's projection and
/// rescaling (Luding, Granular Matter 10, 235, 2008, Eq. 17); when the spring leaves that
/// plane (spins out of it), projection and rescaling err by O(dt²) per step, a first-order
/// method, and this rotation does not.
#[inline]
pub fn turn_spring(spring: [f64; 3], n_old: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    // Rodrigues's formula with w = n_old × n, |w| = sin θ, c = cos θ:
    // R v = v + w × v + w × (w × v)/(1 + c), exact and free of cancellation for small θ.
    let w = cross(n_old, n);
    let c = dot(n_old, n);
    let wv = cross(w, spring);
    let turned = if c > -1.0 {
        add(add(spring, wv), scale(1.0 / (1.0 + c), cross(w, wv)))
    } else {
        spring
    };
    add_scaled(turned, -dot(turned, n), n)
}

/// The lever arm of a tangential force on a sphere of radius R at normal overlap ξ:
/// R − ξ/2, from the centre to the middle of the overlap.
#[inline]
pub fn lever_arm(radius: f64, overlap: f64) -> f64 {
    radius - 0.5 * overlap
}

/// The torque of the tangential force `force` (on i) about the centre of a sphere
/// with lever arm `arm`: −arm · n × F_t. Particle i takes `torque(arm_i, n, F_t)`, its
/// partner j `torque(arm_j, n, F_t)` as well (its force −F_t acts at +arm_j n).
#[inline]
pub fn torque(arm: f64, n: [f64; 3], force: [f64; 3]) -> [f64; 3] {
    scale(-arm, cross(n, force))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(mu: f64) -> Tangential {
        Tangential::History(HistorySpring::new(mu, 1000.0, 2.0).unwrap())
    }

    #[test]
    fn a_sticking_spring_is_hookean_and_a_sliding_one_sits_on_the_cap() {
        let f = history(0.5);
        let (slip, spring) = ([0.1, 0.0, 0.0], [1e-4, 0.0, 0.0]);
        // −k ξ − γ v = −0.1 − 0.2 = −0.3 N, below µ F_n = 0.5 N.
        let t = f.force(1.0, slip, spring);
        assert!(!t.sliding);
        assert_eq!(t.spring, spring);
        assert!((t.force[0] + 0.3).abs() < 1e-15);
        // With F_n = 0.2 N the cap is 0.1 N: the force is scaled onto it, and the spring
        // is set so that −k ξ − γ v gives it.
        let t = f.force(0.2, slip, spring);
        assert!(t.sliding);
        assert!((t.force[0] + 0.1).abs() < 1e-15);
        let again = add_scaled(scale(-1000.0, t.spring), -2.0, slip);
        assert!((again[0] - t.force[0]).abs() < 1e-15);
        // A clipped normal force of zero leaves no tangential force.
        assert_eq!(f.force(0.0, slip, spring).force, [0.0; 3]);
    }

    #[test]
    fn coulomb_opposes_the_slip_with_mu_times_the_normal_force() {
        let f = Tangential::Coulomb { friction: 0.3 };
        let t = f.force(2.0, [0.0, 3.0, 4.0], [0.0; 3]);
        assert!((t.force[1] + 0.6 * 0.6).abs() < 1e-15);
        assert!((t.force[2] + 0.6 * 0.8).abs() < 1e-15);
        assert_eq!(f.force(2.0, [0.0; 3], [0.0; 3]).force, [0.0; 3]);
    }

    #[test]
    fn the_spring_turns_with_the_normal_keeping_its_length() {
        // The normal turns by 30° about z: a spring along y turns with it, one along
        // z (the axis) stays.
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let (n_old, n) = ([1.0, 0.0, 0.0], [c, s, 0.0]);
        let t = turn_spring([0.0, 2.0, 0.0], n_old, n);
        for (got, want) in t.iter().zip([-2.0 * s, 2.0 * c, 0.0]) {
            assert!((got - want).abs() < 1e-15, "{t:?}");
        }
        assert_eq!(turn_spring([0.0, 0.0, 3.0], n_old, n), [0.0, 0.0, 3.0]);
        // A spring out of the turning plane keeps its length and its angle to the axis.
        let t = turn_spring([0.0, 1.0, 1.0], n_old, n);
        assert!(dot(t, n).abs() < 1e-15);
        assert!((norm(t) - 2f64.sqrt()).abs() < 1e-15);
        assert!((t[2] - 1.0).abs() < 1e-15);
        // In one plane it is LAMMPS's projection and rescaling.
        let v = [0.0, 1.0, 0.0];
        let projected = add_scaled(v, -dot(v, n), n);
        let rescaled = scale(norm(v) / norm(projected), projected);
        let t = turn_spring(v, n_old, n);
        for k in 0..3 {
            assert!((t[k] - rescaled[k]).abs() < 1e-15);
        }
    }

    #[test]
    fn rolling_without_slip_has_no_slip_velocity() {
        // A sphere of radius 0.5 rolling on a wall (n = +z) at v = 1 m/s: ω = (0, 2, 0)
        // turns the contact point backwards at the same speed.
        let n = [0.0, 0.0, 1.0];
        let slip = slip_velocity(n, [1.0, 0.0, 0.0], (0.5, [0.0, 2.0, 0.0]), (0.0, [0.0; 3]));
        assert_eq!(slip, [0.0; 3]);
        // Normal motion does not slip.
        let slip = slip_velocity(n, [0.0, 0.0, -1.0], (0.5, [0.0; 3]), (0.5, [0.0; 3]));
        assert_eq!(slip, [0.0; 3]);
    }

    #[test]
    fn the_torques_cancel_the_orbital_torque() {
        let (ri, rj, overlap) = (0.1, 0.2, 0.01);
        let n = [0.0, 1.0, 0.0];
        let f = [0.3, 0.0, -0.2];
        let r = ri + rj - overlap;
        // Orbital torque of the pair: (x_i − x_j) × F_t = r n × F_t.
        let orbital = scale(r, cross(n, f));
        let spins = crate::vec3::add(
            torque(lever_arm(ri, overlap), n, f),
            torque(lever_arm(rj, overlap), n, f),
        );
        for k in 0..3 {
            assert!((orbital[k] + spins[k]).abs() < 1e-16);
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(HistorySpring::new(-0.1, 1.0, 0.0).is_err());
        assert!(HistorySpring::new(0.1, -1.0, 0.0).is_err());
        assert!(HistorySpring::new(0.1, 1.0, -1.0).is_err());
        assert!(HistorySpring::new(f64::NAN, 1.0, 0.0).is_err());
        let e = HistorySpring::new(0.1, 0.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("tangential_stiffness"), "{e}");
    }

    #[test]
    fn frictionless_laws_normalise_to_none() {
        let zero = Tangential::History(HistorySpring::new(0.0, 1.0, 0.0).unwrap());
        assert_eq!(zero.normalised(), Tangential::None);
        assert_eq!(
            Tangential::Coulomb { friction: 0.0 }.normalised(),
            Tangential::None
        );
        let rough = Tangential::Coulomb { friction: 0.2 };
        assert_eq!(rough.normalised(), rough);
        assert_eq!(
            Tangential::None.force(1.0, [1.0, 0.0, 0.0], [0.0; 3]).force,
            [0.0; 3]
        );
    }
}
