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
//!   ([`Friction::force`]);
//! - torques **τ**_i = −(R_i − ξ/2) **n** × **F**_t and **τ**_j = −(R_j − ξ/2) **n** × **F**_t,
//!   ξ the normal overlap ([`lever_arm`]): the orbital and spin torques cancel exactly,
//!   so the total angular momentum is conserved.

use crate::error::{ContactError, Result, non_negative};
use crate::vec3::{add, add_scaled, cross, dot, norm, scale, sub};

/// The moment of inertia of a solid sphere in units of m R²: I = (2/5) m R².
pub const SOLID_SPHERE_INERTIA: f64 = 0.4;

/// Which tangential force law a material uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TangentialModel {
    /// The Cundall–Strack history spring with a dashpot, capped by Coulomb's law.
    History,
    /// Pure Coulomb sliding: |F_t| = µF_n against the slip (Huang & Nydal, Sec. 2).
    Coulomb,
}

impl std::str::FromStr for TangentialModel {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "history" => Ok(Self::History),
            "coulomb" => Ok(Self::Coulomb),
            _ => Err(format!(
                "unknown tangential model \"{s}\": use \"history\" (Cundall-Strack spring, \
                 the default) or \"coulomb\" (pure sliding friction)"
            )),
        }
    }
}

/// The friction of a material: Coulomb's µ and the tangential spring and dashpot.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Friction {
    /// Coulomb's coefficient µ ≥ 0 (0: frictionless).
    pub friction: f64,
    /// k_t in N/m (history model).
    pub stiffness: f64,
    /// γ_t in kg/s (history model).
    pub damping: f64,
    pub model: TangentialModel,
    /// β₀ of Walton's rule for the event-driven engines ([`crate::Walton`]); `None` for a
    /// material of force-based MD. A material has one or the other: with β₀ it has no
    /// spring (k_t = 0) and MD refuses it.
    #[serde(default)]
    pub tangential_restitution: Option<f64>,
}

impl Default for Friction {
    fn default() -> Self {
        Self::NONE
    }
}

impl Friction {
    /// No friction: spheres exchange no tangential force and keep their spins.
    pub const NONE: Self = Self {
        friction: 0.0,
        stiffness: 0.0,
        damping: 0.0,
        model: TangentialModel::History,
        tangential_restitution: None,
    };

    /// Checks the parameters: µ, k_t and γ_t finite and not negative, and a history
    /// spring with friction needs k_t > 0 (the cap resets the spring through 1/k_t).
    pub fn new(
        friction: f64,
        stiffness: f64,
        damping: f64,
        model: TangentialModel,
    ) -> Result<Self> {
        let f = Self {
            friction: non_negative("friction", friction)?,
            stiffness: non_negative("tangential_stiffness", stiffness)?,
            damping: non_negative("tangential_damping", damping)?,
            model,
            tangential_restitution: None,
        };
        if f.friction > 0.0 && model == TangentialModel::History && f.stiffness == 0.0 {
            return Err(ContactError::OutOfRange {
                name: "tangential_stiffness",
                value: 0.0,
                allowed: "(0, ∞) when friction > 0 with the history model (give \
                          tangential_stiffness, or tangential = \"coulomb\", for MD; or \
                          tangential_restitution for Walton's rule of the event engines)",
            });
        }
        Ok(f)
    }

    /// The friction of Walton's rule (event-driven engines): Coulomb's µ and the
    /// tangential restitution β₀ ∈ [−1, 1] of sticking impacts, no spring.
    pub fn walton(friction: f64, tangential_restitution: f64) -> Result<Self> {
        let w = crate::Walton::new(friction, tangential_restitution)?;
        Ok(Self {
            friction: w.friction,
            tangential_restitution: Some(w.tangential_restitution),
            ..Self::NONE
        })
    }

    /// Walton's rule of this material, if it has β₀ and friction (µ > 0).
    pub fn walton_rule(&self) -> Option<crate::Walton> {
        let b = self.tangential_restitution?;
        self.is_active().then_some(crate::Walton {
            friction: self.friction,
            tangential_restitution: b,
        })
    }

    /// True if contacts exchange tangential forces.
    pub fn is_active(&self) -> bool {
        self.friction > 0.0
    }

    /// The tangential force on i and the spring afterwards, given the spring `spring`
    /// already turned and grown for this step, the slip velocity `slip` and the clipped
    /// total normal force `normal_force` ≥ 0 (Cundall & Strack 1979; LAMMPS's
    /// `linear_history` with `limit_damping`; for [`TangentialModel::Coulomb`], Huang &
    /// Nydal Sec. 2, whose spring stays zero).
    #[inline]
    pub fn force(&self, normal_force: f64, slip: [f64; 3], spring: [f64; 3]) -> Tangential {
        let cap = self.friction * normal_force.max(0.0);
        match self.model {
            TangentialModel::Coulomb => {
                let s = norm(slip);
                let force = if s > 0.0 {
                    scale(-cap / s, slip)
                } else {
                    [0.0; 3]
                };
                Tangential {
                    force,
                    spring: [0.0; 3],
                    sliding: s > 0.0,
                }
            }
            TangentialModel::History => {
                let (k, g) = (self.stiffness, self.damping);
                let force = add_scaled(scale(-k, spring), -g, slip);
                let f = norm(force);
                if f <= cap {
                    return Tangential {
                        force,
                        spring,
                        sliding: false,
                    };
                }
                let force = scale(cap / f, force);
                Tangential {
                    force,
                    spring: scale(-1.0 / k, add_scaled(force, g, slip)),
                    sliding: true,
                }
            }
        }
    }
}

/// What [`Friction::force`] gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangential {
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

    fn history(mu: f64) -> Friction {
        Friction::new(mu, 1000.0, 2.0, TangentialModel::History).unwrap()
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
        let f = Friction::new(0.3, 0.0, 0.0, TangentialModel::Coulomb).unwrap();
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
        let h = TangentialModel::History;
        assert!(Friction::new(-0.1, 1.0, 0.0, h).is_err());
        assert!(Friction::new(0.1, -1.0, 0.0, h).is_err());
        assert!(Friction::new(0.1, 1.0, -1.0, h).is_err());
        assert!(Friction::new(f64::NAN, 1.0, 0.0, h).is_err());
        let e = Friction::new(0.1, 0.0, 0.0, h).unwrap_err().to_string();
        assert!(e.contains("tangential_stiffness"), "{e}");
        assert!(Friction::new(0.1, 0.0, 0.0, TangentialModel::Coulomb).is_ok());
        assert!(Friction::new(0.0, 0.0, 0.0, h).is_ok());
        assert!("sticky".parse::<TangentialModel>().is_err());
    }
}
