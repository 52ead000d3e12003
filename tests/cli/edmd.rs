//! End-to-end tests of the event-driven commands (`emdstar check`, `emdstar bench edmd`).

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

fn final_state(v: &serde_json::Value) -> Vec<f64> {
    v["particles"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| {
            let x = p["position"].as_array().unwrap().clone();
            let u = p["velocity"].as_array().unwrap().clone();
            x.into_iter().chain(u).map(|c| c.as_f64().unwrap())
        })
        .collect()
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Müller & Pöschel 2013, Fig. 6: eMD* reproduces the force-based trajectory (MD's own
/// error is ≈1e-4 of l and |v| at its default step), classic eMD does not.
#[test]
fn edmd_pair_emdstar_follows_md_and_emd_does_not() {
    let config = "tests/md/configs/oblique_linear.toml";
    let md = final_state(&emdstar_json(&["pair", config, "--engine", "md", "--json"]));
    let exact = emdstar_json(&[
        "pair", config, "--engine", "emdstar", "--mor", "exact", "--json",
    ]);
    assert_eq!(exact["engine"], "emdstar");
    assert_eq!(exact["stats"]["velocity_events"], 2);
    let table = emdstar_json(&["pair", config, "--engine", "emdstar", "--json"]);
    let emd = emdstar_json(&["pair", config, "--engine", "emd", "--json"]);
    assert!(largest_difference(&final_state(&exact), &md) < 1e-4);
    assert!(largest_difference(&final_state(&table), &md) < 1e-3);
    assert!(largest_difference(&final_state(&emd), &md) > 0.1);
}

/// A damped ball bouncing off an inclined floor under gravity: eMD*'s wall E^φ must
/// not count the wall it hits as blocking the rotation (exception a), and the wall
/// carries the normal part of g during the contact. What eMD* leaves out is of second
/// order in g·τ (τ ≈ 4.9 ms, the linear contact's duration π·√(m/k) with damping):
/// |Δv| < (g·τ)²/2, |Δx| < (g·τ)²/2·t + g·τ². Classic eMD misses by about v_n·τ.
#[test]
fn edmd_pair_emdstar_bounces_off_an_inclined_wall_like_md() {
    let config = "tests/md/configs/incline_damped.toml";
    let md = final_state(&emdstar_json(&["pair", config, "--engine", "md", "--json"]));
    let star = emdstar_json(&[
        "pair", config, "--engine", "emdstar", "--mor", "exact", "--json",
    ]);
    assert_eq!(star["stats"]["wall_collisions"], 1, "{star}");
    assert_eq!(star["stats"]["velocity_events"], 1, "{star}");
    assert_eq!(
        star["stats"]["exceptions"]["rotation_impossible"], 0,
        "{star}"
    );
    let g_tau = 9.81 * 4.9e-3;
    let state = final_state(&star);
    let (x, v) = state.split_at(3);
    let (x_md, v_md) = md.split_at(3);
    let dv = largest_difference(v, v_md);
    let dx = largest_difference(x, x_md);
    assert!(dv < g_tau * g_tau / 2.0, "|dv| = {dv:e}");
    assert!(
        dx < g_tau * g_tau / 2.0 * 0.45 + g_tau * 4.9e-3,
        "|dx| = {dx:e}"
    );
    let emd = final_state(&emdstar_json(&[
        "pair", config, "--engine", "emd", "--json",
    ]));
    assert!(largest_difference(&emd, &md) > 1e-2);
}

#[test]
fn edmd_run_reports_events_exceptions_and_drift() {
    let dir = std::env::temp_dir().join(format!("emdstar-edmd-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (traj, log) = (dir.join("g.xyz"), dir.join("g.log"));
    let v = emdstar_json(&[
        "run",
        "tests/md/configs/gas_small.toml",
        "--engine",
        "emdstar",
        "--mor",
        "table-or-exact",
        "--quiet",
        "--trajectory",
        traj.to_str().unwrap(),
        "--log",
        log.to_str().unwrap(),
    ]);
    assert_eq!(v["engine"], "emdstar");
    assert!(v["stats"]["collisions"].as_u64().unwrap() > 10);
    assert!(v["stats"]["exceptions"]["interference"].is_u64());
    assert!(v["momentum_drift_relative"].as_f64().unwrap() < 1e-12);
    // Dissipative gas: energy only decreases.
    assert!(v["energy_final"].as_f64().unwrap() < v["energy_initial"].as_f64().unwrap());
    let frames = std::fs::read_to_string(&traj).unwrap();
    assert!(frames.lines().count() > 500);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn edmd_bad_configs_get_clear_errors() {
    for (file, expect) in [
        ("overlapping_pair", "overlap"),
        ("wall_cuts_particle", "wall"),
        ("impossible_packing", "impossible"),
    ] {
        let path = format!("tests/md/configs/bad/{file}.toml");
        let err = emdstar_error(&["pair", &path, "--engine", "emdstar"]);
        assert!(err.contains(expect), "{file}: {err}");
    }
    let err = emdstar_error(&[
        "pair",
        "tests/md/configs/oblique_linear.toml",
        "--engine",
        "emdx",
    ]);
    assert!(err.contains("emdstar"), "{err}");
}

#[test]
fn edmd_broad_phases_give_the_same_gas_and_refuse_what_they_cannot_do() {
    let config = "tests/md/configs/gas_small.toml";
    let run = |broad_phase: &str| {
        let v = emdstar_json(&[
            "pair",
            config,
            "--engine",
            "emdstar",
            "--mor",
            "table-or-exact",
            "--broad-phase",
            broad_phase,
            "--json",
        ]);
        (final_state(&v), v["stats"].clone())
    };
    let (crossings, sc) = run("crossings");
    let (epochs, se) = run("epochs");
    assert!(sc["collisions"].as_u64().unwrap() > 50, "{sc}");
    assert_eq!(sc["collisions"], se["collisions"]);
    assert!(
        se["epochs"].as_u64().unwrap() > 0 && sc["epochs"] == 0,
        "{se} {sc}"
    );
    let diff = largest_difference(&crossings, &epochs);
    assert!(diff < 1e-9, "final states differ by {diff:e}");
    let err = emdstar_error(&[
        "pair",
        "tests/md/configs/falling_on_floor.toml",
        "--engine",
        "emdstar",
        "--broad-phase",
        "epochs",
    ]);
    assert!(
        err.contains("gravity") && err.contains("Crossings"),
        "{err}"
    );
}

#[test]
fn bench_soak_conserves_momentum_and_counts_what_it_did() {
    let v = emdstar_json(&[
        "bench",
        "soak",
        "--soak-cells",
        "3",
        "--soak-collisions",
        "3000",
        "--json",
    ]);
    for case in ["hard_spheres", "emdstar_hertz"] {
        let c = &v[case];
        assert_eq!(c["particles"], 108, "{c}");
        assert!(c["collisions"].as_u64().unwrap() >= 3000, "{c}");
        // Every collision conserves momentum: the drift stays at round-off of the
        // thermal momentum, and both gases lose energy.
        assert!(
            c["momentum_drift_over_initial_scale"].as_f64().unwrap() < 1e-12,
            "{c}"
        );
        let k = c["kinetic_energy_ratio"].as_f64().unwrap();
        assert!(k > 0.0 && k < 1.0, "{c}");
        assert!(c["memory_kib"]["process_peak_vmhwm"].as_u64().unwrap_or(1) > 0);
    }
    let hs = &v["hard_spheres"];
    assert!(
        hs["max_impact_overlap_over_contact"].as_f64().unwrap() < 1e-12,
        "{hs}"
    );
    assert_eq!(hs["exceptions_rotation"], 0);
    assert_eq!(hs["fallbacks_exact_mor"], 0);
}

/// Two spinning spheres meeting obliquely, with Walton's rule for the event engines.
const WALTON_PAIR: &str = r#"
t_end = 0.4
[material]
model = "linear"
stiffness = 2000.0
damping = 1.0
density = 1140.0
friction = 0.3
tangential_restitution = 0.4
[[particles]]
radius = 0.1
position = [0.03, -0.5, 0.0]
velocity = [1.25, 2.5, 0.0]
angular_velocity = [0.0, 0.0, 20.0]
[[particles]]
radius = 0.1
position = [-0.03, 0.5, 0.0]
velocity = [1.25, -2.5, 0.0]
"#;

#[test]
fn emd_runs_walton_friction_and_md_emdstar_and_the_hybrid_refuse_its_material() {
    let path = std::env::temp_dir().join(format!("emdstar_walton_{}.toml", std::process::id()));
    std::fs::write(&path, WALTON_PAIR).unwrap();
    let p = path.to_str().unwrap();
    let v = emdstar_json(&["pair", p, "--engine", "emd", "--json"]);
    let spin = |i: usize, k: usize| v["particles"][i]["angular_velocity"][k].as_f64().unwrap();
    // The second sphere spun up from rest about z; the first one's spin changed.
    assert!(
        spin(1, 2).abs() > 1.0 && (spin(0, 2) - 20.0).abs() > 1.0,
        "{v}"
    );
    let md = emdstar_error(&["pair", p, "--engine", "md"]);
    let star = emdstar_error(&["pair", p, "--engine", "emdstar"]);
    let hybrid = emdstar_error(&["pair", p, "--engine", "hybrid"]);
    std::fs::remove_file(&path).unwrap();
    assert!(
        md.contains("tangential_restitution") && md.contains("tangential_stiffness"),
        "{md}"
    );
    // The hybrid is named as the hybrid, not as MD.
    assert!(
        hybrid.contains("hybrid's time-driven part") && hybrid.contains("tangential_stiffness"),
        "{hybrid}"
    );
    assert!(
        star.contains("eMD*") && star.contains("--engine emd"),
        "{star}"
    );
}

#[test]
fn bench_edmd_times_the_asked_collisions_and_keeps_every_round() {
    // 4·4³ = 256 spheres, 2 collisions per particle: 256 pair collisions timed per round;
    // stdout is the JSON alone (the progress bar draws only on a terminal).
    let v = emdstar_json(&[
        "bench",
        "edmd",
        "--hard-spheres-only",
        "--hs-cells",
        "4",
        "--per-particle",
        "2",
        "--rounds",
        "2",
        "--json",
    ]);
    let hs = &v["hard_spheres"];
    assert_eq!(hs["particles"], 256, "{v}");
    assert_eq!(hs["collisions"], 256, "{v}");
    let rounds = hs["rounds"].as_array().expect("rounds");
    assert_eq!(rounds.len(), 2, "{v}");
    let best = hs["collisions_per_second"].as_f64().unwrap();
    assert!(rounds.iter().all(|r| r.as_f64().unwrap() <= best), "{v}");
    assert!(best > 0.0 && best.is_finite(), "{v}");
}

#[test]
fn bench_edmd_refuses_zero_rounds_and_impossible_gases() {
    let err = emdstar_error(&["bench", "edmd", "--rounds", "0"]);
    assert!(err.contains("--rounds"), "{err}");
    // 4·cells³ would overflow: refused before anything is built.
    for cells in ["0", "100000000000"] {
        let err = emdstar_error(&["bench", "edmd", "--hs-cells", cells]);
        assert!(err.contains("--hs-cells must be 1 to"), "{err}");
    }
}

#[test]
fn bench_edmd_friction_sets_md_against_emdstar_with_and_without_friction() {
    // A hundredth of each gas's simulated time: a few collisions at η = 0.1.
    let v = emdstar_json(&[
        "bench",
        "edmd",
        "--friction",
        "--time-scale",
        "0.01",
        "--json",
    ]);
    let rows = v["friction"].as_array().expect("rows");
    assert_eq!(rows.len(), 3, "{v}");
    for row in rows {
        for key in ["ratio", "ratio_friction"] {
            let r = row[key].as_f64().unwrap_or(f64::NAN);
            assert!(r > 0.0 && r.is_finite(), "{key}: {v}");
        }
    }
    // At η = 0.1 the frictional eMD* solves every collision exactly.
    let dense = &rows[2]["emdstar_friction"];
    let solves = dense["frictional_solves"].as_u64().unwrap();
    assert!(
        solves > 0 && Some(solves) == dense["collisions"].as_u64(),
        "{v}"
    );
    let err = emdstar_error(&["bench", "edmd", "--friction", "--time-scale", "2"]);
    assert!(err.contains("--time-scale"), "{err}");
}
