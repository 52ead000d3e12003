//! LAMMPS as a peer of frictional MD: the oblique, spinning, frictional two-sphere
//! collision of tools/lammps/frictional_pair.in (`pair granular hooke … tangential
//! linear_history … limit_damping`, `fix nve/sphere`) run by both codes at the same
//! steps; the final positions, velocities and spins must agree to the codes' truncation
//! error, which shrinks with dt. Skipped, saying so, where `lmp` is not installed.

use emdstar_dem::{ContactEnd, Md, MdOptions};
use emdstar_system::Config;
use std::process::Command;

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tools/lammps/frictional_pair.in"
);
const T_END: f64 = 0.2;
/// Contact distance and relative speed, the units of the comparison.
const L: f64 = 0.17;
const V: f64 = 1.8;

struct Sphere {
    r: f64,
    x: [f64; 3],
    v: [f64; 3],
    w: [f64; 3],
}

const SPHERES: [Sphere; 2] = [
    Sphere {
        r: 0.1,
        x: [0.0, 0.0, 0.0],
        v: [1.0, 0.0, 0.0],
        w: [5.0, -20.0, 30.0],
    },
    Sphere {
        r: 0.07,
        x: [0.25, 0.06, 0.02],
        v: [-0.8, 0.0, 0.1],
        w: [0.0, 10.0, -40.0],
    },
];
// kn, eta_n, kt, gamma_t, mu, density
const MATERIAL: [f64; 6] = [2000.0, 1.0, 600.0, 0.3, 0.3, 1140.0];

/// Final (x, v, ω) of both spheres, scaled by L, V and V/L.
fn scaled(x: [[f64; 3]; 2], v: [[f64; 3]; 2], w: [[f64; 3]; 2]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 0..2 {
        out.extend(x[i].map(|c| c / L));
        out.extend(v[i].map(|c| c / V));
        out.extend(w[i].map(|c| c * L / V));
    }
    out
}

fn emdstar(dt: f64) -> Vec<f64> {
    let [kn, eta, kt, gt, mu, rho] = MATERIAL;
    let mut text = format!(
        "t_end = {T_END}\n[material]\nmodel = \"linear\"\nstiffness = {kn}\ndamping = {eta}\n\
         density = {rho}\nfriction = {mu}\ntangential_stiffness = {kt}\ntangential_damping = {gt}\n"
    );
    for s in &SPHERES {
        text += &format!(
            "[[particles]]\nradius = {}\nposition = {:?}\nvelocity = {:?}\nangular_velocity = {:?}\n",
            s.r, s.x, s.v, s.w
        );
    }
    let system = Config::from_toml(&text).unwrap().build().unwrap();
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: None,
    };
    let mut md = Md::new(system, opts, T_END).unwrap();
    md.advance((T_END / dt).round() as u64).unwrap();
    let p = md.particles_in_config_order();
    let two = |a: &[[f64; 3]]| [a[0], a[1]];
    scaled(two(&p.position), two(&p.velocity), two(&p.angular_velocity))
}

fn lammps(dt: f64) -> Vec<f64> {
    let [kn, eta, kt, gt, mu, rho] = MATERIAL;
    let out = std::env::temp_dir().join(format!("emdstar_peer_{}_{dt:e}.dump", std::process::id()));
    let mut vars: Vec<(String, String)> = vec![
        ("dt".into(), format!("{dt:e}")),
        ("steps".into(), format!("{}", (T_END / dt).round() as u64)),
        ("out".into(), out.display().to_string()),
        ("kn".into(), kn.to_string()),
        ("etan".into(), eta.to_string()),
        ("kt".into(), kt.to_string()),
        ("xgt".into(), (gt / eta).to_string()),
        ("mu".into(), mu.to_string()),
        ("density".into(), rho.to_string()),
    ];
    for (k, s) in SPHERES.iter().enumerate() {
        let n = k + 1;
        vars.push((format!("r{n}"), s.r.to_string()));
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            vars.push((format!("{axis}{n}"), s.x[c].to_string()));
            vars.push((format!("v{axis}{n}"), s.v[c].to_string()));
            vars.push((format!("w{axis}{n}"), s.w[c].to_string()));
        }
    }
    let mut cmd = Command::new("lmp");
    cmd.env("OMP_NUM_THREADS", "1")
        .args(["-in", SCRIPT, "-log", "none", "-screen", "none"]);
    for (name, value) in &vars {
        cmd.arg("-var").arg(name).arg(value);
    }
    let status = cmd.status().expect("lmp runs");
    assert!(status.success(), "lmp failed: {status}");
    let text = std::fs::read_to_string(&out).unwrap();
    let _ = std::fs::remove_file(&out);
    let mut x = [[0.0; 3]; 2];
    let (mut v, mut w) = (x, x);
    let atoms = text
        .lines()
        .skip_while(|l| !l.starts_with("ITEM: ATOMS"))
        .skip(1);
    for line in atoms {
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect();
        let i = f[0] as usize - 1;
        x[i] = [f[1], f[2], f[3]];
        v[i] = [f[4], f[5], f[6]];
        w[i] = [f[7], f[8], f[9]];
    }
    scaled(x, v, w)
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_frictional_collision_agrees_with_lammps() {
    let lmp_runs = Command::new("lmp")
        .arg("-h")
        .output()
        .is_ok_and(|o| o.status.success());
    if !lmp_runs {
        eprintln!("skipped: `lmp` (LAMMPS) is not installed; on Debian: apt-get install lammps");
        return;
    }
    let steps = [1e-4, 2e-5, 4e-6];
    let differences: Vec<f64> = steps
        .iter()
        .map(|&dt| largest_difference(&emdstar(dt), &lammps(dt)))
        .collect();
    for (dt, d) in steps.iter().zip(&differences) {
        eprintln!("dt = {dt:e} s: largest difference {d:.2e} (x/l, v/|v_rel|, ω l/|v_rel|)");
    }
    // Both codes are first order with friction: the difference falls with dt.
    for pair in differences.windows(2) {
        assert!(pair[1] < pair[0] / 2.0, "{differences:?}");
    }
    assert!(differences[2] < 1e-4, "{differences:?}");
}
