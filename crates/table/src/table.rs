//! The in-memory table and its lookups.

use crate::TableInfo;
use crate::error::TableError;
use crate::pair_map::PairMap;
use crate::piece::{Piece, PieceParts};
use crate::poly::NQ;
use emdstar_contact::{
    Impact, Model, Mor, PairLaw, PairProperties, Range, RectBounds, RectCoords, ScaledParams,
};

/// The MoR from the four stored (log) quantities ln(1−ε_r), ln(−ε_ṙ), ln ε_φ, ln ε_t.
#[inline]
pub fn mor_from_logs(q: [f64; NQ]) -> Mor {
    let [one_minus_eps_r, eps_n, eps_phi, eps_t] = crate::fastmath::exp4(q);
    Mor {
        eps_r: 1.0 - one_minus_eps_r,
        one_minus_eps_r,
        eps_rdot: -eps_n,
        eps_phi,
        eps_t,
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

/// A matrix-of-restitution table over the rectangle of a parameter box.
///
/// **Main piece:** the four quantities of [`crate::QUANTITIES`] over (a, b, c) =
/// [`RectBounds::axes`], piecewise polynomial (see the crate documentation). Two
/// limits the engines meet constantly are stored as extra pieces and handled
/// explicitly (never by clamping):
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
/// impacts whose end hinges on the centrifugal force), the central piece is not
/// tabulated and a < 0 lookups there are [`TableError::NotTabulated`].
/// [`WithFallback`] turns both into a counted exact solve.
///
/// A `Table` is immutable after loading: lookups take `&self`, and it is `Send + Sync`,
/// so one table serves any number of threads.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub(crate) model: Model,
    pub(crate) bounds: RectBounds,
    pub(crate) rect: [Range; 3],
    /// d of the b axis map (0: none), see [`BMap`].
    pub(crate) b_map: BMap,
    pub(crate) degree: usize,
    pub(crate) main: Piece,
    pub(crate) elastic: Piece,
    pub(crate) central: Piece,
    pub(crate) central_elastic: Piece,
    pub(crate) info: TableInfo,
}

/// Everything a generator supplies to build a [`Table`], in the forms described on
/// [`Table`].
#[derive(Debug, Clone, PartialEq)]
pub struct TableParts {
    pub bounds: RectBounds,
    /// How the pieces store the b axis.
    pub b_map: BMap,
    /// Total degree of every patch polynomial.
    pub degree: usize,
    /// Over (a, b, c).
    pub main: PieceParts,
    /// Over (a, b), at u = 0.
    pub elastic: PieceParts,
    /// Over (b, c), at s = 0.
    pub central: PieceParts,
    /// Over b, at s = 0 and u = 0.
    pub central_elastic: PieceParts,
    pub info: TableInfo,
}

/// The coordinate in which the pieces store the b axis: b itself (`knee` = 0), or
/// w = ln(1 + (b − b_min)/d) with d = `knee` > 0. The latter puts a singularity at a
/// distance d below b_min (the pass-through of strongly penetrating impacts) far from
/// the patches in w, so few patches resolve the steep MoR at small b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BMap {
    pub b_min: f64,
    pub knee: f64,
}

impl BMap {
    /// w(b).
    #[inline(always)]
    pub fn w(&self, b: f64) -> f64 {
        if self.knee > 0.0 {
            ((b - self.b_min) / self.knee).ln_1p()
        } else {
            b
        }
    }

    /// b(w), the inverse.
    pub fn b(&self, w: f64) -> f64 {
        if self.knee > 0.0 {
            self.b_min + self.knee * w.exp_m1()
        } else {
            w
        }
    }

    /// The ranges of (a, w, c) of the pieces for the rectangle `rect`.
    pub fn piece_rect(&self, rect: &[Range; 3]) -> [Range; 3] {
        [
            rect[0],
            Range::new(self.w(rect[1].min), self.w(rect[1].max)),
            rect[2],
        ]
    }
}

/// The four pieces of a table: their names and which of the axes a, b, c each spans.
pub const PIECES: [(&str, [bool; 3]); 4] = [
    ("main", [true, true, true]),
    ("elastic", [true, true, false]),
    ("central", [false, true, true]),
    ("central_elastic", [false, true, false]),
];

/// The box of a piece that spans the axes `active` of `rect`.
pub fn piece_box(rect: &[Range; 3], active: [bool; 3]) -> ([f64; 3], [f64; 3]) {
    let lo = std::array::from_fn(|k| if active[k] { rect[k].min } else { 0.0 });
    let hi = std::array::from_fn(|k| if active[k] { rect[k].max } else { 0.0 });
    (lo, hi)
}

// Lookups share one table between threads.
const _: fn() = || {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Table>();
};

impl Table {
    /// Assembles and checks a table.
    pub fn from_parts(p: TableParts) -> Result<Self, TableError> {
        let rect = p.bounds.axes();
        if !(p.b_map.knee >= 0.0 && p.b_map.knee.is_finite() && p.b_map.b_min == rect[1].min) {
            return Err(TableError::Corrupt(format!(
                "the b map (knee {}, b_min {}) does not fit the b axis from {}",
                p.b_map.knee, p.b_map.b_min, rect[1].min
            )));
        }
        let prect = p.b_map.piece_rect(&rect);
        if !(1..=16).contains(&p.degree) {
            return Err(TableError::Corrupt(format!(
                "polynomial degree {} is not in 1..=16",
                p.degree
            )));
        }
        let tolerance = p.info.tolerance;
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(TableError::Corrupt(format!(
                "the tolerance {tolerance} is not finite and > 0"
            )));
        }
        let quantum = crate::pack::quantum(tolerance);
        let piece = |k: usize, parts: PieceParts| {
            let (name, active) = PIECES[k];
            let (lo, hi) = piece_box(&prect, active);
            // Only the central pieces may leave patches untabulated.
            Piece::new(name, parts, lo, hi, p.degree, quantum, k >= 2)
        };
        Ok(Self {
            model: p.bounds.model,
            bounds: p.bounds,
            rect,
            b_map: p.b_map,
            degree: p.degree,
            main: piece(0, p.main)?,
            elastic: piece(1, p.elastic)?,
            central: piece(2, p.central)?,
            central_elastic: piece(3, p.central_elastic)?,
            info: p.info,
        })
    }

    /// The force model the table was built for.
    pub fn model(&self) -> Model {
        self.model
    }

    /// The constants of the rectangular map (Eqs. 45-61).
    pub fn bounds(&self) -> &RectBounds {
        &self.bounds
    }

    /// The ranges of a, b and c covered by the main piece.
    pub fn rect(&self) -> [Range; 3] {
        self.rect
    }

    /// Generator, spec, physical box and accuracy of the table.
    pub fn info(&self) -> &TableInfo {
        &self.info
    }

    /// How the pieces store the b axis.
    pub fn b_map(&self) -> BMap {
        self.b_map
    }

    /// Total degree of the patch polynomials.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The four pieces (main, elastic, central, central elastic), as in [`PIECES`].
    pub fn pieces(&self) -> [&Piece; 4] {
        [
            &self.main,
            &self.elastic,
            &self.central,
            &self.central_elastic,
        ]
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

    /// A lookup handle for one pair and law: the constants of the physical map are
    /// computed and checked once, so each [`PairLookup::lookup`] costs only the
    /// impact's own logarithms and the interpolation.
    pub fn pair(&self, law: &PairLaw, pair: &PairProperties) -> Result<PairLookup<'_>, TableError> {
        PairLookup::new(self, law, pair)
    }

    /// A pair's own table: the restriction of this table to the impacts of one pair and
    /// law, two-dimensional, built once (see [`PairTable`](crate::PairTable)). Its
    /// lookups are several times cheaper than [`Table::pair`]'s for the price of a
    /// build of about a millisecond and some hundred kilobytes.
    pub fn pair_table(
        &self,
        law: &PairLaw,
        pair: &PairProperties,
    ) -> Result<crate::PairTable<&Table>, TableError> {
        crate::PairTable::new(self, law, pair)
    }

    /// MoR and time scale of a physical impact: scaling (Eqs. 41, 43, 53), rectangular
    /// coordinates (Eqs. 45-61) and interpolation of all four components. For many
    /// impacts of one pair, [`Table::pair`] avoids redoing the pair's part.
    #[inline]
    pub fn lookup(
        &self,
        law: &PairLaw,
        pair: &PairProperties,
        impact: &Impact,
    ) -> Result<PhysicalLookup, TableError> {
        self.pair(law, pair)?.lookup(impact)
    }

    /// MoR and time scale of an impact of the pair of `map`.
    #[inline]
    pub fn lookup_pair(
        &self,
        map: &PairMap,
        impact: &Impact,
    ) -> Result<PhysicalLookup, TableError> {
        self.expect_model(map.law().model())?;
        let (x, time) = map.coords(&self.bounds, impact)?;
        Ok(PhysicalLookup {
            mor: self.lookup_rect(&x)?,
            time,
            length: impact.normal_speed * time,
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
    #[inline]
    pub fn lookup_rect(&self, x: &RectCoords) -> Result<Mor, TableError> {
        self.logs_at(x).map(mor_from_logs)
    }

    /// The four stored (log) quantities at rectangular coordinates.
    #[inline]
    pub fn logs_at(&self, x: &RectCoords) -> Result<[f64; NQ], TableError> {
        if self.in_main_piece(x) {
            return Ok(self.main.eval([x.a, self.b_map.w(x.b), x.c]));
        }
        let [ra, rb, rc] = self.rect;
        let out = |axis, value: f64, r: Range| TableError::OutOfBox {
            axis,
            value,
            min: r.min,
            max: r.max,
        };
        if x.a.is_nan() || x.a > ra.max {
            return Err(out("a", x.a, ra));
        }
        if !(x.b >= rb.min && x.b <= rb.max) {
            return Err(out("b", x.b, rb));
        }
        if x.c.is_nan() || x.c > rc.max {
            return Err(out("c", x.c, rc));
        }
        // Inside the box's upper ends but not the main piece: an extension.
        self.extension(x, x.a < ra.min, x.c < rc.min)
    }

    /// Whether the main piece holds `x` (no extension, not out of the box; false for
    /// NaN).
    #[inline(always)]
    pub(crate) fn in_main_piece(&self, x: &RectCoords) -> bool {
        let [ra, rb, rc] = self.rect;
        let within = |v: f64, r: Range| v >= r.min && v <= r.max;
        within(x.a, ra) && within(x.b, rb) && within(x.c, rc)
    }

    /// The near-central and nearly elastic extensions (see [`Table`]).
    #[cold]
    fn extension(
        &self,
        x: &RectCoords,
        central: bool,
        elastic: bool,
    ) -> Result<[f64; NQ], TableError> {
        let [ra, _, rc] = self.rect;
        let a = if central { ra.min } else { x.a };
        let w = self.b_map.w(x.b);
        let c = if elastic { rc.min } else { x.c };
        let ta = if central {
            (2.0 * (x.a - ra.min)).exp()
        } else {
            1.0
        };
        let tc = if elastic { (x.c - rc.min).exp() } else { 1.0 };
        // Face values in the extension forms ε_φ/s and (1−ε_r)/u. At t = 0 exactly
        // (c_φ = 0 or c_dis = 0) the lerps below return their low end, so the face is
        // not needed (and not computed: the elastic gas of eMD* lives there).
        let ln_s0 = self.bounds.g.min + ra.min;
        let face = || {
            let mut q = self.main.eval([a, w, c]);
            if central {
                q[2] -= ln_s0;
            }
            if elastic {
                q[0] -= rc.min;
            }
            q
        };
        let lerp = |lo: [f64; NQ], hi: &dyn Fn() -> [f64; NQ], t: f64| -> [f64; NQ] {
            if t == 0.0 {
                return lo;
            }
            let hi = hi();
            std::array::from_fn(|i| lo[i] + t * (hi[i] - lo[i]))
        };
        let elastic_face = || {
            let mut qe = self.elastic.eval([a, w, 0.0]);
            if central {
                qe[2] -= ln_s0;
            }
            qe
        };
        let mut q = if central {
            let central_face = || {
                let mut qc = self.central.eval([0.0, w, c]);
                if elastic {
                    qc[0] -= rc.min;
                }
                qc
            };
            if elastic {
                let qce = self.central_elastic.eval([0.0, w, 0.0]);
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

/// A table shared without copying: a `'static` one (such as an embedded default) or
/// one loaded at run time, behind an `Arc`. Cloning shares it.
#[derive(Debug, Clone)]
pub enum SharedTable {
    Static(&'static Table),
    Owned(std::sync::Arc<Table>),
}

impl std::ops::Deref for SharedTable {
    type Target = Table;
    fn deref(&self) -> &Table {
        match self {
            Self::Static(t) => t,
            Self::Owned(t) => t,
        }
    }
}
