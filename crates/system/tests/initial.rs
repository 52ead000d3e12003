//! Initial states from files: a state written by this project's writers (XYZ, GSD) and
//! read back by `[initial]` is the state written (XYZ to the bit, GSD within single
//! precision); a LAMMPS data file written by hand (as `write_data` writes
//! `atom_style sphere`) is read as its rows say; each bad file gets an error that
//! names what is wrong.

use emdstar_system::gsd::GsdWriter;
use emdstar_system::{Config, System, XyzWriter};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-initial-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const MATERIALS: &str = r#"
t_end = 1.0
[[materials]]
name = "glass"
model = "linear"
stiffness = 2000.0
damping = 0.0
density = 2500.0
friction = 0.3
tangential_stiffness = 1600.0
[[materials]]
name = "steel"
model = "linear"
stiffness = 5000.0
damping = 0.0
density = 7800.0
[[interactions]]
materials = ["glass", "steel"]
model = "linear"
stiffness = 3000.0
friction = 0.0
damping = 0.0
"#;

/// The box of [`original`], closed along z between two walls.
const BOX: &str =
    "[box]\nsize = [2.0, 1.5, 1.0]\nlo = [-1.0, 0.0, 0.5]\nperiodic = [true, true, false]\n";
const WALLS: &str = "[[walls]]\nnormal = [0, 0, 1]\npoint = [0, 0, 0.5]\nmaterial = \"steel\"\n\
                   [[walls]]\nnormal = [0, 0, -1]\npoint = [0, 0, 1.5]\nmaterial = \"steel\"\n";

/// A two-material state in a box periodic along x and y, with spins and image flags.
fn original() -> System {
    let mut text = MATERIALS.to_string();
    text.push_str(BOX);
    text.push_str(WALLS);
    for i in 0..6 {
        let material = if i % 2 == 0 { "glass" } else { "steel" };
        let r = 0.05 + 0.01 * i as f64;
        text.push_str(&format!(
            "[[particles]]\nradius = {r}\nmaterial = \"{material}\"\nposition = [{}, {}, {}]\n\
             velocity = [{}, {}, 0.1]\nangular_velocity = [1.0, {}, -3.0]\n",
            -0.9 + 0.3 * i as f64 + 1.0 / 3.0,
            0.2 + 0.2 * i as f64,
            0.7 + 0.05 * i as f64,
            0.1 * i as f64 - 0.3,
            1.0 / 7.0,
            i as f64 * 0.5
        ));
    }
    let mut system = Config::from_toml(&text).unwrap().build().unwrap();
    for (i, image) in system.particles.image.iter_mut().enumerate() {
        *image = [i as i32 - 2, 3 * i as i32, 0];
    }
    system
}

/// The materials of the species of [`original`], by species number.
const SPECIES_MATERIALS: &str = "types = { 0 = \"glass\", 1 = \"steel\", 2 = \"glass\", 3 = \"steel\", 4 = \"glass\", 5 = \"steel\" }\n";

/// The system `[initial]` with `keys` builds, the config in `dir`, with `extra` keys.
fn read_back(dir: &Path, keys: &str, extra: &str) -> emdstar_system::Result<System> {
    let mut text = MATERIALS.to_string();
    text.push_str(extra);
    text.push_str("[initial]\n");
    text.push_str(keys);
    let mut config = Config::from_toml(&text)?;
    config.dir = Some(dir.to_path_buf());
    config.build()
}

#[test]
fn an_xyz_frame_reads_back_to_the_bit() {
    let dir = scratch("xyz");
    let s = original();
    let mut w = XyzWriter::create(&dir.join("run.xyz")).unwrap();
    let mut moved = s.particles.clone();
    moved.position[0][0] += 0.25;
    w.write_frame(0.0, &moved, s.domain.sim_box.as_ref())
        .unwrap();
    w.write_frame(0.5, &s.particles, s.domain.sim_box.as_ref())
        .unwrap();
    drop(w);
    // This project's type names are its species numbers (radius, mass and material).
    let types = SPECIES_MATERIALS;
    // The species numbers of the file are this system's; the box comes from the file.
    let back = read_back(&dir, &format!("file = \"run.xyz\"\n{types}"), WALLS).unwrap();
    assert_eq!(back.particles, s.particles);
    assert_eq!(back.species, s.species);
    assert_eq!(back.domain.sim_box, s.domain.sim_box);
    // Frame 0 (counted from the start) has the moved particle.
    let first = read_back(
        &dir,
        &format!("file = \"run.xyz\"\nframe = 0\n{types}"),
        WALLS,
    )
    .unwrap();
    assert_eq!(first.particles.position, moved.position);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_gsd_frame_reads_back_within_single_precision() {
    let dir = scratch("gsd");
    let s = original();
    let mut w = GsdWriter::create(&dir.join("run.gsd")).unwrap();
    for t in [0.0, 0.5] {
        w.write_frame(t, &s.particles, s.species.len(), s.domain.sim_box.as_ref())
            .unwrap();
    }
    drop(w);
    let keys = &format!("file = \"run.gsd\"\n{SPECIES_MATERIALS}");
    // GSD boxes are periodic: the config's [box] says which axes are closed.
    let back = read_back(&dir, keys, &format!("{BOX}{WALLS}")).unwrap();
    let (a, b) = (&back.particles, &s.particles);
    assert_eq!(a.len(), b.len());
    let close = |x: f64, y: f64| (x - y).abs() <= 2e-7 * y.abs().max(1.0);
    for i in 0..b.len() {
        assert_eq!(a.species[i], b.species[i]);
        assert_eq!(a.image[i], b.image[i]);
        assert!(close(a.radius[i], b.radius[i]) && close(a.mass[i], b.mass[i]));
        for k in 0..3 {
            assert!(close(a.position[i][k], b.position[i][k]), "x {i}");
            assert!(close(a.velocity[i][k], b.velocity[i][k]), "v {i}");
            assert!(
                close(a.angular_velocity[i][k], b.angular_velocity[i][k]),
                "w {i}"
            );
        }
    }
    // Out of range: the message names the range.
    let err = read_back(
        &dir,
        &format!("{keys}frame = 2\n"),
        &format!("{BOX}{WALLS}"),
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("initial.frame = 2 is out of range") && err.contains("2 frames"),
        "{err}"
    );
    let err = read_back(
        &dir,
        &format!("{keys}frame = -3\n"),
        &format!("{BOX}{WALLS}"),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("out of range"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A LAMMPS data file as `write_data` writes `atom_style sphere`: ids out of order, a
/// coefficient-free header, image flags, a Velocities section with spins.
const LAMMPS_DATA: &str =
    "LAMMPS data file via write_data, version 2 Aug 2023, timestep = 0, units = si

3 atoms
2 atom types

0 2 xlo xhi
-1 1 ylo yhi
0 1.5 zlo zhi

Atoms # sphere

2 2 0.2 7800 1.5 0.5 0.75 1 0 -2
1 1 0.1 2500 0.25 -0.5 0.5 0 0 0
3 1 0.12 2500 1.0 0.0 1.0 0 -1 0

Velocities

3 0 0 -1 0 0 0
1 0.5 -0.25 0 0 0 4
2 1 2 3 0.1 0.2 0.3
";

#[test]
fn a_lammps_data_file_is_read_as_its_rows_say() {
    let dir = scratch("lammps");
    std::fs::write(dir.join("packing.data"), LAMMPS_DATA).unwrap();
    let keys = "file = \"packing.data\"\ntypes = { 1 = \"glass\", 2 = \"steel\" }\n";
    let s = read_back(&dir, keys, "").unwrap();
    let p = &s.particles;
    // Particles in the order of their atom ids.
    assert_eq!(
        p.position,
        vec![[0.25, -0.5, 0.5], [1.5, 0.5, 0.75], [1.0, 0.0, 1.0]]
    );
    assert_eq!(p.radius, vec![0.05, 0.1, 0.06]);
    assert_eq!(
        p.velocity,
        vec![[0.5, -0.25, 0.0], [1.0, 2.0, 3.0], [0.0, 0.0, -1.0]]
    );
    assert_eq!(p.angular_velocity[0], [0.0, 0.0, 4.0]);
    assert_eq!(p.image, vec![[0, 0, 0], [1, 0, -2], [0, -1, 0]]);
    let material = |i: usize| s.species[p.species[i] as usize].material;
    assert_eq!((material(0), material(1), material(2)), (0, 1, 0));
    // m = ρ π d³ / 6.
    let mass = 7800.0 * std::f64::consts::PI * 0.2f64.powi(3) / 6.0;
    assert!((p.mass[1] - mass).abs() < 1e-15 * mass);
    let b = s.domain.sim_box.unwrap();
    assert_eq!(
        (b.lo, b.size, b.periodic),
        ([0.0, -1.0, 0.0], [2.0, 2.0, 1.5], [true; 3])
    );

    // A type the map leaves out.
    let err = read_back(
        &dir,
        "file = \"packing.data\"\ntypes = { 1 = \"glass\" }\n",
        "",
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("type \"2\"") && err.contains("initial.types"),
        "{err}"
    );
    // A map to no material.
    let err = read_back(
        &dir,
        "file = \"packing.data\"\ntypes = { 1 = \"glass\", 2 = \"gold\" }\n",
        "",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("\"gold\", which is no material"), "{err}");
    // A data file holds one state.
    let err = read_back(&dir, &format!("{keys}frame = 0\n"), "")
        .unwrap_err()
        .to_string();
    assert!(err.contains("drop initial.frame"), "{err}");
    // Another atom style (atomic: id type x y z).
    let atomic = LAMMPS_DATA
        .split("Velocities")
        .next()
        .unwrap()
        .replace("2 2 0.2 7800 1.5 0.5 0.75 1 0 -2", "2 2 1.5 0.5 0.75");
    std::fs::write(dir.join("atomic.data"), atomic).unwrap();
    let err = read_back(
        &dir,
        "file = \"atomic.data\"\ntypes = { 1 = \"glass\", 2 = \"steel\" }\n",
        "",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("atom_style sphere"), "{err}");
    // Image flags along a closed axis of the config's box.
    let err = read_back(&dir, keys, &format!("{BOX}{WALLS}"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("image flag") && err.contains("closed"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn files_are_checked_as_inline_particles_are() {
    let dir = scratch("checks");
    // Two spheres overlapping: refused as inline ones are.
    let overlap = "2\nLattice=\"2 0 0 0 2 0 0 0 2\" Properties=species:S:1:pos:R:3:radius:R:1\n\
                   glass 0.5 0.5 0.5 0.1\nglass 0.6 0.5 0.5 0.1\n";
    std::fs::write(dir.join("overlap.xyz"), overlap).unwrap();
    let glass = "types = { glass = \"glass\" }\n";
    let err = read_back(&dir, &format!("file = \"overlap.xyz\"\n{glass}"), "")
        .unwrap_err()
        .to_string();
    assert!(err.contains("overlap"), "{err}");
    // OVITO's names (Position, Radius, Particle Type) read as this project's.
    let ovito = "1\nLattice=\"2 0 0 0 2 0 0 0 2\" Origin=\"-1 -1 -1\" pbc=\"T T T\" \
                 Properties=Particle_Type:S:1:Position:R:3:Radius:R:1\nglass 0.5 0.5 0.5 0.1\n";
    std::fs::write(dir.join("ovito.xyz"), ovito).unwrap();
    let s = read_back(&dir, &format!("file = \"ovito.xyz\"\n{glass}"), "").unwrap();
    assert_eq!(s.particles.position, vec![[0.5; 3]]);
    assert_eq!(s.domain.sim_box.unwrap().lo, [-1.0; 3]);
    // A missing column.
    std::fs::write(
        dir.join("noradius.xyz"),
        "1\nProperties=species:S:1:pos:R:3\nglass 0 0 0\n",
    )
    .unwrap();
    let err = read_back(&dir, &format!("file = \"noradius.xyz\"\n{glass}"), "")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("missing column") && err.contains("radius"),
        "{err}"
    );
    // Not a GSD file, a missing file, a format not read, and two sources at once.
    let err = read_back(&dir, "file = \"ovito.xyz\"\nformat = \"gsd\"\n", "")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("not a GSD file") || err.contains("GSD header"),
        "{err}"
    );
    let err = read_back(&dir, "file = \"absent.gsd\"\n", "")
        .unwrap_err()
        .to_string();
    assert!(err.contains("absent.gsd"), "{err}");
    let err = read_back(&dir, "file = \"a.pdb\"\n", "")
        .unwrap_err()
        .to_string();
    assert!(err.contains("initial.format"), "{err}");
    let mut config = Config::from_toml(&format!(
        "{MATERIALS}[[particles]]\nradius = 0.1\nposition = [0, 0, 0]\nmaterial = \"glass\"\n\
         [initial]\nfile = \"ovito.xyz\"\n"
    ))
    .unwrap();
    config.dir = Some(dir.clone());
    let err = config.build().unwrap_err().to_string();
    assert!(err.contains("not [[particles]] and [initial]"), "{err}");
    // An unknown key of [initial] is named.
    let err = Config::from_toml(&format!(
        "{MATERIALS}[initial]\nfile = \"x.gsd\"\nframes = 1\n"
    ))
    .unwrap_err()
    .to_string();
    assert!(err.contains("frames"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
