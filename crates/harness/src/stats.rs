//! Small statistics helpers: quantiles, least-squares fits and Poisson intervals.

/// The q-quantile (0 ≤ q ≤ 1) of the finite values, by linear interpolation between
/// order statistics; NaN when there are none.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let pos = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let (i, f) = (pos.floor() as usize, pos.fract());
    if i + 1 < v.len() {
        v[i] + f * (v[i + 1] - v[i])
    } else {
        v[i]
    }
}

/// Least-squares line y = a + b·x through the points: (a, b). NaN with fewer than two
/// distinct x.
pub fn linear_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for &(x, y) in points {
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (y - my);
    }
    let b = sxy / sxx;
    (my - b * mx, b)
}

/// Root-mean-square residual of the line (a, b) through the points.
pub fn fit_rms(points: &[(f64, f64)], (a, b): (f64, f64)) -> f64 {
    let s: f64 = points.iter().map(|&(x, y)| (y - a - b * x).powi(2)).sum();
    (s / points.len() as f64).sqrt()
}

/// The mean of independent values and the standard error of that mean (NaN for a single
/// value: there is no scatter to measure).
pub fn mean_and_standard_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// The central 68.3 % (±1σ) confidence interval of a Poisson mean after observing
/// `count` events: Garwood's exact interval in the Wilson–Hilferty cube-root form,
/// good to about 1 % even at a count of 1 (Breslow & Day 1987, Vol. II, Eq. 2.12).
pub fn poisson_interval(count: u64) -> (f64, f64) {
    let z = 1.0;
    let cube =
        |k: f64, sign: f64| k * (1.0 - 1.0 / (9.0 * k) + sign * z / (3.0 * k.sqrt())).powi(3);
    let k = count as f64;
    let lower = if count == 0 { 0.0 } else { cube(k, -1.0) };
    (lower, cube(k + 1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_of_a_ramp() {
        let v: Vec<f64> = (0..=100).map(f64::from).collect();
        assert_eq!(quantile(&v, 0.5), 50.0);
        assert_eq!(quantile(&v, 0.99), 99.0);
        assert!(quantile(&[], 0.5).is_nan());
    }

    #[test]
    fn standard_error_of_a_known_sample() {
        // 1, 2, 3, 4: mean 2.5, sample variance 5/3, standard error √(5/12).
        let (m, se) = mean_and_standard_error(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m, 2.5);
        assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(mean_and_standard_error(&[7.0]).1.is_nan());
    }

    #[test]
    fn fit_recovers_a_line() {
        let p: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 - 2.0 * i as f64)).collect();
        let (a, b) = linear_fit(&p);
        assert!((a - 3.0).abs() < 1e-12 && (b + 2.0).abs() < 1e-12);
        assert!(fit_rms(&p, (a, b)) < 1e-12);
    }

    #[test]
    fn poisson_interval_matches_garwoods_exact_bounds() {
        // Exact central 68.27 % bounds, found by bisection on the Poisson distribution
        // function (P(X ≤ k; upper) = P(X ≥ k; lower) = 0.158655) in a separate script.
        let exact = [
            (0, 0.0, 1.84102),
            (1, 0.17275, 3.29953),
            (2, 0.70819, 4.63786),
            (5, 2.84031, 8.38247),
            (10, 6.89131, 14.26695),
            (40, 33.70200, 47.37726),
            (400, 380.00835, 421.01668),
        ];
        for (k, lo, hi) in exact {
            let (l, h) = poisson_interval(k);
            assert!(
                (l - lo).abs() <= 0.012 * lo.max(0.1),
                "k = {k}: lower {l} vs {lo}"
            );
            assert!((h - hi).abs() <= 0.012 * hi, "k = {k}: upper {h} vs {hi}");
        }
    }
}
