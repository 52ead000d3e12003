//! Shared helpers: random points of the paper's rectangles and relative errors.

use emdstar_contact::{Model, ParameterBox, RectBounds, RectCoords, ScaledParams};
use emdstar_mor::{Mor, SolverOptions};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn bounds(model: Model) -> RectBounds {
    ParameterBox::paper(model).bounds().expect("paper box")
}

/// The 8 corners of the model's rectangle as scaled parameters.
pub fn corners(model: Model) -> Vec<ScaledParams> {
    let b = bounds(model);
    let [a, bb, c] = b.axes();
    let mut out = Vec::new();
    for mask in 0..8 {
        let pick = |r: emdstar_contact::Range, bit: u32| {
            if mask & (1 << bit) == 0 { r.min } else { r.max }
        };
        out.push(b.from_rect(&RectCoords {
            a: pick(a, 0),
            b: pick(bb, 1),
            c: pick(c, 2),
        }));
    }
    out
}

/// `n` points drawn uniformly in the model's rectangle (deterministic for a seed).
pub fn uniform_in_rect(model: Model, n: usize, seed: u64) -> Vec<ScaledParams> {
    let b = bounds(model);
    let [a, bb, c] = b.axes();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let x = RectCoords {
                a: rng.random_range(a.min..=a.max),
                b: rng.random_range(bb.min..=bb.max),
                c: rng.random_range(c.min..=c.max),
            };
            b.from_rect(&x)
        })
        .collect()
}

/// |a − b|/|b|, or |a − b| when b = 0.
pub fn rel(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        (a - b).abs()
    } else {
        ((a - b) / b).abs()
    }
}

pub fn params(l_tilde: f64, c_phi: f64, c_dis: f64) -> ScaledParams {
    ScaledParams {
        l_tilde,
        c_phi,
        c_dis,
    }
}

/// `n` impacts drawn log-uniformly in each physical range of the paper's box for `model`
/// (equal spheres, l = 2R), as scaled parameters.
pub fn log_uniform_physical(model: Model, n: usize, seed: u64) -> Vec<ScaledParams> {
    use emdstar_contact::{
        ForceLaw, Impact, LinearDashpot, PairLaw, PairProperties, Sphere, ViscoelasticHertz, scale,
    };
    let ranges = ParameterBox::paper(model).ranges();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let x: Vec<f64> = ranges
                .iter()
                .map(|(_, r)| rng.random_range(r.min.ln()..=r.max.ln()).exp())
                .collect();
            let (law, radius, density, speed, ecc) = match model {
                Model::Linear => (
                    ForceLaw::Linear(LinearDashpot::new(x[0], x[3]).unwrap()),
                    x[1],
                    x[2],
                    x[4],
                    x[5],
                ),
                Model::Hertz => (
                    ForceLaw::Hertz(ViscoelasticHertz::new(x[0], x[1], x[4]).unwrap()),
                    x[2],
                    x[3],
                    x[5],
                    x[6],
                ),
            };
            let sphere = Sphere::from_density(radius, density).unwrap();
            let pair = PairProperties::spheres(&sphere, &sphere);
            let pair_law = PairLaw::same_material(&law, pair.r_eff).unwrap();
            let impact = Impact::from_speed_eccentricity(speed, ecc).unwrap();
            scale(&pair_law, &pair, &impact).unwrap().params
        })
        .collect()
}

/// Much tighter options than the defaults, as a reference.
pub fn tight() -> SolverOptions {
    SolverOptions {
        rtol: 1e-14,
        atol: 1e-14,
        max_steps: 10_000_000,
    }
}

/// Relative differences of (1−ε_r, ε_ṙ, ε_φ, ε_t) of `m` from the reference `r`.
pub fn mor_errors(m: &Mor, r: &Mor) -> [f64; 4] {
    [
        rel(m.one_minus_eps_r, r.one_minus_eps_r),
        rel(m.eps_rdot, r.eps_rdot),
        rel(m.eps_phi, r.eps_phi),
        rel(m.eps_t, r.eps_t),
    ]
}

/// Central restitution ε of viscoelastic (Hertz) spheres against δ = c_dis, force-zero
/// end, to the six digits published (docs/physics.md, "Reference values").
pub const HERTZ_RESTITUTION: [(f64, f64); 5] = [
    (0.1, 0.892859),
    (0.3, 0.722085),
    (0.5, 0.595252),
    (1.0, 0.393931),
    (2.0, 0.211646),
];

/// The small-δ series of the same: ε = 1 − 1.1534489·δ + 0.7982666·δ² + ….
pub fn hertz_restitution_series(delta: f64) -> f64 {
    1.0 - 1.1534489 * delta + 0.7982666 * delta * delta
}

/// How far the two-term series may lie from the exact ε: its coefficients carry 7
/// decimals (1e-7·δ), the next term is of size δ^{5/2}, and 1e-11 for the solver.
pub fn hertz_series_tolerance(delta: f64) -> f64 {
    1e-7 * delta + delta.powf(2.5) + 1e-11
}
