//! The tangential restitution β₀ of a sticking impact under force-based MD's tangential
//! law ([`Tangential`]): the parameter of Walton's rule ([`crate::Walton`]) that ties an
//! event-driven collision to MD's contact, as HAET's Eqs. 1.1a-b tie the two methods
//! through a normal and a tangential coefficient of restitution (Huang & Nydal, cited
//! in docs/physics.md, "Walton's rule").
//!
//! While a contact sticks (µ → ∞), the slip **g**_t of the contact point and the spring
//! ξ_t obey m_t ġ_t = −k_t ξ_t − γ_t g_t, ξ̇_t = g_t, with the tangential mass
//! 1/m_t = (1 + 1/q)/m_eff (solid spheres, I = q m R², q = 2/5, lever arms taken as the
//! radii; see [`crate::walton`]): a damped oscillator started at ξ_t = 0, g_t = g₀, which
//! runs for the duration t_c of the normal contact. So β₀ = −g_t(t_c)/g₀ with
//! ζ = γ_t/(2m_t) and ω₀² = k_t/m_t:
//! - under-damped: β₀ = −e^{−ζt_c}[cos ωt_c − (ζ/ω) sin ωt_c], ω = √(ω₀² − ζ²);
//! - critical: β₀ = −e^{−ζt_c}(1 − ζt_c);
//! - over-damped: β₀ = −e^{−ζt_c}[cosh Ωt_c − (ζ/Ω) sinh Ωt_c], Ω = √(ζ² − ω₀²).
//!
//! The energy of the oscillator only falls, so |β₀| ≤ 1. Pure Coulomb sliding
//! ([`Tangential::Coulomb`]) has no spring: it slows the slip down to zero and
//! never reverses it, β₀ = 0. Walton's rule then takes β = min(β₀, β_slide), which
//! brings back Coulomb's bound for the actual µ.

use crate::tangential::{HistorySpring, SOLID_SPHERE_INERTIA, Tangential};

/// β₀ of the tangential law `tangential` for a pair of effective mass `m_eff` (a
/// sphere's mass against a wall) whose normal contact lasts `contact_time` (see the
/// module docs): −1 for smooth spheres (the slip is kept), Walton's own β₀ for his rule.
pub fn sticking_restitution(tangential: &Tangential, m_eff: f64, contact_time: f64) -> f64 {
    match tangential {
        Tangential::None => -1.0,
        Tangential::Coulomb { .. } => 0.0,
        Tangential::Walton(w) => w.tangential_restitution,
        Tangential::History(spring) => spring_restitution(spring, m_eff, contact_time),
    }
}

/// β₀ of the sticking oscillator of a history spring (the module docs).
fn spring_restitution(friction: &HistorySpring, m_eff: f64, contact_time: f64) -> f64 {
    let q = SOLID_SPHERE_INERTIA;
    let m_t = m_eff * q / (1.0 + q);
    let zeta = friction.damping / (2.0 * m_t);
    let omega0_sq = friction.stiffness / m_t;
    let t = contact_time;
    let decay = (-zeta * t).exp();
    if zeta * zeta < omega0_sq {
        let omega = (omega0_sq - zeta * zeta).sqrt();
        -decay * ((omega * t).cos() - zeta / omega * (omega * t).sin())
    } else if zeta * zeta == omega0_sq {
        -decay * (1.0 - zeta * t)
    } else {
        let big_omega = (zeta * zeta - omega0_sq).sqrt();
        let x = big_omega * t;
        if x < 1.0 {
            -decay * (x.cosh() - zeta / big_omega * x.sinh())
        } else {
            // e^{−ζt}(cosh x − (ζ/Ω) sinh x) as decaying exponentials (Ω < ζ), which
            // neither overflow nor cancel for strong damping.
            let r = zeta / big_omega;
            let slow = ((big_omega - zeta) * t).exp();
            let fast = (-(big_omega + zeta) * t).exp();
            -0.5 * ((1.0 - r) * slow + (1.0 + r) * fast)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(stiffness: f64, damping: f64) -> Tangential {
        Tangential::History(HistorySpring::new(0.5, stiffness, damping).unwrap())
    }

    /// A plain explicit integration of the sticking oscillator (fine steps, RK4).
    fn integrated(f: &Tangential, m_eff: f64, t_c: f64) -> f64 {
        let Tangential::History(f) = f else {
            panic!("a history spring")
        };
        let m_t = m_eff * SOLID_SPHERE_INERTIA / (1.0 + SOLID_SPHERE_INERTIA);
        let rhs = |x: f64, v: f64| (v, -(f.stiffness * x + f.damping * v) / m_t);
        let steps = 20_000;
        let h = t_c / steps as f64;
        let (mut x, mut v) = (0.0, 1.0);
        for _ in 0..steps {
            let k1 = rhs(x, v);
            let k2 = rhs(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = rhs(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = rhs(x + h * k3.0, v + h * k3.1);
            x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        }
        -v
    }

    #[test]
    fn every_damping_regime_matches_the_integrated_oscillator() {
        let (m_eff, t_c) = (2.0e-3, 1.0e-4);
        let m_t: f64 = m_eff * 2.0 / 7.0;
        let k: f64 = 300.0;
        let critical = 2.0 * (k * m_t).sqrt();
        for damping in [
            0.0,
            0.1 * critical,
            critical,
            1.2 * critical,
            3.0 * critical,
        ] {
            let f = history(k, damping);
            let (got, want) = (
                sticking_restitution(&f, m_eff, t_c),
                integrated(&f, m_eff, t_c),
            );
            assert!(
                (got - want).abs() < 1e-9,
                "γ_t = {damping}: {got} against {want}"
            );
            assert!((-1.0..=1.0).contains(&got));
        }
    }

    #[test]
    fn a_strongly_over_damped_spring_stays_finite_and_barely_turns_the_slip_back() {
        // The dashpot stops the slip at once; the spring then pulls it back at a creep,
        // −g_t ≈ ω₀²/(4ζ²) g₀ (the slow mode): a tiny β₀ > 0, where the plain
        // cosh − sinh form gives ∞ − ∞ = NaN.
        let (m_eff, damping, k) = (2.0e-3, 1.0e6, 300.0);
        let m_t = m_eff * SOLID_SPHERE_INERTIA / (1.0 + SOLID_SPHERE_INERTIA);
        let zeta = damping / (2.0 * m_t);
        let creep = k / m_t / (4.0 * zeta * zeta);
        let beta = sticking_restitution(&history(k, damping), m_eff, 1.0e-2);
        assert!((beta / creep - 1.0).abs() < 1e-3, "{beta} against {creep}");
    }

    #[test]
    fn an_undamped_spring_of_half_a_period_reverses_the_slip() {
        // ω₀ t_c = π: the slip comes back reversed, β₀ = 1.
        let (m_eff, t_c) = (1.0, 0.01);
        let m_t = m_eff * 2.0 / 7.0;
        let k = m_t * (std::f64::consts::PI / t_c).powi(2);
        let beta = sticking_restitution(&history(k, 0.0), m_eff, t_c);
        assert!((beta - 1.0).abs() < 1e-12, "{beta}");
    }

    #[test]
    fn coulomb_sliding_never_reverses_the_slip() {
        let f = Tangential::Coulomb { friction: 0.3 };
        assert_eq!(sticking_restitution(&f, 1.0, 1.0), 0.0);
    }
}
