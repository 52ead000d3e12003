//! `emdstar run --engine hybrid`.

use super::{emdstar_error, emdstar_json};

fn run_hybrid(dir_name: &str, extra: &[&str]) -> serde_json::Value {
    let dir = std::env::temp_dir().join(format!("emdstar-{dir_name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (traj, log) = (dir.join("g.xyz"), dir.join("g.log"));
    let mut args = vec![
        "run",
        "tests/md/configs/gas_small.toml",
        "--engine",
        "hybrid",
        "--mor",
        "table-or-exact",
        "--quiet",
        "--trajectory",
        traj.to_str().unwrap(),
        "--log",
        log.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let v = emdstar_json(&args);
    std::fs::remove_dir_all(&dir).ok();
    v
}

fn run_md() -> serde_json::Value {
    emdstar_json(&[
        "run",
        "tests/md/configs/gas_small.toml",
        "--quiet",
        "--trajectory",
        std::env::temp_dir()
            .join("emdstar-hybrid-md.xyz")
            .to_str()
            .unwrap(),
        "--log",
        std::env::temp_dir()
            .join("emdstar-hybrid-md.log")
            .to_str()
            .unwrap(),
    ])
}

#[test]
fn hybrid_run_on_a_dense_gas_is_md() {
    // The gas (η = 0.2) is dense for thresholds below its local volume fractions: every
    // particle is time-driven from the first decision on.
    let hybrid = run_hybrid(
        "hybrid-dense",
        &["--phi-time", "0.1", "--phi-event", "0.05"],
    );
    let md = run_md();
    assert_eq!(hybrid["engine"], "hybrid");
    let modes = hybrid["mode_counts"].as_array().unwrap();
    assert!(modes.len() > 10);
    assert!(modes.iter().all(|m| m["time_driven"] == 500));
    let (eh, em) = (
        hybrid["energy_drift"].as_f64().unwrap(),
        md["energy_drift"].as_f64().unwrap(),
    );
    assert!((eh - em).abs() < 1e-9, "{eh} {em}");
}

#[test]
fn hybrid_run_with_both_modes_dissipates_like_md_and_conserves_momentum() {
    let v = run_hybrid(
        "hybrid-mixed",
        // Thresholds about the gas's η = 0.2: particles start in both modes and switch.
        &["--phi-time", "0.22", "--phi-event", "0.18"],
    );
    let modes = v["mode_counts"].as_array().unwrap();
    assert!(modes.iter().all(|m| {
        m["event_driven"].as_u64().unwrap() + m["time_driven"].as_u64().unwrap() == 500
    }));
    assert!(
        modes
            .iter()
            .any(|m| m["event_driven"].as_u64().unwrap() > 50)
    );
    let s = &v["stats"];
    assert!(s["collisions"].as_u64().unwrap() > 0);
    assert!(s["switches"]["to_time_driven"].as_u64().unwrap() > 0);
    assert_eq!(s["switches"]["guard_late"], 0);
    assert!(v["momentum_drift_relative"].as_f64().unwrap() < 1e-12);
    // eMD* collisions dissipate as the force law does: the energy lost agrees with
    // MD's on the same gas to 1 % of it.
    let drift = v["energy_drift"].as_f64().unwrap();
    let md = run_md()["energy_drift"].as_f64().unwrap();
    assert!(md < -0.01, "the gas must dissipate for this test: {md}");
    assert!((drift - md).abs() < 0.01 * md.abs(), "{drift} {md}");
}

#[test]
fn hybrid_bad_options_get_clear_errors() {
    let path = "tests/md/configs/gas_small.toml";
    let err = emdstar_error(&[
        "run",
        path,
        "--engine",
        "hybrid",
        "--phi-time",
        "0.1",
        "--phi-event",
        "0.2",
    ]);
    assert!(err.contains("phi_event"), "{err}");
    let err = emdstar_error(&[
        "run",
        path,
        "--engine",
        "hybrid",
        "--contact-end",
        "overlap",
    ]);
    assert!(err.contains("contact_end"), "{err}");
}

#[test]
fn hybrid_pair_conserves_momentum_and_the_elastic_energy() {
    let config = "tests/md/configs/oblique_linear.toml";
    let v = crate::emdstar_json(&["pair", config, "--engine", "hybrid", "--json"]);
    assert_eq!(v["engine"], "hybrid");
    let p = v["particles"].as_array().unwrap();
    let vel = |i: usize, k: usize| p[i]["velocity"][k].as_f64().unwrap();
    // Equal masses, initial velocities (1.25, ±2.5, 0): total (2.5, 0, 0), |v|² 15.625.
    for (k, total) in [2.5, 0.0, 0.0].into_iter().enumerate() {
        assert!((vel(0, k) + vel(1, k) - total).abs() < 1e-12, "{v}");
    }
    let e: f64 = (0..2)
        .flat_map(|i| (0..3).map(move |k| (i, k)))
        .map(|(i, k)| vel(i, k) * vel(i, k))
        .sum();
    assert!((e - 15.625).abs() < 1e-6 * 15.625, "{e}");
}

#[test]
fn hybrid_events_are_emdstar_unless_emd_is_chosen() {
    // Every particle event-driven (φ thresholds far above the gas's 0.2): eMD*'s three
    // events by default, eMD's instantaneous collisions with --events emd.
    let all_ed = ["--phi-time", "0.9", "--phi-event", "0.8"];
    let star = run_hybrid("hybrid-emdstar", &all_ed);
    let emd = run_hybrid("hybrid-emd", &[&all_ed[..], &["--events", "emd"]].concat());
    for v in [&star, &emd] {
        assert!(v["stats"]["cell_crossings"].as_u64().unwrap() > 0, "{v}");
        assert!(v["stats"]["collisions"].as_u64().unwrap() > 10, "{v}");
        assert_eq!(v["stats"]["neighbour_rebuilds"], 0, "{v}");
        assert_eq!(v["stats"]["frictional_solves"], 0, "{v}");
    }
    assert_eq!(star["stats"]["events_by"], "emdstar");
    assert_eq!(emd["stats"]["events_by"], "emd");
    assert!(
        star["stats"]["velocity_events"].as_u64().unwrap() > 0,
        "{star}"
    );
    assert_eq!(emd["stats"]["velocity_events"], 0, "{emd}");
    let (a, b) = (
        star["energy_drift"].as_f64().unwrap(),
        emd["energy_drift"].as_f64().unwrap(),
    );
    // The same law: the gas cools alike (eMD's central restitution is eMD*'s too).
    assert!(a < -0.01 && (a - b).abs() < 0.1 * a.abs(), "{a} {b}");
}
