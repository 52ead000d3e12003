//! Collision physics of the event engine, as pure functions and small caches:
//! the hard-sphere rule with a coefficient of normal restitution, the force laws'
//! central restitution for eMD, and the source of the matrix of restitution for eMD*.

use crate::error::{EngineError, Result};
use emdstar_contact::{LinearDashpot, Model, PairLaw, PairProperties, ScaledParams};
use emdstar_mor::{Mor, solve};
use emdstar_table::{Table, TableError};
use std::collections::HashMap;

/// Velocity change of a pair for the instantaneous collision rule with coefficient of
/// normal restitution ε (Bannerman 2014, Eq. 5; Müller & Pöschel 2013, Eq. 63, here
/// for unequal masses): v_i' = v_i − (m_j/M)(1+ε)(n̂·v_ij)n̂, v_j' = v_j + (m_i/M)(…).
///
/// `r` = r_i − r_j, `v` = v_i − v_j. Returns the changes (Δv_i, Δv_j).
#[inline]
pub fn restitution_kick(
    r: [f64; 3],
    v: [f64; 3],
    m_i: f64,
    m_j: f64,
    eps: f64,
) -> ([f64; 3], [f64; 3]) {
    let inv = 1.0 / (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    let vn = (r[0] * v[0] + r[1] * v[1] + r[2] * v[2]) * inv;
    let total = m_i + m_j;
    let a = -(1.0 + eps) * vn * m_j / total;
    let b = (1.0 + eps) * vn * m_i / total;
    (r.map(|x| a * x), r.map(|x| b * x))
}

/// Where eMD* takes the matrix of restitution from.
pub trait MorSource: Send {
    /// The MoR at scaled parameters `p`, and whether a fallback (exact solve for
    /// parameters a table does not cover) produced it.
    fn mor(&mut self, model: Model, p: &ScaledParams) -> Result<(Mor, bool)>;
    /// A short name for reports ("exact", "table", …).
    fn name(&self) -> &'static str;
}

/// The exact solver of crate emdstar-mor, one ODE solve per collision.
#[derive(Debug, Clone, Copy, Default)]
pub struct ExactMor;

impl MorSource for ExactMor {
    fn mor(&mut self, model: Model, p: &ScaledParams) -> Result<(Mor, bool)> {
        Ok((solve(model, p)?, false))
    }

    fn name(&self) -> &'static str {
        "exact"
    }
}

/// Matrix-of-restitution tables (crate emdstar-table), one per force model at most,
/// optionally falling back to the exact solver for impacts outside a table's box or of
/// a model without a table (each fallback is counted).
pub struct TableMorSource {
    tables: Vec<TableRef>,
    exact_fallback: bool,
}

/// A table that lives for the whole program (a shipped default table) or one read from
/// a file.
pub enum TableRef {
    Static(&'static Table),
    Owned(Box<Table>),
}

impl TableRef {
    fn table(&self) -> &Table {
        match self {
            Self::Static(t) => t,
            Self::Owned(t) => t,
        }
    }
}

impl TableMorSource {
    /// A table that lives for the whole program, e.g. a shipped default table
    /// (`emdstar_table::default_table` with that crate's `embedded-defaults` feature).
    pub fn new(table: &'static Table, exact_fallback: bool) -> Self {
        Self::with_tables(vec![TableRef::Static(table)], exact_fallback)
    }

    /// A table read from a file.
    pub fn from_table(table: Table, exact_fallback: bool) -> Self {
        Self::with_tables(vec![TableRef::Owned(Box::new(table))], exact_fallback)
    }

    /// Tables of distinct models (the first of a model is used).
    pub fn with_tables(tables: Vec<TableRef>, exact_fallback: bool) -> Self {
        Self {
            tables,
            exact_fallback,
        }
    }

    /// Whether a table covers `model`.
    pub fn covers(&self, model: Model) -> bool {
        self.tables.iter().any(|t| t.table().model() == model)
    }
}

impl MorSource for TableMorSource {
    fn mor(&mut self, model: Model, p: &ScaledParams) -> Result<(Mor, bool)> {
        let Some(table) = self
            .tables
            .iter()
            .map(TableRef::table)
            .find(|t| t.model() == model)
        else {
            if self.exact_fallback {
                return Ok((solve(model, p)?, true));
            }
            let have: Vec<&str> = self
                .tables
                .iter()
                .map(|t| t.table().model().name())
                .collect();
            return Err(EngineError::Invalid(format!(
                "the MoR table is for the {} model but the collision follows the {} model; \
                 give a {} table",
                have.join(" and "),
                model.name(),
                model.name()
            )));
        };
        match table.lookup_scaled(p) {
            Ok(m) => Ok((m, false)),
            Err(e @ (TableError::OutOfBox { .. } | TableError::NotTabulated(_))) => {
                if self.exact_fallback {
                    Ok((solve(model, p)?, true))
                } else {
                    Err(EngineError::OutsideTable {
                        what: format!(
                            "l̃ = {}, c_φ = {}, c_dis = {} ({e})",
                            p.l_tilde, p.c_phi, p.c_dis
                        ),
                    })
                }
            }
            Err(e) => Err(EngineError::Invalid(format!("MoR table lookup: {e}"))),
        }
    }

    fn name(&self) -> &'static str {
        if self.exact_fallback {
            "table+exact"
        } else {
            "table"
        }
    }
}

/// Central coefficient of normal restitution of a force law, ε(v_n) (eMD).
#[derive(Debug, Clone)]
pub enum CentralRestitution {
    /// Linear dashpot: independent of the impact speed (Schwager & Pöschel 2007).
    Constant(f64),
    /// Viscoelastic Hertz: a function of c_dis = 3A/(2T) ∝ v_n^{1/5} only
    /// (Müller & Pöschel 2013, Eq. 54 with c_φ = 0), tabulated on demand.
    Hertz {
        /// κ^{2/5} with κ = ρ_el/m_eff, so that T = v_n^{−1/5}/κ^{2/5}.
        kappa_2_5: f64,
        dissipation: f64,
    },
}

impl CentralRestitution {
    /// The central restitution of `law` for a pair with properties `pair`.
    pub fn of(law: &PairLaw, pair: &PairProperties) -> Result<Self> {
        Ok(match *law {
            PairLaw::Linear { stiffness, damping } => Self::Constant(
                LinearDashpot::new(stiffness, damping)?
                    .central_impact(pair.m_eff)?
                    .restitution,
            ),
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => Self::Hertz {
                kappa_2_5: (rho_el / pair.m_eff).powf(0.4),
                dissipation,
            },
        })
    }

    /// ε at normal impact speed `v_n` > 0.
    #[inline]
    pub fn at(&self, v_n: f64, table: &mut HertzRestitution) -> Result<f64> {
        match *self {
            Self::Constant(eps) => Ok(eps),
            Self::Hertz {
                kappa_2_5,
                dissipation,
            } => {
                if dissipation == 0.0 {
                    return Ok(1.0);
                }
                // Eq. (53): T = κ^{−2/5} v_n^{−1/5}; c_dis = 3A/(2T).
                let c_dis = 1.5 * dissipation * kappa_2_5 * v_n.powf(0.2);
                table.at(c_dis)
            }
        }
    }
}

/// ε(c_dis) of the central viscoelastic Hertz impact, solved exactly at nodes of a
/// uniform grid in ln c_dis (spacing 1/32, filled on first use) and interpolated with
/// cubic Lagrange polynomials (relative error ≲ 1e-8; see the tests).
#[derive(Debug, Clone, Default)]
pub struct HertzRestitution {
    nodes: HashMap<i64, f64>,
}

impl HertzRestitution {
    const STEP: f64 = 1.0 / 32.0;
    /// c_dis below which the first-order series ε = 1 − 1.1534489 c_dis + … is used
    /// (Schwager & Pöschel 2008): there its error is below 1e-12.
    const SERIES_BELOW: f64 = 1e-6;

    fn node(&mut self, k: i64) -> Result<f64> {
        if let Some(&eps) = self.nodes.get(&k) {
            return Ok(eps);
        }
        let c_dis = (k as f64 * Self::STEP).exp();
        // l̃ only enters ε_r for a central impact; any l̃ ≫ the scaled overlap (≈ 1) does.
        let p = ScaledParams::new(1e6, 0.0, c_dis)?;
        let eps = -solve(Model::Hertz, &p)?.eps_rdot;
        self.nodes.insert(k, eps);
        Ok(eps)
    }

    /// ε at scaled dissipation `c_dis` ≥ 0.
    pub fn at(&mut self, c_dis: f64) -> Result<f64> {
        if !(c_dis.is_finite() && c_dis >= 0.0) {
            return Err(EngineError::Invalid(format!(
                "scaled dissipation c_dis = {c_dis} must be finite and non-negative"
            )));
        }
        if c_dis < Self::SERIES_BELOW {
            return Ok(1.0 - 1.153_448_9 * c_dis + 0.798_266_6 * c_dis * c_dis);
        }
        let x = c_dis.ln() / Self::STEP;
        let k0 = x.floor() as i64;
        let s = x - k0 as f64;
        let f = [
            self.node(k0 - 1)?,
            self.node(k0)?,
            self.node(k0 + 1)?,
            self.node(k0 + 2)?,
        ];
        // Cubic Lagrange through nodes −1, 0, 1, 2 at offset s ∈ [0, 1).
        let w = [
            -s * (s - 1.0) * (s - 2.0) / 6.0,
            (s + 1.0) * (s - 1.0) * (s - 2.0) / 2.0,
            -(s + 1.0) * s * (s - 2.0) / 2.0,
            (s + 1.0) * s * (s - 1.0) / 6.0,
        ];
        Ok(w.iter().zip(&f).map(|(a, b)| a * b).sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kick_conserves_momentum_and_scales_the_normal_speed() {
        let r = [1.0, 0.5, -0.2];
        let v = [-2.0, 0.3, 0.7];
        let (mi, mj) = (1.5, 0.4);
        let eps = 0.6;
        let (di, dj) = restitution_kick(r, v, mi, mj, eps);
        for k in 0..3 {
            assert!((mi * di[k] + mj * dj[k]).abs() < 1e-14);
        }
        let v_after: [f64; 3] = std::array::from_fn(|k| v[k] + di[k] - dj[k]);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        assert!((dot(v_after, r) + eps * dot(v, r)).abs() < 1e-14);
        // Tangential part unchanged.
        let t = [0.5, -1.0, 0.0];
        assert!(dot(t, r).abs() < 1e-15);
        assert!((dot(v_after, t) - dot(v, t)).abs() < 1e-14);
    }

    #[test]
    fn linear_restitution_is_the_schwager_poeschel_constant() {
        let law = PairLaw::Linear {
            stiffness: 2000.0,
            damping: 1.0,
        };
        let pair = PairProperties {
            l: 0.2,
            m_eff: 2.0,
            r_eff: 0.05,
        };
        // β = γ/(2 m_eff) = 0.25, ω0 = √1000: ε = exp(−β t_c) with
        // t_c = (π − atan(2βω/(ω²−β²)))/ω (docs/physics.md, Schwager & Pöschel 2007).
        let (beta, w0) = (0.25f64, 1000f64.sqrt());
        let w = (w0 * w0 - beta * beta).sqrt();
        let tc = (std::f64::consts::PI - (2.0 * beta * w / (w * w - beta * beta)).atan()) / w;
        let expect = (-beta * tc).exp();
        let c = CentralRestitution::of(&law, &pair).unwrap();
        let got = c.at(3.0, &mut HertzRestitution::default()).unwrap();
        assert!((got - expect).abs() < 1e-12, "{got} {expect}");
    }
}
