//! The friction and spin keys of a config: what they build, and a clear message for
//! every bad input.

use emdstar_contact::{HistorySpring, Tangential, Walton};
use emdstar_system::{Config, System};

/// The tangential law of the particles' contact.
fn tangential(s: &System) -> Tangential {
    *s.interactions().pair(0, 0).tangential()
}

fn config(material: &str, spin: &str) -> String {
    format!(
        r#"
t_end = 1.0
[material]
model = "linear"
stiffness = 2000.0
density = 1140.0
{material}
[[particles]]
radius = 0.1
position = [0.0, 0.0, 0.0]
{spin}
"#
    )
}

fn error(material: &str) -> String {
    Config::from_toml(&config(material, ""))
        .and_then(|c| c.build())
        .unwrap_err()
        .to_string()
}

#[test]
fn friction_and_spins_are_read() {
    let text = config(
        "friction = 0.2\ntangential_stiffness = 500.0\ntangential_damping = 0.1",
        "angular_velocity = [1.0, 2.0, 3.0]",
    );
    let s = Config::from_toml(&text).unwrap().build().unwrap();
    assert_eq!(
        tangential(&s),
        Tangential::History(HistorySpring::new(0.2, 500.0, 0.1).unwrap())
    );
    assert_eq!(s.particles.angular_velocity, vec![[1.0, 2.0, 3.0]]);
    assert!(s.warnings().is_empty());
    let coulomb = config("friction = 0.2\ntangential = \"coulomb\"", "");
    let s = Config::from_toml(&coulomb).unwrap().build().unwrap();
    assert_eq!(tangential(&s), Tangential::Coulomb { friction: 0.2 });
    // Without friction keys: frictionless, no spin.
    let s = Config::from_toml(&config("", "")).unwrap().build().unwrap();
    assert_eq!(tangential(&s), Tangential::None);
    assert_eq!(s.particles.angular_velocity, vec![[0.0; 3]]);
}

#[test]
fn walton_friction_is_read_for_the_event_engines() {
    let text = config("friction = 0.3\ntangential_restitution = -0.25", "");
    let s = Config::from_toml(&text).unwrap().build().unwrap();
    assert_eq!(
        tangential(&s),
        Tangential::Walton(Walton::new(0.3, -0.25).unwrap())
    );
    // Without friction there is no rule to run.
    let text = config("friction = 0.0\ntangential_restitution = 0.5", "");
    let s = Config::from_toml(&text).unwrap().build().unwrap();
    assert_eq!(tangential(&s), Tangential::None);
}

#[test]
fn bad_friction_gets_a_clear_message() {
    let cases = [
        (
            "friction = -0.1\ntangential_stiffness = 1.0",
            "friction must not be negative",
        ),
        (
            "friction = 0.1\ntangential_stiffness = -1.0",
            "tangential_stiffness must not be negative",
        ),
        (
            "friction = 0.1\ntangential_stiffness = 1.0\ntangential_damping = -2.0",
            "tangential_damping must not be negative",
        ),
        ("friction = 0.1", "tangential_stiffness"),
        (
            "tangential_stiffness = 1.0",
            "has no effect without material.friction",
        ),
        (
            "friction = 0.1\ntangential = \"sticky\"",
            "unknown tangential model",
        ),
        (
            "friction = 0.1\ntangential = \"coulomb\"\ntangential_stiffness = 1.0",
            "does not belong to tangential = \"coulomb\"",
        ),
        ("friction = nan\ntangential_stiffness = 1.0", "finite"),
        (
            "friction = 0.1\ntangential_restitution = 1.5",
            "tangential_restitution = 1.5 is outside the allowed range [-1, 1]",
        ),
        (
            "friction = 0.1\ntangential_restitution = -1.2",
            "tangential_restitution = -1.2 is outside",
        ),
        (
            "friction = 0.1\ntangential_restitution = nan",
            "tangential_restitution must be a finite number",
        ),
        (
            "tangential_restitution = 0.5",
            "tangential_restitution has no effect without material.friction",
        ),
        (
            "friction = 0.1\ntangential_restitution = 0.5\ntangential_stiffness = 1.0",
            "one or the other",
        ),
        (
            "friction = 0.1\ntangential_restitution = 0.5\ntangential = \"coulomb\"",
            "material.tangential belongs to force-based MD",
        ),
        ("friction = 0.1", "tangential_restitution"),
    ];
    for (material, want) in cases {
        let e = error(material);
        assert!(e.contains(want), "{material}: {e}");
        assert!(e.contains("material."), "{material}: {e}");
    }
    let e = Config::from_toml(&config("", "angular_velocity = [1.0, inf, 0.0]"))
        .and_then(|c| c.build());
    assert!(e.is_err());
}

#[test]
fn spin_on_a_frictionless_material_is_a_warning() {
    let text = config("", "angular_velocity = [0.0, 0.0, 5.0]");
    let s = Config::from_toml(&text).unwrap().build().unwrap();
    let w = s.warnings();
    assert_eq!(w.len(), 1);
    assert!(
        w[0].contains("frictionless") && w[0].contains("spin"),
        "{w:?}"
    );
}
