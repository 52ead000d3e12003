//! Walton's three-parameter rule for instantaneous collisions of rough spheres: normal
//! restitution e, Coulomb's µ and the tangential restitution β₀ of sticking impacts
//! (O. R. Walton, "Numerical simulation of inelastic, frictional particle-particle
//! interactions", in *Particulate Two-Phase Flow*, ed. M. C. Roco, Butterworth-Heinemann
//! 1993, ch. 25; Huang & Nydal's hybrid method, Eqs. 1.1a-b, 3.2 and 3.3 and appendix A).
//! The derivation for unequal radii and masses is in docs/physics.md, section
//! "Walton's rule".
//!
//! Conventions are those of the tangential force law ([`crate::slip_velocity`]): for
//! particle i against partner j, **n** = (**x**_i − **x**_j)/|**x**_i − **x**_j| (a wall: its
//! normal towards the particle), the contact-point velocity
//! **g** = **v**_ij − (R_i **ω**_i + R_j **ω**_j) × **n**, its normal part g_n = **g**·**n** < 0
//! while approaching and its tangential part **v**_t. The impulse **P** acts on i at
//! −R_i**n** from its centre, −**P** on j at +R_j**n**; a wall is infinitely heavy and does
//! not rotate.
//!
//! - normal: g_n' = −e g_n, J_n = −(1 + e) m_eff g_n (HAET Eq. 1.1a);
//! - tangential: **v**_t' = −β **v**_t (HAET Eq. 1.1b) with β = min(β₀, β_slide) (HAET
//!   Eq. 3.2), β_slide = −1 + µ J_n/(m_t |**v**_t|) the value at which the tangential
//!   impulse reaches Coulomb's bound µ J_n, and 1/m_t = Σ (1/m + R²/I) over both
//!   partners: 1/m_t = (1 + 1/q)/m_eff for solid spheres (I = q m R², q = 2/5), so
//!   β_slide = −1 + (7/2) µ (1 + e) |g_n|/|**v**_t| for any radii and masses;
//! - spins: Δ**ω**_i = −R_i **n** × **P**/I_i and Δ**ω**_j = −R_j **n** × **P**/I_j, so each
//!   sphere's spin changes by |Δ**v**_t|/(q R) (HAET Eq. 3.3) and the angular momentum
//!   about any point is conserved at contact distance.

use crate::error::{ContactError, Result, finite, non_negative};
use crate::tangential::{SOLID_SPHERE_INERTIA, slip_velocity};
use crate::vec3::{add_scaled, cross, dot, norm, scale};

/// The friction of Walton's rule: Coulomb's µ and the tangential restitution β₀ of
/// sticking impacts.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Walton {
    /// µ ≥ 0.
    pub friction: f64,
    /// β₀ ∈ [−1, 1]: −1 smooth (no tangential impulse), 1 perfectly rough (a sticking
    /// impact reverses the slip).
    pub tangential_restitution: f64,
}

impl Walton {
    /// Checks µ ≥ 0 and β₀ ∈ [−1, 1], both finite.
    pub fn new(friction: f64, tangential_restitution: f64) -> Result<Self> {
        non_negative("friction", friction)?;
        let b = finite("tangential_restitution", tangential_restitution)?;
        if !(-1.0..=1.0).contains(&b) {
            return Err(ContactError::OutOfRange {
                name: "tangential_restitution",
                value: b,
                allowed: "[-1, 1] (-1: smooth, 1: perfectly rough)",
            });
        }
        Ok(Self {
            friction,
            tangential_restitution: b,
        })
    }
}

/// A sphere taking part in a collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rough {
    pub velocity: [f64; 3],
    /// Angular velocity in rad/s.
    pub spin: [f64; 3],
    pub radius: f64,
    pub mass: f64,
}

/// What a collision by Walton's rule does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughOutcome {
    /// Velocities after the collision, of i and j (a wall's stays zero).
    pub velocity: [[f64; 3]; 2],
    /// Spins after the collision, of i and j.
    pub spin: [[f64; 3]; 2],
    /// The tangential restitution applied, β = min(β₀, β_slide) (β₀ when nothing slips).
    pub beta: f64,
    /// True if the tangential impulse sits on Coulomb's bound µ J_n (β < β₀).
    pub sliding: bool,
}

/// The collision of sphere `i` with sphere `j` along `n` = (**x**_i − **x**_j)/|…| (unit)
/// by Walton's rule with normal restitution `e`. A pair that does not approach
/// (g_n ≥ 0) gets no tangential impulse.
pub fn rough_pair(n: [f64; 3], i: &Rough, j: &Rough, e: f64, w: &Walton) -> RoughOutcome {
    rough(n, i, Some(j), e, w)
}

/// The collision of sphere `i` with a wall of unit normal `n` (towards the sphere):
/// an infinitely heavy partner at rest that does not rotate.
pub fn rough_wall(n: [f64; 3], i: &Rough, e: f64, w: &Walton) -> RoughOutcome {
    rough(n, i, None, e, w)
}

fn rough(n: [f64; 3], i: &Rough, j: Option<&Rough>, e: f64, w: &Walton) -> RoughOutcome {
    let q = SOLID_SPHERE_INERTIA;
    let (vj, wj, rj, inv_mj) = match j {
        Some(j) => (j.velocity, j.spin, j.radius, 1.0 / j.mass),
        None => ([0.0; 3], [0.0; 3], 0.0, 0.0),
    };
    let inv_mi = 1.0 / i.mass;
    let v_ij = add_scaled(i.velocity, -1.0, vj);
    let g_n = dot(v_ij, n);
    // Normal impulse on i (HAET Eqs. A.5-A.7): g_n' = −e g_n.
    let inv_m_eff = inv_mi + inv_mj;
    let j_n = -(1.0 + e) * g_n / inv_m_eff;
    // Tangential: 1/m_t = Σ (1/m + R²/I) = (1 + 1/q)(1/m_i + 1/m_j).
    let inv_m_t = inv_m_eff + inv_mi / q + inv_mj / q;
    let slip = slip_velocity(n, v_ij, (i.radius, i.spin), (rj, wj));
    let b0 = w.tangential_restitution;
    let stick = scale(-(1.0 + b0) / inv_m_t, slip);
    let bound = w.friction * j_n.max(0.0);
    let s = norm(slip);
    let (p_t, beta, sliding) = if norm(stick) <= bound {
        (stick, b0, false)
    } else {
        // On Coulomb's bound, against the slip (s > 0 here: the sticking impulse is not
        // zero). β = −1 + µ J_n/(m_t |v_t|) < β₀ (HAET Eq. 3.2).
        (scale(-bound / s, slip), -1.0 + bound * inv_m_t / s, true)
    };
    let p = add_scaled(p_t, j_n, n);
    // The normal part of P exerts no torque: n × P = n × P_t.
    let turn = cross(n, p_t);
    let spin_j = if j.is_some() {
        add_scaled(wj, -inv_mj / (q * rj), turn)
    } else {
        wj
    };
    RoughOutcome {
        velocity: [
            add_scaled(i.velocity, inv_mi, p),
            add_scaled(vj, -inv_mj, p),
        ],
        spin: [add_scaled(i.spin, -inv_mi / (q * i.radius), turn), spin_j],
        beta,
        sliding,
    }
}

#[cfg(test)]
#[path = "walton_tests.rs"]
mod tests;
