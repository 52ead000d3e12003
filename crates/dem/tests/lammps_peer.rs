//! LAMMPS as a peer of frictional MD: the oblique, spinning, frictional two-sphere
//! collision of tools/lammps/frictional_pair.in (`pair granular hooke … tangential
//! linear_history … limit_damping`, `fix nve/sphere`), the same for two materials with
//! their own constants and those of their pair (tools/lammps/frictional_types.in,
//! `pair_coeff 1 2`), and a frictional impact on a wall of another material (there a
//! still sphere of 10⁷ times the radius, see the script), run by both codes at the same
//! steps; the final positions, velocities and spins must agree to the codes' truncation
//! error, which shrinks with dt. Skipped, saying so, where `lmp` is not installed.

use emdstar_dem::{ContactEnd, Md, MdOptions};
use emdstar_system::Config;
use std::process::Command;

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tools/lammps/frictional_pair.in"
);
const TYPES_SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tools/lammps/frictional_types.in"
);
const T_END: f64 = 0.2;
/// Contact distance and relative speed, the units of the comparison.
const L: f64 = 0.17;
const V: f64 = 1.8;

#[derive(Clone, Copy)]
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
    let mut vars: Vec<(String, String)> = vec![
        ("kn".into(), kn.to_string()),
        ("etan".into(), eta.to_string()),
        ("kt".into(), kt.to_string()),
        ("xgt".into(), (gt / eta).to_string()),
        ("mu".into(), mu.to_string()),
        ("density".into(), rho.to_string()),
    ];
    vars.extend(sphere_vars(&SPHERES));
    let [x, v, w] = run_lammps(SCRIPT, dt, vars);
    scaled(x, v, w)
}

/// The variables of both spheres: r1 x1 … wz1, the same with 2.
fn sphere_vars(spheres: &[Sphere; 2]) -> Vec<(String, String)> {
    let mut vars = Vec::new();
    for (k, s) in spheres.iter().enumerate() {
        let n = k + 1;
        vars.push((format!("r{n}"), s.r.to_string()));
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            vars.push((format!("{axis}{n}"), s.x[c].to_string()));
            vars.push((format!("v{axis}{n}"), s.v[c].to_string()));
            vars.push((format!("w{axis}{n}"), s.w[c].to_string()));
        }
    }
    vars
}

/// Runs `script` with `vars` for T_END at steps of `dt`, returning the final positions,
/// velocities and spins of atoms 1 and 2.
fn run_lammps(script: &str, dt: f64, mut vars: Vec<(String, String)>) -> [[[f64; 3]; 2]; 3] {
    let out = std::env::temp_dir().join(format!(
        "emdstar_peer_{}_{dt:e}_{}.dump",
        std::process::id(),
        vars.len()
    ));
    vars.push(("dt".into(), format!("{dt:e}")));
    vars.push(("steps".into(), format!("{}", (T_END / dt).round() as u64)));
    vars.push(("out".into(), out.display().to_string()));
    let mut cmd = Command::new("lmp");
    cmd.env("OMP_NUM_THREADS", "1")
        .args(["-in", script, "-log", "none", "-screen", "none"]);
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
    [x, v, w]
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Whether `lmp` runs here (the checks are skipped, saying so, where it does not).
fn lmp_runs() -> bool {
    let runs = Command::new("lmp")
        .arg("-h")
        .output()
        .is_ok_and(|o| o.status.success());
    if !runs {
        eprintln!("skipped: `lmp` (LAMMPS) is not installed; on Debian: apt-get install lammps");
    }
    runs
}

/// The largest differences at the steps `steps` of `ours` against `theirs`, each
/// falling by more than half with the next step and below `bar` at the finest.
fn agree(
    what: &str,
    steps: &[f64],
    ours: impl Fn(f64) -> Vec<f64>,
    theirs: impl Fn(f64) -> Vec<f64>,
    bar: f64,
) {
    let differences: Vec<f64> = steps
        .iter()
        .map(|&dt| largest_difference(&ours(dt), &theirs(dt)))
        .collect();
    for (dt, d) in steps.iter().zip(&differences) {
        eprintln!(
            "{what}: dt = {dt:e} s: largest difference {d:.2e} (x/l, v/|v_rel|, ω l/|v_rel|)"
        );
    }
    // Both codes are first order with friction: the difference falls with dt.
    for pair in differences.windows(2) {
        assert!(pair[1] < pair[0] / 2.0, "{what}: {differences:?}");
    }
    assert!(
        differences[differences.len() - 1] < bar,
        "{what}: {differences:?}"
    );
}

#[test]
fn a_frictional_collision_agrees_with_lammps() {
    if lmp_runs() {
        agree("one material", &[1e-4, 2e-5, 4e-6], emdstar, lammps, 1e-4);
    }
}

/// The constants of a pair of types (or of a material with itself, or of a pair of
/// materials): kn, eta_n, kt, gamma_t, mu.
type Pair = [f64; 5];
const A: Pair = [2000.0, 1.0, 600.0, 0.3, 0.3];
const B: Pair = [3000.0, 0.5, 900.0, 0.2, 0.5];
const AB: Pair = [2500.0, 0.8, 700.0, 0.25, 0.4];
const DENSITIES: [f64; 2] = [1140.0, 2500.0];

/// A linear material, or an [[interactions]] entry's keys, of constants `c`.
fn linear_keys(c: Pair) -> String {
    let [kn, eta, kt, gt, mu] = c;
    format!(
        "model = \"linear\"\nstiffness = {kn}\ndamping = {eta}\nfriction = {mu}\n\
         tangential_stiffness = {kt}\ntangential_damping = {gt}\n"
    )
}

/// The LAMMPS variables of the pair of types `ij`.
fn type_vars(ij: &str, c: Pair) -> Vec<(String, String)> {
    let [kn, eta, kt, gt, mu] = c;
    [
        ("kn", kn),
        ("etan", eta),
        ("kt", kt),
        ("xgt", gt / eta),
        ("mu", mu),
    ]
    .map(|(k, v)| (format!("{k}_{ij}"), v.to_string()))
    .to_vec()
}

fn types_vars(spheres: &[Sphere; 2], still: bool, lo: f64, hi: f64) -> Vec<(String, String)> {
    let mut vars = sphere_vars(spheres);
    vars.extend(type_vars("11", A));
    vars.extend(type_vars("22", B));
    vars.extend(type_vars("12", AB));
    vars.push(("rho1".into(), DENSITIES[0].to_string()));
    vars.push(("rho2".into(), DENSITIES[1].to_string()));
    vars.push(("still".into(), u8::from(still).to_string()));
    vars.push(("lo".into(), lo.to_string()));
    vars.push(("hi".into(), hi.to_string()));
    vars
}

/// emdstar's final state of `particles` with materials a and b and their pair.
fn emdstar_materials(dt: f64, particles: &str, walls: &str) -> [[[f64; 3]; 2]; 3] {
    let text = format!(
        "t_end = {T_END}\n[[materials]]\nname = \"a\"\n{}density = {}\n\
         [[materials]]\nname = \"b\"\n{}density = {}\n\
         [[interactions]]\nmaterials = [\"a\", \"b\"]\n{}{particles}{walls}",
        linear_keys(A),
        DENSITIES[0],
        linear_keys(B),
        DENSITIES[1],
        linear_keys(AB),
    );
    let system = Config::from_toml(&text).unwrap().build().unwrap();
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: None,
    };
    let mut md = Md::new(system, opts, T_END).unwrap();
    md.advance((T_END / dt).round() as u64).unwrap();
    let p = md.particles_in_config_order();
    let pick = |a: &[[f64; 3]]| [a[0], *a.get(1).unwrap_or(&[0.0; 3])];
    [
        pick(&p.position),
        pick(&p.velocity),
        pick(&p.angular_velocity),
    ]
}

#[test]
fn an_unlike_frictional_pair_agrees_with_lammps() {
    if !lmp_runs() {
        return;
    }
    let particles: String = SPHERES
        .iter()
        .zip(["a", "b"])
        .map(|(s, m)| {
            format!(
                "[[particles]]\nradius = {}\nposition = {:?}\nvelocity = {:?}\n\
                 angular_velocity = {:?}\nmaterial = \"{m}\"\n",
                s.r, s.x, s.v, s.w
            )
        })
        .collect();
    let ours = |dt| {
        let [x, v, w] = emdstar_materials(dt, &particles, "");
        scaled(x, v, w)
    };
    let theirs = |dt| {
        let [x, v, w] = run_lammps(TYPES_SCRIPT, dt, types_vars(&SPHERES, false, -2.0, 2.0));
        scaled(x, v, w)
    };
    agree("two materials", &[1e-4, 2e-5, 4e-6], ours, theirs, 1e-4);
}

/// The radius of the still sphere that stands in for the wall in LAMMPS.
const WALL_RADIUS: f64 = 1e6;

#[test]
fn a_frictional_wall_impact_agrees_with_lammps() {
    if !lmp_runs() {
        return;
    }
    // Sphere 1 of material a, oblique and spinning, on a floor z = 0 of material b.
    let ball = Sphere {
        r: 0.1,
        x: [0.0, 0.0, 0.25],
        v: [0.6, 0.3, -1.5],
        w: [5.0, -20.0, 30.0],
    };
    let particles = format!(
        "[[particles]]\nradius = {}\nposition = {:?}\nvelocity = {:?}\n\
         angular_velocity = {:?}\nmaterial = \"a\"\n",
        ball.r, ball.x, ball.v, ball.w
    );
    let floor = "[[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, 0.0]\nmaterial = \"b\"\n";
    // Only sphere 1 is compared (the floor's state is not a sphere's in emdstar).
    let first = |[x, v, w]: [[[f64; 3]; 2]; 3]| {
        let mut out = scaled(x, v, w);
        out.truncate(9);
        out
    };
    let ours = |dt| first(emdstar_materials(dt, &particles, floor));
    let wall = Sphere {
        r: WALL_RADIUS,
        x: [0.0, 0.0, -WALL_RADIUS],
        v: [0.0; 3],
        w: [0.0; 3],
    };
    let theirs = |dt| {
        let spheres = [ball, wall];
        let span = 2.2 * WALL_RADIUS;
        first(run_lammps(
            TYPES_SCRIPT,
            dt,
            types_vars(&spheres, true, -span, span),
        ))
    };
    agree("a wall", &[1e-4, 2e-5, 4e-6], ours, theirs, 1e-4);
}
