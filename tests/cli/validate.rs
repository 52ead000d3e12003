//! `emdstar validate`: the report directory, the exit code and refusals.

use super::{emdstar, emdstar_error};

#[test]
fn validate_fig6_writes_a_passing_report() {
    let dir = std::env::temp_dir().join(format!("emdstar-validate-{}", std::process::id()));
    let out = emdstar(&[
        "validate",
        "--only",
        "fig6",
        "--out",
        dir.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("2a") && stdout.contains("pass"), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["passed"], true);
    assert_eq!(report["checks"].as_array().unwrap().len(), 3);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("fig6_trajectories.png"));
    let png = std::fs::read(dir.join("fig6_trajectories.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn validate_refuses_unknown_scenarios_zero_threads_and_a_missing_lammps() {
    let e = emdstar_error(&["validate", "--only", "figure9"]);
    assert!(
        e.contains("unknown scenario 'figure9'") && e.contains("fig7"),
        "{e}"
    );
    let e = emdstar_error(&["validate", "--threads", "0"]);
    assert!(e.contains("--threads must be at least 1"), "{e}");
    // Before any scenario runs, and with the way out.
    let e = emdstar_error(&["validate", "--lammps", "/no/such/lmp"]);
    assert!(
        e.contains("cannot start /no/such/lmp") && e.contains("apt-get install lammps"),
        "{e}"
    );
}
