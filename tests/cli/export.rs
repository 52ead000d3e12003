//! `emdstar export lammps`: the deck of a frictional cooling gas, run by LAMMPS on two
//! MPI ranks, cools as `emdstar run --engine md` does from the same state (T(t) and
//! T_rot(t) within the gas's noise, 2 %), for the linear law with tangential damping
//! and for viscoelastic Hertz; laws without an exact LAMMPS counterpart are refused.
//! The LAMMPS runs are skipped, saying so, where `lmp` or `mpirun` is missing.

use super::{error_in, stdout_in};
use std::path::Path;
use std::process::Command;

const LINEAR: &str = "t_end = 1.0
[material]
model = \"linear\"
stiffness = 2e5
damping = 90.0
density = 1000.0
friction = 0.4
tangential_stiffness = 5.7e4
tangential_damping = 45.0
";

const HERTZ: &str = "t_end = 0.5
[material]
model = \"hertz\"
young = 1e8
poisson = 0.3
restitution = 0.8
restitution_speed = 1.0
density = 1000.0
friction = 0.4
tangential_stiffness = 5.7e4
tangential_damping = 0.0
";

const GAS: &str = "[gas]
count = 4000
radius = 0.1
arrangement = \"random\"
packing_fraction = 0.1
rms_speed = 1.0
seed = 7
[output]
log_interval = 0.02
";

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-export-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Whether `mpirun -np 2 lmp` can run here.
fn mpi_lammps() -> bool {
    let runs = |cmd: &str, arg: &str| {
        Command::new(cmd)
            .arg(arg)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    runs("lmp", "-h") && runs("mpirun", "--version")
}

/// (t, T, T_rot) of each line of an emdstar thermo log (the deck's log holds its first
/// twelve columns).
fn temperatures(path: &Path) -> Vec<(f64, f64, f64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            assert!(c.len() >= 12, "a log line of at least 12 columns: {l}");
            (c[0], c[5], c[11])
        })
        .collect()
}

/// Exports `config`, runs it in LAMMPS on 2 ranks and with `emdstar run --engine md`,
/// and returns the largest relative differences of T and T_rot after the first fifth
/// of the run, and LAMMPS's loop time.
fn compare(name: &str, config: &str) -> (f64, f64, f64) {
    let dir = scratch(name);
    std::fs::write(dir.join("gas.toml"), config).unwrap();
    stdout_in(&dir, &["export", "lammps", "gas.toml", "deck"]);
    let deck = dir.join("deck");
    let out = Command::new("mpirun")
        .current_dir(&deck)
        .args([
            "--allow-run-as-root",
            "-np",
            "2",
            "lmp",
            "-in",
            "in.emdstar",
            "-log",
            "none",
        ])
        .env("OMP_NUM_THREADS", "1")
        .output()
        .unwrap();
    let screen = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "LAMMPS failed: {screen}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let loop_time: f64 = screen
        .lines()
        .rfind(|l| l.starts_with("Loop time of"))
        .and_then(|l| l.split_whitespace().nth(3)?.parse().ok())
        .unwrap();
    stdout_in(
        &dir,
        &[
            "run",
            "gas.toml",
            "--engine",
            "md",
            "--log",
            "md.log",
            "--trajectory",
            "none",
            "--quiet",
        ],
    );
    let (lammps, md) = (
        temperatures(&deck.join("emdstar.log")),
        temperatures(&dir.join("md.log")),
    );
    assert_eq!(lammps.len(), md.len(), "the same log times");
    let t_end = md.last().unwrap().0;
    let (mut dt, mut dtrot) = (0.0f64, 0.0f64);
    for (l, m) in lammps.iter().zip(&md) {
        assert!(
            (l.0 - m.0).abs() < 1e-9 * t_end,
            "times {} and {}",
            l.0,
            m.0
        );
        if m.0 >= 0.2 * t_end {
            dt = dt.max((l.1 - m.1).abs() / m.1);
            dtrot = dtrot.max((l.2 - m.2).abs() / m.2);
        }
    }
    let (first, last) = (md[0], *md.last().unwrap());
    eprintln!(
        "{name}: LAMMPS on 2 ranks (loop {loop_time:.2} s) against emdstar md: T within {:.2} %, \
         T_rot within {:.2} % (t ≥ {:.2} s); T {:.4} → {:.4} J, T_rot → {:.4} J",
        100.0 * dt,
        100.0 * dtrot,
        0.2 * t_end,
        first.1,
        last.1,
        last.2
    );
    // The gas cooled and spun up: the comparison is not of two idle states.
    assert!(
        last.1 < 0.8 * first.1 && last.2 > 0.05 * last.1,
        "{first:?} → {last:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
    (dt, dtrot, loop_time)
}

#[test]
fn an_exported_deck_cools_in_lammps_on_two_ranks_as_emdstar_md_does() {
    if !mpi_lammps() {
        eprintln!("skipped: lmp or mpirun is not installed (apt-get install lammps)");
        return;
    }
    for (name, law) in [("linear", LINEAR), ("hertz", HERTZ)] {
        let (dt, dtrot, _) = compare(name, &format!("{law}{GAS}"));
        assert!(
            dt < 0.02 && dtrot < 0.02,
            "{name}: T {dt:e}, T_rot {dtrot:e}"
        );
    }
}

#[test]
fn the_deck_holds_each_pair_and_wall_and_laws_without_a_counterpart_are_refused() {
    let dir = scratch("refused");
    // Hertz: k_n = (4/3) E* and η_n0 = 2 A E*/m_eff, from the config's own numbers.
    let hertz = "t_end = 0.1\ngravity = [0.0, 0.0, -9.81]\n[material]\nmodel = \"hertz\"\n\
                 young = 1e8\npoisson = 0.25\ndissipation = 1e-4\ndensity = 1000.0\n\
                 [box]\nsize = [1.0, 1.0, 1.0]\nperiodic = [true, true, false]\n\
                 [[walls]]\nnormal = [0, 0, 1]\npoint = [0, 0, 0]\n\
                 [[walls]]\nnormal = [0, 0, -1]\npoint = [0, 0, 1]\n\
                 [[particles]]\nradius = 0.1\nposition = [0.5, 0.5, 0.5]\n\
                 [[particles]]\nradius = 0.05\nposition = [0.2, 0.5, 0.5]\n";
    std::fs::write(dir.join("hertz.toml"), hertz).unwrap();
    stdout_in(&dir, &["export", "lammps", "hertz.toml", "deck"]);
    let script = std::fs::read_to_string(dir.join("deck/in.emdstar")).unwrap();
    let e_star = 1e8 / (2.0 * (1.0 - 0.25 * 0.25));
    let mass = |r: f64| 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let (m1, m2) = (mass(0.1), mass(0.05));
    let coeff = |line: &str| -> (f64, f64) {
        let l = script
            .lines()
            .find(|l| l.starts_with(line))
            .unwrap_or_else(|| panic!("{line} in {script}"));
        let w: Vec<&str> = l.split_whitespace().collect();
        let at = w.iter().position(|&x| x == "hertz").unwrap();
        (w[at + 1].parse().unwrap(), w[at + 2].parse().unwrap())
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
    for (line, m_eff) in [
        ("pair_coeff      1 1", m1 / 2.0),
        ("pair_coeff      1 2", m1 * m2 / (m1 + m2)),
        ("fix             wall0_2", m2),
    ] {
        let (k_n, eta) = coeff(line);
        assert!(close(k_n, 4.0 / 3.0 * e_star), "{line}: k_n {k_n}");
        assert!(
            close(eta, 2.0 * 1e-4 * e_star / m_eff),
            "{line}: η_n0 {eta}"
        );
    }
    assert!(script.contains("boundary        p p f"), "{script}");
    assert!(
        script.contains("zplane 0e0 NULL") && script.contains("zplane NULL 1e0"),
        "{script}"
    );
    assert!(
        script.contains("fix             gravity all gravity 9.81e0 vector 0e0 0e0 -1e0"),
        "{script}"
    );
    // Written once; a second export into the same directory is refused without --force.
    let err = error_in(&dir, &["export", "lammps", "hertz.toml", "deck"]);
    assert!(err.contains("--force"), "{err}");

    let refused = [
        ("tangential = \"coulomb\"\nfriction = 0.3\n", "Coulomb"),
        ("tangential_restitution = 0.4\nfriction = 0.3\n", "Walton"),
        (
            "friction = 0.3\ntangential_stiffness = 1e4\ntangential_damping = 1.0\n",
            "tangential damping",
        ),
    ];
    for (keys, why) in refused {
        let text = hertz.replace("density = 1000.0\n", &format!("density = 1000.0\n{keys}"));
        std::fs::write(dir.join("bad.toml"), text).unwrap();
        let err = error_in(&dir, &["export", "lammps", "bad.toml", "bad"]);
        assert!(
            err.contains(why) && err.contains("no exact LAMMPS counterpart"),
            "{err}"
        );
    }
    // (In free space: a slanted wall cuts a periodic box.)
    let slanted = "t_end = 0.1\n[material]\nmodel = \"linear\"\nstiffness = 1e4\ndamping = 1.0\n\
                   density = 1000.0\n[[walls]]\nnormal = [0, 0.6, 0.8]\npoint = [0, 0, -1]\n\
                   [[particles]]\nradius = 0.1\nposition = [0.5, 0.5, 0.5]\n";
    std::fs::write(dir.join("slanted.toml"), slanted).unwrap();
    let err = error_in(&dir, &["export", "lammps", "slanted.toml", "slanted"]);
    assert!(err.contains("walls[0]"), "{err}");
    // A vibrated wall would stand still in fix wall/gran: refused, naming it.
    let vibrated = "t_end = 0.1\n[material]\nmodel = \"linear\"\nstiffness = 1e4\n\
                    damping = 1.0\ndensity = 1000.0\n[box]\nsize = [1.0, 1.0, 1.0]\n\
                    periodic = [true, true, false]\n[[walls]]\nnormal = [0, 0, 1]\n\
                    point = [0, 0, 0.05]\namplitude = 0.01\nfrequency = 5.0\n[[walls]]\n\
                    normal = [0, 0, -1]\npoint = [0, 0, 1]\n[[particles]]\nradius = 0.1\n\
                    position = [0.5, 0.5, 0.5]\n";
    std::fs::write(dir.join("vibrated.toml"), vibrated).unwrap();
    let err = error_in(&dir, &["export", "lammps", "vibrated.toml", "vibrated"]);
    assert!(
        err.contains("walls[0].amplitude") && err.contains("at rest"),
        "{err}"
    );
    assert!(!dir.join("vibrated").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
