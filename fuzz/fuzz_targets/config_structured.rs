//! Structured random configs, valid and invalid: a config drawn by `arbitrary` (small
//! systems, values mostly of physical size, sometimes extreme, sometimes a wrong key),
//! written as TOML, parsed, built, set up by every engine and run for a fixed number of
//! steps or events. A result or an error, never a panic, a hang or unbounded memory.
#![no_main]

#[allow(dead_code)] // each target uses part of it
mod common;

use emdstar_system::Config;
use libfuzzer_sys::arbitrary::{self, Arbitrary};
use libfuzzer_sys::fuzz_target;
use toml::{Table, Value};

/// A number: mostly m·10^e with a small mantissa and exponent, sometimes any f64.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Num {
    Nice(i8, i8),
    Raw(f64),
}

impl Num {
    fn value(self) -> f64 {
        match self {
            Self::Nice(m, e) => f64::from(m) * 10f64.powi(i32::from(e % 12)),
            Self::Raw(x) => x,
        }
    }
}

/// A number (TOML spells NaN and infinities `nan`, `inf`).
fn num(x: Num) -> Value {
    Value::Float(x.value())
}

fn vec3(v: [Num; 3]) -> Value {
    Value::Array(v.iter().map(|&x| num(x)).collect())
}

#[derive(Arbitrary, Debug)]
enum ModelChoice {
    Linear,
    Hertz,
    Other(String),
}

#[derive(Arbitrary, Debug)]
struct Material {
    model: ModelChoice,
    stiffness: Option<Num>,
    damping: Option<Num>,
    young: Option<Num>,
    poisson: Option<Num>,
    dissipation: Option<Num>,
    restitution: Option<Num>,
    restitution_speed: Option<Num>,
    density: Option<Num>,
    friction: Option<Num>,
    tangential: Option<TangentialChoice>,
    tangential_stiffness: Option<Num>,
    tangential_damping: Option<Num>,
    tangential_restitution: Option<Num>,
}

#[derive(Arbitrary, Debug)]
enum TangentialChoice {
    History,
    Coulomb,
    Other(String),
}

#[derive(Arbitrary, Debug)]
struct Particle {
    radius: Num,
    /// Where the particle sits: on a lattice site of spacing 4 radii, plus an offset.
    site: (u8, u8, u8),
    offset: Option<[Num; 3]>,
    velocity: Option<[Num; 3]>,
    angular_velocity: Option<[Num; 3]>,
    mass: Option<Num>,
}

#[derive(Arbitrary, Debug)]
enum Arrangement {
    Lattice,
    Fcc,
    Random,
    Other(String),
}

#[derive(Arbitrary, Debug)]
struct Gas {
    count: u8,
    radius: Num,
    mass: Option<Num>,
    arrangement: Arrangement,
    packing_fraction: Option<Num>,
    rms_speed: Num,
    seed: u64,
}

#[derive(Arbitrary, Debug)]
struct Walls {
    normal: [Num; 3],
    point: [Num; 3],
}

#[derive(Arbitrary, Debug)]
struct Input {
    t_end: Num,
    gravity: Option<[Num; 3]>,
    material: Material,
    particles: Vec<Particle>,
    gas: Option<Gas>,
    sim_box: Option<([Num; 3], Option<[Num; 3]>, Option<[bool; 3]>)>,
    walls: Vec<Walls>,
    md_dt: Option<Num>,
    /// A key the schema does not have, at the top level.
    stray_key: bool,
    /// Steps or events to run.
    steps: u8,
}

fn put(t: &mut Table, key: &str, v: Option<Value>) {
    if let Some(v) = v {
        t.insert(key.into(), v);
    }
}

impl Input {
    fn toml(&self) -> String {
        let mut top = Table::new();
        top.insert("t_end".into(), num(self.t_end));
        put(&mut top, "gravity", self.gravity.map(vec3));
        let m = &self.material;
        let mut mat = Table::new();
        let model = match &m.model {
            ModelChoice::Linear => "linear".to_string(),
            ModelChoice::Hertz => "hertz".to_string(),
            ModelChoice::Other(s) => s.clone(),
        };
        mat.insert("model".into(), Value::String(model));
        for (key, v) in [
            ("stiffness", m.stiffness),
            ("damping", m.damping),
            ("young", m.young),
            ("poisson", m.poisson),
            ("dissipation", m.dissipation),
            ("restitution", m.restitution),
            ("restitution_speed", m.restitution_speed),
            ("density", m.density),
            ("friction", m.friction),
            ("tangential_stiffness", m.tangential_stiffness),
            ("tangential_damping", m.tangential_damping),
            ("tangential_restitution", m.tangential_restitution),
        ] {
            put(&mut mat, key, v.map(num));
        }
        let tangential = m.tangential.as_ref().map(|t| match t {
            TangentialChoice::History => "history".to_string(),
            TangentialChoice::Coulomb => "coulomb".to_string(),
            TangentialChoice::Other(s) => s.clone(),
        });
        put(&mut mat, "tangential", tangential.map(Value::String));
        top.insert("material".into(), Value::Table(mat));
        let particles: Vec<Value> = self
            .particles
            .iter()
            .take(common::MAX_PARTICLES as usize)
            .map(|p| {
                let mut t = Table::new();
                let r = p.radius.value();
                let off = p.offset.map_or([0.0; 3], |o| o.map(Num::value));
                let site = [p.site.0, p.site.1, p.site.2];
                let x: Vec<Value> = (0..3)
                    .map(|k| Value::Float(4.0 * r.abs() * f64::from(site[k] % 4) + off[k]))
                    .collect();
                t.insert("radius".into(), Value::Float(r));
                t.insert("position".into(), Value::Array(x));
                put(&mut t, "velocity", p.velocity.map(vec3));
                put(&mut t, "angular_velocity", p.angular_velocity.map(vec3));
                put(&mut t, "mass", p.mass.map(num));
                Value::Table(t)
            })
            .collect();
        if !particles.is_empty() {
            top.insert("particles".into(), Value::Array(particles));
        }
        if let Some(g) = &self.gas {
            let mut t = Table::new();
            t.insert("count".into(), Value::Integer(i64::from(g.count % 65)));
            t.insert("radius".into(), num(g.radius));
            put(&mut t, "mass", g.mass.map(num));
            let arrangement = match &g.arrangement {
                Arrangement::Lattice => "lattice".to_string(),
                Arrangement::Fcc => "fcc".to_string(),
                Arrangement::Random => "random".to_string(),
                Arrangement::Other(s) => s.clone(),
            };
            t.insert("arrangement".into(), Value::String(arrangement));
            put(&mut t, "packing_fraction", g.packing_fraction.map(num));
            t.insert("rms_speed".into(), num(g.rms_speed));
            t.insert("seed".into(), Value::Integer((g.seed >> 1) as i64));
            top.insert("gas".into(), Value::Table(t));
        }
        if let Some((size, lo, periodic)) = &self.sim_box {
            let mut t = Table::new();
            t.insert("size".into(), vec3(*size));
            put(&mut t, "lo", lo.map(vec3));
            put(
                &mut t,
                "periodic",
                periodic.map(|p| Value::Array(p.iter().map(|&b| Value::Boolean(b)).collect())),
            );
            top.insert("box".into(), Value::Table(t));
        }
        let walls: Vec<Value> = self
            .walls
            .iter()
            .take(6)
            .map(|w| {
                let mut t = Table::new();
                t.insert("normal".into(), vec3(w.normal));
                t.insert("point".into(), vec3(w.point));
                Value::Table(t)
            })
            .collect();
        if !walls.is_empty() {
            top.insert("walls".into(), Value::Array(walls));
        }
        if let Some(dt) = self.md_dt {
            let mut t = Table::new();
            t.insert("dt".into(), num(dt));
            top.insert("md".into(), Value::Table(t));
        }
        if self.stray_key {
            top.insert("stray".into(), Value::Boolean(true));
        }
        toml::to_string(&top).expect("a TOML table serialises")
    }
}

fuzz_target!(|input: Input| {
    let text = input.toml();
    // `EMDSTAR_FUZZ_PRINT=1` shows the config of a replayed finding.
    if std::env::var_os("EMDSTAR_FUZZ_PRINT").is_some() {
        eprintln!("{text}\nsteps: {}", u32::from(input.steps % 64) + 1);
    }
    let Ok(config) = Config::from_toml(&text) else {
        return;
    };
    if !common::small_enough(&config) {
        return;
    }
    let Ok(system) = config.build() else {
        return;
    };
    let steps = u32::from(input.steps % 64) + 1;
    for kind in common::KINDS {
        if let Some(mut engine) = common::build(kind, &config, system.clone()) {
            common::run_bounded(&mut engine, steps);
        }
    }
});
