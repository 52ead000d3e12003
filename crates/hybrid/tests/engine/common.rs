//! Helpers shared by the hybrid engine's tests.

use emdstar_contact::Vec3;
use emdstar_dem::{ContactEnd, Md, MdOptions, shortest_contact_time};
use emdstar_system::{Config, Particles, System};

pub fn system(text: &str) -> System {
    Config::from_toml(text).unwrap().build().unwrap()
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

/// Largest difference of positions (minimum image) and of velocities.
pub fn max_difference(a: &Particles, b: &Particles, system: &System) -> (f64, f64) {
    let mut dx: f64 = 0.0;
    let mut dv: f64 = 0.0;
    for i in 0..a.len() {
        let d: [f64; 3] = std::array::from_fn(|k| a.position[i][k] - b.position[i][k]);
        let d = system.sim_box.map_or(d, |bx| bx.min_image(d));
        let w: [f64; 3] = std::array::from_fn(|k| a.velocity[i][k] - b.velocity[i][k]);
        dx = dx.max(Vec3::from(d).norm());
        dv = dv.max(Vec3::from(w).norm());
    }
    (dx, dv)
}
