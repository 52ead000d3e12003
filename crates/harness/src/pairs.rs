//! The pair sweep: seeded random oblique impacts over the paper's Tab. I (linear
//! dashpot) and Tab. II (viscoelastic Hertz) boxes, run through MD at several time steps,
//! eMD and eMD* (table and exact MoR), and compared with the exact two-body outcome
//! after the collision has ended (Müller & Pöschel 2013, Sec. IV with the MoR of
//! Sec. II; [`emdstar_mor::rule::exact_collision`]).
//!
//! Errors are the worse of the two spheres: position error in units of the contact
//! distance l = R₁ + R₂, velocity error in units of the impact speed |v₁ − v₂|.

use crate::engines::{EventKind, event_engine, event_state, free_spheres, md_engine, md_state};
use crate::{HarnessError, Result};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ParameterBox, Range,
    ScaledImpact, Sphere, Vec3, ViscoelasticHertz, scale,
};
use emdstar_dem::shortest_contact_time;
use emdstar_mor::Mor;
use emdstar_mor::rule::{Body, Outcome, resolve};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

/// What to sweep.
#[derive(Debug, Clone, Serialize)]
pub struct PairSettings {
    /// Impacts drawn per force law.
    pub impacts_per_model: usize,
    /// MD time steps, as steps per contact duration (dt = τ/n).
    pub md_steps_per_contact: Vec<u32>,
    /// Fraction of pairs with unequal radii (R₂/R₁ log-uniform in [1/4, 1]).
    pub unequal_fraction: f64,
    pub seed: u64,
}

/// Position and velocity error of one run against the exact outcome.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Errors {
    /// max_i |Δx_i| / l.
    pub position: f64,
    /// max_i |Δv_i| / |v₁ − v₂|.
    pub velocity: f64,
}

/// One impact and every engine's error on it.
#[derive(Debug, Clone, Serialize)]
pub struct ImpactResult {
    pub model: &'static str,
    pub radii: [f64; 2],
    /// Relative speed at contact, m/s.
    pub speed: f64,
    pub eccentricity: f64,
    /// l̃ = l/X; its inverse X/l is the softness (penetration scale over size).
    pub l_tilde: f64,
    pub c_dis: f64,
    /// Exact collision duration τ = ε_t·T, s.
    pub duration: f64,
    /// Whether the default table covers the impact (else eMD* (table) used the
    /// counted exact fallback).
    pub in_table_box: bool,
    /// Largest relative error of the table's 1−ε_r, ε_ṙ, ε_φ, ε_t against the exact
    /// solve (NaN outside the box).
    pub table_mor_error: f64,
    /// The error the table's MoR implies through the collision rule (NaN outside).
    pub table_implied: Errors,
    pub emd: Errors,
    pub emdstar_table: Errors,
    pub emdstar_exact: Errors,
    /// MD at each entry of [`PairSettings::md_steps_per_contact`]; `None` if MD failed.
    pub md: Vec<Option<Errors>>,
    /// MD time step of each level, s.
    pub md_dt: Vec<f64>,
    /// Exact-solver fallbacks of eMD* (table).
    pub table_fallbacks: u64,
}

/// The whole sweep.
#[derive(Debug, Clone, Serialize)]
pub struct PairSweep {
    pub settings: PairSettings,
    pub impacts: Vec<ImpactResult>,
    /// Impacts without an exact reference (the solver refused them), with the reason.
    pub skipped: Vec<String>,
}

/// An impact to run: material, spheres, and the motion at contact.
#[derive(Debug, Clone, Copy)]
struct Draw {
    law: ForceLaw,
    density: f64,
    radii: [f64; 2],
    speed: f64,
    eccentricity: f64,
    /// Centre-of-mass velocity, m/s.
    cm_velocity: [f64; 3],
}

fn log_uniform(rng: &mut ChaCha8Rng, r: Range) -> f64 {
    let u: f64 = rng.random();
    (r.min.ln() + u * (r.max.ln() - r.min.ln())).exp()
}

fn uniform(rng: &mut ChaCha8Rng, r: Range) -> f64 {
    let u: f64 = rng.random();
    r.min + u * (r.max - r.min)
}

/// Draws one impact from the paper's box of `model`: scales log-uniform, Poisson's
/// ratio uniform, and the eccentricity uniform over its full range [0, 0.999] (beyond
/// the box's [0.01, 0.99], where eMD* (table) takes the counted exact fallback).
fn draw(model: Model, unequal_fraction: f64, rng: &mut ChaCha8Rng) -> Result<Draw> {
    let (law, radius, density, speed) = match ParameterBox::paper(model) {
        ParameterBox::Linear(b) => {
            let law =
                LinearDashpot::new(log_uniform(rng, b.stiffness), log_uniform(rng, b.damping))?;
            (ForceLaw::Linear(law), b.radius, b.density, b.speed)
        }
        ParameterBox::Hertz(b) => {
            let law = ViscoelasticHertz::new(
                log_uniform(rng, b.young),
                uniform(rng, b.poisson),
                log_uniform(rng, b.dissipation),
            )?;
            (ForceLaw::Hertz(law), b.radius, b.density, b.speed)
        }
    };
    let r1 = log_uniform(rng, radius);
    let unequal = rng.random::<f64>() < unequal_fraction;
    let r2 = if unequal {
        r1 * log_uniform(rng, Range::new(0.25, 1.0))
    } else {
        r1
    };
    let speed = log_uniform(rng, speed);
    let cm_velocity = std::array::from_fn(|_| speed * (rng.random::<f64>() - 0.5) * 0.5);
    Ok(Draw {
        law,
        density: log_uniform(rng, density),
        radii: [r1, r2],
        speed,
        eccentricity: uniform(rng, Range::new(0.0, 0.999)),
        cm_velocity,
    })
}

/// The two bodies at first touch: r = r₁ − r₂ = l·x̂, centre of mass at the origin,
/// relative velocity with normal part −v_n x̂ and tangential part v_t ŷ.
fn bodies_at_touch(d: &Draw, masses: [f64; 2]) -> [Body; 2] {
    let l = d.radii[0] + d.radii[1];
    let total = masses[0] + masses[1];
    let e = d.eccentricity;
    let v_rel = Vec3::new(-d.speed * (1.0 - e * e).sqrt(), d.speed * e, 0.0);
    let n = Vec3::new(l, 0.0, 0.0);
    let v_cm = Vec3::from(d.cm_velocity);
    [
        Body {
            position: n * (masses[1] / total),
            velocity: v_cm + v_rel * (masses[1] / total),
            mass: masses[0],
        },
        Body {
            position: -n * (masses[0] / total),
            velocity: v_cm - v_rel * (masses[0] / total),
            mass: masses[1],
        },
    ]
}

/// Free flight of an outcome's bodies to `dt` after its end.
fn after(outcome: &Outcome, dt: f64) -> [(Vec3, Vec3); 2] {
    outcome
        .after
        .map(|b| (b.position + b.velocity * dt, b.velocity))
}

fn errors(
    reference: &[(Vec3, Vec3); 2],
    x: &[[f64; 3]],
    v: &[[f64; 3]],
    l: f64,
    speed: f64,
) -> Errors {
    let mut e = Errors {
        position: 0.0,
        velocity: 0.0,
    };
    for i in 0..2 {
        let dx = (reference[i].0 - Vec3::from(x[i])).norm() / l;
        let dv = (reference[i].1 - Vec3::from(v[i])).norm() / speed;
        e.position = e.position.max(if dx.is_nan() { f64::INFINITY } else { dx });
        e.velocity = e.velocity.max(if dv.is_nan() { f64::INFINITY } else { dv });
    }
    e
}

/// Largest relative difference of the four MoR components.
fn mor_error(table: &Mor, exact: &Mor) -> f64 {
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    rel(table.one_minus_eps_r, exact.one_minus_eps_r)
        .max(rel(table.eps_rdot, exact.eps_rdot))
        .max(rel(table.eps_phi, exact.eps_phi))
        .max(rel(table.eps_t, exact.eps_t))
}

/// Most MD steps one level may take (strongly damped Hertz contacts can outlast the
/// elastic contact time, which bounds the step, by orders of magnitude).
const MAX_MD_STEPS: f64 = 2e6;

fn run_impact(d: &Draw, settings: &PairSettings) -> Result<ImpactResult> {
    let spheres = [
        Sphere::from_density(d.radii[0], d.density)?,
        Sphere::from_density(d.radii[1], d.density)?,
    ];
    let pair = PairProperties::spheres(&spheres[0], &spheres[1]);
    let law = PairLaw::same_material(&d.law, pair.r_eff)?;
    let touch = bodies_at_touch(d, [spheres[0].mass, spheres[1].mass]);
    let (exact, exact_mor) = emdstar_mor::rule::exact_collision(&law, &pair, &touch)?;
    let r = touch[0].position - touch[1].position;
    let v = touch[0].velocity - touch[1].velocity;
    let scaled: ScaledImpact = scale(&law, &pair, &Impact::from_relative(&r, &v)?)?;
    let tau = exact.duration;
    let l = pair.l;

    // Start before the touch, end after the collision; t_touch is not a multiple of
    // the MD steps.
    let t_touch = 0.37 * tau;
    let t_end = t_touch + 1.5 * tau;
    let reference = after(&exact, t_end - t_touch - tau);
    let start: Vec<(f64, [f64; 3], [f64; 3])> = (0..2)
        .map(|i| {
            let p = touch[i].position - touch[i].velocity * t_touch;
            (d.radii[i], p.into(), touch[i].velocity.into())
        })
        .collect();
    let system = free_spheres(&d.law, d.density, &start)?;

    let event = |kind| -> Result<(Errors, u64)> {
        let mut e = event_engine(&system, kind)?;
        e.run_until(t_end)?;
        let (x, v) = event_state(&mut e);
        Ok((
            errors(&reference, &x, &v, l, d.speed),
            e.stats().mor_fallbacks,
        ))
    };
    let (emd, _) = event(EventKind::Emd)?;
    let (emdstar_table, table_fallbacks) = event(EventKind::EmdStarTable)?;
    let (emdstar_exact, _) = event(EventKind::EmdStarExact)?;

    let table = emdstar_table::default_table(d.law.model())?;
    let (in_table_box, table_mor_error, table_implied) = match table.lookup_scaled(&scaled.params) {
        Ok(m) => {
            let mor = Mor {
                eps_r: m.eps_r,
                one_minus_eps_r: m.one_minus_eps_r,
                eps_rdot: m.eps_rdot,
                eps_phi: m.eps_phi,
                eps_t: m.eps_t,
            };
            let o = resolve(&touch, l, &mor, scaled.time);
            let state = after(&o, t_end - t_touch - o.duration);
            let x = state.map(|s| s.0.into());
            let v = state.map(|s| s.1.into());
            (
                true,
                mor_error(&mor, &exact_mor),
                errors(&reference, &x, &v, l, d.speed),
            )
        }
        Err(_) => (
            false,
            f64::NAN,
            Errors {
                position: f64::NAN,
                velocity: f64::NAN,
            },
        ),
    };

    // MD: dt = τ_ref/n, τ_ref the exact duration or the elastic bound MD enforces.
    let tau_ref = match shortest_contact_time(&system, t_end)? {
        Some(tc) => tau.min(tc),
        None => tau,
    };
    let mut md = Vec::new();
    let mut md_dt = Vec::new();
    for &n in &settings.md_steps_per_contact {
        let steps = (t_end / (tau_ref / n as f64)).ceil();
        let dt = t_end / steps;
        md_dt.push(dt);
        if steps > MAX_MD_STEPS {
            md.push(None);
            continue;
        }
        let run = md_engine(system.clone(), dt, t_end).and_then(|mut m| {
            m.advance(steps as u64)?;
            Ok(m)
        });
        md.push(run.ok().map(|m| {
            let (x, v) = md_state(&m);
            errors(&reference, &x, &v, l, d.speed)
        }));
    }
    Ok(ImpactResult {
        model: d.law.model().name(),
        radii: d.radii,
        speed: d.speed,
        eccentricity: d.eccentricity,
        l_tilde: scaled.params.l_tilde,
        c_dis: scaled.params.c_dis,
        duration: tau,
        in_table_box,
        table_mor_error,
        table_implied,
        emd,
        emdstar_table,
        emdstar_exact,
        md,
        md_dt,
        table_fallbacks,
    })
}

/// Runs the sweep, impacts in parallel (rayon); the result does not depend on the
/// number of threads.
pub fn sweep(settings: &PairSettings, progress: &(dyn Fn() + Sync)) -> Result<PairSweep> {
    if settings.md_steps_per_contact.iter().any(|&n| n < 10) {
        return Err(HarnessError::Invalid(
            "MD needs at least 10 steps per contact (MD refuses coarser steps)".into(),
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
    let mut draws = Vec::new();
    for model in [Model::Linear, Model::Hertz] {
        for _ in 0..settings.impacts_per_model {
            draws.push(draw(model, settings.unequal_fraction, &mut rng)?);
        }
    }
    let results: Vec<Result<ImpactResult>> = draws
        .par_iter()
        .map(|d| {
            let r = run_impact(d, settings);
            progress();
            r
        })
        .collect();
    let mut impacts = Vec::new();
    let mut skipped = Vec::new();
    for (d, r) in draws.iter().zip(results) {
        match r {
            Ok(x) => impacts.push(x),
            Err(e) => skipped.push(format!("{d:?}: {e}")),
        }
    }
    Ok(PairSweep {
        settings: settings.clone(),
        impacts,
        skipped,
    })
}
