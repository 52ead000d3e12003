//! A frictional gas cooling by MD and by eMD* with the exact frictional contact: the
//! translational and rotational temperatures agree (within the noise of two small
//! gases); Walton's eMD is run beside them.

use emdstar_harness::friction_cooling::{FrictionCoolingSettings, run};

#[test]
fn md_and_frictional_emdstar_cool_alike() {
    let s = FrictionCoolingSettings {
        gases: 2,
        samples: 9,
        t_end: 0.5,
        ..FrictionCoolingSettings::quick()
    };
    let out = run(&s, &|_| {}).unwrap();
    let md = &out.curves[0];
    // Friction turns translational energy into spin: the spins, at rest at first, hold
    // a good share of the energy.
    let k = out.picks[0];
    assert!(md.rotational[k] > 0.2 * md.temperature[k], "{md:?}");
    // Two gases of 512: the temperatures scatter by about 3 % between the engines.
    for (what, diffs) in [("T", &out.translational[0]), ("T_rot", &out.rotational[0])] {
        eprintln!("eMD* against MD, {what}: {diffs:?}");
        assert!(diffs.iter().all(|d| *d < 0.1), "{what}: {diffs:?}");
    }
    assert!(out.curves[1].frictional_solves == out.curves[1].collisions);
}
