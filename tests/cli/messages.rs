//! What `emdstar run` says about a bad value: the key that is wrong, once, with the
//! line the config sets it on, numbers in scientific notation; the same refusal on
//! every engine, before anything is written. And the warnings for keys the chosen
//! engine does not use.

use crate::{emdstar_in, error_in};
use std::path::PathBuf;

const ENGINES: [&str; 4] = ["md", "emd", "emdstar", "hybrid"];

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-messages-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two Hertz spheres 1 cm in radius meeting head on at ±1 m/s, with `material` keys
/// and `extra` top-level keys and sections.
fn pair(material: &str, first: &str, extra: &str) -> String {
    format!(
        "t_end = 0.1\n{extra}[material]\nmodel = \"hertz\"\npoisson = 0.3\n{material}\n\
         [[particles]]\n{first}\nposition = [0.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\n\
         [[particles]]\nradius = 0.01\nposition = [0.03, 0.0, 0.0]\nvelocity = [-1.0, 0.0, 0.0]\n"
    )
}

const GLASS: &str = "young = 1e9\ndensity = 2500.0";
const SPHERE: &str = "radius = 0.01";

/// The line (from 1) of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no line starts with {start:?}"))
}

/// Every bad value of the list, and those the up-front checks added: each is
/// refused by every engine with the key named once, on its line, and no number of
/// more than 17 digits in a row.
#[test]
fn each_bad_value_names_its_key_once_with_its_line_on_every_engine() {
    let gas = |material: &str| {
        format!(
            "t_end = 0.1\n[material]\nmodel = \"hertz\"\npoisson = 0.3\n{material}\n[gas]\n\
             count = 8\nradius = 0.01\narrangement = \"lattice\"\npacking_fraction = 0.01\n\
             rms_speed = 1.0\nseed = 1\n"
        )
    };
    let sheared = |top: &str, box_keys: &str| {
        format!(
            "t_end = 0.1\n{top}[material]\nmodel = \"hertz\"\npoisson = 0.3\nyoung = 1e9\n\
             density = 2500.0\n[gas]\ncount = 8\nradius = 0.01\narrangement = \"lattice\"\n\
             rms_speed = 1.0\nseed = 1\n[box]\nsize = [0.2, 0.2, 0.2]\n{box_keys}"
        )
    };
    let frictional = "t_end = 0.1\n[material]\nmodel = \"linear\"\nstiffness = 1e4\n\
                      damping = 0.1\ndensity = 1000.0\nfriction = 0.5\n\
                      tangential_stiffness = 1e4\ntangential_damping = 1e308\n[gas]\ncount = 8\n\
                      radius = 0.01\narrangement = \"lattice\"\npacking_fraction = 0.01\n\
                      rms_speed = 1.0\nseed = 1\n";
    // (config, key, the start of the line that sets it, words of the message)
    let cases: Vec<(String, &str, &str, &str)> = vec![
        (
            gas("young = 1e9\ndensity = 1e308"),
            "material.density",
            "density = 1e308",
            "out of range",
        ),
        (
            pair(GLASS, "radius = 1e308", ""),
            "particles[0].radius",
            "radius = 1e308",
            "out of range",
        ),
        (
            pair("young = 1e308\ndensity = 2500.0", SPHERE, ""),
            "material.young",
            "young = 1e308",
            "not a finite number",
        ),
        (
            frictional.to_string(),
            "material.tangential_damping",
            "tangential_damping",
            "out of range",
        ),
        (
            pair(GLASS, "radius = 0.01\nmass = 1e200", ""),
            "particles[0].mass",
            "mass = 1e200",
            "out of range",
        ),
        (
            pair("young = -1.0\ndensity = 2500.0", SPHERE, ""),
            "material.young",
            "young = -1.0",
            "greater than zero",
        ),
        (
            pair(GLASS, SPHERE, "").replace(
                "velocity = [-1.0, 0.0, 0.0]",
                "velocity = [-1.0, 0.0, 0.0, 4.0]",
            ),
            "particles[1].velocity",
            "velocity = [-1.0, 0.0, 0.0, 4.0]",
            "expected 3 numbers, got 4",
        ),
        (
            pair(GLASS, SPHERE, "gravity = [0.0, 1e308, 0.0]\n"),
            "gravity",
            "gravity",
            "too large",
        ),
        (
            pair("young = 1e3\ndensity = 1000.0", SPHERE, ""),
            "material.young",
            "young = 1e3",
            "centres pass through each other",
        ),
        (
            pair(GLASS, SPHERE, "") + "[md]\ndt = nan\n",
            "md.dt",
            "dt = nan",
            "greater than zero",
        ),
        (
            pair(GLASS, SPHERE, "") + "[md]\ndt = 0.0\n",
            "md.dt",
            "dt = 0.0",
            "greater than zero",
        ),
        (
            pair(GLASS, SPHERE, "") + "[md]\nskin = -1.0\n",
            "md.skin",
            "skin = -1.0",
            "≥ 0",
        ),
        (
            sheared("", "shear_rate = nan\n"),
            "box.shear_rate",
            "shear_rate = nan",
            "finite",
        ),
        (
            sheared(
                "",
                "shear_rate = 2.0\n[driving]\nkind = \"andersen\"\ntemperature = 1e-3\nrate = 10.0\n",
            ),
            "driving.kind",
            "kind = \"andersen\"",
            "shear flow",
        ),
        (
            sheared("", "periodic = [true, false, true]\nshear_rate = 2.0\n"),
            "box.shear_rate",
            "shear_rate = 2.0",
            "periodic along x",
        ),
        (
            sheared("gravity = [0.0, -9.81, 0.0]\n", "shear_rate = 2.0\n"),
            "box.shear_rate",
            "shear_rate = 2.0",
            "along z only",
        ),
        (
            pair(GLASS, SPHERE, "") + "[events]\ntc = -1e-5\n",
            "events.tc",
            "tc = -1e-5",
            "greater than zero",
        ),
    ];
    assert_refused_naming_the_key("keys", &cases);
}

/// Runs each case (config text, key, start of the key's line, words of the message) on
/// every engine: refused, naming the key once with its line, numbers in at most 17
/// digits, and nothing written.
fn assert_refused_naming_the_key(name: &str, cases: &[(String, &str, &str, &str)]) {
    let dir = scratch(name);
    for (k, (text, key, line_start, words)) in cases.iter().enumerate() {
        let name = format!("case{k}.toml");
        std::fs::write(dir.join(&name), text).unwrap();
        let line = line_of(text, line_start);
        for engine in ENGINES {
            let err = error_in(&dir, &["run", &name, "--engine", engine, "--quiet"]);
            let what = format!("{engine}, {key}: {err}");
            let names_line = [format!("line {line}:"), format!("(line {line})")]
                .iter()
                .any(|mark| err.contains(mark));
            assert!(names_line, "{what}");
            assert!(err.contains(words), "{what}");
            assert_eq!(err.matches(key).count(), 1, "{what}");
            let longest_digits = err
                .split(|c: char| !c.is_ascii_digit())
                .map(str::len)
                .max()
                .unwrap_or(0);
            assert!(longest_digits <= 17, "{what}");
        }
    }
    // Refused before anything was written.
    let written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.ends_with(".toml"))
        .collect();
    assert!(written.is_empty(), "{written:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `emdstar run CONFIG --quiet --trajectory none` with `args` in `dir`, expects
/// success and returns its warnings.
fn warnings(dir: &std::path::Path, config: &str, args: &[&str]) -> Vec<String> {
    let mut all = vec!["run", config, "--quiet", "--trajectory", "none"];
    all.extend_from_slice(args);
    let out = emdstar_in(dir, &all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{all:?}: {stderr}");
    stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .map(str::to_string)
        .collect()
}

/// A key the chosen engine does not use is a one-line warning naming it, its line and
/// the engine; the engines that use it say nothing.
#[test]
fn keys_an_engine_does_not_use_are_warned_about_on_that_engine_only() {
    let dir = scratch("unused");
    let text = pair(GLASS, SPHERE, "") + "[md]\ndt = 1e-5\n[events]\ntc = 1e-4\n";
    std::fs::write(dir.join("both.toml"), &text).unwrap();
    let (dt, tc) = (line_of(&text, "dt = "), line_of(&text, "tc = "));
    for engine in ENGINES {
        let warnings = warnings(&dir, "both.toml", &["--engine", engine, "--log", "none"]);
        let (unused, line) = match engine {
            "md" | "hybrid" => ("[events] tc", tc),
            _ => ("[md] dt", dt),
        };
        assert_eq!(warnings.len(), 1, "{engine}: {warnings:?}");
        assert!(
            warnings[0].contains(&format!(
                "line {line}: {unused} is not used by --engine {engine}"
            )),
            "{engine}: {warnings:?}"
        );
    }
}

/// An `[output]` interval whose output the run does not write is a warning with its
/// line; with the output written, nothing is said.
#[test]
fn an_interval_of_an_output_not_written_is_warned_about() {
    let dir = scratch("intervals");
    let text = pair(GLASS, SPHERE, "") + "[output]\nlog_interval = 0.01\n";
    std::fs::write(dir.join("out.toml"), &text).unwrap();
    let line = line_of(&text, "log_interval");
    let warnings = |log: &str| warnings(&dir, "out.toml", &["--log", log]);
    let none = warnings("none");
    assert_eq!(none.len(), 1, "{none:?}");
    assert!(
        none[0].contains(&format!("line {line}: [output] log_interval has no effect")),
        "{none:?}"
    );
    assert!(warnings("out.log").is_empty());
}

/// Two soft spheres that would pass through each other (Y = 1 kPa at ±1 m/s; the
/// issue's case ran through on MD with +2.7 % energy) are refused up front. The
/// message's speed and factor agree with Hertz's law: at that speed a Young's modulus
/// that factor higher compresses the pair exactly to the centres' meeting, and a
/// config with it is accepted.
#[test]
fn soft_spheres_that_would_pass_through_each_other_are_refused_with_the_factor_that_suffices() {
    let dir = scratch("soft");
    let soft = pair("young = 1e3\ndensity = 1000.0", SPHERE, "");
    std::fs::write(dir.join("soft.toml"), &soft).unwrap();
    let err = error_in(&dir, &["run", "soft.toml", "--engine", "md", "--quiet"]);
    let number_after = |words: &str| -> f64 {
        err.split(words)
            .nth(1)
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|f| f.parse().ok())
            .unwrap_or_else(|| panic!("no number after {words:?} in {err}"))
    };
    let (factor, v) = (
        number_after("by a factor of at least "),
        number_after("meeting at "),
    );
    // The rms relative speed of ±1 m/s: √2 m/s.
    assert!((v - 2f64.sqrt()).abs() < 1e-3, "{err}");
    // Hertz: ξ_max = (5 m_eff v² / (4 ρ_el))^{2/5} with ρ_el = (4/3) E* √R_eff,
    // E* = Y / (2(1 − ν²)), m_eff = m/2, R_eff = R/2.
    let (r, nu) = (0.01f64, 0.3);
    let m = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * 1000.0;
    let rho_el = |y: f64| 4.0 / 3.0 * y / (2.0 * (1.0 - nu * nu)) * (r / 2.0).sqrt();
    let compression = |y: f64| (5.0 * (m / 2.0) * v * v / (4.0 * rho_el(y))).powf(0.4);
    assert!(compression(1e3) > 2.0 * r);
    assert!(
        (compression(1e3 * factor) - 2.0 * r).abs() < 1e-3 * r,
        "{factor}"
    );
    let stiffer = soft.replace("young = 1e3", &format!("young = {:e}", 1.01 * 1e3 * factor));
    std::fs::write(dir.join("stiffer.toml"), &stiffer).unwrap();
    let out = emdstar_in(
        &dir,
        &[
            "run",
            "stiffer.toml",
            "--engine",
            "md",
            "--quiet",
            "--t-end",
            "1e-6",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A ball over a floor and under a lid (closed z, periodic x and y), the floor's keys
/// `floor`.
fn vibrated(floor: &str, periodic: &str) -> String {
    format!(
        "t_end = 0.01\ngravity = [0.0, 0.0, -9.81]\n[material]\nmodel = \"hertz\"\n\
         poisson = 0.3\n{GLASS}\n[box]\nsize = [0.1, 0.1, 0.1]\nperiodic = {periodic}\n\
         [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, 0.01]\n{floor}\n\
         [[walls]]\nnormal = [0.0, 0.0, -1.0]\npoint = [0.0, 0.0, 0.1]\n\
         [[particles]]\n{SPHERE}\nposition = [0.05, 0.05, 0.05]\n"
    )
}

/// Bad keys of a vibrated wall are refused by every engine with the key and its line.
#[test]
fn bad_vibrated_walls_are_refused_with_the_key_and_its_line() {
    let closed = "[true, true, false]";
    // (config, key, the start of the line that sets it, words of the message)
    let cases = [
        (
            vibrated("amplitude = -1e-3\nfrequency = 20.0", closed),
            "walls[0].amplitude",
            "amplitude",
            "greater than zero",
        ),
        (
            vibrated("amplitude = 1e-3\nfrequency = inf", closed),
            "walls[0].frequency",
            "frequency",
            "greater than zero",
        ),
        (
            vibrated("amplitude = 1e-3\nfrequency = 20.0\nphase = nan", closed),
            "walls[0].phase",
            "phase",
            "finite",
        ),
        (
            vibrated("amplitude = 1e-3", closed),
            "walls[0].amplitude",
            "amplitude",
            "needs both",
        ),
        (
            vibrated("phase = 1.0", closed),
            "walls[0].phase",
            "phase",
            "belongs to a vibrated wall",
        ),
        (
            vibrated("amplitude = 1e-3\nfrequency = 20.0", "[true, true, true]"),
            "walls[0].amplitude",
            "amplitude",
            "periodic z axis",
        ),
        (
            vibrated("amplitude = 0.02\nfrequency = 20.0", closed),
            "walls[0].amplitude",
            "amplitude",
            "out of the box along z",
        ),
    ];
    assert_refused_naming_the_key("vibrated", &cases);
}

/// eMD* takes a vibrated wall's velocity as constant over a contact: where a contact
/// lasts more than 5 % of the wall's cycle (ω t_c; Hertz, Y = 1 GPa, R = 1 cm at the
/// wall's speed A ω: t_c ≈ 0.6 ms against 8 ms at 20 Hz), a warning with the key and
/// its line; not at 5 Hz (ω t_c ≈ 0.02), nor on MD, which resolves the contact.
#[test]
fn emdstar_warns_when_a_vibrated_wall_moves_much_during_a_contact() {
    let dir = scratch("vibrated-contact");
    let fast = vibrated("amplitude = 1e-3\nfrequency = 20.0", "[true, true, false]");
    let slow = vibrated("amplitude = 1e-3\nfrequency = 5.0", "[true, true, false]");
    std::fs::write(dir.join("fast.toml"), &fast).unwrap();
    std::fs::write(dir.join("slow.toml"), &slow).unwrap();
    let args = |engine| ["--engine", engine, "--log", "none"];
    let warned = warnings(&dir, "fast.toml", &args("emdstar"));
    let line = line_of(&fast, "frequency");
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].contains(&format!("line {line}: walls[0].frequency: eMD* takes")),
        "{warned:?}"
    );
    assert_eq!(warnings(&dir, "fast.toml", &args("hybrid")), warned);
    assert!(warnings(&dir, "slow.toml", &args("emdstar")).is_empty());
    assert!(warnings(&dir, "fast.toml", &args("md")).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}
