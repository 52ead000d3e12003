//! Rectangularised coordinates (a, b, c) of the scaled parameter space
//! (Müller & Pöschel 2013, Sec. V, Eqs. 45-50 and 55-61).
//!
//! With s = c_φ/l̃ = e/√(1−e²) and p = 1/2 (linear) or 2/5 (Hertz):
//! - a = ln(c_φ/c_φ^min) = ln s − g_min, Eq. (46);
//! - b = ln(l̃/l̃^min) = ln l̃ − p·ln(1+s²) − m_min, Eqs. (49) and (57);
//! - c = ln c_dis for the linear dashpot (c_dis does not depend on the impact there),
//!   and c = ln(c_dis/c_dis^min) = ln c_dis − ln l̃ + ½ln(1+s²) − c_min for Hertz, Eq. (60).
//!
//! The bounds g, m and c come from a [`ParameterBox`] of physical ranges, which
//! assumes two equal spheres of one material, l = 2R, m_eff = m/2 and R_eff = R/2, as the
//! paper's Tabs. I and II do. Any pair, equal or not, maps to (a, b, c); an unequal pair
//! may simply land outside the rectangle of an equal-sphere box.

use crate::error::{ContactError, Result, finite};
use crate::scaled::l_tilde_exponent;
use crate::{Model, ScaledParams};
use std::f64::consts::PI;

/// A closed interval [min, max].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub min: f64,
    pub max: f64,
}

impl Range {
    pub const fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// max − min.
    pub fn width(&self) -> f64 {
        self.max - self.min
    }

    /// Whether `x` lies in [min, max].
    pub fn contains(&self, x: f64) -> bool {
        x >= self.min && x <= self.max
    }

    fn check(&self, name: &'static str) -> Result<()> {
        finite(name, self.min)?;
        finite(name, self.max)?;
        if !(self.min > 0.0 && self.max >= self.min) {
            return Err(ContactError::OutOfRange {
                name,
                value: self.min,
                allowed: "0 < min <= max",
            });
        }
        Ok(())
    }
}

/// Physical ranges of the linear-dashpot model, as in the paper's Tab. I.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearBox {
    /// k, N/m.
    pub stiffness: Range,
    /// R, m.
    pub radius: Range,
    /// ρ, kg/m³.
    pub density: Range,
    /// γ, kg/s.
    pub damping: Range,
    /// |v|, m/s.
    pub speed: Range,
    /// e = d/l.
    pub eccentricity: Range,
}

/// Physical ranges of the viscoelastic Hertz model, as in the paper's Tab. II.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzBox {
    /// Y, Pa.
    pub young: Range,
    /// ν.
    pub poisson: Range,
    /// R, m.
    pub radius: Range,
    /// ρ, kg/m³.
    pub density: Range,
    /// A, s.
    pub dissipation: Range,
    /// |v|, m/s.
    pub speed: Range,
    /// e = d/l.
    pub eccentricity: Range,
}

/// A box of physical parameters for one model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParameterBox {
    Linear(LinearBox),
    Hertz(HertzBox),
}

impl ParameterBox {
    /// Tab. I of Müller & Pöschel 2013 (linear dashpot).
    pub fn paper_table_1() -> Self {
        Self::Linear(LinearBox {
            stiffness: Range::new(1e3, 1e6),
            radius: Range::new(0.001, 0.1),
            density: Range::new(250.0, 3250.0),
            damping: Range::new(0.01, 1.25),
            speed: Range::new(0.001, 25.0),
            eccentricity: Range::new(0.01, 0.99),
        })
    }

    /// Tab. II of Müller & Pöschel 2013 (viscoelastic Hertz).
    pub fn paper_table_2() -> Self {
        Self::Hertz(HertzBox {
            young: Range::new(1e7, 1e11),
            poisson: Range::new(0.2, 0.5),
            radius: Range::new(0.001, 0.1),
            density: Range::new(250.0, 3250.0),
            dissipation: Range::new(1e-6, 1.0),
            speed: Range::new(0.001, 25.0),
            eccentricity: Range::new(0.01, 0.99),
        })
    }

    /// The paper's box for `model`.
    pub fn paper(model: Model) -> Self {
        match model {
            Model::Linear => Self::paper_table_1(),
            Model::Hertz => Self::paper_table_2(),
        }
    }

    pub fn model(&self) -> Model {
        match self {
            Self::Linear(_) => Model::Linear,
            Self::Hertz(_) => Model::Hertz,
        }
    }

    /// The named physical ranges, in a fixed order.
    pub fn ranges(&self) -> Vec<(&'static str, Range)> {
        match self {
            Self::Linear(b) => vec![
                ("stiffness", b.stiffness),
                ("radius", b.radius),
                ("density", b.density),
                ("damping", b.damping),
                ("speed", b.speed),
                ("eccentricity", b.eccentricity),
            ],
            Self::Hertz(b) => vec![
                ("young", b.young),
                ("poisson", b.poisson),
                ("radius", b.radius),
                ("density", b.density),
                ("dissipation", b.dissipation),
                ("speed", b.speed),
                ("eccentricity", b.eccentricity),
            ],
        }
    }

    /// The bounds g, m, c of the rectangle.
    ///
    /// Each of g, m and c is a product of powers of the physical parameters (ν enters
    /// through 1/(1−ν²)), hence monotone in each of them, so its extremes lie on the
    /// box's corners; all 2⁶ or 2⁷ corners are evaluated.
    pub fn bounds(&self) -> Result<RectBounds> {
        let ranges = self.ranges();
        for (name, r) in &ranges {
            r.check(name)?;
        }
        let e = ranges.last().expect("eccentricity is last").1;
        if e.max >= 1.0 {
            return Err(ContactError::OutOfRange {
                name: "eccentricity",
                value: e.max,
                allowed: "(0, 1)",
            });
        }
        if let Self::Hertz(b) = self
            && b.poisson.max >= 1.0
        {
            return Err(ContactError::OutOfRange {
                name: "poisson",
                value: b.poisson.max,
                allowed: "(0, 1)",
            });
        }
        let n = ranges.len();
        let mut g = Range::new(f64::INFINITY, f64::NEG_INFINITY);
        let (mut m, mut c) = (g, g);
        let mut corner = vec![0.0; n];
        for mask in 0u32..(1 << n) {
            for (i, (_, r)) in ranges.iter().enumerate() {
                corner[i] = if mask & (1 << i) == 0 { r.min } else { r.max };
            }
            let (gi, mi, ci) = self.corner_values(&corner);
            for (acc, x) in [(&mut g, gi), (&mut m, mi), (&mut c, ci)] {
                acc.min = acc.min.min(x);
                acc.max = acc.max.max(x);
            }
        }
        Ok(RectBounds {
            model: self.model(),
            g,
            m,
            c,
        })
    }

    /// (g, m, c) at one physical point, in the order of [`Self::ranges`].
    fn corner_values(&self, p: &[f64]) -> (f64, f64, f64) {
        let g_of = |e: f64| -0.5 * (1.0 / (e * e) - 1.0).ln();
        match self {
            Self::Linear(_) => {
                let [k, r, rho, gamma, v, e] = p.try_into().expect("six linear parameters");
                let m_eff = 2.0 / 3.0 * PI * r.powi(3) * rho;
                let omega = (k / m_eff).sqrt();
                // m = ln(lω/v), Eq. (48); third axis ln c_dis = ln(γ/(m_eff ω)), Eq. (43).
                (
                    g_of(e),
                    (2.0 * r * omega / v).ln(),
                    (gamma / (m_eff * omega)).ln(),
                )
            }
            Self::Hertz(_) => {
                let [y, nu, r, rho, a, v, e] = p.try_into().expect("seven Hertz parameters");
                let m_eff = 2.0 / 3.0 * PI * r.powi(3) * rho;
                let rho_el = 2.0 * y * (r / 2.0).sqrt() / (3.0 * (1.0 - nu * nu));
                let kappa = rho_el / m_eff;
                let l = 2.0 * r;
                // m = ln(l(κ/v²)^{2/5}), Eq. (56); c = ln(3Av/(2l)), Eq. (59).
                (
                    g_of(e),
                    (l * (kappa / (v * v)).powf(0.4)).ln(),
                    (1.5 * a * v / l).ln(),
                )
            }
        }
    }
}

/// The constants that make the scaled parameter space a rectangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectBounds {
    pub model: Model,
    /// Range of g = −½ln(1/e² − 1) = ln(c_φ/l̃), Eq. (45).
    pub g: Range,
    /// Range of m: ln(lω/v) (linear, Eq. 48) or ln(l(κ/v²)^{2/5}) (Hertz, Eq. 56).
    pub m: Range,
    /// Range of ln c_dis (linear) or of ln(3Av/(2l)) (Hertz, Eq. 59).
    pub c: Range,
}

/// A point in rectangularised coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectCoords {
    pub a: f64,
    pub b: f64,
    pub c: f64,
}

impl RectBounds {
    /// The ranges of the a, b and c axes.
    pub fn axes(&self) -> [Range; 3] {
        let c = match self.model {
            Model::Linear => self.c,
            Model::Hertz => Range::new(0.0, self.c.width()),
        };
        [
            Range::new(0.0, self.g.width()),
            Range::new(0.0, self.m.width()),
            c,
        ]
    }

    /// Whether a point lies in the rectangle.
    pub fn contains(&self, x: &RectCoords) -> bool {
        let [a, b, c] = self.axes();
        a.contains(x.a) && b.contains(x.b) && c.contains(x.c)
    }

    /// Scaled parameters to rectangular coordinates (forward map).
    ///
    /// c_φ = 0 (a central impact) gives a = −∞, and c_dis = 0 gives c = −∞: both lie
    /// outside any rectangle, and callers must treat them explicitly.
    pub fn to_rect(&self, p: &ScaledParams) -> RectCoords {
        let ln_s = p.c_phi.ln() - p.l_tilde.ln();
        let soft = ln1p_exp(2.0 * ln_s);
        let ln_l = p.l_tilde.ln();
        let exponent = l_tilde_exponent(self.model);
        let c = match self.model {
            Model::Linear => p.c_dis.ln(),
            Model::Hertz => p.c_dis.ln() - ln_l + 0.5 * soft - self.c.min,
        };
        RectCoords {
            a: ln_s - self.g.min,
            b: ln_l - exponent * soft - self.m.min,
            c,
        }
    }

    /// Rectangular coordinates to scaled parameters (inverse map, Eqs. 50 and 61).
    pub fn from_rect(&self, x: &RectCoords) -> ScaledParams {
        let ln_s = x.a + self.g.min;
        let soft = ln1p_exp(2.0 * ln_s);
        let ln_l = x.b + self.m.min + l_tilde_exponent(self.model) * soft;
        let ln_c_dis = match self.model {
            Model::Linear => x.c,
            Model::Hertz => x.c + self.c.min + ln_l - 0.5 * soft,
        };
        ScaledParams {
            l_tilde: ln_l.exp(),
            c_phi: (ln_l + ln_s).exp(),
            c_dis: ln_c_dis.exp(),
        }
    }
}

/// ln(1 + eˣ) without overflow or loss of digits.
fn ln1p_exp(x: f64) -> f64 {
    if x > 30.0 {
        x + (-x).exp()
    } else {
        x.exp().ln_1p()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn ln1p_exp_is_accurate_everywhere() {
        assert_relative_eq!(ln1p_exp(0.0), 2f64.ln());
        assert_relative_eq!(ln1p_exp(-40.0), (-40f64).exp(), max_relative = 1e-14);
        assert_relative_eq!(ln1p_exp(40.0), 40.0, max_relative = 1e-15);
    }

    #[test]
    fn a_bad_box_is_rejected() {
        let ParameterBox::Linear(mut b) = ParameterBox::paper_table_1() else {
            unreachable!()
        };
        b.eccentricity = Range::new(0.1, 1.0);
        assert!(ParameterBox::Linear(b).bounds().is_err());
        b.eccentricity = Range::new(0.1, 0.5);
        b.radius = Range::new(0.2, 0.1);
        assert!(ParameterBox::Linear(b).bounds().is_err());
        b.radius = Range::new(f64::NAN, 0.1);
        assert!(ParameterBox::Linear(b).bounds().is_err());
    }
}
