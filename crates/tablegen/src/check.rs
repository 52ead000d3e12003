//! Accuracy check: table lookups against exact solves at seeded random points.

use crate::generate::Solver;
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, PairLaw, PairProperties, RectCoords, ScaledParams, Sphere,
    ViscoelasticHertz, scale,
};
use emdstar_table::{Mor, Table, TableError};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Where to draw the sample points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Region {
    /// Physical impacts of the table's box (its Tab. I or II ranges, stored in the
    /// file): each parameter drawn log-uniformly in its range, then scaled and mapped
    /// to (a, b, c). The image of the box is a part of the rectangle only (b and c
    /// share parameters). This is the accuracy goal.
    Physical,
    /// Uniformly in the table's rectangle.
    Rect,
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
    /// Samples the table did not answer (outside its rectangle, e.g. below a spec's
    /// `m_min`, or not tabulated): an exact-solve fallback region, left out of the errors.
    pub outside: usize,
    pub components: Vec<ComponentError>,
    /// Largest relative error over all components in each of [`BINS`] equal bins of
    /// the a, b and c axes (where the table falls short).
    pub by_axis: [[f64; BINS]; 3],
}

/// Bins per axis of [`CheckReport::by_axis`].
pub const BINS: usize = 8;

fn relative_errors(t: &Mor, e: &Mor) -> [f64; 4] {
    let rel = |a: f64, b: f64| if a == b { 0.0 } else { ((a - b) / b).abs() };
    [
        rel(t.one_minus_eps_r, e.one_minus_eps_r),
        rel(t.eps_rdot, e.eps_rdot),
        rel(t.eps_phi, e.eps_phi),
        rel(t.eps_t, e.eps_t),
    ]
}

/// Seeded sample points (the same for any thread count): rectangular coordinates, and
/// the scaled parameters where the region gives them directly (physical impacts).
pub fn sample_points(
    table: &Table,
    n: usize,
    seed: u64,
    region: Region,
) -> Result<Vec<(RectCoords, ScaledParams)>, String> {
    let [ax, bx, cx] = table.rect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    let bounds = table.bounds();
    (0..n)
        .map(|_| {
            if region == Region::Physical {
                let p = physical_sample(table, &mut |r: [f64; 2]| {
                    uniform(r[0].ln(), r[1].ln()).exp()
                })?;
                return Ok((bounds.to_rect(&p), p));
            }
            let (a_lo, a_hi) = match region {
                Region::Central => (ax.min - 6.0, ax.min),
                _ => (ax.min, ax.max),
            };
            let (c_lo, c_hi) = match region {
                Region::Elastic => (cx.min - 10.0, cx.min),
                _ => (cx.min, cx.max),
            };
            let x = RectCoords {
                a: uniform(a_lo, a_hi),
                b: uniform(bx.min, bx.max),
                c: uniform(c_lo, c_hi),
            };
            Ok((x, bounds.from_rect(&x)))
        })
        .collect()
}

/// Scaled parameters of one physical impact of the table's box, each parameter drawn
/// by `draw` from its [min, max] (two equal spheres, as in the paper's tables).
fn physical_sample(
    table: &Table,
    draw: &mut dyn FnMut([f64; 2]) -> f64,
) -> Result<ScaledParams, String> {
    let (law, pair, impact) = physical_impact(table, draw)?;
    Ok(scale(&law, &pair, &impact)
        .map_err(|e| e.to_string())?
        .params)
}

/// One physical impact of the table's box: law, pair and impact, each parameter drawn
/// by `draw` from its [min, max] (two equal spheres, as in the paper's tables).
pub fn physical_impact(
    table: &Table,
    draw: &mut dyn FnMut([f64; 2]) -> f64,
) -> Result<(PairLaw, PairProperties, Impact), String> {
    let info = table.info();
    let mut get = |name: &str| -> Result<f64, String> {
        let k = info
            .box_names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| format!("the table's box lacks the parameter {name}"))?;
        Ok(draw(info.box_ranges[k]))
    };
    let err = |e: emdstar_contact::ContactError| e.to_string();
    let law = match table.model() {
        emdstar_contact::Model::Linear => {
            ForceLaw::Linear(LinearDashpot::new(get("stiffness")?, get("damping")?).map_err(err)?)
        }
        emdstar_contact::Model::Hertz => ForceLaw::Hertz(
            ViscoelasticHertz::new(get("young")?, get("poisson")?, get("dissipation")?)
                .map_err(err)?,
        ),
    };
    let sphere = Sphere::from_density(get("radius")?, get("density")?).map_err(err)?;
    let impact =
        Impact::from_speed_eccentricity(get("speed")?, get("eccentricity")?).map_err(err)?;
    let pair = PairProperties::spheres(&sphere, &sphere);
    let law = PairLaw::same_material(&law, pair.r_eff).map_err(err)?;
    Ok((law, pair, impact))
}

/// Compares the table with exact solves at `n` random points.
pub fn check(
    table: &Table,
    solve: &Solver,
    n: usize,
    seed: u64,
    region: Region,
) -> Result<CheckReport, String> {
    let all = sample_points(table, n, seed, region)?;
    let answered: Vec<Option<[f64; 4]>> = all
        .par_iter()
        .map(|(x, p)| {
            let got = match table.lookup_scaled(p) {
                Ok(m) => m,
                Err(TableError::NotTabulated(_)) => return Ok(None),
                Err(TableError::OutOfBox { .. }) if region == Region::Physical => {
                    return Ok(None);
                }
                Err(e) => return Err(format!("lookup at {x:?}: {e}")),
            };
            let exact =
                solve(table.model(), p).map_err(|e| format!("exact solve at {x:?}: {e}"))?;
            Ok(Some(relative_errors(&got, &exact)))
        })
        .collect::<Result<_, String>>()?;
    let outside = answered.iter().filter(|e| e.is_none()).count();
    let (points, errors): (Vec<RectCoords>, Vec<[f64; 4]>) = all
        .iter()
        .zip(&answered)
        .filter_map(|((x, _), e)| e.map(|e| (*x, e)))
        .unzip();
    if errors.is_empty() {
        return Err(format!("none of the {n} samples lies in the table"));
    }
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
    let [ax, bx, cx] = table.rect();
    for (x, e) in points.iter().zip(&errors) {
        let worst = e.iter().fold(0.0f64, |m, v| m.max(*v));
        for (k, (v, r)) in [(x.a, ax), (x.b, bx), (x.c, cx)].into_iter().enumerate() {
            let (lo, hi) = match (k, region) {
                (0, Region::Central) => (r.min - 6.0, r.min),
                (2, Region::Elastic) => (r.min - 10.0, r.min),
                _ => (r.min, r.max),
            };
            let bin = (((v - lo) / (hi - lo) * BINS as f64).max(0.0) as usize).min(BINS - 1);
            by_axis[k][bin] = by_axis[k][bin].max(worst);
        }
    }
    Ok(CheckReport {
        samples: n,
        outside,
        components,
        by_axis,
    })
}
