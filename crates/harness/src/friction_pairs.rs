//! Frictional pair impacts: the exact frictional contact of eMD*
//! (`emdstar_mor::frictional`) against MD at two fine steps, with Walton's instantaneous
//! rule beside them (the frictional counterpart of Fig. 6 of Müller & Pöschel 2013).
//!
//! Each impact is drawn at random: the normal law (linear dashpot or viscoelastic
//! Hertz, damped or not), µ log-uniform in [0.05, 1], a history spring (damped or not),
//! spins up to 3|v|/R, equal or unequal radii, eccentricity up to 0.9. MD starts the
//! pair a little before touch and runs until the contact is over; the exact solution is
//! carried ballistically to the same time. Errors are in units of l (positions) and
//! |v_rel| (velocities, and spins times their sphere's radius), of relative position,
//! relative velocity and both spins.

use crate::engines::{EventKind, event_engine, event_state, md_engine};
use crate::{HarnessError, Result};
use emdstar_contact::vec3::{add, add_scaled, dot, norm, scale, sub};
use emdstar_contact::{HistorySpring, PairLaw, Rough, SOLID_SPHERE_INERTIA, Walton, rough_pair};
use emdstar_mor::SolverOptions;
use emdstar_mor::frictional::{Spinning, solve_frictional};
use emdstar_system::{Config, MaterialConfig, ParticleConfig, Simulation, System};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;

const DENSITY: f64 = 1140.0;
const STIFFNESS: f64 = 2000.0;
const YOUNG: f64 = 1e7;
const POISSON: f64 = 0.3;

/// What to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionPairSettings {
    pub impacts: usize,
    pub seed: u64,
    /// MD's coarser step as a fraction of the contact time; the finer is half of it.
    pub md_dt_fraction: f64,
}

impl FrictionPairSettings {
    pub fn quick() -> Self {
        Self {
            impacts: 24,
            seed: 1,
            md_dt_fraction: 1.0 / 400.0,
        }
    }
}

/// Errors of one engine on one impact: relative position (units of l), relative
/// velocity and spins (units of |v_rel|, spins times radius).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StateError {
    pub position: f64,
    pub velocity: f64,
    pub spin: f64,
}

/// One impact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FrictionImpact {
    pub hertz: bool,
    pub friction: f64,
    pub unequal: bool,
    pub eccentricity: f64,
    /// Stick–slip switches of the exact contact.
    pub switches: usize,
    /// MD at the coarser and the finer step against the exact solution.
    pub md_coarse: StateError,
    pub md_fine: StateError,
    /// MD's own truncation error at the finer step, |MD(dt) − MD(dt/2)|.
    pub md_truncation: StateError,
    /// Walton's rule (e and β₀ of the same contact, applied at touch).
    pub walton: StateError,
    /// The eMD* engine (its three events with the exact frictional contact).
    pub emdstar: StateError,
}

/// All impacts.
#[derive(Debug, Clone, Serialize)]
pub struct FrictionPairs {
    pub impacts: Vec<FrictionImpact>,
}

/// Relative state of a pair: r, v, ω₁, ω₂.
type Relative = ([f64; 3], [f64; 3], [[f64; 3]; 2]);

struct Drawn {
    law_config: MaterialConfig,
    law: PairLaw,
    friction: HistorySpring,
    radii: [f64; 2],
    masses: [f64; 2],
    spins: [[f64; 3]; 2],
    normal: [f64; 3],
    velocity: [f64; 3],
    eccentricity: f64,
    hertz: bool,
}

fn unit(rng: &mut ChaCha8Rng) -> [f64; 3] {
    loop {
        let x: [f64; 3] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n = norm(x);
        if n > 0.1 && n <= 1.0 {
            return scale(1.0 / n, x);
        }
    }
}

fn draw(rng: &mut ChaCha8Rng, k: usize) -> Result<Drawn> {
    let hertz = k % 2 == 1;
    let unequal = k % 4 >= 2;
    let damped = rng.random_range(0.0..1.0) < 0.7;
    let radii = [
        0.1,
        if unequal {
            rng.random_range(0.05..0.2)
        } else {
            0.1
        },
    ];
    let masses = radii.map(|r| 4.0 / 3.0 * std::f64::consts::PI * r * r * r * DENSITY);
    let m_eff = masses[0] * masses[1] / (masses[0] + masses[1]);
    let r_eff = radii[0] * radii[1] / (radii[0] + radii[1]);
    let mut cfg = MaterialConfig {
        model: if hertz { "hertz" } else { "linear" }.into(),
        density: Some(DENSITY),
        ..Default::default()
    };
    // Normal stiffness scale k_n: the linear k, or Hertz's secant 1.5 ρ_el √Ξ at 1 m/s.
    let (law, k_n) = if hertz {
        let dissipation = if damped { 2e-4 } else { 0.0 };
        cfg.young = Some(YOUNG);
        cfg.poisson = Some(POISSON);
        cfg.dissipation = Some(dissipation);
        let e_star = YOUNG / (2.0 * (1.0 - POISSON * POISSON));
        let rho_el = 4.0 / 3.0 * e_star * r_eff.sqrt();
        let peak = (1.25 * m_eff / rho_el).powf(0.4);
        (
            PairLaw::Hertz {
                rho_el,
                dissipation,
            },
            1.5 * rho_el * peak.sqrt(),
        )
    } else {
        let damping = if damped { 2.0 } else { 0.0 };
        cfg.stiffness = Some(STIFFNESS);
        cfg.damping = Some(damping);
        (
            PairLaw::Linear {
                stiffness: STIFFNESS,
                damping,
            },
            STIFFNESS,
        )
    };
    let mu = 0.05 * 20f64.powf(rng.random_range(0.0..1.0));
    let k_t = 2.0 / 7.0 * k_n * rng.random_range(0.5..1.5);
    let gamma_t = if rng.random_range(0.0..1.0) < 0.5 {
        0.0
    } else {
        0.2 * (k_t * m_eff).sqrt()
    };
    cfg.friction = Some(mu);
    cfg.tangential_stiffness = Some(k_t);
    cfg.tangential_damping = Some(gamma_t);
    let friction = HistorySpring::new(mu, k_t, gamma_t)?;
    let speed: f64 = rng.random_range(0.5..3.0);
    let spins = radii.map(|r| scale(rng.random_range(0.0..3.0) * speed / r, unit(rng)));
    let normal = unit(rng);
    let e: f64 = rng.random_range(0.0..0.9);
    let side = {
        let a = unit(rng);
        let t = add_scaled(a, -dot(a, normal), normal);
        scale(1.0 / norm(t), t)
    };
    let velocity = scale(
        speed,
        add_scaled(scale(e, side), -(1.0 - e * e).sqrt(), normal),
    );
    Ok(Drawn {
        law_config: cfg,
        law,
        friction,
        radii,
        masses,
        spins,
        normal,
        velocity,
        eccentricity: e,
        hertz,
    })
}

/// The pair as a system: started `lead` before touch, its centre of mass at rest.
fn pair_system(d: &Drawn, lead: f64, t_obs: f64) -> Result<System> {
    let l = d.radii[0] + d.radii[1];
    let m = d.masses;
    let total = m[0] + m[1];
    let r_start = sub(scale(l, d.normal), scale(lead, d.velocity));
    let particles = (0..2)
        .map(|i| {
            let share = if i == 0 { m[1] / total } else { -m[0] / total };
            ParticleConfig {
                radius: d.radii[i],
                position: add([1.0; 3], scale(share, r_start)),
                velocity: scale(share, d.velocity),
                angular_velocity: d.spins[i],
                ..Default::default()
            }
        })
        .collect();
    let config = Config {
        t_end: t_obs,
        material: Some(d.law_config.clone()),
        particles,
        ..Config::default()
    };
    Ok(config.build()?)
}

/// MD's relative state at `t_obs`, the pair started `lead` before touch.
fn md_run(d: &Drawn, lead: f64, dt: f64, t_obs: f64) -> Result<Relative> {
    let mut md = md_engine(pair_system(d, lead, t_obs)?, dt, t_obs)?;
    let steps = (t_obs / dt).round() as u64;
    md.advance(steps)
        .map_err(|e| HarnessError::Invalid(e.to_string()))?;
    let p = md.particles_in_config_order();
    let r = sub(p.position[0], p.position[1]);
    let v = sub(p.velocity[0], p.velocity[1]);
    Ok((r, v, [p.angular_velocity[0], p.angular_velocity[1]]))
}

/// The eMD* engine's relative state at `t_obs` (exact contacts with friction).
fn emdstar_run(d: &Drawn, lead: f64, t_obs: f64) -> Result<Relative> {
    let system = pair_system(d, lead, t_obs)?;
    let mut engine = event_engine(&system, EventKind::EmdStarExact)?;
    engine
        .advance_to(t_obs)
        .map_err(|e| HarnessError::Invalid(e.to_string()))?;
    let (x, v) = event_state(&mut engine);
    let w = engine.angular_velocities();
    Ok((sub(x[0], x[1]), sub(v[0], v[1]), [w[0], w[1]]))
}

fn error(d: &Drawn, a: &Relative, b: &Relative) -> StateError {
    let l = d.radii[0] + d.radii[1];
    let speed = norm(d.velocity);
    let spin = (0..2)
        .map(|i| norm(sub(a.2[i], b.2[i])) * d.radii[i] / speed)
        .fold(0.0, f64::max);
    StateError {
        position: norm(sub(a.0, b.0)) / l,
        velocity: norm(sub(a.1, b.1)) / speed,
        spin,
    }
}

fn one(settings: &FrictionPairSettings, k: usize) -> Result<FrictionImpact> {
    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed.wrapping_mul(1_000_003) + k as u64);
    let d = draw(&mut rng, k)?;
    let l = d.radii[0] + d.radii[1];
    let bodies = [0, 1].map(|i| Spinning {
        radius: d.radii[i],
        mass: d.masses[i],
        spin: d.spins[i],
    });
    let touch = scale(l, d.normal);
    let exact = solve_frictional(
        &d.law,
        &d.friction,
        &bodies,
        touch,
        d.velocity,
        &SolverOptions::default(),
    )
    .map_err(|e| HarnessError::Invalid(format!("exact frictional contact: {e}")))?;
    let tau = exact.duration;
    // MD steps are whole fractions of τ so that touch and observation fall on steps.
    let per_contact = (1.0 / settings.md_dt_fraction).round();
    let dt = tau / per_contact;
    let lead = 0.25 * tau;
    let t_obs = lead + 1.5 * tau;
    let exact_state = (
        add_scaled(exact.separation, t_obs - lead - tau, exact.velocity),
        exact.velocity,
        exact.spins,
    );
    let coarse = md_run(&d, lead, dt, t_obs)?;
    let fine = md_run(&d, lead, 0.5 * dt, t_obs)?;
    // Walton's rule at touch: e of this normal law (the exact contact without friction),
    // β₀ of the sticking tangential oscillator over the contact, −cos(ω_t τ), with the
    // tangential mass m_eff/(1 + m_eff Σ R²/I) (Schäfer, Dippel & Wolf 1996, Sec. 3).
    let smooth = solve_frictional(
        &d.law,
        &HistorySpring::new(0.0, 1.0, 0.0)?,
        &bodies,
        touch,
        d.velocity,
        &SolverOptions::default(),
    )
    .map_err(|e| HarnessError::Invalid(format!("exact frictionless contact: {e}")))?;
    let v_n0 = dot(d.velocity, d.normal);
    let n_end = scale(1.0 / norm(smooth.separation), smooth.separation);
    let e = -dot(smooth.velocity, n_end) / v_n0;
    let m_eff = d.masses[0] * d.masses[1] / (d.masses[0] + d.masses[1]);
    let inv_inertia: f64 = (0..2)
        .map(|i| 1.0 / (SOLID_SPHERE_INERTIA * d.masses[i]))
        .sum();
    let m_t = m_eff / (1.0 + m_eff * inv_inertia);
    let omega_t = (d.friction.stiffness / m_t).sqrt();
    let beta = -(omega_t * smooth.duration).cos();
    let walton = Walton::new(d.friction.friction, beta.clamp(-1.0, 1.0))?;
    let total = d.masses[0] + d.masses[1];
    let rough = [0, 1].map(|i| Rough {
        velocity: scale(
            if i == 0 { d.masses[1] } else { -d.masses[0] } / total,
            d.velocity,
        ),
        spin: d.spins[i],
        radius: d.radii[i],
        mass: d.masses[i],
    });
    let w = rough_pair(d.normal, &rough[0], &rough[1], e.clamp(0.0, 1.0), &walton);
    let v_w = sub(w.velocity[0], w.velocity[1]);
    let walton_state = (add_scaled(touch, t_obs - lead, v_w), v_w, w.spin);
    Ok(FrictionImpact {
        hertz: d.hertz,
        friction: d.friction.friction,
        unequal: d.radii[0] != d.radii[1],
        eccentricity: d.eccentricity,
        switches: exact.switches,
        md_coarse: error(&d, &coarse, &exact_state),
        md_fine: error(&d, &fine, &exact_state),
        md_truncation: error(&d, &coarse, &fine),
        walton: error(&d, &walton_state, &exact_state),
        emdstar: error(&d, &emdstar_run(&d, lead, t_obs)?, &exact_state),
    })
}

/// Runs the impacts (in parallel, in seed order).
pub fn run(settings: &FrictionPairSettings) -> Result<FrictionPairs> {
    let impacts = (0..settings.impacts)
        .into_par_iter()
        .map(|k| one(settings, k))
        .collect::<Result<Vec<_>>>()?;
    Ok(FrictionPairs { impacts })
}

/// Median and largest of a list.
pub fn median_and_worst(mut x: Vec<f64>) -> (f64, f64) {
    x.sort_by(f64::total_cmp);
    match x.len() {
        0 => (f64::NAN, f64::NAN),
        n => (x[n / 2], x[n - 1]),
    }
}

impl FrictionPairs {
    /// Median and worst of one error of one engine over the impacts.
    pub fn summary(&self, of: impl Fn(&FrictionImpact) -> f64) -> (f64, f64) {
        median_and_worst(self.impacts.iter().map(of).collect())
    }
}

/// One error of an impact.
type Pick<'a> = dyn Fn(&FrictionImpact) -> f64 + 'a;

/// The errors of each impact against the exact contact, sorted by Walton's: MD at both
/// steps, MD's truncation, Walton's rule, and the eMD* engine (positions, left;
/// velocities and spins, right).
pub fn plot(p: &FrictionPairs, path: &std::path::Path) -> std::result::Result<(), String> {
    use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
    let mut order: Vec<usize> = (0..p.impacts.len()).collect();
    order.sort_by(|&a, &b| {
        p.impacts[a]
            .walton
            .position
            .total_cmp(&p.impacts[b].walton.position)
    });
    let floor = 1e-16;
    let mut panels = Vec::new();
    for (title, what) in [
        ("relative position / l", 0),
        ("velocities, spins R ω / |v_rel|", 1),
    ] {
        let pick = |e: &StateError| {
            if what == 0 {
                e.position
            } else {
                e.velocity.max(e.spin)
            }
        };
        let mut panel = Panel::new(
            format!("frictional impacts after the contact: {title}"),
            Axis::linear("impact (sorted by Walton's miss)"),
            Axis::log("distance from the exact contact"),
        );
        panel.legend = LegendAt::LowerRight;
        let series: [(&str, &Pick, usize, Style); 5] = [
            (
                "Walton's rule (eMD)",
                &|i| pick(&i.walton),
                1,
                Style::Points(4),
            ),
            (
                "MD, dt = τ/400",
                &|i| pick(&i.md_coarse),
                0,
                Style::Points(3),
            ),
            ("MD, dt = τ/800", &|i| pick(&i.md_fine), 3, Style::Points(3)),
            (
                "MD(τ/400) − MD(τ/800)",
                &|i| pick(&i.md_truncation),
                4,
                Style::Points(2),
            ),
            ("eMD* engine", &|i| pick(&i.emdstar), 2, Style::Points(3)),
        ];
        for (label, of, color, style) in series {
            let pts = order
                .iter()
                .enumerate()
                .map(|(x, &k)| (x as f64, of(&p.impacts[k]).max(floor)))
                .collect();
            panel
                .series
                .push(Series::new(label, pts, PALETTE[color], style));
        }
        panels.push(panel);
    }
    write_png(path, (1500, 650), 1, 2, &panels)
}
