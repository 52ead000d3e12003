//! Restitution as input: the dissipation that gives a central impact a chosen coefficient
//! of normal restitution.
//!
//! For a central impact (c_φ = 0) the scaled equations of Müller & Pöschel 2013 reduce to
//! ξ'' = −ξ − c_dis·ξ' (linear dashpot, Eq. 42) and ξ'' = −ξ^{3/2} − c_dis·√ξ·ξ'
//! (viscoelastic Hertz, Eq. 54) in the overlap ξ = l̃ − r̃, started at ξ = 0, ξ' = 1
//! (Eq. 44) and ended where the force vanishes (Eq. 10). So ε_n = −ε_ṙ (Eq. 21) is a
//! function of c_dis alone, decreasing from 1 at c_dis = 0. [`central_c_dis`] inverts it
//! with the exact solver [`crate::solve`]; [`with_restitution`] turns c_dis into the
//! physical constant of one pair at one normal speed:
//!
//! - linear: c_dis = γT/m_eff with T = 1/ω, ω = √(k/m_eff) (Eqs. 41, 43), so
//!   γ = c_dis·√(k·m_eff), the same at every speed;
//! - Hertz: c_dis = 3A/(2T) with T = κ^{−2/5}·v^{−1/5}, κ = ρ_el/m_eff (Eq. 53 and below
//!   Eq. 54), so A = (2/3)·c_dis·T depends on the speed v at which ε_n is asked for: at
//!   other speeds the same A gives other ε_n (ε_n falls as v grows).

use crate::solver::{SolveError, solve};
use emdstar_contact::{
    ContactError, ForceLaw, LinearDashpot, Model, PairLaw, PairProperties, ScaledParams,
    ViscoelasticHertz,
};
use std::fmt;

/// The largest scaled dissipation searched. ε_n falls towards 0 as c_dis grows; at this
/// bound it is 1.0e-8 (linear) and 2.8e-7 (Hertz), and a smaller restitution is refused.
pub const MAX_C_DIS: f64 = 1e4;

/// The contact distance used for the central solves. ε_n does not depend on it (see the
/// module documentation); it only has to exceed the largest overlap, which is at most
/// about 1.1 (the elastic Hertz impact).
const L_TILDE: f64 = 1e3;

/// Why no dissipation was found.
#[derive(Debug, Clone, PartialEq)]
pub enum InverseError {
    /// The restitution is not in (0, 1].
    OutOfRange(f64),
    /// Even [`MAX_C_DIS`] leaves the impact more elastic than asked for.
    Unreachable {
        restitution: f64,
        /// ε_n at [`MAX_C_DIS`].
        smallest: f64,
    },
    /// A physical parameter was refused.
    Contact(ContactError),
    /// The forward solve failed.
    Solve(SolveError),
}

impl fmt::Display for InverseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OutOfRange(e) => write!(
                f,
                "restitution = {e} is outside (0, 1]: a coefficient of normal restitution is \
                 greater than 0 and at most 1 (1 is elastic)"
            ),
            Self::Unreachable {
                restitution,
                smallest,
            } => write!(
                f,
                "restitution = {restitution} cannot be reached: the smallest central \
                 restitution searched (scaled dissipation c_dis = {MAX_C_DIS:e}) is \
                 {smallest:.3e}; give a larger restitution"
            ),
            Self::Contact(e) => e.fmt(f),
            Self::Solve(e) => write!(f, "the collision ODE could not be solved: {e}"),
        }
    }
}

impl std::error::Error for InverseError {}

impl From<ContactError> for InverseError {
    fn from(e: ContactError) -> Self {
        Self::Contact(e)
    }
}

impl From<SolveError> for InverseError {
    fn from(e: SolveError) -> Self {
        Self::Solve(e)
    }
}

/// ε_n = −ε_ṙ of a central impact with scaled dissipation `c_dis`, by the exact solver.
pub fn central_restitution_scaled(model: Model, c_dis: f64) -> Result<f64, InverseError> {
    let params = ScaledParams::new(L_TILDE, 0.0, c_dis)?;
    Ok(-solve(model, &params)?.eps_rdot)
}

/// The scaled dissipation c_dis at which a central impact has normal restitution
/// `restitution` ∈ (0, 1]: 0 for 1, else the root of ε_n(c_dis) = restitution, located to
/// a few units of the last place of the solver's ε_n (far below 1e-10).
pub fn central_c_dis(model: Model, restitution: f64) -> Result<f64, InverseError> {
    if !(restitution > 0.0 && restitution <= 1.0) {
        return Err(InverseError::OutOfRange(restitution));
    }
    if restitution == 1.0 {
        return Ok(0.0);
    }
    let miss = |c: f64| -> Result<f64, InverseError> {
        Ok(central_restitution_scaled(model, c)? - restitution)
    };
    // Bracket: ε_n decreases from 1 at c_dis = 0; double until it drops below the target.
    let (mut lo, mut f_lo) = (0.0, 1.0 - restitution);
    let mut hi = 0.1;
    let mut f_hi = miss(hi)?;
    while f_hi > 0.0 {
        if hi >= MAX_C_DIS {
            return Err(InverseError::Unreachable {
                restitution,
                smallest: f_hi + restitution,
            });
        }
        (lo, f_lo) = (hi, f_hi);
        hi = (2.0 * hi).min(MAX_C_DIS);
        f_hi = miss(hi)?;
    }
    if f_hi == 0.0 {
        return Ok(hi);
    }
    // Illinois (regula falsi with halving of the stale end) on the bracket.
    let mut side = 0i8;
    for _ in 0..200 {
        let c = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let c = if c > lo && c < hi { c } else { 0.5 * (lo + hi) };
        let f = miss(c)?;
        if f == 0.0 || (hi - lo) <= 4.0 * f64::EPSILON * hi {
            return Ok(c);
        }
        if f > 0.0 {
            (lo, f_lo) = (c, f);
            if side == 1 {
                f_hi *= 0.5;
            }
            side = 1;
        } else {
            (hi, f_hi) = (c, f);
            if side == -1 {
                f_lo *= 0.5;
            }
            side = -1;
        }
        if f.abs() <= 1e-14 {
            return Ok(c);
        }
    }
    Ok(0.5 * (lo + hi))
}

/// `law` with its dissipation (γ or A) replaced by the one that gives a central impact of
/// `pair` at normal speed `speed` (m/s) the normal restitution `restitution`. The elastic
/// constants of `law` are kept; for the linear dashpot the result does not depend on
/// `speed` (any positive value will do).
pub fn with_restitution(
    law: &ForceLaw,
    pair: &PairProperties,
    speed: f64,
    restitution: f64,
) -> Result<ForceLaw, InverseError> {
    let speed = emdstar_contact::check::positive("speed", speed)?;
    let m_eff = emdstar_contact::check::positive("effective mass", pair.m_eff)?;
    let c_dis = central_c_dis(law.model(), restitution)?;
    Ok(match law {
        ForceLaw::Linear(l) => {
            // Eq. (43) with T = 1/ω, Eq. (41).
            let damping = c_dis * (l.stiffness * m_eff).sqrt();
            ForceLaw::Linear(LinearDashpot::new(l.stiffness, damping)?)
        }
        ForceLaw::Hertz(h) => {
            let PairLaw::Hertz { rho_el, .. } = PairLaw::same_material(law, pair.r_eff)? else {
                unreachable!("a Hertz material gives a Hertz pair law")
            };
            // Eq. (53): T = κ^{-2/5} v^{-1/5}; c_dis = 3A/(2T) below Eq. (54).
            let time = (rho_el / m_eff).powf(-0.4) * speed.powf(-0.2);
            let dissipation = 2.0 / 3.0 * c_dis * time;
            ForceLaw::Hertz(ViscoelasticHertz::new(h.young, h.poisson, dissipation)?)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_needs_no_dissipation_and_bad_values_are_refused() {
        for model in [Model::Linear, Model::Hertz] {
            assert_eq!(central_c_dis(model, 1.0), Ok(0.0));
            for bad in [0.0, -0.5, 1.0 + 1e-12, f64::NAN, f64::INFINITY] {
                assert!(matches!(
                    central_c_dis(model, bad),
                    Err(InverseError::OutOfRange(_))
                ));
            }
            let tiny = central_c_dis(model, 1e-9);
            assert!(
                matches!(tiny, Err(InverseError::Unreachable { smallest, .. }) if smallest > 1e-9),
                "{tiny:?}"
            );
        }
    }
}
