//! Normal force laws of frictionless spheres, material by material and pair by pair.
//!
//! Sign conventions (docs/physics.md, "Pair quantities"): overlap ξ = l − |r| > 0 in contact, ξ̇ = −ṙ > 0 while
//! approaching, and a positive force repels.

use crate::error::{ContactError, Result, non_negative, positive};
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// The two force models of Müller & Pöschel 2013, Sec. V.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// Linear spring-dashpot, Eq. (40).
    Linear,
    /// Viscoelastic Hertz contact, Eq. (51).
    Hertz,
}

impl Model {
    /// The lower-case name used in configs, specs and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::Hertz => "hertz",
        }
    }
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Model {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "linear" => Ok(Self::Linear),
            "hertz" => Ok(Self::Hertz),
            other => Err(format!(
                "unknown force model '{other}': expected 'linear' or 'hertz'"
            )),
        }
    }
}

/// Linear spring-dashpot material: F = kξ + γξ̇ (Müller & Pöschel 2013, Eq. 40).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDashpot {
    /// Spring constant k in N/m.
    pub stiffness: f64,
    /// Dashpot constant γ in kg/s.
    pub damping: f64,
}

impl LinearDashpot {
    /// Checks k > 0 and γ ≥ 0.
    pub fn new(stiffness: f64, damping: f64) -> Result<Self> {
        Ok(Self {
            stiffness: positive("stiffness", stiffness)?,
            damping: non_negative("damping", damping)?,
        })
    }

    /// Duration and restitution of a central impact of reduced mass `m_eff`, with the
    /// collision ending where the force vanishes.
    ///
    /// Schwager & Pöschel, Granular Matter 9, 465 (2007), all four damping regimes
    /// (the under-damped ones share one `atan2` form).
    pub fn central_impact(&self, m_eff: f64) -> Result<CentralImpact> {
        let m_eff = positive("effective mass", m_eff)?;
        let omega0 = (self.stiffness / m_eff).sqrt();
        let beta = self.damping / (2.0 * m_eff);
        let duration = if beta < omega0 {
            let omega = (omega0 * omega0 - beta * beta).sqrt();
            (PI - (2.0 * beta * omega).atan2(omega * omega - beta * beta)) / omega
        } else if beta == omega0 {
            2.0 / beta
        } else {
            let big_omega = (beta * beta - omega0 * omega0).sqrt();
            ((beta + big_omega) / (beta - big_omega)).ln() / big_omega
        };
        Ok(CentralImpact {
            duration,
            restitution: (-beta * duration).exp(),
        })
    }
}

/// Viscoelastic Hertz material (Brilliantov et al. 1996; Müller & Pöschel 2013, Eq. 51).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscoelasticHertz {
    /// Young's modulus Y in Pa.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Dissipative constant A in s.
    pub dissipation: f64,
}

impl ViscoelasticHertz {
    /// Checks Y > 0, −1 < ν ≤ 0.5 and A ≥ 0.
    pub fn new(young: f64, poisson: f64, dissipation: f64) -> Result<Self> {
        let poisson = crate::error::finite("poisson", poisson)?;
        if !(poisson > -1.0 && poisson <= 0.5) {
            return Err(ContactError::OutOfRange {
                name: "poisson",
                value: poisson,
                allowed: "(-1, 0.5]",
            });
        }
        Ok(Self {
            young: positive("young", young)?,
            poisson,
            dissipation: non_negative("dissipation", dissipation)?,
        })
    }

    /// Y/(1−ν²), the plane-strain modulus that enters Hertz's law.
    fn plane_strain_modulus(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }
}

/// Duration and normal restitution of a central impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentralImpact {
    /// Contact duration in s.
    pub duration: f64,
    /// Coefficient of normal restitution.
    pub restitution: f64,
}

/// A material's force law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ForceLaw {
    Linear(LinearDashpot),
    Hertz(ViscoelasticHertz),
}

impl ForceLaw {
    /// Which of the two models this is.
    pub fn model(&self) -> Model {
        match self {
            Self::Linear(_) => Model::Linear,
            Self::Hertz(_) => Model::Hertz,
        }
    }
}

/// The force law of one particular pair, with the materials and the geometry folded in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairLaw {
    /// F = kξ + γξ̇.
    Linear { stiffness: f64, damping: f64 },
    /// F = ρ_el ξ^{3/2} + (3/2) A ρ_el √ξ ξ̇, Müller & Pöschel 2013, Eqs. (51)-(52).
    Hertz { rho_el: f64, dissipation: f64 },
}

impl PairLaw {
    /// The law between materials `a` and `b` for a pair of effective radius `r_eff`
    /// (use the sphere's radius against a flat wall).
    ///
    /// Hertz moduli mix by the standard contact-mechanics rule
    /// 1/E* = (1−ν₁²)/Y₁ + (1−ν₂²)/Y₂, with ρ_el = (4/3)E*√R_eff, which reduces to
    /// Eq. (52) for equal materials. The dissipative constant A and the linear
    /// constants k and γ have no standard mixing rule, so they must agree.
    pub fn between(a: &ForceLaw, b: &ForceLaw, r_eff: f64) -> Result<Self> {
        let r_eff = positive("effective radius", r_eff)?;
        match (a, b) {
            (ForceLaw::Linear(x), ForceLaw::Linear(y)) => {
                if x != y {
                    return Err(ContactError::IncompatibleMaterials(format!(
                        "linear dashpots (k={}, γ={}) and (k={}, γ={}) differ, and the \
                         linear model has no standard mixing rule; give both materials the \
                         same stiffness and damping",
                        x.stiffness, x.damping, y.stiffness, y.damping
                    )));
                }
                Ok(Self::Linear {
                    stiffness: x.stiffness,
                    damping: x.damping,
                })
            }
            (ForceLaw::Hertz(x), ForceLaw::Hertz(y)) => {
                if x.dissipation != y.dissipation {
                    return Err(ContactError::IncompatibleMaterials(format!(
                        "viscoelastic dissipation constants A={} s and A={} s differ, and A \
                         has no standard mixing rule; give both materials the same A",
                        x.dissipation, y.dissipation
                    )));
                }
                let e_star =
                    1.0 / (1.0 / x.plane_strain_modulus() + 1.0 / y.plane_strain_modulus());
                Ok(Self::Hertz {
                    rho_el: 4.0 / 3.0 * e_star * r_eff.sqrt(),
                    dissipation: x.dissipation,
                })
            }
            _ => Err(ContactError::IncompatibleMaterials(
                "a linear-dashpot material cannot touch a Hertz material".into(),
            )),
        }
    }

    /// The law between two spheres of one material.
    pub fn same_material(law: &ForceLaw, r_eff: f64) -> Result<Self> {
        Self::between(law, law, r_eff)
    }

    /// Which model this is.
    pub fn model(&self) -> Model {
        match self {
            Self::Linear { .. } => Model::Linear,
            Self::Hertz { .. } => Model::Hertz,
        }
    }

    /// Normal force F(ξ, ξ̇), zero out of contact and clipped so that it never
    /// attracts: F = max(0, …) (Schwager & Pöschel 2007).
    #[inline]
    pub fn normal_force(&self, overlap: f64, overlap_rate: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        let f = match *self {
            Self::Linear { stiffness, damping } => stiffness * overlap + damping * overlap_rate,
            Self::Hertz {
                rho_el,
                dissipation,
            } => rho_el * overlap.sqrt() * (overlap + 1.5 * dissipation * overlap_rate),
        };
        f.max(0.0)
    }

    /// Central-impact duration of the undamped law at normal speed `v_n`, in s:
    /// π/ω (linear) or τ̃·T with τ̃ from [`hertz_elastic_scaled_duration`].
    pub fn elastic_duration(&self, m_eff: f64, v_n: f64) -> Result<f64> {
        let m_eff = positive("effective mass", m_eff)?;
        let v_n = positive("normal speed", v_n)?;
        Ok(match *self {
            Self::Linear { stiffness, .. } => PI / (stiffness / m_eff).sqrt(),
            Self::Hertz { rho_el, .. } => {
                let kappa = rho_el / m_eff;
                hertz_elastic_scaled_duration() * kappa.powf(-0.4) * v_n.powf(-0.2)
            }
        })
    }
}

/// Scaled duration of an elastic central Hertz impact,
/// τ̃ = (4/5)(5/4)^{2/5} √π Γ(2/5)/Γ(9/10) ≈ 3.218065 (from energy conservation in Eq. 54).
pub fn hertz_elastic_scaled_duration() -> f64 {
    0.8 * 1.25f64.powf(0.4) * PI.sqrt() * (ln_gamma(0.4) - ln_gamma(0.9)).exp()
}

/// ln Γ(x) for x > 0 by the Lanczos approximation (g = 7, nine terms; ≈1e-15 relative).
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1−x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        sum += c / (x + i as f64);
    }
    let t = x + G + 0.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn ln_gamma_matches_known_values() {
        // Γ(1/2) = √π, Γ(5) = 24, Γ(1/3) = 2.678938534707747...
        assert_relative_eq!(ln_gamma(0.5).exp(), PI.sqrt(), max_relative = 1e-14);
        assert_relative_eq!(ln_gamma(5.0).exp(), 24.0, max_relative = 1e-14);
        assert_relative_eq!(
            ln_gamma(1.0 / 3.0).exp(),
            2.678_938_534_707_747_6,
            max_relative = 1e-14
        );
    }

    #[test]
    fn hertz_elastic_duration_is_the_published_value() {
        assert_relative_eq!(
            hertz_elastic_scaled_duration(),
            3.218065,
            max_relative = 2e-7
        );
    }

    #[test]
    fn force_is_clipped_and_zero_out_of_contact() {
        let lin = PairLaw::Linear {
            stiffness: 10.0,
            damping: 1.0,
        };
        assert_eq!(lin.normal_force(-1e-3, 5.0), 0.0);
        assert_eq!(lin.normal_force(1e-3, -5.0), 0.0);
        assert_relative_eq!(lin.normal_force(0.1, 0.5), 1.5);
        let hz = PairLaw::Hertz {
            rho_el: 4.0,
            dissipation: 0.1,
        };
        assert_relative_eq!(
            hz.normal_force(0.25, 2.0),
            4.0 * 0.125 + 1.5 * 0.1 * 4.0 * 0.5 * 2.0
        );
        assert_eq!(hz.normal_force(0.25, -100.0), 0.0);
    }

    #[test]
    fn hertz_mixing_reduces_to_eq_52_for_equal_materials() {
        let m = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 1e-3).unwrap());
        let r_eff: f64 = 0.05;
        let PairLaw::Hertz { rho_el, .. } = PairLaw::same_material(&m, r_eff).unwrap() else {
            panic!("expected Hertz");
        };
        assert_relative_eq!(
            rho_el,
            2.0 * 1e9 * r_eff.sqrt() / (3.0 * (1.0 - 0.16)),
            max_relative = 1e-14
        );
    }

    #[test]
    fn incompatible_materials_are_rejected_with_a_reason() {
        let lin = ForceLaw::Linear(LinearDashpot::new(1e3, 0.0).unwrap());
        let lin2 = ForceLaw::Linear(LinearDashpot::new(2e3, 0.0).unwrap());
        let hz = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 0.0).unwrap());
        let hz2 = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-4).unwrap());
        for (a, b) in [(&lin, &lin2), (&lin, &hz), (&hz, &hz2)] {
            let err = PairLaw::between(a, b, 0.1).unwrap_err();
            assert!(
                matches!(err, ContactError::IncompatibleMaterials(_)),
                "{err}"
            );
        }
        // Different Hertz moduli do mix.
        let hz3 = ForceLaw::Hertz(ViscoelasticHertz::new(2e9, 0.2, 0.0).unwrap());
        assert!(PairLaw::between(&hz, &hz3, 0.1).is_ok());
    }

    #[test]
    fn bad_material_parameters_are_rejected() {
        assert!(LinearDashpot::new(0.0, 0.0).is_err());
        assert!(LinearDashpot::new(1.0, -1.0).is_err());
        assert!(LinearDashpot::new(f64::NAN, 0.0).is_err());
        assert!(ViscoelasticHertz::new(1e9, 0.6, 0.0).is_err());
        assert!(ViscoelasticHertz::new(-1e9, 0.3, 0.0).is_err());
        assert!(ViscoelasticHertz::new(1e9, 0.3, f64::INFINITY).is_err());
    }
}
