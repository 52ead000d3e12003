//! Where the stretches of the fast frictional contact solver end, at loose tolerances,
//! against the reference solver at 1e-12: a stick–slip switch there and back between two
//! stages of a long step (a short slide within a sticking stretch) must be found however
//! long the steps are, and the tail must not take over where the sliding force crosses
//! its direction by chance.

#[allow(dead_code)]
#[path = "../benches/shared/gas_impacts.rs"]
mod gas_impacts;

use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{HistorySpring, solve_contact};
use gas_impacts::{errors, impacts, law};

/// Impacts `from..to` of the gas solved at rtol = atol = `tol` are each within `bar` of
/// the reference.
fn within(from: usize, to: usize, tol: f64, bar: f64) {
    let points: Vec<_> = impacts(to, 7).into_iter().skip(from).collect();
    let law = law();
    let spring = HistorySpring::new(0.3, 1e5, 0.0).unwrap();
    let loose = SolverOptions {
        rtol: tol,
        atol: tol,
        ..SolverOptions::default()
    };
    let ends: Vec<_> = points
        .iter()
        .map(|i| solve_contact(&law, &spring, &i.bodies, i.r, i.v, &loose).unwrap())
        .collect();
    for (k, e) in errors(&law, &spring, &points, &ends).iter().enumerate() {
        assert!(*e < bar, "impact {}: {e:e}", from + k);
    }
}

#[test]
fn short_slides_between_stages_are_found_at_a_loose_tolerance() {
    // Impact 777 of these slides for about 6e-4 of its contact time inside one sticking
    // step at 1e-8 with no stage in the slide; missed, its outcome is 6e-5 off.
    within(740, 800, 1e-8, 1e-7);
}

#[test]
fn the_tail_does_not_take_over_on_a_chance_crossing() {
    // Near the end of impact 4792 (α ≈ 0.4: the lagged direction is no attractor) the
    // sliding force passes within 3e-6 of the tail's direction at one check at 3e-9; taken
    // over there, the outcome is 1.2e-7 off.
    within(4788, 4800, 3e-9, 3e-8);
}
