//! The bound of the switch function between stage nodes and the search of a gap, on
//! functions whose minima and roots are known.

use super::*;

/// g at the switch nodes of a step of unit length (the start known, or not).
fn values_of(g: impl Fn(f64) -> f64, start_known: bool) -> [f64; 9] {
    let mut values = SWITCH_NODES.map(&g);
    if !start_known {
        values[0] = f64::NAN;
    }
    values
}

/// Switch node j with its value.
fn node(values: &[f64; 9], j: usize) -> (f64, f64) {
    (SWITCH_NODES[j], values[j])
}

#[test]
fn the_lowest_value_bounds_every_function_of_that_curvature() {
    // Cubics on [0, w]: their curvature is largest at an end, and none dips below the
    // bound; the parabola of that curvature reaches it.
    for (k, &(c0, c1, c2, c3, w)) in [
        (1.0, -3.0, 2.0, 0.5, 1.0),
        (0.2, 0.1, 4.0, -3.0, 0.5),
        (-0.1, 2.0, 1.0, 1.0, 2.0),
        (0.5, -0.5, -2.0, 4.0, 1.0),
        (3.0, 1.0, 0.0, 0.0, 1.0),
    ]
    .iter()
    .enumerate()
    {
        let g = |t: f64| c0 + t * (c1 + t * (c2 + t * c3));
        let curvature = (2.0 * c2).abs().max((2.0 * c2 + 6.0 * c3 * w).abs());
        let (low, at) = lowest(g(0.0), g(w), w, curvature);
        let least = (0..=10_000)
            .map(|i| g(w * i as f64 / 10_000.0))
            .fold(f64::INFINITY, f64::min);
        assert!(least >= low - 1e-12, "cubic {k}: {least} below {low}");
        assert!((0.0..=w).contains(&at), "cubic {k}: at {at}");
        let parabola = |t: f64| g(0.0) + (g(w) - g(0.0)) * t / w - 0.5 * curvature * t * (w - t);
        let lowest_parabola = (0..=10_000)
            .map(|i| parabola(w * i as f64 / 10_000.0))
            .fold(f64::INFINITY, f64::min);
        assert!(
            (lowest_parabola - low).abs() <= 1e-7,
            "cubic {k}: {lowest_parabola} vs {low}"
        );
    }
}

#[test]
fn a_dip_below_zero_between_two_stages_is_found_and_located() {
    // (s − 0.46)² − 10⁻³: positive at every node, below zero on 0.46 ± 0.0316, between
    // the nodes 1/3 and 0.6.
    let g = |s: f64| (s - 0.46) * (s - 0.46) - 1e-3;
    for start_known in [true, false] {
        let values = values_of(g, start_known);
        assert!(values[1..].iter().all(|&v| v > 0.0));
        let (k, first) = first_flagged(&values, usize::from(!start_known));
        let first = first.expect("the gap of the dip is flagged");
        assert!(
            SWITCH_NODES[first] <= 0.43 && SWITCH_NODES[first + 1] >= 0.46,
            "gap {first}"
        );
        let enough = 1e-12;
        let x = (first..8)
            .find_map(|j| first_dip(g, node(&values, j), node(&values, j + 1), k, enough));
        let x = x.expect("the dip is found");
        let exact = 0.46 - 1e-3f64.sqrt();
        // |g'| ≈ 0.063 at the root.
        assert!((x - exact).abs() <= 2.0 * enough / 0.063, "{x} vs {exact}");
    }
}

#[test]
fn a_function_that_stays_above_zero_has_no_crossing() {
    // Near zero but above it: the gap may be flagged, but its search finds nothing.
    let near = |s: f64| (s - 0.46) * (s - 0.46) + 1e-3;
    let values = values_of(near, true);
    let (k, first) = first_flagged(&values, 0);
    if let Some(first) = first {
        assert!((first..8).all(|j| {
            first_dip(near, node(&values, j), node(&values, j + 1), k, 1e-12).is_none()
        }));
    }
    // Far from zero: nothing is flagged.
    let far = |s: f64| (s - 0.46) * (s - 0.46) + 0.1;
    assert_eq!(first_flagged(&values_of(far, true), 0).1, None);
    // A crossing at a node is flagged at the gap before it.
    let values = values_of(|s: f64| 0.5 - s, true);
    let first = first_flagged(&values, 0)
        .1
        .expect("the crossing is flagged");
    assert!(values[first] > 0.0 && values[first + 1] <= 0.0);
}
