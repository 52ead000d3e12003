//! The scaling of the collision to three dimensionless parameters (l̃, c_φ, c_dis).
//!
//! Müller & Pöschel 2013: Eqs. (11)-(14) in general, Eqs. (41)-(43) for the linear
//! dashpot and Eq. (53) with c_dis = 3A/(2T) for viscoelastic Hertz spheres. In both
//! models X = v_n·T, so c_φ = T·L/(m_eff X²) = l̃·v_t/v_n.

use crate::error::{ContactError, Result, finite, non_negative, positive};
use crate::{Impact, Model, PairLaw, PairProperties};

/// The three parameters of the scaled collision ODE, Eqs. (42) and (54).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaledParams {
    /// l̃ = l/X, the contact distance in units of the length scale.
    pub l_tilde: f64,
    /// c_φ, the scaled angular momentum, Eq. (13).
    pub c_phi: f64,
    /// c_dis, the scaled dissipation, Eq. (43) or below Eq. (54).
    pub c_dis: f64,
}

impl ScaledParams {
    /// Checks l̃ > 0, c_φ ≥ 0 and c_dis ≥ 0, all finite.
    pub fn new(l_tilde: f64, c_phi: f64, c_dis: f64) -> Result<Self> {
        Ok(Self {
            l_tilde: positive("l_tilde", l_tilde)?,
            c_phi: non_negative("c_phi", c_phi)?,
            c_dis: non_negative("c_dis", c_dis)?,
        })
    }

    /// c_φ/l̃ = v_t/v_n = e/√(1−e²), Eq. (45).
    pub fn tangent_ratio(&self) -> f64 {
        self.c_phi / self.l_tilde
    }
}

/// The scaled parameters together with the time and length scales that undo them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaledImpact {
    pub params: ScaledParams,
    /// T, in s.
    pub time: f64,
    /// X, in m.
    pub length: f64,
}

/// Scales a physical impact.
pub fn scale(law: &PairLaw, pair: &PairProperties, impact: &Impact) -> Result<ScaledImpact> {
    let v_n = positive("normal speed", impact.normal_speed)?;
    let v_t = non_negative("tangential speed", impact.tangential_speed)?;
    let m_eff = positive("effective mass", pair.m_eff)?;
    let l = positive("contact distance", pair.l)?;
    let (time, c_dis_of) = match *law {
        PairLaw::Linear { stiffness, damping } => {
            // Eq. (41): T = 1/ω, ω = √(k/m_eff); Eq. (43): c_dis = γT/m_eff.
            let omega = (stiffness / m_eff).sqrt();
            (1.0 / omega, damping / (m_eff * omega))
        }
        PairLaw::Hertz {
            rho_el,
            dissipation,
        } => {
            // Eq. (53): T = κ^{-2/5} v_n^{-1/5}, κ = ρ_el/m_eff; c_dis = 3A/(2T).
            let kappa = rho_el / m_eff;
            let t = kappa.powf(-0.4) * v_n.powf(-0.2);
            (t, 1.5 * dissipation / t)
        }
    };
    let length = v_n * time;
    let l_tilde = l / length;
    let params = ScaledParams::new(l_tilde, l_tilde * (v_t / v_n), c_dis_of)?;
    finite("time scale", time)?;
    if !(time > 0.0 && length > 0.0) {
        return Err(ContactError::NotPositive {
            name: "time or length scale",
            value: time.min(length),
        });
    }
    Ok(ScaledImpact {
        params,
        time,
        length,
    })
}

/// Exponent p in ln l̃ = m + p·ln(1 + (c_φ/l̃)²): 1/2 for Eq. (48), 2/5 for Eq. (55).
pub fn l_tilde_exponent(model: Model) -> f64 {
    match model {
        Model::Linear => 0.5,
        Model::Hertz => 0.4,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ForceLaw, LinearDashpot, Sphere, ViscoelasticHertz};
    use approx::assert_relative_eq;

    #[test]
    fn linear_scaling_matches_eq_47() {
        // Fig. 6 parameters: k = 2 kN/m, R = 0.1 m, ρ = 1140 kg/m³, v = 5 m/s, e = 0.3.
        let s = Sphere::from_density(0.1, 1140.0).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = PairLaw::same_material(
            &ForceLaw::Linear(LinearDashpot::new(2000.0, 0.3).unwrap()),
            pair.r_eff,
        )
        .unwrap();
        let imp = Impact::from_speed_eccentricity(5.0, 0.3).unwrap();
        let sc = scale(&law, &pair, &imp).unwrap();
        let omega = (2000.0 / (s.mass / 2.0)).sqrt();
        // Eq. (47): l̃ = lω/(v√(1−e²)).
        assert_relative_eq!(
            sc.params.l_tilde,
            0.2 * omega / (5.0 * (1.0f64 - 0.09).sqrt()),
            max_relative = 1e-14
        );
        // Eq. (45): ln c_φ = ln l̃ − ½ ln(1/e² − 1).
        assert_relative_eq!(
            sc.params.c_phi.ln(),
            sc.params.l_tilde.ln() - 0.5 * (1.0 / 0.09 - 1.0f64).ln(),
            max_relative = 1e-14
        );
        assert_relative_eq!(
            sc.params.c_dis,
            0.3 / (s.mass / 2.0 * omega),
            max_relative = 1e-14
        );
    }

    #[test]
    fn hertz_scaling_matches_eqs_55_and_59() {
        let s = Sphere::from_density(0.01, 2500.0).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let a = 1e-4;
        let law = PairLaw::same_material(
            &ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, a).unwrap()),
            pair.r_eff,
        )
        .unwrap();
        let (v, e) = (2.0, 0.6);
        let imp = Impact::from_speed_eccentricity(v, e).unwrap();
        let sc = scale(&law, &pair, &imp).unwrap();
        let PairLaw::Hertz { rho_el, .. } = law else {
            unreachable!()
        };
        let kappa = rho_el / pair.m_eff;
        let ratio = sc.params.tangent_ratio();
        // Eq. (55).
        assert_relative_eq!(
            sc.params.l_tilde.ln(),
            (pair.l * (kappa / (v * v)).powf(0.4)).ln() + 0.4 * (1.0 + ratio * ratio).ln(),
            max_relative = 1e-13
        );
        // Eq. (59).
        assert_relative_eq!(
            sc.params.c_dis.ln(),
            (1.5 * a * v / pair.l).ln() + sc.params.l_tilde.ln() - 0.5 * (1.0 + ratio * ratio).ln(),
            max_relative = 1e-13
        );
    }
}
