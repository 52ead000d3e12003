//! Exact restarts: MD saved in mid-run and restored into a fresh engine continues
//! bitwise as the uninterrupted run, however the run is cut into strides; the same
//! state saves to the same bytes.

use emdstar_dem::{ContactEnd, Md, MdOptions, shortest_contact_time};
use emdstar_system::{Config, System};

/// A damped Hertz gas in contact (η = 0.3) under gravity between a floor and a lid,
/// periodic sideways: rebuilds, wall contacts and many pair contacts within the run.
fn gas() -> System {
    Config::from_toml(
        r#"
t_end = 0.2
gravity = [0.0, 0.0, -9.81]
[material]
model = "hertz"
young = 1e8
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 200
radius = 0.1
arrangement = "random"
rms_speed = 1.0
seed = 4
[box]
size = [1.5, 1.5, 1.5]
periodic = [true, true, false]
[[walls]]
normal = [0.0, 0.0, 1.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, 0.0, -1.0]
point = [0.0, 0.0, 1.5]
"#,
    )
    .unwrap()
    .build()
    .unwrap()
}

fn md(system: &System) -> Md {
    let dt = 0.02 * shortest_contact_time(system, 0.2).unwrap().unwrap();
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: None,
    };
    Md::new(system.clone(), opts, 0.2).unwrap()
}

#[test]
fn a_restored_run_continues_bitwise_and_strides_do_not_matter() {
    let system = gas();
    let steps = 3000;
    let mut straight = md(&system);
    straight.stride(steps).unwrap();

    // The same run in uneven strides, read in between.
    let mut pieces = md(&system);
    for n in [1, 7, 500, 13, 979] {
        pieces.stride(n).unwrap();
        let _ = (pieces.thermo(), pieces.particles_in_config_order());
    }
    let stop = pieces.steps();
    let saved = pieces.save_state();
    assert_eq!(saved, pieces.save_state());

    let mut resumed = md(&system);
    resumed.restore_state(&saved).unwrap();
    assert_eq!(
        resumed.save_state(),
        saved,
        "the same state, the same bytes"
    );
    resumed.stride(steps - stop).unwrap();
    pieces.stride(steps - stop).unwrap();

    let reference = straight.particles_in_config_order();
    assert_eq!(resumed.particles_in_config_order(), reference);
    assert_eq!(pieces.particles_in_config_order(), reference);
    assert_eq!(resumed.save_state(), straight.save_state());
    let th = straight.thermo();
    assert!(
        straight.rebuilds() > 3 && th.contacts > 10,
        "{} {th:?}",
        straight.rebuilds()
    );

    // Synchronising (what `advance` does at its end) changes only the rounding of
    // what follows, never the state in between.
    let mut synced = md(&system);
    synced.advance(steps).unwrap();
    let (a, b) = (synced.particles_in_config_order(), reference);
    let dv = a
        .velocity
        .iter()
        .zip(&b.velocity)
        .flat_map(|(u, w)| (0..3).map(move |k| (u[k] - w[k]).abs()))
        .fold(0.0, f64::max);
    assert!(dv < 1e-9, "{dv}");
}

#[test]
fn a_state_of_another_step_or_size_is_refused() {
    let system = gas();
    let saved = md(&system).save_state();
    let mut coarser = Md::new(
        system.clone(),
        MdOptions {
            dt: 2.0 * md(&system).options().dt,
            contact_end: ContactEnd::ForceZero,
            skin: None,
        },
        0.2,
    )
    .unwrap();
    let err = coarser.restore_state(&saved).unwrap_err();
    assert!(err.contains("--dt"), "{err}");
    assert!(coarser.restore_state(&saved[..10]).is_err());
}
