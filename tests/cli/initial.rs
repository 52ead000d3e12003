//! A run started from a file (`[initial]`): the last frame of a run's XYZ trajectory
//! continues it (its temperature and image flags as the run left them), and a run
//! never writes over its initial file. (The event-driven eMD collides instantly: its
//! frames hold no overlapping pairs, which a state is refused with, as inline ones are.)

use super::{error_in, stdout_in};

const MATERIAL: &str = "t_end = 0.2
[material]
model = \"hertz\"
young = 1e7
poisson = 0.3
dissipation = 1e-4
density = 1000.0
";

const GAS: &str = "[gas]
count = 200
radius = 0.05
arrangement = \"random\"
packing_fraction = 0.05
rms_speed = 2.0
seed = 3
";

const FROM_FILE: &str = "[initial]
file = \"first.xyz\"
";

fn last_log_line(path: &std::path::Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let line = text.lines().rfind(|l| !l.starts_with('#')).unwrap();
    line.split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect()
}

#[test]
fn a_run_continues_from_the_last_frame_of_its_trajectory() {
    let dir = std::env::temp_dir().join(format!("emdstar-cli-initial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("gas.toml"), format!("{MATERIAL}{GAS}")).unwrap();
    std::fs::write(dir.join("next.toml"), format!("{MATERIAL}{FROM_FILE}")).unwrap();
    stdout_in(
        &dir,
        &[
            "run",
            "gas.toml",
            "--engine",
            "emd",
            "--trajectory",
            "first.xyz",
            "--log",
            "first.log",
            "--quiet",
        ],
    );
    let frames = std::fs::read_to_string(dir.join("first.xyz")).unwrap();
    let crossed = frames
        .lines()
        .skip(frames.lines().count() - 200)
        .any(|l| !l.ends_with(" 0 0 0"));
    assert!(
        crossed,
        "some sphere crossed a face in the first run (image flags not all 0)"
    );
    stdout_in(
        &dir,
        &[
            "run",
            "next.toml",
            "--engine",
            "emd",
            "--trajectory",
            "next.gsd",
            "--log",
            "next.log",
            "--quiet",
        ],
    );
    let end = last_log_line(&dir.join("first.log"));
    let text = std::fs::read_to_string(dir.join("next.log")).unwrap();
    let start: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    // Kinetic energy and temperature as the first run ended (summed in another order).
    for k in [2, 5] {
        assert!(
            (start[k] - end[k]).abs() <= 1e-12 * end[k],
            "column {k}: {} and {}",
            start[k],
            end[k]
        );
    }
    // A run never writes over its initial file.
    let err = error_in(
        &dir,
        &[
            "run",
            "next.toml",
            "--trajectory",
            "first.xyz",
            "--log",
            "none",
        ],
    );
    assert!(err.contains("initial state"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
