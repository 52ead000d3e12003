//! The exact frictional contact of eMD* against MD at fine steps, Walton's rule beside.

use emdstar_harness::friction_pairs::{FrictionPairSettings, StateError, run};

fn worst(e: &StateError) -> f64 {
    e.position.max(e.velocity).max(e.spin)
}

#[test]
fn the_exact_frictional_contact_is_mds_limit_and_waltons_rule_misses_it() {
    let settings = FrictionPairSettings {
        impacts: 8,
        ..FrictionPairSettings::quick()
    };
    let out = run(&settings).unwrap();
    for i in &out.impacts {
        let (fine, trunc, walton) = (worst(&i.md_fine), worst(&i.md_truncation), worst(&i.walton));
        eprintln!(
            "hertz {} µ {:.2} e {:.2}: MD(dt/2) − exact {fine:.1e}, MD(dt) − MD(dt/2) \
             {trunc:.1e}, Walton − exact {walton:.1e}",
            i.hertz, i.friction, i.eccentricity
        );
        // MD converges to the exact contact: at the finer step it is no further from it
        // than its own step changes it (first order: about as far).
        assert!(fine <= 1.5 * trunc + 1e-9, "{i:?}");
        // The engine's three events carry the exact contact through: MD's limit too.
        let engine = worst(&i.emdstar);
        assert!(
            engine < 1e-7,
            "eMD* engine against its exact contact: {engine:e}"
        );
        // The instantaneous rule misses by far more than MD's truncation.
        assert!(walton > 100.0 * fine && walton > 1e-3, "{i:?}");
    }
    let (median_fine, _) = out.summary(|i| worst(&i.md_fine));
    assert!(median_fine < 1e-4, "median {median_fine:e}");
}
