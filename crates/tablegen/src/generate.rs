//! The adaptive fit: every patch's Chebyshev coefficients from exact solves, in
//! parallel, deterministically.
//!
//! Each top cell of each piece (a *unit*) is refined on its own: a patch is fitted by
//! interpolating the exact solutions at the (n+2)³ Chebyshev extreme points of its box
//! (n the degree; fewer on a piece's missing axes) and keeping the terms of total degree
//! ≤ n. Its error estimate per quantity is the sum of the magnitudes of the dropped
//! coefficients; above the tolerance, the box is bisected along the axis that carries
//! most of them. The units are numbered piece by piece, cells in C order, and each one's
//! tree in breadth-first order, so the result is bitwise the same for any thread count,
//! and a shard `i/n` (the contiguous unit range `[U·i/n, U·(i+1)/n)`) plus [`merge`]
//! reproduces a single run byte for byte.

use crate::spec::Spec;
use emdstar_contact::{Model, RectCoords, ScaledParams};
use emdstar_table::{
    LEAF, Mor, NQ, PIECES, PieceParts, Table, TableInfo, TableParts, Terms, mor_to_logs, piece_box,
};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

/// An exact MoR solver, `emdstar_mor::solve` in production.
pub type Solver = dyn Fn(Model, &ScaledParams) -> Result<Mor, String> + Sync;

/// The production solver: `emdstar_mor::solve` with its default tolerances.
pub fn exact_solver(model: Model, p: &ScaledParams) -> Result<Mor, String> {
    emdstar_mor::solve(model, p).map_err(|e| e.to_string())
}

/// The generator's name and version, stored in every table.
pub fn generator_version() -> String {
    format!("emdstar-tablegen {}", env!("CARGO_PKG_VERSION"))
}

/// s = c_φ/l̃ used to sample the central limit (relative error O(s²) = 1e-16).
const CENTRAL_S: f64 = 1e-8;

/// Bisections of a central piece's top cell at most while it isolates the region where
/// the central limit is not tabulated.
const CENTRAL_DEPTH: usize = 5;

/// One unit of work: a top cell of a piece.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// Index into [`PIECES`].
    pub piece: usize,
    pub cell: usize,
    pub bx: [[f64; 2]; 3],
}

/// The refined tree of one unit, in breadth-first order (root first).
#[derive(Debug, Clone, PartialEq)]
pub struct UnitTree {
    pub tree: Vec<[i64; 2]>,
    pub split: Vec<f64>,
    pub cheb: Vec<[f64; NQ]>,
    /// Largest error estimate of its patches, per quantity.
    pub error: [f64; NQ],
}

/// The top cells of every piece of a spec, in unit order.
pub fn units(spec: &Spec) -> Vec<Unit> {
    let rect = spec.b_map().piece_rect(&spec.rect());
    let mut out = Vec::new();
    for (piece, (_, active)) in PIECES.iter().enumerate() {
        let (lo, hi) = piece_box(&rect, *active);
        let cells: [usize; 3] = std::array::from_fn(|k| if active[k] { spec.cells[k] } else { 1 });
        for cell in 0..cells.iter().product() {
            let idx = [
                cell / (cells[1] * cells[2]),
                cell / cells[2] % cells[1],
                cell % cells[2],
            ];
            // The same arithmetic as the reader's check of the trees.
            let bx = std::array::from_fn(|k| {
                let w = (hi[k] - lo[k]) / cells[k] as f64;
                let a = lo[k] + w * idx[k] as f64;
                let b = if idx[k] + 1 == cells[k] {
                    hi[k]
                } else {
                    lo[k] + w * (idx[k] + 1) as f64
                };
                [a, b]
            });
            out.push(Unit { piece, cell, bx });
        }
    }
    out
}

/// Number of units (top cells of all pieces) of a spec.
pub fn unit_count(spec: &Spec) -> usize {
    units(spec).len()
}

/// The four stored values of `piece` at `x` (see [`Table`] for the forms); NaN where a
/// central piece has no limit.
pub fn point_values(
    spec: &Spec,
    solve: &Solver,
    piece: usize,
    x: [f64; 3],
) -> Result<[f64; NQ], String> {
    let rect = spec.rect();
    let bounds = &spec.bounds;
    let central = piece >= 2;
    let elastic = piece == 1 || piece == 3;
    let a_central = CENTRAL_S.ln() - bounds.g.min;
    let a = if central { a_central } else { x[0] };
    let b = spec.b_map().b(x[1]);
    let c = if elastic { rect[2].min } else { x[2] };
    let at_face = bounds.from_rect(&RectCoords { a, b, c });
    let p = ScaledParams {
        c_dis: if elastic { 0.0 } else { at_face.c_dis },
        ..at_face
    };
    let m = match solve(spec.model, &p) {
        Ok(m) => m,
        // No central limit here (e.g. strongly overdamped Hertz impacts that only end
        // thanks to the centrifugal force): not tabulated.
        Err(_) if central => return Ok([f64::NAN; NQ]),
        Err(e) => {
            return Err(format!(
                "solve failed at (a = {a}, b = {b}, c = {c}, scaled {p:?}): {e}"
            ));
        }
    };
    let mut q = mor_to_logs(&m);
    if elastic {
        // (1−ε_r)/u → c_dis/(u·l̃) as c_dis → 0 (the collision ends at ξ̃ = c_dis·ṙ̃ with
        // ṙ̃ → 1); ε_ṙ = −1 exactly (energy conservation).
        q[0] = at_face.c_dis.ln() - c - p.l_tilde.ln();
        q[1] = 0.0;
    }
    if central {
        q[2] -= a + bounds.g.min;
        if !central_extension_holds(spec, solve, &q, b, c, elastic) {
            return Ok([f64::NAN; NQ]);
        }
    }
    if let Some(i) = q.iter().position(|x| !x.is_finite() && !central) {
        return Err(format!(
            "(a = {a}, b = {b}, c = {c}) gave a non-finite stored value {} from {m:?}",
            emdstar_table::QUANTITIES[i]
        ));
    }
    Ok(q)
}

/// Largest error in the stored logs that the near-central extension may make.
const CENTRAL_TOLERANCE: f64 = 3e-7;

/// Whether the reader's near-central extension (linear in s² between the central
/// value `q0` at s = 0 and the a = 0 face) reproduces exact solves below the box at
/// (b, c). Where strong damping makes the end of the collision hinge on the centrifugal
/// force, the MoR is not smooth in s² at all (errors up to 70% in ε_t were measured):
/// such points are not tabulated, so lookups there are `NotTabulated` (a counted exact
/// solve with a fallback) instead of wrong.
fn central_extension_holds(
    spec: &Spec,
    solve: &Solver,
    q0: &[f64; NQ],
    b: f64,
    c: f64,
    elastic: bool,
) -> bool {
    let bounds = &spec.bounds;
    let logs_at = |a: f64| -> Option<[f64; NQ]> {
        let at = bounds.from_rect(&RectCoords { a, b, c });
        let p = ScaledParams {
            c_dis: if elastic { 0.0 } else { at.c_dis },
            ..at
        };
        let mut q = mor_to_logs(&solve(spec.model, &p).ok()?);
        if elastic {
            q[0] = at.c_dis.ln() - c - at.l_tilde.ln();
            q[1] = 0.0;
        }
        q[2] -= a + bounds.g.min;
        Some(q)
    };
    let Some(face) = logs_at(0.0) else {
        return false;
    };
    // t = (s/s_face)² = e^{2a}: the middle and the near-central end of the extension.
    [-0.5 * 2f64.ln(), -2.0].into_iter().all(|a| {
        let t = (2.0 * a).exp();
        logs_at(a).is_some_and(|exact| {
            (0..NQ).all(|i| {
                let lerp = q0[i] + t * (face[i] - q0[i]);
                (lerp - exact[i]).abs() <= CENTRAL_TOLERANCE
            })
        })
    })
}

/// A fitted patch.
struct Fit {
    /// Kept Chebyshev coefficients in term order; None where not tabulated (some
    /// point NaN).
    cheb: Option<Vec<[f64; NQ]>>,
    error: [f64; NQ],
    /// Whether some but not all points were NaN.
    mixed: bool,
    /// The axis carrying most of the dropped coefficients.
    worst_axis: usize,
}

/// Fits the polynomial of `piece` on box `bx`.
fn fit(spec: &Spec, solve: &Solver, piece: usize, bx: &[[f64; 2]; 3]) -> Result<Fit, String> {
    let active = PIECES[piece].1;
    let n = spec.degree;
    let np = n + 1; // highest index of the tensor interpolant
    let count: [usize; 3] = std::array::from_fn(|k| if active[k] { np + 1 } else { 1 });
    let node = |k: usize, j: usize| -> f64 {
        if !active[k] {
            return 0.0;
        }
        let t = (std::f64::consts::PI * j as f64 / np as f64).cos();
        0.5 * (bx[k][0] + bx[k][1]) + 0.5 * (bx[k][1] - bx[k][0]) * t
    };
    let total = count.iter().product::<usize>();
    let mut vals = Vec::with_capacity(total);
    for i in 0..count[0] {
        for j in 0..count[1] {
            for k in 0..count[2] {
                vals.push(point_values(
                    spec,
                    solve,
                    piece,
                    [node(0, i), node(1, j), node(2, k)],
                )?);
            }
        }
    }
    let nans = vals.iter().filter(|v| v.iter().any(|x| x.is_nan())).count();
    if nans > 0 {
        return Ok(Fit {
            cheb: None,
            error: [0.0; NQ],
            mixed: nans < total,
            worst_axis: (0..3)
                .filter(|&k| active[k])
                .max_by(|&x, &y| (bx[x][1] - bx[x][0]).total_cmp(&(bx[y][1] - bx[y][0])))
                .expect("an active axis"),
        });
    }
    // Chebyshev coefficients of the tensor interpolant, one axis at a time (DCT-I).
    let mut coef = vals;
    let stride = [count[1] * count[2], count[2], 1];
    for k in 0..3 {
        if !active[k] {
            continue;
        }
        let m = count[k];
        let mut line = vec![[0.0; NQ]; m];
        for base in 0..total {
            if (base / stride[k]) % m != 0 {
                continue;
            }
            for (kk, slot) in line.iter_mut().enumerate() {
                let mut s = [0.0; NQ];
                for j in 0..m {
                    let w = if j == 0 || j == m - 1 { 0.5 } else { 1.0 }
                        * (std::f64::consts::PI * (kk * j) as f64 / np as f64).cos();
                    let v = coef[base + j * stride[k]];
                    for (s, v) in s.iter_mut().zip(v) {
                        *s += w * v;
                    }
                }
                let f = if kk == 0 || kk == m - 1 { 1.0 } else { 2.0 } / np as f64;
                *slot = s.map(|x| x * f);
            }
            for (j, v) in line.iter().enumerate() {
                coef[base + j * stride[k]] = *v;
            }
        }
    }
    let max = std::array::from_fn(|k| if active[k] { n } else { 0 });
    let terms = Terms::new(n, max);
    let mut error = [0.0; NQ];
    let mut by_axis = [0.0; 3];
    let mut kept = Vec::with_capacity(terms.len());
    for p in &terms.powers {
        kept.push(coef[p[0] * stride[0] + p[1] * stride[1] + p[2] * stride[2]]);
    }
    for i in 0..count[0] {
        for j in 0..count[1] {
            for k in 0..count[2] {
                if i + j + k <= n && i <= max[0] && j <= max[1] && k <= max[2] {
                    continue;
                }
                let c = coef[i * stride[0] + j * stride[1] + k * stride[2]];
                let size = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (e, x) in error.iter_mut().zip(c) {
                    *e += x.abs();
                }
                let sum = (i + j + k) as f64;
                for (a, idx) in [i, j, k].into_iter().enumerate() {
                    by_axis[a] += size * idx as f64 / sum;
                }
            }
        }
    }
    let worst_axis = (0..3)
        .filter(|&k| active[k])
        .max_by(|&x, &y| by_axis[x].total_cmp(&by_axis[y]))
        .expect("an active axis");
    Ok(Fit {
        cheb: Some(kept),
        error,
        mixed: false,
        worst_axis,
    })
}

/// Refines the given units (all of them together, level by level, in parallel).
pub fn refine(
    spec: &Spec,
    solve: &Solver,
    units: &[Unit],
    progress: bool,
) -> Result<Vec<UnitTree>, String> {
    let bar = if progress {
        ProgressBar::new_spinner()
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} {spinner} {msg}").expect("valid template"),
    );
    let mut trees: Vec<UnitTree> = units
        .iter()
        .map(|_| UnitTree {
            tree: vec![[LEAF, 0]],
            split: vec![0.0],
            cheb: Vec::new(),
            error: [0.0; NQ],
        })
        .collect();
    let mut patches = vec![0usize; units.len()];
    // (unit, node, box, depth)
    let mut frontier: Vec<(usize, usize, [[f64; 2]; 3], usize)> = units
        .iter()
        .enumerate()
        .map(|(u, unit)| (u, 0, unit.bx, 0))
        .collect();
    let (mut fitted, mut leaves) = (0usize, 0usize);
    while !frontier.is_empty() {
        bar.set_message(format!(
            "{fitted} patches fitted, {leaves} kept, {} at this level",
            frontier.len()
        ));
        let fits: Vec<Fit> = frontier
            .par_iter()
            .map(|(u, _, bx, _)| fit(spec, solve, units[*u].piece, bx))
            .collect::<Result<_, _>>()?;
        fitted += fits.len();
        let mut next = Vec::new();
        for ((u, node, bx, depth), f) in frontier.into_iter().zip(fits) {
            let central = units[u].piece >= 2;
            let limit = if central {
                CENTRAL_DEPTH
            } else {
                spec.max_depth
            };
            let worst = f.error.iter().fold(0.0f64, |m, x| m.max(*x));
            let accept = match &f.cheb {
                Some(_) => worst <= spec.tolerance || depth >= spec.max_depth,
                None => !f.mixed || depth >= limit,
            };
            let t = &mut trees[u];
            if accept {
                t.tree[node] = [LEAF, patches[u] as i64];
                patches[u] += 1;
                leaves += 1;
                match f.cheb {
                    Some(c) => {
                        t.cheb.extend(c);
                        for (e, x) in t.error.iter_mut().zip(f.error) {
                            *e = e.max(x);
                        }
                    }
                    None => {
                        let nt = Terms::new(spec.degree, term_max(spec, units[u].piece)).len();
                        t.cheb.extend(std::iter::repeat_n([f64::NAN; NQ], nt));
                    }
                }
                continue;
            }
            let k = f.worst_axis;
            let mid = 0.5 * (bx[k][0] + bx[k][1]);
            let first = t.tree.len();
            t.tree[node] = [k as i64, first as i64];
            t.split[node] = mid;
            t.tree.extend([[LEAF, 0], [LEAF, 0]]);
            t.split.extend([0.0, 0.0]);
            let (mut below, mut above) = (bx, bx);
            below[k][1] = mid;
            above[k][0] = mid;
            next.push((u, first, below, depth + 1));
            next.push((u, first + 1, above, depth + 1));
        }
        frontier = next;
    }
    bar.finish_and_clear();
    Ok(trees)
}

fn term_max(spec: &Spec, piece: usize) -> [usize; 3] {
    let active = PIECES[piece].1;
    std::array::from_fn(|k| if active[k] { spec.degree } else { 0 })
}

/// Assembles a table from the trees of all units, in unit order.
pub fn assemble(spec: &Spec, trees: Vec<UnitTree>) -> Result<Table, String> {
    let all = units(spec);
    if trees.len() != all.len() {
        return Err(format!("expected {} units, got {}", all.len(), trees.len()));
    }
    let mut pieces: Vec<PieceParts> = Vec::new();
    let mut error = [0.0f64; NQ];
    for (piece, (_, active)) in PIECES.iter().enumerate() {
        let cells: [usize; 3] = std::array::from_fn(|k| if active[k] { spec.cells[k] } else { 1 });
        let nt = Terms::new(spec.degree, term_max(spec, piece)).len();
        let mut p = PieceParts {
            cells,
            roots: Vec::new(),
            tree: Vec::new(),
            split: Vec::new(),
            cheb: Vec::new(),
        };
        for (unit, t) in all.iter().zip(&trees) {
            if unit.piece != piece {
                continue;
            }
            let node0 = p.tree.len() as i64;
            let patch0 = (p.cheb.len() / nt) as i64;
            p.roots.push(node0 as usize);
            p.tree.extend(t.tree.iter().map(|&[axis, next]| {
                if axis == LEAF {
                    [LEAF, next + patch0]
                } else {
                    [axis, next + node0]
                }
            }));
            p.split.extend(&t.split);
            p.cheb.extend(&t.cheb);
            for (e, x) in error.iter_mut().zip(t.error) {
                *e = e.max(x);
            }
        }
        pieces.push(p);
    }
    let info = TableInfo {
        generator: generator_version(),
        spec: spec.text.clone(),
        box_names: spec
            .parameter_box
            .ranges()
            .iter()
            .map(|(n, _)| n.to_string())
            .collect(),
        box_ranges: spec
            .parameter_box
            .ranges()
            .iter()
            .map(|(_, r)| [r.min, r.max])
            .collect(),
        tolerance: spec.tolerance,
        estimated_error: error,
    };
    let mut it = pieces.into_iter();
    let mut next = || it.next().expect("four pieces");
    Table::from_parts(TableParts {
        bounds: spec.bounds,
        b_map: spec.b_map(),
        degree: spec.degree,
        main: next(),
        elastic: next(),
        central: next(),
        central_elastic: next(),
        info,
    })
    .map_err(|e| e.to_string())
}

/// Builds the whole table.
pub fn build(spec: &Spec, solve: &Solver, progress: bool) -> Result<Table, String> {
    let trees = refine(spec, solve, &units(spec), progress)?;
    assemble(spec, trees)
}
