//! The in-memory table and its lookups.

use crate::TableInfo;
use crate::error::TableError;
use crate::interp::{Axis, NQ, Stencil, Stretch, interp3};
use emdstar_contact::{
    Impact, Model, Mor, PairLaw, PairProperties, RectBounds, RectCoords, ScaledParams, scale,
};

/// The MoR from the four stored (log) quantities ln(1−ε_r), ln(−ε_ṙ), ln ε_φ, ln ε_t.
pub fn mor_from_logs(q: [f64; NQ]) -> Mor {
    let one_minus_eps_r = q[0].exp();
    Mor {
        eps_r: 1.0 - one_minus_eps_r,
        one_minus_eps_r,
        eps_rdot: -q[1].exp(),
        eps_phi: q[2].exp(),
        eps_t: q[3].exp(),
    }
}

/// The four stored (log) quantities of a MoR (the inverse of [`mor_from_logs`]).
pub fn mor_to_logs(m: &Mor) -> [f64; NQ] {
    [
        m.one_minus_eps_r.ln(),
        (-m.eps_rdot).ln(),
        m.eps_phi.ln(),
        m.eps_t.ln(),
    ]
}

/// A lookup from physical parameters: the MoR and the scales that undo the scaling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalLookup {
    pub mor: Mor,
    /// T, s: the collision lasts τ = ε_t·T.
    pub time: f64,
    /// X, m.
    pub length: f64,
}

/// A matrix-of-restitution table over the rectangle of a parameter box.
///
/// Main grid: the four quantities of [`crate::QUANTITIES`] on a uniform grid over
/// (a, b, c) = [`RectBounds::axes`]. Two limits the engines meet constantly are stored
/// as extra slices and handled explicitly (never by clamping):
/// - **near-central impacts**, a < 0 (e below the box, c_φ → 0, a → −∞): every
///   quantity, with ε_φ replaced by ε_φ/s (s = c_φ/l̃), is a smooth function of s²;
///   the table holds its s = 0 slice over (b, c) and interpolates linearly in s²
///   between it and the a = 0 face. c_φ = 0 gives ε_φ = 0 exactly.
/// - **nearly elastic impacts**, c below the box (c_dis → 0, c → −∞): every quantity,
///   with 1−ε_r replaced by (1−ε_r)/u (u = e^c ∝ c_dis), is smooth in u; the table
///   holds its u = 0 slice over (a, b) (ε_ṙ = −1 exactly there by energy conservation,
///   and (1−ε_r)/c_dis → 1/l̃ because the collision ends at ξ̃ = c_dis·ṙ̃) and
///   interpolates linearly in u. c_dis = 0 gives ε_r = 1 and ε_ṙ = −1 exactly.
/// - both at once use the (b)-line of central elastic impacts, bilinearly in (s², u).
///
/// Anything beyond the upper ends of a, b or c, or below b = 0, is a
/// [`TableError::OutOfBox`]. Where the central extension does not hold (strongly damped
/// impacts whose end hinges on the centrifugal force: the generator's solve at c_φ → 0
/// does not finish, or the extension misses exact solves at two points below the box by
/// more than 3e-7 in a stored log), the central slice holds NaN and a < 0 lookups there
/// are [`TableError::NotTabulated`]. [`WithFallback`] turns both into a counted exact solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub(crate) model: Model,
    pub(crate) bounds: RectBounds,
    pub(crate) axes: [Axis; 3],
    pub(crate) main: Vec<f64>,
    pub(crate) elastic: Vec<f64>,
    pub(crate) central: Vec<f64>,
    pub(crate) central_elastic: Vec<f64>,
    pub(crate) info: TableInfo,
}

/// Everything a generator supplies to build a [`Table`]; arrays in C order with the
/// four quantities innermost, in the forms described on [`Table`].
#[derive(Debug, Clone, PartialEq)]
pub struct TableParts {
    pub bounds: RectBounds,
    /// Nodes per axis (a, b, c).
    pub n: [usize; 3],
    /// Interpolation points per axis.
    pub order: [usize; 3],
    /// Node crowding per axis ([`Stretch::NONE`] for a uniform axis).
    pub stretch: [Stretch; 3],
    /// `[na][nb][nc][4]`.
    pub main: Vec<f64>,
    /// `[na][nb][4]`, at u = 0.
    pub elastic: Vec<f64>,
    /// `[nb][nc][4]`, at s = 0.
    pub central: Vec<f64>,
    /// `[nb][4]`, at s = 0 and u = 0.
    pub central_elastic: Vec<f64>,
    pub info: TableInfo,
}

/// Axes of a grid of `n` nodes with `order`-point stencils over the rectangle of `bounds`.
pub fn grid_axes(
    bounds: &RectBounds,
    n: [usize; 3],
    order: [usize; 3],
    stretch: [Stretch; 3],
) -> [Axis; 3] {
    let r = bounds.axes();
    [0, 1, 2].map(|k| Axis::new(r[k].min, r[k].max, n[k], order[k], stretch[k]))
}

impl Table {
    /// Assembles a table, checking the sizes.
    pub fn from_parts(p: TableParts) -> Result<Self, TableError> {
        let axes = grid_axes(&p.bounds, p.n, p.order, p.stretch);
        for (ax, name) in axes.iter().zip(["a", "b", "c"]) {
            ax.check()
                .map_err(|why| TableError::Input(format!("axis {name}: {why}")))?;
        }
        let [na, nb, nc] = p.n;
        for (name, v, len) in [
            ("main", &p.main, na * nb * nc),
            ("elastic", &p.elastic, na * nb),
            ("central", &p.central, nb * nc),
            ("central_elastic", &p.central_elastic, nb),
        ] {
            if v.len() != len * NQ {
                return Err(TableError::Input(format!(
                    "{name} has {} values, expected {}",
                    v.len(),
                    len * NQ
                )));
            }
        }
        Ok(Self {
            model: p.bounds.model,
            bounds: p.bounds,
            axes,
            main: p.main,
            elastic: p.elastic,
            central: p.central,
            central_elastic: p.central_elastic,
            info: p.info,
        })
    }

    pub fn model(&self) -> Model {
        self.model
    }

    pub fn bounds(&self) -> &RectBounds {
        &self.bounds
    }

    pub fn axes(&self) -> &[Axis; 3] {
        &self.axes
    }

    pub fn info(&self) -> &TableInfo {
        &self.info
    }

    /// Stored value of quantity `q` at main-grid node (i, j, k).
    pub fn node_value(&self, i: usize, j: usize, k: usize, q: usize) -> f64 {
        let [_, nb, nc] = self.axes.map(|a| a.n);
        self.main[((i * nb + j) * nc + k) * NQ + q]
    }

    /// The same data interpolated with other stencils (points per axis), e.g. to
    /// compare orders without regenerating.
    pub fn with_order(&self, order: [usize; 3]) -> Result<Self, TableError> {
        let mut t = self.clone();
        for (ax, o) in t.axes.iter_mut().zip(order) {
            *ax = ax.with_order(o);
            ax.check().map_err(TableError::Input)?;
        }
        Ok(t)
    }

    /// Fails with [`TableError::WrongModel`] unless the table is for `model`.
    pub fn expect_model(&self, model: Model) -> Result<(), TableError> {
        if model == self.model {
            Ok(())
        } else {
            Err(TableError::WrongModel {
                table: self.model,
                requested: model,
            })
        }
    }

    /// MoR and time scale of a physical impact: scaling (Eqs. 41, 43, 53), rectangular
    /// coordinates (Eqs. 45-61) and interpolation of all four components.
    ///
    /// The coordinates come straight from the physical parameters, in the paper's own
    /// forms (three logarithms instead of the scaled parameters' six transcendental
    /// calls), with s = v_t/v_n and v = |v|:
    /// - a = ln s − g_min, Eq. (45);
    /// - b = ln(lω/v) − m_min (linear, Eq. 48) or ln(l(κ/v²)^{2/5}) − m_min (Hertz, Eq. 56);
    /// - c = ln(γ/(m_eff ω)) (linear, Eq. 43) or ln(3Av/(2l)) − c_min (Hertz, Eq. 59).
    #[inline]
    pub fn lookup(
        &self,
        law: &PairLaw,
        pair: &PairProperties,
        impact: &Impact,
    ) -> Result<PhysicalLookup, TableError> {
        self.expect_model(law.model())?;
        let (v_n, v_t, m_eff, l) = (
            impact.normal_speed,
            impact.tangential_speed,
            pair.m_eff,
            pair.l,
        );
        let plausible = v_n > 0.0 && v_t >= 0.0 && m_eff > 0.0 && l > 0.0;
        if !(plausible && v_n.is_finite() && v_t.is_finite() && m_eff.is_finite() && l.is_finite())
        {
            // Let the scaling say what is wrong.
            scale(law, pair, impact)?;
            return Err(TableError::Input(format!(
                "impact {impact:?} or pair {pair:?} cannot be scaled"
            )));
        }
        let v2 = v_n * v_n + v_t * v_t;
        let bounds = &self.bounds;
        let (time, b, c) = match *law {
            PairLaw::Linear { stiffness, damping } => {
                // Eq. (41): T = 1/ω = √(m_eff/k).
                let omega2 = stiffness / m_eff;
                let time = (m_eff / stiffness).sqrt();
                let b = 0.5 * (l * l * omega2 / v2).ln() - bounds.m.min;
                (time, b, (damping * time / m_eff).ln())
            }
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => {
                // Eq. (53): T = κ^{-2/5} v_n^{-1/5} = (κ² v_n)^{-1/5}.
                let kappa = rho_el / m_eff;
                let mut time = (kappa * kappa * v_n).powf(-0.2);
                if !(time.is_finite() && time > 0.0) {
                    time = kappa.powf(-0.4) * v_n.powf(-0.2);
                }
                let b = 0.4 * (l * l * l.sqrt() * kappa / v2).ln() - bounds.m.min;
                let c = (1.5 * dissipation * v2.sqrt() / l).ln() - bounds.c.min;
                (time, b, c)
            }
        };
        let x = RectCoords {
            a: (v_t / v_n).ln() - bounds.g.min,
            b,
            c,
        };
        if !(time.is_finite() && time > 0.0 && x.b.is_finite() && !x.c.is_nan()) {
            scale(law, pair, impact)?;
            return Err(TableError::Input(format!(
                "the law {law:?} gives no finite scaling for impact {impact:?}"
            )));
        }
        Ok(PhysicalLookup {
            mor: self.lookup_rect(&x)?,
            time,
            length: v_n * time,
        })
    }

    /// MoR at scaled parameters (l̃ > 0, c_φ ≥ 0, c_dis ≥ 0).
    #[inline]
    pub fn lookup_scaled(&self, p: &ScaledParams) -> Result<Mor, TableError> {
        let valid = p.l_tilde > 0.0 && p.c_phi >= 0.0 && p.c_dis >= 0.0;
        if !(valid && p.l_tilde.is_finite() && p.c_phi.is_finite() && p.c_dis.is_finite()) {
            return Err(TableError::Input(format!(
                "scaled parameters must be finite with l_tilde > 0, c_phi >= 0, c_dis >= 0; got {p:?}"
            )));
        }
        self.lookup_rect(&self.bounds.to_rect(p))
    }

    /// MoR at rectangular coordinates; a = −∞ (central) and c = −∞ (elastic) allowed.
    pub fn lookup_rect(&self, x: &RectCoords) -> Result<Mor, TableError> {
        self.logs_at(x).map(mor_from_logs)
    }

    /// The four stored (log) quantities at rectangular coordinates.
    pub fn logs_at(&self, x: &RectCoords) -> Result<[f64; NQ], TableError> {
        let [ax, bx, cx] = &self.axes;
        let out = |axis, value: f64, r: &Axis, lo: f64| TableError::OutOfBox {
            axis,
            value,
            min: lo,
            max: r.max,
        };
        if x.a.is_nan() || x.a > ax.max {
            return Err(out("a", x.a, ax, ax.min));
        }
        if !(x.b >= bx.min && x.b <= bx.max) {
            return Err(out("b", x.b, bx, bx.min));
        }
        if x.c.is_nan() || x.c > cx.max {
            return Err(out("c", x.c, cx, cx.min));
        }
        let central = x.a < ax.min;
        let elastic = x.c < cx.min;
        let sa = if central {
            Stencil::at(0)
        } else {
            ax.stencil(x.a)
        };
        let sb = bx.stencil(x.b);
        let sc = if elastic {
            Stencil::at(0)
        } else {
            cx.stencil(x.c)
        };
        let [na, nb, nc] = self.axes.map(|a| a.n);
        if !(central || elastic) {
            return Ok(interp3(&self.main, [na, nb, nc], &[sa, sb, sc]));
        }
        let ta = if central {
            (2.0 * (x.a - ax.min)).exp()
        } else {
            1.0
        };
        let tc = if elastic { (x.c - cx.min).exp() } else { 1.0 };
        // Face values in the extension forms ε_φ/s and (1−ε_r)/u. At t = 0 exactly
        // (c_φ = 0 or c_dis = 0) the lerps below return their low end, so the face is
        // not needed (and not computed: the elastic gas of eMD* lives there).
        let ln_s0 = self.bounds.g.min + ax.min;
        let face = || {
            let mut q = interp3(&self.main, [na, nb, nc], &[sa, sb, sc]);
            if central {
                q[2] -= ln_s0;
            }
            if elastic {
                q[0] -= cx.min;
            }
            q
        };
        let one = Stencil::at(0);
        let lerp = |lo: [f64; NQ], hi: &dyn Fn() -> [f64; NQ], t: f64| -> [f64; NQ] {
            if t == 0.0 {
                return lo;
            }
            let hi = hi();
            std::array::from_fn(|i| lo[i] + t * (hi[i] - lo[i]))
        };
        let elastic_face = || {
            let mut qe = interp3(&self.elastic, [na, nb, 1], &[sa, sb, one]);
            if central {
                qe[2] -= ln_s0;
            }
            qe
        };
        let mut q = if central {
            let central_face = || {
                let mut qc = interp3(&self.central, [1, nb, nc], &[one, sb, sc]);
                if elastic {
                    qc[0] -= cx.min;
                }
                qc
            };
            if elastic {
                let qce = interp3(&self.central_elastic, [1, nb, 1], &[one, sb, one]);
                let low = lerp(qce, &central_face, tc);
                lerp(low, &|| lerp(elastic_face(), &face, tc), ta)
            } else {
                lerp(central_face(), &face, ta)
            }
        } else {
            lerp(elastic_face(), &face, tc)
        };
        if q.iter().any(|v| v.is_nan()) {
            return Err(TableError::NotTabulated(format!(
                "near-central impact at (a, b, c) = ({}, {}, {}), where the central limit \
                 c_phi -> 0 has no finite collision or the MoR is not smooth enough in c_phi \
                 to be tabulated (strong damping, or nearly passing-through impacts)",
                x.a, x.b, x.c
            )));
        }
        if central {
            q[2] += x.a + self.bounds.g.min;
        }
        if elastic {
            q[0] += x.c;
        }
        Ok(q)
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
/// the caller passes one, e.g. `|m, p| emdstar_mor::solve(m, p).map(...)`. Every
/// fallback is counted in [`WithFallback::fallbacks`].
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

    /// Number of exact solves so far.
    pub fn fallbacks(&self) -> u64 {
        self.fallbacks.load(std::sync::atomic::Ordering::Relaxed)
    }
}
