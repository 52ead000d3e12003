//! Checkpoint bytes through the resume path of every engine: the file parsed (magic,
//! version, lengths, checksum), its state restored into an engine built from a small
//! gas, and a few steps or events run from there. The state decoder also sees the
//! input directly, so that its checks are fuzzed behind the checksum too.
#![no_main]

#[allow(dead_code)] // each target uses part of it
mod common;

use emdstar_system::{Checkpoint, Config, System};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

/// Two Hertz spheres flying at each other in a closed box, and eight gas spheres in a
/// periodic one; the first byte of the input picks the system and the engine.
const CONFIGS: [&str; 2] = [
    r#"
t_end = 0.01
[material]
model = "hertz"
young = 1e8
poisson = 0.3
restitution = 0.8
restitution_speed = 1.0
density = 2500.0
[box]
size = [0.1, 0.1, 0.1]
periodic = [false, false, false]
[[walls]]
normal = [1.0, 0.0, 0.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [-1.0, 0.0, 0.0]
point = [0.1, 0.0, 0.0]
[[walls]]
normal = [0.0, 1.0, 0.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, -1.0, 0.0]
point = [0.0, 0.1, 0.0]
[[walls]]
normal = [0.0, 0.0, 1.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, 0.0, -1.0]
point = [0.0, 0.0, 0.1]
[[particles]]
radius = 0.01
position = [0.03, 0.05, 0.05]
velocity = [1.0, 0.1, 0.0]
[[particles]]
radius = 0.01
position = [0.07, 0.05, 0.05]
velocity = [-1.0, 0.0, 0.0]
"#,
    r#"
t_end = 0.1
[material]
model = "linear"
stiffness = 1e4
damping = 0.05
density = 2500.0
[gas]
count = 8
radius = 0.01
arrangement = "lattice"
packing_fraction = 0.05
rms_speed = 1.0
seed = 3
"#,
];

fn configs() -> &'static [Config; 2] {
    static PARSED: OnceLock<[Config; 2]> = OnceLock::new();
    PARSED.get_or_init(|| CONFIGS.map(|text| Config::from_toml(text).expect("a valid config")))
}

/// The systems of the two configs, built once: building is the same for every input
/// (for the Hertz pair it solves for the restitution's dissipation), and it is not what
/// this target tests.
fn systems() -> &'static [System; 2] {
    static BUILT: OnceLock<[System; 2]> = OnceLock::new();
    BUILT.get_or_init(|| {
        configs()
            .each_ref()
            .map(|c| c.build().expect("the fixed configs build"))
    })
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, bytes)) = data.split_first() else {
        return;
    };
    let config = &configs()[usize::from(pick & 1)];
    let system = systems()[usize::from(pick & 1)].clone();
    let kind = common::KINDS[usize::from(pick >> 1) % 3];
    let state = match Checkpoint::from_bytes(bytes, "fuzz.ckpt") {
        Ok(ckpt) => ckpt.state,
        // Past the checksum: the state decoder on the raw bytes.
        Err(_) => bytes.to_vec(),
    };
    let Some(mut engine) = common::build(kind, config, system) else {
        panic!("the fixed configs set up with every engine");
    };
    if engine.sim_mut().restore_state(&state).is_ok() {
        common::run_bounded(&mut engine, 20);
    }
});
