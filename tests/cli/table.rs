//! End-to-end tests of `emdstar table ...` and `emdstar mor --table`.

use super::{error_in, stdout_in};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-table-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const LINEAR_IMPACT: [&str; 14] = [
    "--model",
    "linear",
    "--stiffness",
    "1e5",
    "--damping",
    "0.1",
    "--radius",
    "0.005",
    "--density",
    "2500",
    "--speed",
    "1",
    "--eccentricity",
    "0.4",
];

fn mor_json(dir: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["mor"];
    args.extend(LINEAR_IMPACT);
    args.push("--json");
    args.extend(extra);
    serde_json::from_str(&stdout_in(dir, &args)).unwrap()
}

#[test]
fn mor_answers_from_the_embedded_default_table_in_any_directory() {
    let dir = scratch("default");
    let exact = mor_json(&dir, &[]);
    let table = mor_json(&dir, &["--table", "default"]);
    assert_eq!(exact["source"], "exact");
    assert_eq!(table["source"], "table");
    for key in ["one_minus_eps_r", "eps_rdot", "eps_phi", "eps_t"] {
        let (e, t) = (
            exact["mor"][key].as_f64().unwrap(),
            table["mor"][key].as_f64().unwrap(),
        );
        assert!(((t - e) / e).abs() < 1e-3, "{key}: table {t} vs exact {e}");
    }
}

#[test]
fn mor_table_refuses_points_outside_the_box_and_wrong_models() {
    let dir = scratch("refuse");
    let mut args = vec!["mor"];
    args.extend(LINEAR_IMPACT);
    args.extend(["--table", "default"]);
    args[12] = "1e-7"; // --speed far below the box: b = ln(l̃/l̃_min) too large
    let err = error_in(&dir, &args);
    assert!(err.contains("outside the table's box"), "{err}");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let hertz = root.join("tables/hertz.npz");
    let mut args = vec!["mor"];
    args.extend(LINEAR_IMPACT);
    args.extend(["--table", hertz.to_str().unwrap()]);
    let err = error_in(&dir, &args);
    assert!(
        err.contains("wrong model: the table is for the hertz model"),
        "{err}"
    );
}

#[test]
fn build_shard_merge_verify_check_and_plot_a_tiny_table() {
    let dir = scratch("build");
    std::fs::write(
        dir.join("tiny.toml"),
        "model = \"linear\"\nbox = \"paper_table_1\"\ncells = [1, 2, 1]\ndegree = 3\ntolerance = 1e-2\nmax_depth = 1\n",
    )
    .unwrap();
    stdout_in(&dir, &["table", "build", "tiny.toml", "--threads", "2"]);
    let single = std::fs::read(dir.join("tiny.npz")).unwrap();
    // A job array of three: each job builds its shard, one job merges.
    for i in 0..3 {
        stdout_in(
            &dir,
            &["table", "build", "tiny.toml", "--shard", &format!("{i}/3")],
        );
    }
    stdout_in(
        &dir,
        &[
            "table",
            "merge",
            "tiny.part-2-of-3.npz",
            "tiny.part-0-of-3.npz",
            "tiny.part-1-of-3.npz",
            "--out",
            "merged.npz",
        ],
    );
    assert!(std::fs::read(dir.join("merged.npz")).unwrap() == single);
    let out = stdout_in(&dir, &["table", "verify", "tiny.toml", "--threads", "1"]);
    assert!(out.contains("matches"), "{out}");
    std::fs::write(
        dir.join("tiny.toml"),
        "model = \"linear\"\nbox = \"paper_table_1\"\ncells = [1, 1, 2]\ndegree = 3\ntolerance = 1e-2\nmax_depth = 1\n",
    )
    .unwrap();
    let err = error_in(&dir, &["table", "verify", "tiny.toml"]);
    assert!(err.contains("does not match its spec"), "{err}");
    let out = stdout_in(&dir, &["table", "check", "tiny.npz", "--samples", "40"]);
    for name in ["1-eps_r", "eps_rdot", "eps_phi", "eps_t"] {
        assert!(out.lines().any(|l| l.starts_with(name)), "{out}");
    }
    let err = error_in(&dir, &["table", "build", "tiny.toml", "--shard", "3/3"]);
    assert!(err.contains("need 0 <= I < N"), "{err}");
    // The embedded font labels the plots: no system font needed.
    stdout_in(
        &dir,
        &[
            "table", "plot", "tiny.npz", "--out", "plots", "--c=-3,1", "--res", "20",
        ],
    );
    assert!(dir.join("plots/linear_slice0.png").exists());
    assert!(dir.join("plots/linear_slice1.png").exists());
    let err = error_in(
        &dir,
        &[
            "table",
            "plot",
            "tiny.npz",
            "--out",
            "plots",
            "--font",
            "missing.ttf",
        ],
    );
    assert!(err.contains("cannot read font missing.ttf"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
