//! `[material] restitution` against the forward problem: the system a config builds must
//! give its reference spheres' central impacts the restitution asked for, by the exact
//! solver on the physical impact (both force laws, several restitutions and speeds).

use emdstar_contact::{Impact, PairLaw, PairProperties, Sphere, scale};
use emdstar_mor::solve;
use emdstar_system::{Config, System};

fn build(material: &str, particles: &str) -> Result<System, String> {
    let text = format!("t_end = 1.0\n[material]\n{material}\ndensity = 1140.0\n{particles}");
    Config::from_toml(&text)
        .and_then(|c| c.build())
        .map_err(|e| e.to_string())
}

const GAS: &str = "[gas]\ncount = 27\nradius = 0.05\narrangement = \"lattice\"\n\
                   packing_fraction = 0.01\nrms_speed = 1.0\nseed = 3\n";

/// ε_n of a central impact at normal speed `v` of two spheres of species 0.
fn central_restitution(system: &System, v: f64) -> f64 {
    let s = system.species[0];
    let sphere = Sphere::new(s.radius, s.mass).unwrap();
    let pair = PairProperties::spheres(&sphere, &sphere);
    let law = *system.interactions().pair(0, 0).law();
    let impact = Impact::from_speed_eccentricity(v, 0.0).unwrap();
    let scaled = scale(&law, &pair, &impact).unwrap();
    -solve(law.model(), &scaled.params).unwrap().eps_rdot
}

#[test]
fn hertz_gas_gets_its_restitution_at_its_speed() {
    for e in [0.95, 0.7, 0.2] {
        for v in [0.1, 1.0, 5.0] {
            let material = format!(
                "model = \"hertz\"\nyoung = 1e8\npoisson = 0.3\nrestitution = {e}\nrestitution_speed = {v}"
            );
            let system = build(&material, GAS).unwrap();
            let PairLaw::Hertz { dissipation, .. } = system.interactions().pair(0, 0).law() else {
                panic!("not Hertz")
            };
            assert!(*dissipation > 0.0);
            let got = central_restitution(&system, v);
            assert!((got - e).abs() < 1e-10, "ε = {e} at {v} m/s: {got}");
        }
    }
}

#[test]
fn linear_particles_get_their_restitution_at_any_speed() {
    // Two explicit spheres of radius 0.02 m: the reference is the first entry.
    let particles = "[[particles]]\nradius = 0.02\nposition = [0.0, 0.0, 0.0]\n\
                     [[particles]]\nradius = 0.02\nposition = [0.1, 0.0, 0.0]\n";
    for e in [0.9, 0.5, 0.05] {
        let material = format!("model = \"linear\"\nstiffness = 1e4\nrestitution = {e}");
        let system = build(&material, particles).unwrap();
        for v in [0.01, 1.0] {
            let got = central_restitution(&system, v);
            assert!((got - e).abs() < 1e-10, "ε = {e} at {v} m/s: {got}");
        }
    }
}

#[test]
fn restitution_one_is_elastic_and_bad_values_are_refused() {
    let elastic = build(
        "model = \"linear\"\nstiffness = 1e4\nrestitution = 1.0",
        GAS,
    )
    .unwrap();
    let PairLaw::Linear { damping, .. } = elastic.interactions().pair(0, 0).law() else {
        panic!("not linear")
    };
    assert_eq!(*damping, 0.0);
    let cases = [
        (
            "model = \"linear\"\nstiffness = 1e4\nrestitution = 0.0",
            "outside (0, 1]",
        ),
        (
            "model = \"linear\"\nstiffness = 1e4\nrestitution = 1.5",
            "outside (0, 1]",
        ),
        (
            "model = \"linear\"\nstiffness = 1e4\nrestitution = 1e-12",
            "cannot be reached",
        ),
        (
            "model = \"linear\"\nstiffness = 1e4\nrestitution = 0.5\ndamping = 1.0",
            "either material.damping or material.restitution",
        ),
        (
            "model = \"linear\"\nstiffness = 1e4\nrestitution = 0.5\nrestitution_speed = 1.0",
            "same at every speed",
        ),
        (
            "model = \"hertz\"\nyoung = 1e8\npoisson = 0.3\nrestitution = 0.5",
            "needs material.restitution_speed",
        ),
        (
            "model = \"hertz\"\nyoung = 1e8\npoisson = 0.3\nrestitution = 0.5\nrestitution_speed = -1.0",
            "material.restitution_speed = -1 must be a finite number greater than zero",
        ),
        (
            "model = \"hertz\"\nyoung = 1e8\npoisson = 0.3\nrestitution = 0.5\nrestitution_speed = 1.0\ndissipation = 1e-4",
            "either material.dissipation or material.restitution",
        ),
        (
            "model = \"hertz\"\nyoung = 1e8\npoisson = 0.3\nrestitution_speed = 1.0",
            "restitution_speed needs material.restitution",
        ),
    ];
    for (material, needle) in cases {
        let err = build(material, GAS).unwrap_err();
        assert!(
            err.contains(needle),
            "{material}: {err:?} should contain {needle:?}"
        );
    }
}

#[test]
fn the_note_names_the_value_used() {
    let text = format!(
        "t_end = 1.0\n[material]\nmodel = \"hertz\"\nyoung = 1e8\npoisson = 0.3\n\
         restitution = 0.8\nrestitution_speed = 2.0\ndensity = 1140.0\n{GAS}"
    );
    let config = Config::from_toml(&text).unwrap();
    let system = config.build().unwrap();
    let PairLaw::Hertz { dissipation, .. } = system.interactions().pair(0, 0).law() else {
        panic!("not Hertz")
    };
    let note = &system.interactions().notes()[0];
    assert!(note.contains(&format!("{dissipation:.10e}")), "{note}");
    assert!(
        note.contains("at 2 m/s") && note.contains("radius 0.05 m"),
        "{note}"
    );
}
