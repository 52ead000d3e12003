//! The pair's part of the map from physical parameters to table coordinates
//! ([`PairMap`]): computed and checked once per law and pair. Its logarithms and
//! exponential are the crate's own (a few units in the last place, no library calls).

use crate::error::TableError;
use crate::fastmath::{exp, ln};
use emdstar_contact::{Impact, PairLaw, PairProperties, RectBounds, RectCoords};

/// The pair-dependent constants of the physical map, for one law and pair: computed
/// and checked once, then used by [`Table::lookup_pair`](crate::Table::lookup_pair) for any table of the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairMap {
    law: PairLaw,
    pair: PairProperties,
    kind: PairKind,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum PairKind {
    /// b = b0 − ½ ln v² − m_min, c fixed, T fixed.
    Linear { b0: f64, c: f64, time: f64 },
    /// b = b0 − 0.4 ln v² − m_min, c = c0 + ½ ln v² − c_min, T = e^{t0 − 0.2 ln v_n}.
    Hertz { b0: f64, c0: f64, t0: f64 },
}

impl PairMap {
    /// Checks the law and the pair and folds them into the constants of the map, in the
    /// paper's own forms (Eqs. 41-61), with v = |v|:
    /// - a = ln(v_t/v_n) − g_min, Eq. (45);
    /// - b = ln(lω/v) − m_min (linear, Eq. 48) or ln(l(κ/v²)^{2/5}) − m_min (Hertz, Eq. 56);
    /// - c = ln(γ/(m_eff ω)) (linear, Eq. 43) or ln(3Av/(2l)) − c_min (Hertz, Eq. 59).
    pub fn new(law: &PairLaw, pair: &PairProperties) -> Result<Self, TableError> {
        let positive = |name: &str, x: f64| {
            if x > 0.0 && x.is_finite() {
                Ok(x)
            } else {
                Err(TableError::Input(format!(
                    "{name} must be finite and > 0, got {x}"
                )))
            }
        };
        let non_negative = |name: &str, x: f64| {
            if x >= 0.0 && x.is_finite() {
                Ok(x)
            } else {
                Err(TableError::Input(format!(
                    "{name} must be finite and >= 0, got {x}"
                )))
            }
        };
        let m_eff = positive("effective mass", pair.m_eff)?;
        let l = positive("contact distance", pair.l)?;
        let kind = match *law {
            PairLaw::Linear { stiffness, damping } => {
                let k = positive("stiffness", stiffness)?;
                let damping = non_negative("damping", damping)?;
                // Eq. (41): T = 1/ω = √(m_eff/k).
                let time = (m_eff / k).sqrt();
                PairKind::Linear {
                    b0: ln(l / time),
                    c: ln(damping * time / m_eff),
                    time,
                }
            }
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => {
                let rho_el = positive("rho_el", rho_el)?;
                let dissipation = non_negative("dissipation", dissipation)?;
                let ln_kappa = ln(rho_el) - ln(m_eff);
                // Eq. (53): T = κ^{-2/5} v_n^{-1/5}.
                PairKind::Hertz {
                    b0: 0.4 * (2.5 * ln(l) + ln_kappa),
                    c0: ln(1.5 * dissipation / l),
                    t0: -0.4 * ln_kappa,
                }
            }
        };
        Ok(Self {
            law: *law,
            pair: *pair,
            kind,
        })
    }

    /// The law of this map.
    pub fn law(&self) -> &PairLaw {
        &self.law
    }

    /// The pair of this map.
    pub fn pair(&self) -> &PairProperties {
        &self.pair
    }

    /// The rectangular coordinates and time scale T of an impact, for `bounds`.
    #[inline]
    pub fn coords(
        &self,
        bounds: &RectBounds,
        impact: &Impact,
    ) -> Result<(RectCoords, f64), TableError> {
        self.coords_and_u(bounds, impact)
            .map(|(x, time, _)| (x, time))
    }

    /// [`PairMap::coords`] and u = ln |v|², the coordinate of the pair's line through
    /// the rectangle ([`PairMap::line`]).
    #[inline]
    pub(crate) fn coords_and_u(
        &self,
        bounds: &RectBounds,
        impact: &Impact,
    ) -> Result<(RectCoords, f64, f64), TableError> {
        let (v_n, v_t) = (impact.normal_speed, impact.tangential_speed);
        // One branch (NaN fails every comparison).
        if !((v_n > 0.0) & (v_t >= 0.0) & (v_n < f64::INFINITY) & (v_t < f64::INFINITY)) {
            return Err(TableError::Input(format!(
                "the impact needs a finite normal speed > 0 and tangential speed >= 0, got \
                 {v_n} and {v_t}"
            )));
        }
        let ln_v2 = ln(v_n * v_n + v_t * v_t);
        let a = ln(v_t / v_n) - bounds.g.min;
        let (x, time) = match self.kind {
            PairKind::Linear { b0, c, time } => (
                RectCoords {
                    a,
                    b: b0 - 0.5 * ln_v2 - bounds.m.min,
                    c,
                },
                time,
            ),
            PairKind::Hertz { b0, c0, t0 } => (
                RectCoords {
                    a,
                    b: b0 - 0.4 * ln_v2 - bounds.m.min,
                    c: c0 + 0.5 * ln_v2 - bounds.c.min,
                },
                exp(t0 - 0.2 * ln(v_n)),
            ),
        };
        Ok((x, time, ln_v2))
    }

    /// The pair's impacts lie on a line through the rectangle: b and c are affine in
    /// u = ln |v|² (and a = ln(v_t/v_n) − g_min is free). Returns [offset, slope] of b
    /// and of c: b = b₀ − ½u (linear) or b₀ − 0.4u (Hertz); c is the pair's constant
    /// (linear) or c₀ + ½u (Hertz), Eqs. (48), (56), (59).
    pub(crate) fn line(&self, bounds: &RectBounds) -> [[f64; 2]; 2] {
        match self.kind {
            PairKind::Linear { b0, c, .. } => [[b0 - bounds.m.min, -0.5], [c, 0.0]],
            PairKind::Hertz { b0, c0, .. } => [[b0 - bounds.m.min, -0.4], [c0 - bounds.c.min, 0.5]],
        }
    }
}
