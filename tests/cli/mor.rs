//! `emdstar mor` against independent references: the analytic limits and the
//! Schwager & Pöschel central-dashpot formulas (docs/physics.md, "Reference values").

use crate::{emdstar_error, emdstar_json};
use std::f64::consts::PI;

fn get(v: &serde_json::Value, path: &[&str]) -> f64 {
    path.iter()
        .fold(v, |v, k| &v[*k])
        .as_f64()
        .unwrap_or_else(|| panic!("{path:?} missing in {v}"))
}

#[test]
fn scaled_linear_elastic_central_is_half_a_period() {
    let v = emdstar_json(&[
        "mor", "--model", "linear", "--scaled", "3", "0", "0", "--json",
    ]);
    assert_eq!(v["source"], "exact");
    assert_eq!(v["model"], "linear");
    assert!((get(&v, &["mor", "eps_t"]) - PI).abs() < 1e-9);
    assert!((get(&v, &["mor", "eps_rdot"]) + 1.0).abs() < 1e-9);
    assert!(get(&v, &["mor", "eps_phi"]).abs() < 1e-12);
    assert!(v["scaled"]["T"].is_null());
    // A central impact lies outside the paper's rectangle (e < 0.01).
    assert!(v["rect"].is_null());
}

#[test]
fn physical_central_dashpot_matches_schwager_poeschel() {
    // k = 2000 N/m, γ = 3 kg/s, R = 0.1 m, ρ = 1140 kg/m³: β < ω0/√2.
    let mut args = linear_with("--damping", "3");
    for (flag, value) in [("--speed", "2"), ("--eccentricity", "0")] {
        let at = args.iter().position(|a| *a == flag).unwrap() + 1;
        args[at] = value;
    }
    args.push("--json");
    let v = emdstar_json(&args);
    let m_eff = 4.0 / 3.0 * PI * 0.1f64.powi(3) * 1140.0 / 2.0;
    let w0 = (2000.0 / m_eff).sqrt();
    let beta = 3.0 / (2.0 * m_eff);
    let w = (w0 * w0 - beta * beta).sqrt();
    let tc = (PI - (2.0 * beta * w / (w * w - beta * beta)).atan()) / w;
    let duration = get(&v, &["mor", "eps_t"]) * get(&v, &["scaled", "T"]);
    assert!((duration / tc - 1.0).abs() < 1e-9, "{duration} vs {tc}");
    assert!((-get(&v, &["mor", "eps_rdot"]) / (-beta * tc).exp() - 1.0).abs() < 1e-9);
}

#[test]
fn oblique_impact_reports_paper_coordinates() {
    let v = emdstar_json(&[
        "mor",
        "--model",
        "hertz",
        "--young",
        "1e9",
        "--poisson",
        "0.4",
        "--dissipation",
        "1e-4",
        "--radius",
        "0.01",
        "--density",
        "2500",
        "--speed",
        "1",
        "--eccentricity",
        "0.5",
        "--json",
    ]);
    for k in ["a", "b", "c"] {
        assert!(v["rect"][k].is_f64(), "rect.{k} missing: {v}");
    }
    let l = get(&v, &["scaled", "l"]);
    let c_phi = get(&v, &["scaled", "c_phi"]);
    // Eq. (45): c_φ/l̃ = e/√(1−e²).
    assert!((c_phi / l - 0.5 / 0.75f64.sqrt()).abs() < 1e-12);
    let one_minus = get(&v, &["mor", "one_minus_eps_r"]);
    assert!((1.0 - get(&v, &["mor", "eps_r"]) - one_minus).abs() < 1e-15);
    assert!(one_minus > 0.0 && get(&v, &["mor", "eps_phi"]) > 0.0);
}

#[test]
fn readable_summary_without_json() {
    let out = crate::emdstar(&["mor", "--model", "hertz", "--scaled", "100", "50", "0.1"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("ε_φ") && text.contains("ε_t"), "{text}");
}

/// A valid linear-dashpot call with the value of `flag` replaced by `value`.
fn linear_with(flag: &str, value: &'static str) -> Vec<&'static str> {
    let mut args = vec![
        "mor",
        "--model",
        "linear",
        "--stiffness",
        "2000",
        "--damping",
        "0",
        "--radius",
        "0.1",
        "--density",
        "1140",
        "--speed",
        "5",
        "--eccentricity",
        "0.3",
    ];
    let at = args
        .iter()
        .position(|a| *a == flag)
        .expect("a flag of the call")
        + 1;
    args[at] = value;
    args
}

#[test]
fn bad_input_is_refused_with_a_reason() {
    let mut cases: Vec<(Vec<&str>, &str)> = vec![
        (
            linear_with("--stiffness", "NaN"),
            "stiffness must be a finite number",
        ),
        (
            linear_with("--stiffness", "-1"),
            "stiffness must be greater than zero",
        ),
        (
            linear_with("--damping", "-0.5"),
            "damping must not be negative",
        ),
        (
            linear_with("--radius", "0"),
            "radius must be greater than zero",
        ),
        (
            linear_with("--density", "inf"),
            "density must be a finite number",
        ),
        (
            linear_with("--speed", "0"),
            "speed must be greater than zero",
        ),
        (
            linear_with("--speed", "-5"),
            "speed must be greater than zero",
        ),
        (linear_with("--eccentricity", "1"), "eccentricity"),
        (linear_with("--eccentricity", "-0.1"), "eccentricity"),
        (
            vec![
                "mor",
                "--model",
                "linear",
                "--stiffness",
                "2000",
                "--radius",
                "0.1",
            ],
            "needs --damping",
        ),
        (
            vec!["mor", "--model", "plastic", "--scaled", "1", "1", "1"],
            "plastic",
        ),
        (
            vec!["mor", "--model", "hertz", "--scaled", "-1", "1", "1"],
            "l_tilde",
        ),
        (
            vec!["mor", "--model", "hertz", "--scaled", "1", "NaN", "1"],
            "c_phi",
        ),
        (
            vec![
                "mor", "--model", "hertz", "--scaled", "1", "1", "1", "--radius", "0.1",
            ],
            "--radius cannot be combined with --scaled",
        ),
    ];
    let mut foreign = linear_with("--speed", "5");
    foreign.extend(["--young", "1e9"]);
    cases.push((foreign, "--young does not belong to --model linear"));
    for (args, needle) in cases {
        let err = emdstar_error(&args);
        assert!(
            err.contains(needle),
            "{args:?}: message {err:?} should contain {needle:?}"
        );
    }
}
