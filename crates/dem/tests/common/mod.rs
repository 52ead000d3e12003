//! Shared set-ups of the MD tests.
#![allow(dead_code)]

use emdstar_contact::{
    ForceLaw, LinearDashpot, PairLaw, PairProperties, Tangential, Vec3, ViscoelasticHertz,
};
use emdstar_dem::{ContactEnd, Md, MdOptions};
use emdstar_mor::rule::{Body, exact_collision};
use emdstar_system::{Domain, Particles, Species, System};

pub const RADIUS: f64 = 0.1;
pub const DENSITY: f64 = 1140.0;

/// Linear dashpot of Müller & Pöschel's Fig. 6 (k = 2 kN/m) with damping γ.
pub fn linear(damping: f64) -> ForceLaw {
    ForceLaw::Linear(LinearDashpot::new(2000.0, damping).unwrap())
}

/// Viscoelastic Hertz, Y = 1 GPa, ν = 0.4, dissipative constant A.
pub fn hertz(a: f64) -> ForceLaw {
    ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, a).unwrap())
}

pub fn species() -> Species {
    let s = emdstar_contact::Sphere::from_density(RADIUS, DENSITY).unwrap();
    Species::new(s.radius, s.mass)
}

pub fn free_system(material: ForceLaw, bodies: &[(Vec3, Vec3)]) -> System {
    let species = vec![species()];
    let mut particles = Particles::default();
    for (x, v) in bodies {
        particles.push(&species, 0, [x.x, x.y, x.z], [v.x, v.y, v.z]);
    }
    System::one_material(
        particles,
        species,
        &material,
        Tangential::None,
        Domain::default(),
    )
    .unwrap()
}

/// A two-sphere collision: equal spheres meeting with relative speed `speed` and
/// eccentricity `e`, with its exact outcome (eMD* rule with the exact MoR).
pub struct Collision {
    pub law: ForceLaw,
    /// Both bodies at first touch.
    pub touch: [Body; 2],
    /// Both bodies τ after first touch, the collision over.
    pub after: [Body; 2],
    /// τ, the exact contact duration.
    pub duration: f64,
    pub l: f64,
    pub speed: f64,
}

impl Collision {
    pub fn new(law: ForceLaw, speed: f64, e: f64) -> Self {
        let s = species();
        let sphere = s.sphere();
        let pair = PairProperties::spheres(&sphere, &sphere);
        let pair_law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        // Contact configuration: r = x1 − x2 along a tilted axis, v_rel with eccentricity e.
        let axis = Vec3::new(0.3, -0.2, 0.9).normalize();
        let side = axis.cross(&Vec3::new(1.0, 0.0, 0.0)).normalize();
        let v_rel = (-axis * (1.0 - e * e).sqrt() + side * e) * speed;
        let drift = Vec3::new(0.4, 0.1, -0.3);
        let x1 = Vec3::new(0.01, 0.02, -0.03);
        let touch = [
            Body {
                position: x1,
                velocity: drift + v_rel * 0.5,
                mass: s.mass,
            },
            Body {
                position: x1 - axis * pair.l,
                velocity: drift - v_rel * 0.5,
                mass: s.mass,
            },
        ];
        let (outcome, _) = exact_collision(&pair_law, &pair, &touch).unwrap();
        Self {
            law,
            touch,
            after: outcome.after,
            duration: outcome.duration,
            l: pair.l,
            speed,
        }
    }

    /// The root-mean-square of [`Self::error_at`] over seven start times: the phase
    /// of the step at which the spheres touch differs from run to run, and so does the
    /// error constant; the mean shows the order without that scatter.
    pub fn error(&self, per_contact: u64, end: ContactEnd) -> f64 {
        let sq: f64 = (0..7)
            .map(|m| {
                self.error_at(per_contact, end, 0.3137 + 0.0419 * m as f64)
                    .powi(2)
            })
            .sum();
        (sq / 7.0).sqrt()
    }

    /// Runs MD with about `per_contact` steps per contact duration τ and returns
    /// max(|Δx|/l, |Δv|/|v_rel|) at the end. The spheres touch `pre`·τ after the start
    /// and the run ends 1.6·τ after the touch.
    pub fn error_at(&self, per_contact: u64, end: ContactEnd, pre: f64) -> f64 {
        let t_pre = pre * self.duration;
        let t_end = t_pre + 1.6 * self.duration;
        let steps = (t_end / self.duration * per_contact as f64).round() as u64;
        let start = self
            .touch
            .map(|b| (b.position - b.velocity * t_pre, b.velocity));
        let exact = self.after.map(|b| {
            (
                b.position + b.velocity * (t_end - t_pre - self.duration),
                b.velocity,
            )
        });
        let system = free_system(self.law, &start);
        let opts = MdOptions {
            dt: t_end / steps as f64,
            contact_end: end,
            skin: None,
        };
        let mut md = Md::new(system, opts, t_end).unwrap();
        md.advance(steps).unwrap();
        let p = md.particles_in_config_order();
        let mut err: f64 = 0.0;
        for (k, (x, v)) in exact.iter().enumerate() {
            let dx = Vec3::from(p.position[k]) - x;
            let dv = Vec3::from(p.velocity[k]) - v;
            err = err.max(dx.norm() / self.l).max(dv.norm() / self.speed);
        }
        err
    }
}

/// Observed orders log2(e(dt)/e(dt/2)) along a halving sequence of step counts.
pub fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// The least-squares slope of log2 e against the halving index: the observed order
/// over the whole sequence (robust against the phase-dependent scatter of single
/// ratios when the contact start falls at a different point of the step each time).
pub fn fitted_order(errors: &[f64]) -> f64 {
    let n = errors.len() as f64;
    let xs: Vec<f64> = (0..errors.len()).map(|k| k as f64).collect();
    let ys: Vec<f64> = errors.iter().map(|e| -e.log2()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// An MD engine with default-ish options.
pub fn engine(system: System, dt: f64, t_end: f64) -> Md {
    Md::new(
        system,
        MdOptions {
            dt,
            contact_end: ContactEnd::ForceZero,
            skin: None,
        },
        t_end,
    )
    .unwrap()
}
