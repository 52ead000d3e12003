//! Lookups from physical parameters: the pair's part of the map built once
//! ([`PairMap`], [`PairLookup`]), and the counted exact fallback ([`WithFallback`]).

use crate::error::TableError;
use crate::table::{PhysicalLookup, Table};
use emdstar_contact::{
    Impact, Model, Mor, PairLaw, PairProperties, RectBounds, RectCoords, ScaledParams,
};

/// The pair-dependent constants of the physical map, for one law and pair: computed
/// and checked once, then used by [`Table::lookup_pair`] for any table of the model.
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
                    b0: (l / time).ln(),
                    c: (damping * time / m_eff).ln(),
                    time,
                }
            }
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => {
                let rho_el = positive("rho_el", rho_el)?;
                let dissipation = non_negative("dissipation", dissipation)?;
                let ln_kappa = rho_el.ln() - m_eff.ln();
                // Eq. (53): T = κ^{-2/5} v_n^{-1/5}.
                PairKind::Hertz {
                    b0: 0.4 * (2.5 * l.ln() + ln_kappa),
                    c0: (1.5 * dissipation / l).ln(),
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
        let (v_n, v_t) = (impact.normal_speed, impact.tangential_speed);
        if !(v_n > 0.0 && v_t >= 0.0 && v_n.is_finite() && v_t.is_finite()) {
            return Err(TableError::Input(format!(
                "the impact needs a finite normal speed > 0 and tangential speed >= 0, got \
                 {v_n} and {v_t}"
            )));
        }
        let ln_v2 = (v_n * v_n + v_t * v_t).ln();
        let a = (v_t / v_n).ln() - bounds.g.min;
        Ok(match self.kind {
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
                (t0 - 0.2 * v_n.ln()).exp(),
            ),
        })
    }
}

/// A table and a [`PairMap`]: lookups of one pair's impacts.
#[derive(Debug, Clone, Copy)]
pub struct PairLookup<'t> {
    table: &'t Table,
    map: PairMap,
}

impl<'t> PairLookup<'t> {
    /// Checks that `table` is for the law's model and builds the map.
    pub fn new(table: &'t Table, law: &PairLaw, pair: &PairProperties) -> Result<Self, TableError> {
        table.expect_model(law.model())?;
        Ok(Self {
            table,
            map: PairMap::new(law, pair)?,
        })
    }

    /// The table this handle looks up.
    pub fn table(&self) -> &'t Table {
        self.table
    }

    /// The pair's constants.
    pub fn map(&self) -> &PairMap {
        &self.map
    }

    /// MoR, time and length scale of one impact of the pair.
    #[inline]
    pub fn lookup(&self, impact: &Impact) -> Result<PhysicalLookup, TableError> {
        self.table.lookup_pair(&self.map, impact)
    }
}

/// Where a [`WithFallback`] answer came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    Table,
    ExactSolve,
}

/// A table plus a caller-chosen exact solver for points outside the box.
///
/// The reader cannot solve the collision ODE itself (it does not depend on the solver);
/// the caller passes one, e.g. `|m, p| emdstar_mor::solve(m, p).map_err(|e| e.to_string())`.
/// Every fallback is counted in [`WithFallback::fallbacks`].
pub struct WithFallback<'t, F> {
    table: &'t Table,
    solve: F,
    fallbacks: std::sync::atomic::AtomicU64,
}

impl<'t, F> WithFallback<'t, F>
where
    F: Fn(Model, &ScaledParams) -> Result<Mor, String>,
{
    pub fn new(table: &'t Table, solve: F) -> Self {
        Self {
            table,
            solve,
            fallbacks: 0.into(),
        }
    }

    /// Table lookup, or the exact solve when the point lies outside the box.
    pub fn lookup_scaled(&self, p: &ScaledParams) -> Result<(Mor, Source), TableError> {
        match self.table.lookup_scaled(p) {
            Ok(m) => Ok((m, Source::Table)),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) => {
                self.fallbacks
                    .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let m = (self.solve)(self.table.model, p).map_err(TableError::Fallback)?;
                Ok((m, Source::ExactSolve))
            }
            Err(e) => Err(e),
        }
    }

    /// Table lookup of a physical impact of the pair of `map`, or the exact solve when
    /// it lies outside the box.
    pub fn lookup_pair(
        &self,
        map: &PairMap,
        impact: &Impact,
    ) -> Result<(PhysicalLookup, Source), TableError> {
        match self.table.lookup_pair(map, impact) {
            Ok(hit) => Ok((hit, Source::Table)),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) => {
                self.fallbacks
                    .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let s = emdstar_contact::scale(map.law(), map.pair(), impact)?;
                let mor =
                    (self.solve)(self.table.model, &s.params).map_err(TableError::Fallback)?;
                Ok((
                    PhysicalLookup {
                        mor,
                        time: s.time,
                        length: s.length,
                    },
                    Source::ExactSolve,
                ))
            }
            Err(e) => Err(e),
        }
    }

    /// Number of exact solves so far.
    pub fn fallbacks(&self) -> u64 {
        self.fallbacks.load(std::sync::atomic::Ordering::Relaxed)
    }
}
