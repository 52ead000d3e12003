//! µ = 0 gives today's trajectories bitwise: a damped gas under gravity between walls
//! (hundreds of contacts, list rebuilds), with the hash of its final positions and
//! velocities as the frictionless engine gave them before friction existed.

use emdstar_dem::{ContactEnd, Md, MdOptions, shortest_contact_time};
use emdstar_system::{Config, System};

fn gas(material: &str) -> System {
    Config::from_toml(&format!(
        r#"
t_end = 0.2
gravity = [0.0, 0.0, -9.81]
[material]
{material}
density = 1140.0
[gas]
count = 200
radius = 0.1
arrangement = "random"
rms_speed = 1.0
seed = 4
[box]
size = [1.5, 1.5, 1.5]
periodic = [true, true, false]
[[walls]]
normal = [0.0, 0.0, 1.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, 0.0, -1.0]
point = [0.0, 0.0, 1.5]
"#
    ))
    .unwrap()
    .build()
    .unwrap()
}

/// FNV-1a over the little-endian bytes of `words`.
fn fnv(words: impl Iterator<Item = u64>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for w in words {
        for b in w.to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn final_hash(material: &str) -> (u64, u64) {
    let system = gas(material);
    let dt = 0.02 * shortest_contact_time(&system, 0.2).unwrap().unwrap();
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: None,
    };
    let mut md = Md::new(system, opts, 0.2).unwrap();
    md.advance(3000).unwrap();
    let p = md.particles_in_config_order();
    assert!(p.angular_velocity.iter().all(|w| *w == [0.0; 3]));
    let words = p.position.iter().chain(&p.velocity).flatten();
    (fnv(words.map(|x| x.to_bits())), md.rebuilds())
}

#[test]
fn mu_zero_reproduces_the_frictionless_trajectories_bitwise() {
    let hertz = "model = \"hertz\"\nyoung = 1e8\npoisson = 0.4\ndissipation = 1e-4";
    let linear = "model = \"linear\"\nstiffness = 5e4\ndamping = 2.0";
    let mu_zero = "\nfriction = 0.0\ntangential_stiffness = 1e4\ntangential_damping = 1.0";
    // (hash, rebuilds) of the frictionless engine.
    let golden = [
        (hertz, (0xecdc_5158_3418_beb2, 36)),
        (linear, (0x674a_3b44_c5b1_2e44, 297)),
    ];
    for (material, want) in golden {
        assert_eq!(final_hash(material), want, "{material}");
        assert_eq!(
            final_hash(&format!("{material}{mu_zero}")),
            want,
            "{material}"
        );
    }
}
