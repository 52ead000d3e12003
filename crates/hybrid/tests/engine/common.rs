//! Helpers shared by the hybrid engine's tests.

use emdstar_contact::Vec3;
use emdstar_dem::{ContactEnd, Md, MdOptions, shortest_contact_time};
use emdstar_edmd::rules::ExactMor;
use emdstar_edmd::{Engine, Interference, Physics, Stats};
use emdstar_hybrid::{Hybrid, HybridOptions};
use emdstar_system::{Config, Particles, System};

pub fn system(text: &str) -> System {
    Config::from_toml(text).unwrap().build().unwrap()
}

/// A dilute damped linear gas (k = 2000 N/m, γ = 1 kg/s, R = 0.1 m, ρ = 1140 kg/m³,
/// η = 0.01, rms speed 1 m/s), placed at random.
pub fn dilute_gas(t_end: f64, count: usize, seed: u64) -> System {
    system(&format!(
        "t_end = {t_end}\n[material]\nmodel = \"linear\"\nstiffness = 2000.0\ndamping = 1.0\n\
         density = 1140.0\n[gas]\ncount = {count}\nradius = 0.1\narrangement = \"random\"\n\
         packing_fraction = 0.01\nrms_speed = 1.0\nseed = {seed}\n"
    ))
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

/// The eMD* engine (exact MoR) run to `t_end`: the final state and its counters.
pub fn emdstar_reference(system: &System, t_end: f64) -> (Particles, Stats) {
    let physics = Physics::EmdStar {
        interactions: system.interactions().clone(),
        mor: Box::new(ExactMor),
        interference: Interference::HitOnly,
    };
    let mut e: Engine = Engine::new(&system.particles, &system.domain, physics).unwrap();
    e.run_until(t_end).unwrap();
    let mut state = system.particles.clone();
    e.write_state(&mut state);
    (state, *e.stats())
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
