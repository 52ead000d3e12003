//! `emdstar mor --restitution` and `--restitution-curve` against the forward problem:
//! the computed γ or A, given back to `emdstar mor` as --damping or --dissipation, must
//! give the restitution asked for; the linear dashpot also against Schwager & Pöschel's
//! closed form.

use crate::{emdstar_error, emdstar_json};
use std::f64::consts::PI;

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

/// `emdstar mor` for two spheres R = 0.1 m, ρ = 1140 kg/m³, central, at `speed`.
fn central(material: &[&str], speed: &str) -> serde_json::Value {
    let mut args = vec!["mor"];
    args.extend(material);
    args.extend([
        "--radius",
        "0.1",
        "--density",
        "1140",
        "--speed",
        speed,
        "--eccentricity",
        "0",
        "--json",
    ]);
    emdstar_json(&args)
}

const HERTZ: [&str; 6] = ["--model", "hertz", "--young", "1e9", "--poisson", "0.4"];
const LINEAR: [&str; 4] = ["--model", "linear", "--stiffness", "2000"];

#[test]
fn hertz_restitution_gives_back_its_dissipation() {
    for (e, speed) in [("0.9", "0.3"), ("0.5", "2"), ("0.05", "10")] {
        let mut material = HERTZ.to_vec();
        material.extend(["--restitution", e]);
        let fitted = central(&material, speed);
        let target: f64 = e.parse().unwrap();
        assert!(
            (num(&fitted["mor"], "eps_rdot") + target).abs() < 1e-10,
            "{fitted}"
        );
        let a = num(&fitted, "dissipation");
        // The forward call with that A, as a user would make it.
        let text = format!("{a:e}");
        let mut forward = HERTZ.to_vec();
        forward.extend(["--dissipation", &text]);
        let v = central(&forward, speed);
        assert!(v.get("dissipation").is_none());
        assert!(
            (num(&v["mor"], "eps_rdot") + target).abs() < 1e-10,
            "ε = {e} at {speed} m/s: A = {a:e} gives {v}"
        );
    }
}

#[test]
fn linear_restitution_matches_schwager_poeschel() {
    let m_eff = 4.0 / 3.0 * PI * 0.1f64.powi(3) * 1140.0 / 2.0;
    for e in ["0.95", "0.3", "0.01"] {
        let mut material = LINEAR.to_vec();
        material.extend(["--restitution", e]);
        let gamma = num(&central(&material, "1"), "damping");
        // Schwager & Pöschel 2007, force-zero end, in closed form.
        let w0 = (2000.0 / m_eff).sqrt();
        let beta = gamma / (2.0 * m_eff);
        let tc = if beta < w0 {
            let w = (w0 * w0 - beta * beta).sqrt();
            (PI - (2.0 * beta * w).atan2(w * w - beta * beta)) / w
        } else {
            let big = (beta * beta - w0 * w0).sqrt();
            ((beta + big) / (beta - big)).ln() / big
        };
        let target: f64 = e.parse().unwrap();
        assert!(
            ((-beta * tc).exp() - target).abs() < 1e-10 * target.max(0.01),
            "ε = {e}: γ = {gamma}"
        );
        // Another speed, same γ: the linear dashpot's ε does not depend on it.
        assert_eq!(num(&central(&material, "3"), "damping"), gamma);
    }
}

#[test]
fn curve_passes_through_the_restitution_asked_for() {
    let mut args = vec!["mor"];
    args.extend(HERTZ);
    args.extend([
        "--restitution",
        "0.7",
        "--speed",
        "2",
        "--radius",
        "0.1",
        "--density",
        "1140",
        "--restitution-curve",
        "--curve-points",
        "9",
        "--json",
    ]);
    let v = emdstar_json(&args);
    let curve = v["curve"].as_array().expect("a curve");
    assert_eq!(curve.len(), 9);
    // Default range: speed/100 to 100·speed, so the middle point is the speed asked for.
    let mid = &curve[4];
    assert!((num(mid, "speed") - 2.0).abs() < 1e-12);
    assert!((num(mid, "eps_n") - 0.7).abs() < 1e-10, "{mid}");
    // Viscoelastic spheres: ε_n falls as the speed grows, and contacts get shorter.
    for w in curve.windows(2) {
        assert!(num(&w[1], "eps_n") < num(&w[0], "eps_n"), "{v}");
        assert!(num(&w[1], "duration") < num(&w[0], "duration"), "{v}");
    }
    // The linear dashpot keeps its ε at every speed.
    let mut args = vec!["mor"];
    args.extend(LINEAR);
    args.extend([
        "--damping",
        "3",
        "--radius",
        "0.1",
        "--density",
        "1140",
        "--restitution-curve",
        "--curve-speeds",
        "0.01",
        "1",
        "--json",
    ]);
    let v = emdstar_json(&args);
    let eps: Vec<f64> = v["curve"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| num(p, "eps_n"))
        .collect();
    assert!(eps.iter().all(|e| (e - eps[0]).abs() < 1e-10), "{eps:?}");
}

#[test]
fn bad_restitution_is_refused_with_a_reason() {
    let with = |extra: &[&'static str]| {
        let mut a = vec!["mor"];
        a.extend(HERTZ);
        a.extend(["--radius", "0.1", "--density", "1140"]);
        a.extend(extra);
        a
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            with(&["--restitution", "0", "--speed", "1", "--eccentricity", "0"]),
            "outside (0, 1]",
        ),
        (
            with(&[
                "--restitution",
                "1.01",
                "--speed",
                "1",
                "--eccentricity",
                "0",
            ]),
            "outside (0, 1]",
        ),
        (
            with(&[
                "--restitution",
                "1e-12",
                "--speed",
                "1",
                "--eccentricity",
                "0",
            ]),
            "cannot be reached",
        ),
        (
            with(&["--restitution", "0.8", "--eccentricity", "0"]),
            "needs --speed",
        ),
        (
            with(&[
                "--restitution",
                "0.8",
                "--dissipation",
                "1e-4",
                "--speed",
                "1",
                "--eccentricity",
                "0",
            ]),
            "either --dissipation or --restitution",
        ),
        (
            with(&[
                "--restitution",
                "0.8",
                "--speed",
                "1",
                "--restitution-curve",
                "--eccentricity",
                "0",
            ]),
            "remove --eccentricity",
        ),
        (
            with(&[
                "--dissipation",
                "1e-4",
                "--restitution-curve",
                "--curve-speeds",
                "2",
                "1",
            ]),
            "0 < LO < HI",
        ),
        (
            with(&[
                "--dissipation",
                "1e-4",
                "--speed",
                "1",
                "--eccentricity",
                "0",
                "--plot",
                "x.png",
            ]),
            "--plot belongs to --restitution-curve",
        ),
        (
            with(&[
                "--dissipation",
                "1e-4",
                "--speed",
                "1",
                "--eccentricity",
                "0",
                "--curve-points",
                "5",
            ]),
            "--curve-points belongs to --restitution-curve",
        ),
        (
            vec![
                "mor",
                "--model",
                "hertz",
                "--scaled",
                "1",
                "1",
                "1",
                "--restitution",
                "0.5",
            ],
            "--restitution cannot be combined with --scaled",
        ),
    ];
    for (args, needle) in cases {
        let err = emdstar_error(&args);
        assert!(
            err.contains(needle),
            "{args:?}: message {err:?} should contain {needle:?}"
        );
    }
}
