//! Shared helpers: random points of the paper's rectangles and relative errors.

use emdstar_contact::{Model, ParameterBox, RectBounds, RectCoords, ScaledParams};
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
