//! Every config of `examples/configs/` runs, with a short t_end, through the engines its
//! comments name, and the engines agree with each other where physics says they must.

use super::{error_in, stdout_in};
use emdstar_contact::{Impact, PairProperties, scale};
use emdstar_system::Config;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The configs these tests cover; a new example must be added here (and tested).
const EXAMPLES: [&str; 12] = [
    "cooling_hertz_gas.toml",
    "driven_bed.toml",
    "driven_dense_gas.toml",
    "driven_gas.toml",
    "frictional_gas_walls.toml",
    "glass_beads_steel_box.toml",
    "oblique_collision.toml",
    "polydisperse_mixture.toml",
    "restitution_input.toml",
    "sheared_gas.toml",
    "vibrated_bed.toml",
    "walls_gravity.toml",
];

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/configs")
        .join(name)
}

/// A copy of example `name` with `t_end = t_end`, in a fresh directory (where the runs
/// write their trajectory and log).
fn short_copy(name: &str, t_end: f64) -> (PathBuf, PathBuf) {
    let text = std::fs::read_to_string(example(name)).unwrap();
    let mut replaced = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with("t_end =") {
                replaced += 1;
                format!("t_end = {t_end}")
            } else {
                l.to_string()
            }
        })
        .collect();
    assert_eq!(replaced, 1, "{name} has one t_end line");
    let dir = std::env::temp_dir().join(format!(
        "emdstar-example-{}-{}",
        name.trim_end_matches(".toml"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    (dir, path)
}

/// `emdstar run` of a config in its directory: the summary JSON.
fn run(dir: &Path, config: &Path, engine: &str) -> Value {
    let path = config.display().to_string();
    let mut args = vec!["run", &path, "--engine", engine, "--quiet"];
    if engine != "md" {
        args.extend(["--mor", "table-or-exact"]);
    }
    let out = stdout_in(dir, &args);
    let summary: Value = serde_json::from_str(&out).expect("a summary JSON");
    assert_eq!(summary["engine"], engine);
    summary
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn every_example_config_is_covered() {
    let mut found: Vec<String> = std::fs::read_dir(example(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    found.sort();
    assert_eq!(found, EXAMPLES, "add a test for each example config");
    for name in EXAMPLES {
        let config = Config::from_file(&example(name)).unwrap();
        config.build().unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn the_sheared_gas_resists_the_shear_and_heats_up_in_emdstar_emd_and_md() {
    let (dir, config) = short_copy("sheared_gas.toml", 0.3);
    let emd = run(&dir, &config, "emd");
    let star = run(&dir, &config, "emdstar");
    // MD steps through the contacts (0.7 ms each, 1/50 of it a step): a shorter run (the same
    // directory and file, the config rewritten).
    let (_, config) = short_copy("sheared_gas.toml", 0.05);
    let md = run(&dir, &config, "md");
    for summary in [&emd, &star, &md] {
        let p = &summary["means"]["pressure_tensor_pa"];
        let (pxy, pxz, pyz) = (
            p[3].as_f64().unwrap(),
            p[4].as_f64().unwrap(),
            p[5].as_f64().unwrap(),
        );
        // The shear stress opposes the flow (P_xy < 0, a positive viscosity); the
        // other off-diagonal parts are noise.
        assert!(
            pxy < 0.0 && pxz.abs() < 0.25 * pxy.abs() && pyz.abs() < 0.25 * pxy.abs(),
            "{summary}"
        );
        // Shear heating outweighs the dissipation from the start's 3.5 mJ.
        assert!(
            num(summary, "granular_temperature_final") > 3.6e-3,
            "{summary}"
        );
    }
    // eMD* and eMD shear the same gas over the same 0.3 s: the same shear stress
    // within the noise of 2000 spheres (some 5 %).
    let pxy = |s: &Value| s["means"]["pressure_tensor_pa"][3].as_f64().unwrap();
    assert!(
        (pxy(&star) / pxy(&emd) - 1.0).abs() < 0.15,
        "eMD* {star}, eMD {emd}"
    );
    let path = config.display().to_string();
    let err = error_in(&dir, &["run", &path, "--engine", "hybrid"]);
    assert!(
        err.contains("line 31") && err.contains("box.shear_rate") && err.contains("emdstar"),
        "hybrid: {err}"
    );
    for engine in ["emd", "emdstar"] {
        let err = error_in(
            &dir,
            &["run", &path, "--engine", engine, "--broad-phase", "epochs"],
        );
        assert!(
            err.contains("box.shear_rate") && err.contains("crossings"),
            "{engine}: {err}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn cooling_gas_cools_alike_in_md_and_emdstar() {
    let (dir, config) = short_copy("cooling_hertz_gas.toml", 0.05);
    let md = run(&dir, &config, "md");
    let star = run(&dir, &config, "emdstar");
    assert!(num(&md, "energy_drift") < -0.05, "the gas cools: {md}");
    let (t_md, t_star) = (
        num(&md, "granular_temperature_final"),
        num(&star, "granular_temperature_final"),
    );
    assert!(relative(t_star, t_md) < 0.02, "T: eMD* {t_star}, MD {t_md}");
    assert!(dir.join("cooling_hertz_gas.xyz").exists());
    assert!(dir.join("cooling_hertz_gas.log").exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn glass_beads_in_a_steel_box_cool_alike_in_md_emdstar_and_the_hybrid() {
    let (dir, config) = short_copy("glass_beads_steel_box.toml", 0.01);
    let md = run(&dir, &config, "md");
    let star = run(&dir, &config, "emdstar");
    let hybrid = run(&dir, &config, "hybrid");
    // Bead–bead and bead–wall collisions both cool the gas (by a fifth in 10 ms).
    assert!(num(&md, "energy_drift") < -0.1, "{md}");
    let t = |v: &Value| num(v, "granular_temperature_final");
    for other in [&star, &hybrid] {
        assert!(relative(t(other), t(&md)) < 0.01, "T: {other}\nMD {md}");
    }
    assert!(
        star["stats"]["wall_collisions"].as_u64().unwrap() > 50,
        "{star}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_frictional_gas_between_walls_is_the_same_run_in_emdstar_and_the_hybrid() {
    let (dir, config) = short_copy("frictional_gas_walls.toml", 0.1);
    let star = run(&dir, &config, "emdstar");
    let hybrid = run(&dir, &config, "hybrid");
    let md = run(&dir, &config, "md");
    // Every bead stays event-driven in the hybrid: its events are the eMD* engine's.
    assert_eq!(hybrid["stats"]["time_driven_particle_steps"], 0, "{hybrid}");
    for key in ["collisions", "wall_collisions", "frictional_solves"] {
        assert_eq!(star["stats"][key], hybrid["stats"][key], "{key}");
    }
    for key in ["interference", "rotation_impossible"] {
        let (a, b) = (&star["stats"]["exceptions"], &hybrid["stats"]["exceptions"]);
        assert_eq!(a[key], b[key], "{key}");
    }
    let solves = star["stats"]["frictional_solves"].as_u64().unwrap();
    let collisions = star["stats"]["collisions"].as_u64().unwrap();
    let walls = star["stats"]["wall_collisions"].as_u64().unwrap();
    assert!(collisions > 50 && walls > 50, "{star}");
    assert_eq!(
        solves,
        collisions + walls,
        "every collision is an exact solve"
    );
    let t = |v: &Value| num(v, "granular_temperature_final");
    assert_eq!(t(&star), t(&hybrid));
    // MD runs the same contacts by time steps: the same cooling, to the chaos of 0.1 s.
    assert!(relative(t(&md), t(&star)) < 0.02, "T: MD {md}\neMD* {star}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn gas_between_walls_falls_alike_in_md_and_hybrid() {
    let (dir, config) = short_copy("walls_gravity.toml", 0.05);
    let md = run(&dir, &config, "md");
    let hybrid = run(&dir, &config, "hybrid");
    // Gravity pulls momentum downwards: about −M·g·t over 0.05 s (walls push back).
    let pz = |v: &Value| v["momentum_drift"][2].as_f64().unwrap();
    assert!(pz(&md) < 0.0 && pz(&hybrid) < 0.0, "{md}\n{hybrid}");
    let (e_md, e_hybrid) = (num(&md, "energy_final"), num(&hybrid, "energy_final"));
    assert!(
        relative(e_hybrid, e_md) < 0.01,
        "E: hybrid {e_hybrid}, MD {e_md}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_bed_on_a_vibrated_floor_runs_alike_in_every_engine() {
    let (dir, config) = short_copy("vibrated_bed.toml", 0.15);
    let md = run(&dir, &config, "md");
    let star = run(&dir, &config, "emdstar");
    let emd = run(&dir, &config, "emd");
    let hybrid = run(&dir, &config, "hybrid");
    // The beads fall onto the floor and are thrown up: the same energy after 0.15 s,
    // to the chaos of the bed (measured: eMD* 3.8 %, eMD 2.3 %, the hybrid 4.4 % from
    // MD), and the same mean pressure over the run (measured: within 1.5 %).
    let e = |v: &Value| num(v, "energy_final");
    let p = |v: &Value| v["means"]["pressure_pa"].as_f64().unwrap();
    for other in [&star, &emd, &hybrid] {
        assert!(relative(e(other), e(&md)) < 0.08, "E: {other}\nMD {md}");
        assert!(relative(p(other), p(&md)) < 0.04, "p: {other}\nMD {md}");
        let walls = other["stats"]["wall_collisions"].as_u64().unwrap();
        assert!(walls > 100, "{other}");
    }
    // The hybrid ran both modes.
    let steps = hybrid["stats"]["time_driven_particle_steps"]
        .as_u64()
        .unwrap();
    let collisions = hybrid["stats"]["collisions"].as_u64().unwrap();
    assert!(steps > 0 && collisions > 0, "{hybrid}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// The final positions of a `pair` run, flattened.
fn final_positions(v: &Value) -> Vec<f64> {
    v["particles"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p["position"].as_array().unwrap().clone())
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn oblique_collision_emdstar_lands_where_md_does_and_emd_does_not() {
    let config = example("oblique_collision.toml").display().to_string();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pair = |engine: &str| -> Vec<f64> {
        let out = stdout_in(dir, &["pair", &config, "--engine", engine, "--json"]);
        final_positions(&serde_json::from_str(&out).unwrap())
    };
    let (md, star, emd) = (pair("md"), pair("emdstar"), pair("emd"));
    let off = |a: &[f64]| {
        a.iter()
            .zip(&md)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    // Units of l = 0.2 m. The paper's Fig. 6: eMD* follows MD, eMD does not.
    assert!(off(&star) / 0.2 < 1e-5, "eMD* {star:?} vs MD {md:?}");
    assert!(off(&emd) / 0.2 > 1e-2, "eMD {emd:?} vs MD {md:?}");
}

#[test]
fn restitution_input_gives_its_restitution_and_runs() {
    let config = Config::from_file(&example("restitution_input.toml")).unwrap();
    let system = config.build().unwrap();
    // The forward problem: a central impact of two gas spheres at 1 m/s.
    let s = system.species[0].sphere();
    let pair = PairProperties::spheres(&s, &s);
    let law = *system.interactions().pair(0, 0).law();
    let impact = Impact::from_speed_eccentricity(1.0, 0.0).unwrap();
    let scaled = scale(&law, &pair, &impact).unwrap();
    let mor = emdstar_mor::solve(law.model(), &scaled.params).unwrap();
    assert!((-mor.eps_rdot - 0.8).abs() < 1e-10, "{mor:?}");

    let (dir, path) = short_copy("restitution_input.toml", 0.5);
    let md = run(&dir, &path, "md");
    let star = run(&dir, &path, "emdstar");
    let (t_md, t_star) = (
        num(&md, "granular_temperature_final"),
        num(&star, "granular_temperature_final"),
    );
    assert!(num(&star, "energy_drift") < 0.0);
    assert!(relative(t_star, t_md) < 0.01, "T: eMD* {t_star}, MD {t_md}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn elastic_mixture_keeps_its_energy() {
    let (dir, config) = short_copy("polydisperse_mixture.toml", 2.0);
    let md = run(&dir, &config, "md");
    let star = run(&dir, &config, "emdstar");
    assert!(star["stats"]["collisions"].as_u64().unwrap() > 10, "{star}");
    assert!(num(&star, "energy_drift").abs() < 1e-12, "{star}");
    assert!(num(&md, "energy_drift").abs() < 1e-4, "{md}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn driven_gas_reaches_the_same_steady_state_in_md_and_emdstar() {
    let (dir, config) = short_copy("driven_gas.toml", 1.0);
    let md = run(&dir, &config, "md");
    let star = run(&dir, &config, "emdstar");
    // From T = m·(1 m/s)²/3 the gas heats to its steady state (about 2.4e-3 J by
    // Enskog's collision rate, 0.3 s to relax) and stays there.
    let t = |v: &Value| num(v, "granular_temperature_final");
    assert!(t(&md) > 1.6e-3 && t(&md) < 3.2e-3, "{md}");
    assert!(relative(t(&star), t(&md)) < 0.1, "T: eMD* {star}\nMD {md}");
    // The same kicks at the same times, so the same momentum: zero.
    for v in [&md, &star] {
        let p = v["momentum_drift"].as_array().unwrap();
        assert!(p.iter().all(|c| c.as_f64().unwrap().abs() < 1e-12), "{v}");
    }
    let mean = |v: &Value, key: &str| v["means"][key].as_f64().unwrap();
    for key in ["pressure_pa", "collision_rate_per_s"] {
        assert!(
            relative(mean(&star, key), mean(&md, key)) < 0.05,
            "{key}: eMD* {star}\nMD {md}"
        );
    }
    // The log ends with the observables' columns.
    let log = std::fs::read_to_string(dir.join("driven_gas.log")).unwrap();
    let header = log.lines().next().unwrap();
    assert!(
        header.ends_with("collision_rate[1/s] sonine_a2"),
        "{header}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The mean height of the particles at the end of a run, from the log's last potential
/// energy Σ m g z (gravity along −z) and the total mass.
fn final_mean_height(log: &Path, total_mass: f64, g: f64) -> f64 {
    let text = std::fs::read_to_string(log).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split_whitespace().collect();
    let column = header
        .iter()
        .position(|h| *h == "potential_energy[J]")
        .expect("a potential energy column")
        - 1; // the header starts with "#"
    let last = text.lines().last().unwrap();
    let pe: f64 = last
        .split_whitespace()
        .nth(column)
        .unwrap()
        .parse()
        .unwrap();
    pe / (total_mass * g)
}

#[test]
fn the_driven_bed_falls_and_stays_agitated_on_md_and_the_hybrid() {
    // 1000 glass beads (r = 5 mm) start spread over 0.4 m (mean height 0.196 m); free
    // fall from there takes about 0.2 s. White noise must not hold the centre of mass up:
    // a tick takes off only its own kicks' mean. A close-packed bed over 0.2 × 0.2 m
    // would have its mean height near 11 mm; the noise keeps it looser.
    let (dir, config) = short_copy("driven_bed.toml", 0.6);
    let mass = 1000.0 * 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.005f64.powi(3);
    let mut heights = Vec::new();
    for engine in ["md", "hybrid"] {
        let summary = run(&dir, &config, engine);
        let z = final_mean_height(&dir.join("driven_bed.log"), mass, 9.81);
        assert!(
            (0.011..0.03).contains(&z),
            "{engine}: mean height {z} m, {summary}"
        );
        assert!(
            num(&summary, "granular_temperature_final") > 0.0,
            "{summary}"
        );
        heights.push(z);
    }
    assert!(
        relative(heights[1], heights[0]) < 0.05,
        "mean heights md {} and hybrid {} m",
        heights[0],
        heights[1]
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn driven_dense_gas_runs_in_both_modes_of_the_hybrid_as_in_md() {
    let (dir, config) = short_copy("driven_dense_gas.toml", 0.8);
    let md = run(&dir, &config, "md");
    let hybrid = run(&dir, &config, "hybrid");
    // Clusters turn time-driven from about 0.3 s on; the rest stays event-driven.
    let last = hybrid["mode_counts"]
        .as_array()
        .unwrap()
        .last()
        .unwrap()
        .clone();
    let count = |key: &str| last[key].as_u64().unwrap();
    assert!(
        count("time_driven") >= 100 && count("event_driven") >= 100,
        "{last}"
    );
    assert!(
        hybrid["stats"]["collisions"].as_u64().unwrap() > 1000,
        "{hybrid}"
    );
    // The same kicks at the same steps: zero momentum, and MD's state within noise
    // (measured: 1.7 % in T, 1.6 % in p over 2 s).
    for v in [&md, &hybrid] {
        let p = v["momentum_drift"].as_array().unwrap();
        assert!(p.iter().all(|c| c.as_f64().unwrap().abs() < 1e-12), "{v}");
    }
    let t = |v: &Value| num(v, "granular_temperature_final");
    assert!(
        relative(t(&hybrid), t(&md)) < 0.1,
        "T: hybrid {hybrid}\nMD {md}"
    );
    let p = |v: &Value| v["means"]["pressure_pa"].as_f64().unwrap();
    assert!(
        relative(p(&hybrid), p(&md)) < 0.1,
        "p: hybrid {hybrid}\nMD {md}"
    );
    // On one thread the same run, byte for byte.
    let one = dir.join("one-thread");
    std::fs::create_dir_all(&one).unwrap();
    let copy = one.join("driven_dense_gas.toml");
    std::fs::copy(&config, &copy).unwrap();
    let path = copy.display().to_string();
    let args = [
        "run",
        &path,
        "--engine",
        "hybrid",
        "--mor",
        "table-or-exact",
        "--threads",
        "1",
        "--quiet",
    ];
    stdout_in(&one, &args);
    for ext in ["log", "xyz"] {
        let file = format!("driven_dense_gas.{ext}");
        assert!(
            std::fs::read(dir.join(&file)).unwrap() == std::fs::read(one.join(&file)).unwrap(),
            "{file} differs on one thread"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn driving_is_refused_where_it_cannot_run() {
    // Its own directory (the other test of this example removes short_copy's).
    let dir = std::env::temp_dir().join(format!("emdstar-driving-refused-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("driven_gas.toml");
    std::fs::copy(example("driven_gas.toml"), &config).unwrap();
    let path = config.display().to_string();
    let err = error_in(
        &dir,
        &[
            "run",
            &path,
            "--engine",
            "emd",
            "--broad-phase",
            "epochs",
            "--quiet",
        ],
    );
    assert!(
        err.contains("[driving]") && err.contains("crossings"),
        "{err}"
    );
    let text = std::fs::read_to_string(&config).unwrap();
    for (from, to, key) in [
        ("strength = 2.0", "strength = -1.0", "driving.strength"),
        ("rate = 200.0", "rate = inf", "driving.rate"),
        (
            "kind = \"white_noise\"",
            "kind = \"shaker\"",
            "driving.kind",
        ),
        ("strength = 2.0", "temperature = 1.0", "driving.temperature"),
    ] {
        std::fs::write(&config, text.replace(from, to)).unwrap();
        let err = error_in(&dir, &["run", &path, "--engine", "md", "--quiet"]);
        assert!(err.contains(key), "{to}: {err}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}
