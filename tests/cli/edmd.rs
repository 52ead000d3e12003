//! End-to-end tests of the event-driven commands (`emdstar check`).

use crate::{emdstar_error, emdstar_json};

#[test]
fn edmd_bouncing_ball_stable_never_fails() {
    let v = emdstar_json(&["check", "bouncing-ball", "--samples", "2000", "--json"]);
    assert_eq!(v["samples"], 2000);
    assert_eq!(v["failures"], 0);
    assert_eq!(v["mean_events"], 1000.0);
    assert!(v["max_overlap"].as_f64().unwrap() < 1e-14);
}

#[test]
fn edmd_bouncing_ball_naive_fails_often() {
    let v = emdstar_json(&[
        "check",
        "bouncing-ball",
        "--samples",
        "2000",
        "--naive",
        "--json",
    ]);
    let failures = v["failures"].as_u64().unwrap();
    assert!(failures > 200, "{v}");
}

#[test]
fn edmd_bouncing_ball_rejects_elastic_balls() {
    let err = emdstar_error(&[
        "check",
        "bouncing-ball",
        "--restitution",
        "1",
        "--samples",
        "5",
    ]);
    assert!(err.contains("--restitution"), "{err}");
}

#[test]
fn edmd_inelastic_overlaps_stay_at_round_off() {
    let v = emdstar_json(&[
        "check",
        "inelastic-overlaps",
        "--cells",
        "4",
        "--collisions",
        "20000",
        "--json",
    ]);
    assert_eq!(v["particles"], 256);
    assert!(v["max_impact_overlap"].as_f64().unwrap() < 1e-12, "{v}");
}
