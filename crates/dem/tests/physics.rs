//! Conservation laws, restitution against published and analytic values, the LAMMPS
//! contact-end option, determinism across thread counts, and refused input.

mod common;

use common::*;
use emdstar_contact::{LinearDashpot, PairLaw, PairProperties, Vec3};
use emdstar_dem::{ContactEnd, Md, MdError, MdOptions, shortest_contact_time};
use emdstar_system::{Config, System, Wall};

/// A periodic gas from a config snippet.
fn gas(material: &str, count: usize, eta: f64, arrangement: &str) -> System {
    let text = format!(
        "t_end = 1.0\n[material]\n{material}\ndensity = 1140.0\n[gas]\ncount = {count}\n\
         radius = 0.1\narrangement = \"{arrangement}\"\npacking_fraction = {eta}\n\
         rms_speed = 1.0\nseed = 3\n"
    );
    Config::from_toml(&text).unwrap().build().unwrap()
}

const HERTZ_ELASTIC: &str = "model = \"hertz\"\nyoung = 1e9\npoisson = 0.4\ndissipation = 0.0";
const HERTZ_DAMPED: &str = "model = \"hertz\"\nyoung = 1e9\npoisson = 0.4\ndissipation = 2e-4";

/// Largest |E(t) − E(0)|/E(0) over a run of `steps` steps of `dt`, sampled every 10.
fn energy_error(system: &System, dt: f64, steps: u64) -> (f64, u64) {
    let mut md = engine(system.clone(), dt, dt * steps as f64);
    let e0 = md.thermo().total_energy();
    let mut worst: f64 = 0.0;
    let mut contacts = 0;
    for _ in 0..steps / 10 {
        md.advance(10).unwrap();
        let th = md.thermo();
        contacts += th.contacts as u64;
        worst = worst.max((th.total_energy() - e0).abs() / e0);
    }
    (worst, contacts)
}

#[test]
fn elastic_gas_conserves_energy_to_second_order() {
    // 216 Hertz spheres at η = 0.25: about 30 collisions per particle-second.
    let system = gas(HERTZ_ELASTIC, 216, 0.25, "random");
    let tc = shortest_contact_time(&system, 0.0).unwrap().unwrap();
    let t = 0.15;
    let dt = tc / 25.0;
    let (e1, contacts) = energy_error(&system, dt, (t / dt) as u64);
    let (e2, _) = energy_error(&system, dt / 2.0, (t / dt) as u64 * 2);
    println!(
        "elastic gas: max |ΔE|/E = {e1:.3e} (dt = t_c/25), {e2:.3e} (t_c/50); contact samples {contacts}"
    );
    assert!(contacts > 50, "the run must see collisions");
    // Velocity Verlet's energy error is bounded and O(dt²) (a shadow Hamiltonian).
    assert!(e1 < 5e-4, "energy error {e1}");
    let ratio = e1 / e2;
    assert!(
        (3.0..8.0).contains(&ratio),
        "error ratio for dt/2 is {ratio}, second order gives 4"
    );
}

#[test]
fn damped_gas_conserves_momentum_to_round_off() {
    let system = gas(HERTZ_DAMPED, 343, 0.3, "lattice");
    let tc = shortest_contact_time(&system, 0.0).unwrap().unwrap();
    let mut md = engine(system, tc / 50.0, 1.0);
    let p0 = md.thermo().momentum;
    let scale: f64 = md.system().particles.mass.iter().sum::<f64>() * 1.0;
    let e0 = md.thermo().kinetic_energy;
    md.advance(3000).unwrap();
    let th = md.thermo();
    let dp = (Vec3::from(th.momentum) - Vec3::from(p0)).norm() / scale;
    println!(
        "damped gas: |ΔP|/(M v_rms) = {dp:.3e}, kinetic energy {e0:.3e} -> {:.3e}",
        th.kinetic_energy
    );
    assert!(th.kinetic_energy < 0.99 * e0, "the gas must have cooled");
    assert!(dp < 1e-14, "momentum drift {dp}");
}

#[test]
fn central_wall_bounce_has_the_laws_restitution() {
    let s = species();
    let wall = Wall {
        normal: [0.0, 0.0, 1.0],
        point: [0.0, 0.0, -0.5],
        vibration: None,
    };
    let bounce = |law, v0: f64| {
        let mut system = free_system(
            law,
            &[(
                Vec3::new(0.0, 0.0, -0.5 + RADIUS + 0.01),
                Vec3::new(0.3, 0.0, -v0),
            )],
        );
        system.domain.walls.push(wall);
        let tc = shortest_contact_time(&system, 0.0).unwrap().unwrap();
        let t_end = 0.01 / v0 + 3.0 * tc;
        let steps = (t_end / (tc / 4000.0)).ceil() as u64;
        let mut md = engine(system, t_end / steps as f64, t_end);
        md.advance(steps).unwrap();
        let v = md.system().particles.velocity[0];
        assert_eq!(
            v[0], 0.3,
            "a frictionless wall keeps the tangential velocity"
        );
        v[2] / v0
    };
    // Linear dashpot: Schwager & Pöschel 2007 (m_eff = m against a wall).
    let gamma = 20.0;
    let exact = LinearDashpot::new(2000.0, gamma)
        .unwrap()
        .central_impact(s.mass)
        .unwrap()
        .restitution;
    let eps = bounce(linear(gamma), 2.0);
    println!("linear wall bounce: ε = {eps:.6}, Schwager & Pöschel {exact:.6}");
    assert!((eps - exact).abs() < 2e-5);
    // Hertz: the published ε(δ = c_dis) for δ = 0.3 and 1.0 (docs/physics.md, "Reference values").
    let v0: f64 = 1.5;
    let PairLaw::Hertz { rho_el, .. } = PairLaw::same_material(&hertz(0.0), RADIUS).unwrap() else {
        unreachable!()
    };
    let wall_pair = PairProperties::sphere_wall(&s.sphere());
    let t_scale = (rho_el / wall_pair.m_eff).powf(-0.4) * v0.powf(-0.2);
    for (delta, published) in [(0.3, 0.722085), (1.0, 0.393931)] {
        let a = delta * 2.0 * t_scale / 3.0; // c_dis = 3A/(2T)
        let eps = bounce(hertz(a), v0);
        println!("hertz wall bounce δ = {delta}: ε = {eps:.6}, published {published}");
        assert!((eps - published).abs() < 5e-4, "ε = {eps}");
    }
}

#[test]
fn overlap_zero_option_matches_the_unclipped_dashpot() {
    // With F unclipped until ξ = 0 the linear dashpot is the plain damped oscillator:
    // t_c = π/ω and ε = exp(−βπ/ω) (e.g. Schwager & Pöschel 2007, Eq. 5).
    let s = species();
    let (k, gamma, v0) = (2000.0, 15.0, 2.0);
    let m_eff = s.mass / 2.0;
    let beta = gamma / (2.0 * m_eff);
    let omega = (k / m_eff - beta * beta).sqrt();
    let exact = (-beta * std::f64::consts::PI / omega).exp();
    let clipped = LinearDashpot::new(k, gamma)
        .unwrap()
        .central_impact(m_eff)
        .unwrap()
        .restitution;
    let run = |end| {
        let system = free_system(
            linear(gamma),
            &[
                (Vec3::new(0.1001, 0.0, 0.0), Vec3::new(-v0 / 2.0, 0.0, 0.0)),
                (Vec3::new(-0.1001, 0.0, 0.0), Vec3::new(v0 / 2.0, 0.0, 0.0)),
            ],
        );
        let t_end = 0.2;
        let steps = 40_000;
        let mut md = Md::new(
            system,
            MdOptions {
                dt: t_end / steps as f64,
                contact_end: end,
                skin: None,
            },
            t_end,
        )
        .unwrap();
        md.advance(steps).unwrap();
        let p = md.particles_in_config_order();
        (p.velocity[0][0] - p.velocity[1][0]) / v0
    };
    let (overlap, force) = (run(ContactEnd::OverlapZero), run(ContactEnd::ForceZero));
    println!(
        "overlap-zero ε = {overlap:.6} (exact {exact:.6}); force-zero ε = {force:.6} (exact {clipped:.6})"
    );
    assert!((overlap - exact).abs() < 2e-4);
    assert!((force - clipped).abs() < 2e-4);
    assert!(overlap < force, "the attractive tail dissipates more");
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // More particles than one chunk, so that the parallel sweep runs with 2 threads.
    let mut system = gas(HERTZ_DAMPED, 2197, 0.3, "random");
    let tc = shortest_contact_time(&system, 0.0).unwrap().unwrap();
    let run = |threads, system: &System| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            // A thin skin, so that the particles are re-sorted several times.
            let opts = MdOptions {
                dt: tc / 50.0,
                contact_end: ContactEnd::ForceZero,
                skin: Some(0.01),
            };
            let mut md = Md::new(system.clone(), opts, 1.0).unwrap();
            md.advance(400).unwrap();
            (md.particles_in_config_order(), md.thermo(), md.rebuilds())
        })
    };
    // Without gravity the sweeps skip the velocity write-back; with it they do not.
    for gravity in [[0.0; 3], [0.3, -1.0, -9.81]] {
        system.domain.gravity = gravity;
        let (a, b) = (run(1, &system), run(2, &system));
        assert!(
            a.1.contacts > 0 && a.2 > 1,
            "contacts {} rebuilds {}",
            a.1.contacts,
            a.2
        );
        assert_eq!(a.0.position, b.0.position);
        assert_eq!(a.0.velocity, b.0.velocity);
        assert_eq!(a.1, b.1);
    }
}

#[test]
fn bad_engine_input_is_refused_with_the_reason() {
    let system = gas(HERTZ_ELASTIC, 27, 0.1, "lattice");
    let tc = shortest_contact_time(&system, 0.0).unwrap().unwrap();
    let opts = |dt, skin| MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin,
    };
    let err = Md::new(system.clone(), opts(tc / 5.0, None), 1.0)
        .err()
        .unwrap();
    assert!(matches!(err, MdError::DtTooCoarse { .. }), "{err}");
    assert!(err.to_string().contains("1/10"), "{err}");
    for dt in [f64::NAN, -1e-6, 0.0] {
        assert!(matches!(
            Md::new(system.clone(), opts(dt, None), 1.0),
            Err(MdError::BadDt(_))
        ));
    }
    assert!(matches!(
        Md::new(system.clone(), opts(tc / 50.0, Some(-0.1)), 1.0),
        Err(MdError::BadSkin(_))
    ));
    // 27 spheres at η = 0.1: box side ≈ 1.04 m < 3 cells of 2R + skin = 0.4 m.
    let err = Md::new(system, opts(tc / 50.0, Some(0.2)), 1.0)
        .err()
        .unwrap();
    assert!(matches!(err, MdError::BoxTooSmall { .. }), "{err}");
    assert!(
        err.to_string().contains("too small for the cell list"),
        "{err}"
    );
}
