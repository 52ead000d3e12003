//! End-to-end tests of `emdstar pair|run|bench --engine md` and of the example configs.

use super::{emdstar, emdstar_json};
use emdstar_contact::{PairProperties, Sphere, Vec3};
use emdstar_mor::rule::{Body, exact_collision};
use emdstar_system::Config;
use std::path::{Path, PathBuf};

fn configs() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/md/configs")
}

fn config(name: &str) -> String {
    configs().join(name).display().to_string()
}

/// The exact state at t_end of the two particles of a config: free flight to first
/// touch, the eMD* rule with the exact MoR, free flight to t_end.
fn exact_pair(path: &str) -> (Vec<(Vec3, Vec3)>, f64, f64) {
    let config = Config::from_file(Path::new(path)).unwrap();
    let system = config.build().unwrap();
    let p = &system.particles;
    let (x1, x2) = (Vec3::from(p.position[0]), Vec3::from(p.position[1]));
    let (v1, v2) = (Vec3::from(p.velocity[0]), Vec3::from(p.velocity[1]));
    let (s1, s2) = (
        Sphere::new(p.radius[0], p.mass[0]).unwrap(),
        Sphere::new(p.radius[1], p.mass[1]).unwrap(),
    );
    let pair = PairProperties::spheres(&s1, &s2);
    let law = *system.interactions().pair(p.species[0], p.species[1]).law();
    // |r + v t| = l: the first root of a quadratic.
    let (r, v) = (x1 - x2, v1 - v2);
    let (a, b, c) = (v.dot(&v), 2.0 * r.dot(&v), r.dot(&r) - pair.l * pair.l);
    let t0 = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    let touch = [
        Body {
            position: x1 + v1 * t0,
            velocity: v1,
            mass: s1.mass,
        },
        Body {
            position: x2 + v2 * t0,
            velocity: v2,
            mass: s2.mass,
        },
    ];
    let (outcome, _) = exact_collision(&law, &pair, &touch).unwrap();
    let rest = config.t_end - t0 - outcome.duration;
    assert!(rest > 0.0, "the collision must be over at t_end");
    let exact = outcome
        .after
        .iter()
        .map(|b| (b.position + b.velocity * rest, b.velocity))
        .collect();
    (exact, pair.l, v.norm())
}

#[test]
fn pair_default_dt_is_within_1e_4_of_the_exact_collision() {
    for name in [
        "oblique_linear.toml",
        "oblique_linear_damped.toml",
        "central_linear_damped.toml",
        "oblique_hertz_damped.toml",
        "central_hertz_elastic.toml",
    ] {
        let path = config(name);
        let out = emdstar_json(&["pair", &path, "--engine", "md", "--json"]);
        assert_eq!(out["engine"], "md");
        let (exact, l, v_rel) = exact_pair(&path);
        let mut err: f64 = 0.0;
        for (k, (x, v)) in exact.iter().enumerate() {
            let get = |key: &str| {
                let a = out["particles"][k][key].as_array().unwrap();
                Vec3::new(
                    a[0].as_f64().unwrap(),
                    a[1].as_f64().unwrap(),
                    a[2].as_f64().unwrap(),
                )
            };
            err = err
                .max((get("position") - x).norm() / l)
                .max((get("velocity") - v).norm() / v_rel);
        }
        println!("{name}: normalised error {err:.2e} at the default dt");
        assert!(err < 1e-4, "{name}: error {err:e}");
        let t = out["t"].as_f64().unwrap();
        assert!((t - Config::from_file(Path::new(&path)).unwrap().t_end).abs() < 1e-12);
    }
}

#[test]
fn bad_configs_are_refused_with_their_reason() {
    let mut dir: Vec<_> = std::fs::read_dir(configs().join("bad"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    dir.sort();
    assert!(dir.len() >= 20);
    for path in dir {
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# expect: "))
            .expect("first line '# expect: ...'");
        let out = emdstar(&["pair", path.to_str().unwrap(), "--engine", "md", "--json"]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{}: accepted", path.display());
        assert!(
            !stderr.contains("panicked"),
            "{}: panicked: {stderr}",
            path.display()
        );
        assert!(
            stderr.contains(expect),
            "{}: expected '{expect}' in: {stderr}",
            path.display()
        );
    }
}

#[test]
fn unknown_engines_and_bad_steps_are_refused_clearly() {
    let out = emdstar(&["pair", &config("oblique_linear.toml"), "--engine", "lammps"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown engine"));
    for bad in ["--dt=nan", "--dt=-1e-5", "--dt=0"] {
        let out = emdstar(&["pair", &config("oblique_linear.toml"), bad]);
        assert!(String::from_utf8_lossy(&out.stderr).contains("must be a finite number"));
    }
}

#[test]
fn run_writes_trajectory_log_and_summary() {
    let dir = std::env::temp_dir().join(format!("emdstar_md_run_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (traj, log) = (dir.join("gas.xyz"), dir.join("gas.log"));
    let summary = emdstar_json(&[
        "run",
        &config("gas_small.toml"),
        "--engine",
        "md",
        "--quiet",
        "--threads",
        "2",
        "--trajectory",
        traj.to_str().unwrap(),
        "--log",
        log.to_str().unwrap(),
    ]);
    assert_eq!(summary["particles"], 500);
    assert!(summary["particle_steps_per_s"].as_f64().unwrap() > 0.0);
    // Damped gas: energy only decreases; momentum stays zero to round-off.
    let drift = summary["energy_drift"].as_f64().unwrap();
    assert!(drift < 0.0 && drift > -0.5, "{drift}");
    assert!(summary["momentum_drift_relative"].as_f64().unwrap() < 1e-13);
    let xyz = std::fs::read_to_string(&traj).unwrap();
    let frames: Vec<&str> = xyz.lines().filter(|l| l.starts_with("Lattice=")).collect();
    assert_eq!(frames.len(), 5, "t = 0, 0.005, ..., 0.02");
    assert!(
        frames[0].contains("pbc=\"T T T\"") && frames[0].contains("velo:R:3:radius:R:1:omega:R:3")
    );
    assert_eq!(xyz.lines().count(), 5 * 502);
    let log_text = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = log_text.lines().skip(1).collect();
    // Every 0.001 s (rounded to whole steps) and at t_end.
    assert!((21..=22).contains(&lines.len()), "{} lines", lines.len());
    // … energies, temperature, momentum, contacts, rotational energy and temperature,
    // then pressure, its tensor, collision rate and a2.
    assert_eq!(lines[0].split_whitespace().count(), 21);
    let t_last: f64 = lines
        .last()
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((t_last - 0.02).abs() < 1e-12);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_ball_bounces_on_the_floor_and_stays_in_the_box() {
    let out = emdstar_json(&[
        "pair",
        &config("falling_on_floor.toml"),
        "--engine",
        "md",
        "--json",
    ]);
    let z = out["particles"][0]["position"][2].as_f64().unwrap();
    let x = out["particles"][0]["position"][0].as_f64().unwrap();
    // Dropped from 0.4 m above contact: first impact after 0.286 s, so at 0.5 s it is
    // on its way up or down again, above the floor and below the drop height.
    assert!(z > 0.1 && z < 0.5, "{z}");
    // A frictionless floor leaves the x motion uniform.
    assert!((x - 0.2 * 0.5).abs() < 1e-12, "{x}");
}

#[test]
fn a_frictional_pair_runs_on_md_emdstar_and_the_hybrid_and_emd_without_walton_refuses_it() {
    let path = config("oblique_frictional.toml");
    let out = emdstar(&["pair", &path, "--engine", "md", "--json", "--dt", "1e-4"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let spins: Vec<f64> = (0..2)
        .flat_map(|i| {
            json["particles"][i]["angular_velocity"]
                .as_array()
                .unwrap()
                .iter()
                .map(|w| w.as_f64().unwrap())
                .collect::<Vec<_>>()
        })
        .collect();
    // Friction spun the second sphere up from rest and changed the first one's spin.
    assert!(
        spins[5].abs() > 1.0 && (spins[2] - 20.0).abs() > 1.0,
        "{spins:?}"
    );
    // eMD* solves the same contact exactly: MD's spins at dt = 1e-4 (about 1/200 of the
    // contact) differ from it by MD's first-order truncation, well below 1 %.
    let out = emdstar(&["pair", &path, "--engine", "emdstar", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let star: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for i in 0..2 {
        for k in 0..3 {
            let a = star["particles"][i]["angular_velocity"][k]
                .as_f64()
                .unwrap();
            let b = spins[3 * i + k];
            assert!(
                (a - b).abs() < 0.01 * 20.0,
                "spin {i} {k}: eMD* {a}, MD {b}"
            );
        }
    }
    // The hybrid's pair collides event-driven (it is never dense: φ thresholds 1), by
    // the eMD* engine's exact contact.
    let hybrid = ["pair", &path, "--engine", "hybrid", "--json"];
    let out = emdstar(&[&hybrid[..], &["--phi-time", "1", "--phi-event", "1"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for i in 0..2 {
        assert_eq!(
            json["particles"][i]["angular_velocity"], star["particles"][i]["angular_velocity"],
            "the hybrid's spins are eMD*'s"
        );
    }
    // Classic eMD needs Walton's β₀ (tangential_restitution), which this material lacks.
    let out = emdstar(&["pair", &path, "--engine", "emd"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "emd accepted friction without β₀");
    assert!(
        stderr.contains("friction") && stderr.contains("--engine md"),
        "{stderr}"
    );
    // A spin on a frictionless material is a warning, not an error.
    let frictionless =
        std::env::temp_dir().join(format!("emdstar_spin_{}.toml", std::process::id()));
    let text = std::fs::read_to_string(&path).unwrap();
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("friction") && !l.starts_with("tangential"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&frictionless, text).unwrap();
    let out = emdstar(&[
        "pair",
        frictionless.to_str().unwrap(),
        "--engine",
        "emd",
        "--json",
    ]);
    std::fs::remove_file(&frictionless).unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("warning: 1 particles spin"));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["particles"][0]["angular_velocity"][2], 20.0);
}
