//! Exact restarts of the hybrid with both modes present: saved at a step boundary
//! (eMD* transients, queued events, TD contacts in progress) and restored into a fresh
//! engine, it continues bitwise as the uninterrupted run.

use crate::common::{hybrid_with, step, system};
use emdstar_hybrid::{HybridOptions, Mode};

#[test]
fn a_restored_mixed_run_continues_bitwise() {
    let sys = system(
        r#"
t_end = 0.02
[material]
model = "hertz"
young = 1e9
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 300
radius = 0.1
arrangement = "random"
packing_fraction = 0.2
rms_speed = 1.0
seed = 9
"#,
    );
    let t_end = 0.02;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions {
        phi_time: 0.25,
        phi_event: 0.2,
        ..HybridOptions::with_dt(dt)
    };
    let mut straight = hybrid_with(&sys, opts, t_end);
    straight.advance(steps).unwrap();

    let mut first = hybrid_with(&sys, opts, t_end);
    first.advance(steps / 2).unwrap();
    assert!(
        first.count(Mode::Event) > 0 && first.count(Mode::Time) > 0,
        "both modes at the checkpoint"
    );
    let saved = first.save_state();
    assert_eq!(saved, first.save_state());
    let mut resumed = hybrid_with(&sys, opts, t_end);
    resumed.restore_state(&saved).unwrap();
    assert_eq!(
        resumed.save_state(),
        saved,
        "the same state, the same bytes"
    );
    resumed.advance(steps - steps / 2).unwrap();

    assert_eq!(resumed.particles(), straight.particles());
    assert_eq!(resumed.stats(), straight.stats());
    assert_eq!(resumed.modes(), straight.modes());
    let s = straight.stats();
    assert!(s.ed.pair_collisions > 0 && s.td_particle_steps > 0, "{s:?}");

    // Another config's state is refused.
    let other = HybridOptions {
        phi_time: 0.3,
        ..opts
    };
    let mut wrong = hybrid_with(&sys, other, t_end);
    let err = wrong.restore_state(&saved).unwrap_err().to_string();
    assert!(err.contains("hybrid options"), "{err}");
}

#[test]
fn a_restored_run_of_event_driven_particles_only_continues_bitwise() {
    // A dilute gas: every particle event-driven from the start, so the engine keeps no
    // neighbour list; its checkpoint must still restore.
    let sys = system(
        r#"
t_end = 0.05
[material]
model = "hertz"
young = 1e9
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 200
radius = 0.01
arrangement = "random"
packing_fraction = 0.01
rms_speed = 1.0
seed = 4
"#,
    );
    let t_end = 0.05;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions::with_dt(dt);
    let mut straight = hybrid_with(&sys, opts, t_end);
    straight.advance(steps).unwrap();

    let mut first = hybrid_with(&sys, opts, t_end);
    first.advance(steps / 2).unwrap();
    assert_eq!(first.count(Mode::Time), 0, "every particle event-driven");
    let saved = first.save_state();
    let mut resumed = hybrid_with(&sys, opts, t_end);
    resumed.restore_state(&saved).unwrap();
    assert_eq!(resumed.save_state(), saved);
    resumed.advance(steps - steps / 2).unwrap();
    assert_eq!(resumed.particles(), straight.particles());
    assert_eq!(resumed.stats(), straight.stats());
    assert!(straight.stats().ed.pair_collisions > 0);
}
