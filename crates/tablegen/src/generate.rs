//! The grid sweep: every node solved exactly, in parallel, deterministically.
//!
//! The nodes are numbered in one fixed order: the main grid `[a][b][c]`, then the
//! elastic slice `[a][b]`, the central slice `[b][c]` and the central-elastic line
//! `[b]`. Each node's four values depend on that node alone, so the result is bitwise
//! the same for any thread count, and a shard `i/n` (the contiguous node range
//! `[N·i/n, N·(i+1)/n)`) plus [`merge`] reproduces a single run byte for byte.

use crate::spec::Spec;
use emdstar_contact::{Model, RectCoords, ScaledParams};
use emdstar_table::npz::{Array, Data, read_npz, write_npz};
use emdstar_table::{Mor, NQ, Table, TableInfo, TableParts, mor_to_logs};
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

/// Number of nodes (solves) of a spec.
pub fn node_count(spec: &Spec) -> usize {
    let [na, nb, nc] = spec.nodes;
    na * nb * nc + na * nb + nb * nc + nb
}

/// The four stored values of node `k` (see [`Table`] for the forms).
pub fn node_values(spec: &Spec, solve: &Solver, k: usize) -> Result<[f64; NQ], String> {
    let [na, nb, nc] = spec.nodes;
    let [ax, bx, cx] = spec.axes();
    let bounds = &spec.bounds;
    let a_central = CENTRAL_S.ln() - bounds.g.min;
    let (a, b, c, central, elastic) = if k < na * nb * nc {
        let (i, j, l) = (k / (nb * nc), k / nc % nb, k % nc);
        (ax.node(i), bx.node(j), cx.node(l), false, false)
    } else if k < na * nb * (nc + 1) {
        let r = k - na * nb * nc;
        (ax.node(r / nb), bx.node(r % nb), cx.min, false, true)
    } else if k < na * nb * (nc + 1) + nb * nc {
        let r = k - na * nb * (nc + 1);
        (a_central, bx.node(r / nc), cx.node(r % nc), true, false)
    } else if k < node_count(spec) {
        let r = k - na * nb * (nc + 1) - nb * nc;
        (a_central, bx.node(r), cx.min, true, true)
    } else {
        return Err(format!("node {k} does not exist"));
    };
    let at_face = bounds.from_rect(&RectCoords { a, b, c });
    let p = ScaledParams {
        c_dis: if elastic { 0.0 } else { at_face.c_dis },
        ..at_face
    };
    let m = match solve(spec.model, &p) {
        Ok(m) => m,
        // No central limit here (e.g. strongly overdamped Hertz impacts that only end
        // thanks to the centrifugal force): stored as NaN, looked up as NotTabulated.
        Err(_) if central => return Ok([f64::NAN; NQ]),
        Err(e) => {
            return Err(format!(
                "solve failed at node {k} (a = {a}, b = {b}, c = {c}, scaled {p:?}): {e}"
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
            "node {k} (a = {a}, b = {b}, c = {c}) gave a non-finite stored value {} from {m:?}",
            emdstar_table::QUANTITIES[i]
        ));
    }
    Ok(q)
}

/// Largest error in the stored logs that the near-central extension may make at a node.
const CENTRAL_TOLERANCE: f64 = 3e-7;

/// Whether the reader's near-central extension (linear in s² between the central slice
/// value `q0` at s = 0 and the a = 0 face) reproduces exact solves below the box at
/// (b, c). Where strong damping makes the end of the collision hinge on the centrifugal
/// force, the MoR is not smooth in s² at all (errors up to 70% in ε_t were measured):
/// such nodes are stored as NaN, so lookups there are `NotTabulated` (a counted exact
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
            // The same forms as the elastic slice (see `node_values`).
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

/// Solves nodes `range` in parallel (current rayon pool), with an optional progress bar.
pub fn solve_range(
    spec: &Spec,
    solve: &Solver,
    range: std::ops::Range<usize>,
    progress: bool,
) -> Result<Vec<f64>, String> {
    let bar = if progress {
        ProgressBar::new(range.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{wide_bar}] {pos}/{len} nodes, {per_sec}, ETA {eta}",
        )
        .expect("valid template"),
    );
    let values: Result<Vec<[f64; NQ]>, String> = range
        .into_par_iter()
        .map(|k| {
            let v = node_values(spec, solve, k);
            bar.inc(1);
            v
        })
        .collect();
    bar.finish_and_clear();
    Ok(values?.into_iter().flatten().collect())
}

/// Assembles a table from all node values, in node order.
pub fn assemble(spec: &Spec, values: Vec<f64>) -> Result<Table, String> {
    let [na, nb, nc] = spec.nodes;
    let cut = |from: usize, len: usize| values[from * NQ..(from + len) * NQ].to_vec();
    if values.len() != node_count(spec) * NQ {
        return Err(format!(
            "expected {} values, got {}",
            node_count(spec) * NQ,
            values.len()
        ));
    }
    let n_main = na * nb * nc;
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
    };
    Table::from_parts(TableParts {
        bounds: spec.bounds,
        n: spec.nodes,
        order: spec.order,
        stretch: spec.stretch,
        main: cut(0, n_main),
        elastic: cut(n_main, na * nb),
        central: cut(n_main + na * nb, nb * nc),
        central_elastic: cut(n_main + na * nb + nb * nc, nb),
        info,
    })
    .map_err(|e| e.to_string())
}

/// Builds the whole table.
pub fn build(spec: &Spec, solve: &Solver, progress: bool) -> Result<Table, String> {
    let values = solve_range(spec, solve, 0..node_count(spec), progress)?;
    assemble(spec, values)
}

/// Node range of shard `i` of `n` (0-based i).
pub fn shard_range(spec: &Spec, i: usize, n: usize) -> std::ops::Range<usize> {
    let total = node_count(spec);
    total * i / n..total * (i + 1) / n
}

/// Builds shard `i` of `n` as a part file (bytes).
pub fn build_shard(
    spec: &Spec,
    solve: &Solver,
    i: usize,
    n: usize,
    progress: bool,
) -> Result<Vec<u8>, String> {
    if n == 0 || i >= n {
        return Err(format!(
            "shard {i}/{n} is invalid: use --shard I/N with 0 <= I < N"
        ));
    }
    let range = shard_range(spec, i, n);
    let values = solve_range(spec, solve, range.clone(), progress)?;
    Ok(write_npz(&[
        ("part_of", Array::str_scalar(&generator_version())),
        ("spec", Array::str_scalar(&spec.text)),
        ("shard", Array::i64(vec![2], vec![i as i64, n as i64])),
        (
            "range",
            Array::i64(vec![2], vec![range.start as i64, range.end as i64]),
        ),
        ("values", Array::f64(vec![range.len(), NQ], values)),
    ]))
}

/// Merges the part files of all shards (any order) into the table.
pub fn merge(parts: &[Vec<u8>]) -> Result<Table, String> {
    let mut pieces = Vec::new();
    let mut spec_text: Option<String> = None;
    for (p, bytes) in parts.iter().enumerate() {
        let members = read_npz(bytes).map_err(|e| format!("part {}: {e}", p + 1))?;
        let find = |name: &str| {
            members
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, a)| &a.data)
                .ok_or_else(|| format!("part {} is not a shard file (no {name})", p + 1))
        };
        let (Data::Str(spec), Data::I64(shard), Data::I64(range), Data::F64(values)) = (
            find("spec")?,
            find("shard")?,
            find("range")?,
            find("values")?,
        ) else {
            return Err(format!("part {} has malformed members", p + 1));
        };
        match &spec_text {
            None => spec_text = Some(spec[0].clone()),
            Some(s) if *s != spec[0] => {
                return Err(format!("part {} was built from a different spec", p + 1));
            }
            _ => {}
        }
        pieces.push((
            shard[0],
            shard[1],
            range[0] as usize,
            range[1] as usize,
            values.clone(),
        ));
    }
    let spec = Spec::parse(spec_text.as_deref().ok_or("no parts given")?)?;
    pieces.sort_by_key(|p| p.0);
    let n = pieces[0].1;
    let mut next = 0;
    let mut values = Vec::with_capacity(node_count(&spec) * NQ);
    for (k, (i, nn, start, end, v)) in pieces.into_iter().enumerate() {
        if nn != n || i != k as i64 || start != next || v.len() != (end - start) * NQ {
            return Err(format!(
                "the parts do not form shards 0..{n} of one run: shard {k} is missing, \
                 duplicated or inconsistent"
            ));
        }
        next = end;
        values.extend(v);
    }
    if next != node_count(&spec) {
        return Err(format!(
            "the parts stop at node {next} of {}: a shard is missing",
            node_count(&spec)
        ));
    }
    assemble(&spec, values)
}
