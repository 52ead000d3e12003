//! MD against eMD* (exact MoR, tables, the exact frictional contact) on random impacts
//! of unlike materials and of spheres on walls of another material, each against the
//! exact two-body outcome (`emdstar_mor::rule`): eMD* must land on it, and MD within its
//! own truncation error (its distance from the outcome at τ/800 no more than one and a
//! half times its step change from τ/400).

use emdstar_contact::vec3::{add_scaled, dot, norm, scale};
use emdstar_contact::{Impact, scale as scale_impact};
use emdstar_harness::engines::{EventKind, event_engine, event_state, md_engine};
use emdstar_mor::rule::{Body, exact_collision, frictional_collision, resolve_wall};
use emdstar_mor::{SolverOptions, solve};
use emdstar_system::{Config, Simulation, System};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DENSITIES: [f64; 2] = [1140.0, 2500.0];

/// One random impact: the two materials' keys and their pair's entry, the spheres (or
/// one sphere and the wall) and their motion.
struct Draw {
    hertz: bool,
    frictional: bool,
    materials: [String; 2],
    entry: String,
    radii: [f64; 2],
    /// Relative velocity at touch, the normal there (x_1 − x_2 direction, or the wall's).
    velocity: [f64; 3],
    normal: [f64; 3],
    spins: [[f64; 3]; 2],
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

fn draw(rng: &mut ChaCha8Rng, hertz: bool, frictional: bool) -> Draw {
    let friction = |rng: &mut ChaCha8Rng, k_t: f64| {
        if frictional {
            format!(
                "friction = {}\ntangential_stiffness = {k_t}\ntangential_damping = {}\n",
                rng.random_range(0.1..0.8),
                rng.random_range(0.0..0.5)
            )
        } else {
            String::new()
        }
    };
    let material = |rng: &mut ChaCha8Rng, k: usize| {
        let (law, k_t) = if hertz {
            let young: f64 = 10f64.powf(rng.random_range(7.0..9.0));
            let law = format!(
                "model = \"hertz\"\nyoung = {young:e}\npoisson = {}\n",
                rng.random_range(0.2..0.45)
            );
            (law, 2e4)
        } else {
            let k: f64 = rng.random_range(1e3..1e4);
            (format!("model = \"linear\"\nstiffness = {k}\n"), 0.3 * k)
        };
        format!("{law}density = {}\n{}", DENSITIES[k], friction(rng, k_t))
    };
    let materials = [material(rng, 0), material(rng, 1)];
    // The pair's own dissipation (and, for the linear law, stiffness) and friction.
    let entry = if hertz {
        format!(
            "dissipation = {:e}\n{}",
            rng.random_range(0.0..2e-4),
            friction(rng, 2e4)
        )
    } else {
        let k: f64 = rng.random_range(1e3..1e4);
        format!(
            "model = \"linear\"\nstiffness = {k}\ndamping = {}\n{}",
            rng.random_range(0.0..3.0),
            friction(rng, 0.3 * k)
        )
    };
    let radii = [rng.random_range(0.05..0.1), rng.random_range(0.05..0.1)];
    let speed: f64 = rng.random_range(0.5..3.0);
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
    let spins = if frictional {
        radii.map(|r| scale(rng.random_range(0.0..2.0) * speed / r, unit(rng)))
    } else {
        [[0.0; 3]; 2]
    };
    Draw {
        hertz,
        frictional,
        materials,
        entry,
        radii,
        velocity,
        normal,
        spins,
    }
}

fn mass(d: &Draw, k: usize) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * d.radii[k].powi(3) * DENSITIES[k]
}

/// The config of `d`: sphere 1 of material a and, for a pair, sphere 2 of b started so
/// that they touch at `lead` (the centre of mass at rest at the origin); for a wall,
/// sphere 1 alone above a wall of b through the origin.
fn config(d: &Draw, wall: bool, lead: f64, t_end: f64) -> System {
    let m = [mass(d, 0), mass(d, 1)];
    let sphere = |k: usize, x: [f64; 3], v: [f64; 3]| {
        format!(
            "[[particles]]\nradius = {}\nposition = {x:?}\nvelocity = {v:?}\n\
             angular_velocity = {:?}\nmaterial = \"{}\"\n",
            d.radii[k],
            d.spins[k],
            ["a", "b"][k]
        )
    };
    let bodies = if wall {
        let touch = scale(d.radii[0], d.normal);
        sphere(0, add_scaled(touch, -lead, d.velocity), d.velocity)
            + &format!(
                "[[walls]]\nnormal = {:?}\npoint = [0.0, 0.0, 0.0]\nmaterial = \"b\"\n",
                d.normal
            )
    } else {
        let l = d.radii[0] + d.radii[1];
        let r0 = add_scaled(scale(l, d.normal), -lead, d.velocity);
        let share = [m[1] / (m[0] + m[1]), -m[0] / (m[0] + m[1])];
        sphere(0, scale(share[0], r0), scale(share[0], d.velocity))
            + &sphere(1, scale(share[1], r0), scale(share[1], d.velocity))
    };
    let text = format!(
        "t_end = {t_end}\n[[materials]]\nname = \"a\"\n{}[[materials]]\nname = \"b\"\n{}\
         [[interactions]]\nmaterials = [\"a\", \"b\"]\n{}{bodies}",
        d.materials[0], d.materials[1], d.entry
    );
    Config::from_toml(&text)
        .and_then(|c| c.build())
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Positions, velocities and spins of the bodies that move (scaled by l, |v| and |v|/l).
fn scaled(d: &Draw, x: &[[f64; 3]], v: &[[f64; 3]], w: &[[f64; 3]]) -> Vec<f64> {
    let l = d.radii[0] + if x.len() > 1 { d.radii[1] } else { 0.0 };
    let speed = norm(d.velocity);
    let mut out = Vec::new();
    for k in 0..x.len() {
        out.extend(x[k].map(|c| c / l));
        out.extend(v[k].map(|c| c / speed));
        out.extend(w[k].map(|c| c * l / speed));
    }
    out
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The exact state at `t_obs` of `d` touching at `lead` (in the frame of [`config`]),
/// and the contact's duration.
fn exact(d: &Draw, wall: bool, lead: f64, t_obs: f64) -> (Vec<f64>, f64) {
    let system = config(d, wall, lead, t_obs);
    let p = &system.particles;
    let at_touch = |k: usize| Body {
        position: add_scaled(p.position[k], lead, p.velocity[k]).into(),
        velocity: p.velocity[k].into(),
        mass: p.mass[k],
    };
    if wall {
        let contact = system.interactions().wall(0, 0);
        assert!(
            !d.frictional,
            "frictional walls are checked where eMD* solves them"
        );
        let v_n = -dot(d.velocity, d.normal);
        let impact = Impact {
            normal_speed: v_n,
            tangential_speed: 0.0,
        };
        let scaled_impact = scale_impact(contact.law(), &contact.props, &impact).unwrap();
        let mor = solve(contact.law().model(), &scaled_impact.params).unwrap();
        let out = resolve_wall(
            &at_touch(0),
            &d.normal.into(),
            contact.props.l,
            &mor,
            scaled_impact.time,
        );
        let after = out.after[0];
        let rest = t_obs - lead - out.duration;
        let x = add_scaled(after.position.into(), rest, after.velocity.into());
        return (
            scaled(d, &[x], &[after.velocity.into()], &[[0.0; 3]]),
            out.duration,
        );
    }
    let contact = system.interactions().pair(0, 1);
    let bodies = [at_touch(0), at_touch(1)];
    let (out, spins) = match contact.tangential() {
        emdstar_contact::Tangential::History(spring) => frictional_collision(
            contact.law(),
            spring,
            &bodies,
            d.radii,
            d.spins,
            &SolverOptions::default(),
        )
        .unwrap(),
        _ => (
            exact_collision(contact.law(), &contact.props, &bodies)
                .unwrap()
                .0,
            d.spins,
        ),
    };
    let rest = t_obs - lead - out.duration;
    let x = out
        .after
        .map(|b| add_scaled(b.position.into(), rest, b.velocity.into()));
    let v = out.after.map(|b| b.velocity.into());
    (scaled(d, &x, &v, &spins), out.duration)
}

fn md(d: &Draw, wall: bool, lead: f64, t_obs: f64, steps: f64) -> Vec<f64> {
    let dt = t_obs / steps;
    let mut md = md_engine(config(d, wall, lead, t_obs), dt, t_obs).unwrap();
    md.advance(steps as u64).unwrap();
    let p = md.particles_in_config_order();
    scaled(d, &p.position, &p.velocity, &p.angular_velocity)
}

fn emdstar(d: &Draw, wall: bool, lead: f64, t_obs: f64, kind: EventKind) -> Vec<f64> {
    let mut e = event_engine(&config(d, wall, lead, t_obs), kind).unwrap();
    e.advance_to(t_obs).unwrap();
    let w = e.angular_velocities();
    let (x, v) = event_state(&mut e);
    scaled(d, &x, &v, &w)
}

/// Runs `impacts` draws of each kind and checks every engine against the exact outcome.
fn check(wall: bool, frictional: bool, impacts: usize, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for k in 0..impacts {
        let d = draw(&mut rng, k % 2 == 1, frictional);
        // The contact's duration first, then a start a quarter of it before touch and
        // an observation half of it after its end.
        let (_, tau) = exact(&d, wall, 1.0, 3.0);
        let (lead, t_obs) = (0.25 * tau, 2.0 * tau);
        let (reference, _) = exact(&d, wall, lead, t_obs);
        // τ/400 and τ/800, over the run of 2τ.
        let coarse = md(&d, wall, lead, t_obs, 800.0);
        let fine = md(&d, wall, lead, t_obs, 1600.0);
        let (md_error, md_change) = (distance(&fine, &reference), distance(&fine, &coarse));
        let kinds: &[EventKind] = if frictional {
            &[EventKind::EmdStarExact]
        } else {
            &[EventKind::EmdStarExact, EventKind::EmdStarTable]
        };
        let what = format!(
            "{} {} impact {k} ({})",
            if wall { "wall" } else { "pair" },
            if frictional { "frictional" } else { "smooth" },
            if d.hertz { "Hertz" } else { "linear" }
        );
        for &kind in kinds {
            let star = distance(&emdstar(&d, wall, lead, t_obs, kind), &reference);
            let bar = if kind == EventKind::EmdStarExact {
                1e-7
            } else {
                1e-5
            };
            eprintln!(
                "{what}: eMD* ({}) {star:.1e}; MD at τ/800 {md_error:.1e} (step change {md_change:.1e})",
                kind.name()
            );
            assert!(star < bar, "{what}: eMD* ({}) {star:e}", kind.name());
        }
        assert!(
            md_error <= 1.5 * md_change + 1e-9,
            "{what}: MD {md_error:e} from the outcome, its step change {md_change:e}"
        );
    }
}

#[test]
fn unlike_smooth_pairs_agree_with_the_exact_collision() {
    check(false, false, 8, 1);
}

#[test]
fn unlike_frictional_pairs_agree_with_the_exact_contact() {
    check(false, true, 8, 2);
}

#[test]
fn smooth_wall_impacts_of_another_material_agree_with_the_exact_collision() {
    check(true, false, 8, 3);
}
