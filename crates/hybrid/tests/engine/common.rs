//! Helpers shared by the hybrid engine's tests.

use emdstar_contact::Vec3;
use emdstar_dem::{ContactEnd, Md, MdOptions, shortest_contact_time};
use emdstar_edmd::rules::ExactMor;
use emdstar_edmd::{BroadPhaseKind, Engine, Interference, Physics, Stats};
use emdstar_hybrid::{Hybrid, HybridOptions};
use emdstar_system::{Config, Particles, System};

pub fn system(text: &str) -> System {
    Config::from_toml(text).unwrap().build().unwrap()
}

/// Elastic linear spheres (k = 2000 N/m, R = 0.1 m, ρ = 1140 kg/m³) with the given
/// positions and velocities; `extra` holds further config lines (e.g. a `[box]`).
pub fn elastic_spheres(t_end: f64, extra: &str, bodies: &[([f64; 3], [f64; 3])]) -> System {
    let mut text = format!(
        "t_end = {t_end}\n[material]\nmodel = \"linear\"\nstiffness = 2000.0\ndensity = 1140.0\n{extra}"
    );
    for (x, v) in bodies {
        text += &format!("[[particles]]\nradius = 0.1\nposition = {x:?}\nvelocity = {v:?}\n");
    }
    system(&text)
}

/// A time step of `fraction` × the shortest expected contact time, fitting `t_end`
/// a whole number of times.
pub fn step(system: &System, t_end: f64, fraction: f64) -> (f64, u64) {
    let tc = shortest_contact_time(system, t_end).unwrap().unwrap();
    let steps = (t_end / (fraction * tc)).ceil();
    (t_end / steps, steps as u64)
}

pub fn md(system: &System, dt: f64, skin: f64, t_end: f64) -> Md {
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: Some(skin),
    };
    Md::new(system.clone(), opts, t_end).unwrap()
}

/// The hybrid engine with the exact MoR.
pub fn hybrid_with(system: &System, opts: HybridOptions, t_end: f64) -> Hybrid {
    Hybrid::new(system.clone(), opts, Box::new(ExactMor), t_end).unwrap()
}

/// The eMD* engine (exact MoR) on cell crossings, as the hybrid's event core runs.
pub fn emdstar_engine(system: &System) -> Engine {
    let physics = Physics::EmdStar {
        interactions: system.interactions().clone(),
        mor: Box::new(ExactMor),
        interference: Interference::HitOnly,
    };
    Engine::with_broad_phase(
        &system.particles,
        &system.domain,
        physics,
        BroadPhaseKind::Crossings,
    )
    .unwrap()
}

/// The eMD* engine (exact MoR, on cell crossings) run to `t_end`: the final state
/// (spins included) and its counters.
pub fn emdstar_reference(system: &System, t_end: f64) -> (Particles, Stats) {
    let mut e = emdstar_engine(system);
    e.run_until(t_end).unwrap();
    let mut state = system.particles.clone();
    e.write_state(&mut state);
    (state, *e.stats())
}

/// A step count and the time step of `fraction` × the shortest contact time that
/// lasts about `t_end`, with the end time the hybrid reaches after them exactly.
pub fn steps_to(system: &System, t_end: f64, fraction: f64) -> (f64, u64, f64) {
    let (dt, steps) = step(system, t_end, fraction);
    (dt, steps, steps as f64 * dt)
}

/// Largest difference of positions (minimum image) and of velocities.
pub fn max_difference(a: &Particles, b: &Particles, system: &System) -> (f64, f64) {
    let mut dx: f64 = 0.0;
    let mut dv: f64 = 0.0;
    for i in 0..a.len() {
        let d: [f64; 3] = std::array::from_fn(|k| a.position[i][k] - b.position[i][k]);
        let d = system.domain.sim_box.map_or(d, |bx| bx.min_image(d));
        let w: [f64; 3] = std::array::from_fn(|k| a.velocity[i][k] - b.velocity[i][k]);
        dx = dx.max(Vec3::from(d).norm());
        dv = dv.max(Vec3::from(w).norm());
    }
    (dx, dv)
}

/// A dense damped Hertz gas (η = 0.3): time-driven by its volume fraction.
pub fn dense_hertz_gas() -> System {
    system(
        r#"
t_end = 0.1
[material]
model = "hertz"
young = 1e9
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 64
radius = 0.1
arrangement = "random"
packing_fraction = 0.3
rms_speed = 1.0
seed = 5
"#,
    )
}

/// An elastic gas under gravity between a floor and a lid (periodic sideways; with
/// dissipation, particles come to rest on the floor and the event budget hands them
/// to TD).
pub fn gas_under_gravity(damping: f64) -> System {
    system(&format!(
        r#"
t_end = 0.6
gravity = [0.0, 0.0, -9.81]
[material]
model = "linear"
stiffness = 2e5
damping = {damping}
density = 1140.0
[gas]
count = 150
radius = 0.05
arrangement = "random"
rms_speed = 2.0
seed = 4
[box]
size = [3.0, 3.0, 3.0]
periodic = [true, true, false]
[[walls]]
normal = [0.0, 0.0, 1.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, 0.0, -1.0]
point = [0.0, 0.0, 3.0]
"#
    ))
}
