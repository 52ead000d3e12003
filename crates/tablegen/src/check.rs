//! Accuracy check: table lookups against exact solves at seeded random points.

use crate::generate::Solver;
use emdstar_contact::{RectCoords, ScaledParams};
use emdstar_table::{Table, TableMor};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Where to draw the sample points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    /// Uniformly in the table's rectangle (the accuracy goal).
    Box,
    /// Near-central impacts below the box: a uniform in [a_min − 6, a_min).
    Central,
    /// Nearly elastic impacts below the box: c uniform in [c_min − 10, c_min).
    Elastic,
}

/// Component names in report order.
pub const COMPONENTS: [&str; 4] = ["1-eps_r", "eps_rdot", "eps_phi", "eps_t"];

/// Relative errors of one component.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentError {
    pub name: &'static str,
    pub max: f64,
    pub p99: f64,
    /// Where the largest error occurred.
    pub worst_at: RectCoords,
}

/// The result of a check.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    pub samples: usize,
    pub components: Vec<ComponentError>,
    /// Largest relative error over all components in each of [`BINS`] equal bins of
    /// the a, b and c axes (where the table falls short).
    pub by_axis: [[f64; BINS]; 3],
}

/// Bins per axis of [`CheckReport::by_axis`].
pub const BINS: usize = 8;

fn relative_errors(t: &TableMor, e: &TableMor) -> [f64; 4] {
    let rel = |a: f64, b: f64| if a == b { 0.0 } else { ((a - b) / b).abs() };
    [
        rel(t.one_minus_eps_r, e.one_minus_eps_r),
        rel(t.eps_rdot, e.eps_rdot),
        rel(t.eps_phi, e.eps_phi),
        rel(t.eps_t, e.eps_t),
    ]
}

/// Seeded sample points (the same for any thread count).
pub fn sample_points(table: &Table, n: usize, seed: u64, region: Region) -> Vec<RectCoords> {
    let [ax, bx, cx] = *table.axes();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    (0..n)
        .map(|_| {
            let (a_lo, a_hi) = match region {
                Region::Central => (ax.min - 6.0, ax.min),
                _ => (ax.min, ax.max),
            };
            let (c_lo, c_hi) = match region {
                Region::Elastic => (cx.min - 10.0, cx.min),
                _ => (cx.min, cx.max),
            };
            RectCoords {
                a: uniform(a_lo, a_hi),
                b: uniform(bx.min, bx.max),
                c: uniform(c_lo, c_hi),
            }
        })
        .collect()
}

/// Compares the table with exact solves at `n` random points.
pub fn check(
    table: &Table,
    solve: &Solver,
    n: usize,
    seed: u64,
    region: Region,
) -> Result<CheckReport, String> {
    let points = sample_points(table, n, seed, region);
    let errors: Vec<[f64; 4]> = points
        .par_iter()
        .map(|x| {
            let p: ScaledParams = table.bounds().from_rect(x);
            let exact =
                solve(table.model(), &p).map_err(|e| format!("exact solve at {x:?}: {e}"))?;
            let got = table.lookup_rect(x).map_err(|e| e.to_string())?;
            Ok(relative_errors(&got, &exact))
        })
        .collect::<Result<_, String>>()?;
    let components = (0..4)
        .map(|q| {
            let mut v: Vec<(f64, usize)> =
                errors.iter().enumerate().map(|(i, e)| (e[q], i)).collect();
            v.sort_by(|x, y| x.0.total_cmp(&y.0));
            let (max, worst) = *v.last().expect("at least one sample");
            let p99 = v[((v.len() as f64 * 0.99).ceil() as usize).clamp(1, v.len()) - 1].0;
            ComponentError {
                name: COMPONENTS[q],
                max,
                p99,
                worst_at: points[worst],
            }
        })
        .collect();
    let mut by_axis = [[0.0f64; BINS]; 3];
    let [ax, bx, cx] = *table.axes();
    for (x, e) in points.iter().zip(&errors) {
        let worst = e.iter().fold(0.0f64, |m, v| m.max(*v));
        for (k, (v, r)) in [(x.a, ax), (x.b, bx), (x.c, cx)].into_iter().enumerate() {
            let (lo, hi) = match (k, region) {
                (0, Region::Central) => (r.min - 6.0, r.min),
                (2, Region::Elastic) => (r.min - 10.0, r.min),
                _ => (r.min, r.max),
            };
            let bin = (((v - lo) / (hi - lo) * BINS as f64) as usize).min(BINS - 1);
            by_axis[k][bin] = by_axis[k][bin].max(worst);
        }
    }
    Ok(CheckReport {
        samples: n,
        components,
        by_axis,
    })
}
