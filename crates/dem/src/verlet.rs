//! The kicks and drifts of velocity Verlet (see the crate docs).

/// max(a, b) that lets a NaN through (so that a blow-up is noticed).
#[inline(always)]
pub(crate) fn max_nan(a: f64, b: f64) -> f64 {
    if b > a || b.is_nan() { b } else { a }
}

/// v += a·`kick` for the particles `ids` (a: their contact accelerations); returns
/// their largest |v|² (NaN passes).
pub fn kick_contacts(velocity: &mut [[f64; 3]], acc: &[[f64; 3]], ids: &[u32], kick: f64) -> f64 {
    let mut v2_max: f64 = 0.0;
    for &i in ids {
        let (i, a) = (i as usize, acc[i as usize]);
        let v = velocity[i];
        let w = [v[0] + a[0] * kick, v[1] + a[1] * kick, v[2] + a[2] * kick];
        velocity[i] = w;
        v2_max = max_nan(v2_max, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    v2_max
}

/// The gravity kick and the drift of one particle: w = v + `gk` (w = v if `gravity` is
/// false), y = x + w·dt. Returns (y, w).
#[inline(always)]
pub fn kick_drift(
    x: [f64; 3],
    v: [f64; 3],
    gk: [f64; 3],
    dt: f64,
    gravity: bool,
) -> ([f64; 3], [f64; 3]) {
    let w = if gravity {
        [v[0] + gk[0], v[1] + gk[1], v[2] + gk[2]]
    } else {
        v
    };
    ([x[0] + w[0] * dt, x[1] + w[1] * dt, x[2] + w[2] * dt], w)
}
