//! Lees–Edwards shear on MD, eMD and eMD*: a free sphere through the sliding face
//! against the analytic image; an oblique inelastic collision across the face in MD
//! against eMD's kick (the dashpot acts on the image's relative velocity), and on eMD*
//! against the same collision inside the box; MD against eMD on the same sheared
//! inelastic gas (a stiff linear contact, so that MD's spheres are nearly hard): the
//! shear stress P_xy and the temperature agree within the noise; and MD against eMD*
//! in the steady state of a sheared inelastic gas: kT, the pressure tensor and a₂.

use emdstar_engines::observe::{reading, since};
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::{Config, Particles};

fn engine(text: &str, kind: EngineKind) -> AnyEngine {
    let config = Config::from_toml(text).unwrap();
    let system = config.build().unwrap();
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    AnyEngine::build(&options, &config, system, 1.0 / 50.0).unwrap()
}

fn material(restitution: f64) -> String {
    format!(
        "[material]\nmodel = \"linear\"\nstiffness = 1e5\nrestitution = {restitution}\n\
         density = 1.909859\n"
    )
}

#[test]
fn a_free_sphere_through_the_sliding_face_lands_on_its_image_in_md_and_emd() {
    // γ̇ = 0.3/s, L = (5, 4, 6) m: the image above moves at 1.2 m/s; the sphere leaves
    // through the top at t = 2 s (Δ = 2.4 m) and is read at t = 3 s.
    let text = format!(
        "t_end = 3.0\n{}[[particles]]\nradius = 0.2\nposition = [1.0, 3.5, 2.0]\n\
         velocity = [0.7, 0.25, -0.1]\n[box]\nsize = [5.0, 4.0, 6.0]\nshear_rate = 0.3\n",
        material(1.0)
    );
    let want_x = (1.0_f64 + 0.7 * 2.0 - 2.4 + (0.7 - 1.2) * 1.0).rem_euclid(5.0);
    for kind in [EngineKind::Md, EngineKind::Emd] {
        let mut e = engine(&text, kind);
        let sim = e.sim_mut();
        sim.advance_to(3.0).unwrap();
        let p = sim.particles();
        let (x, v) = (p.position[0], p.velocity[0]);
        assert!((sim.time() - 3.0).abs() < 1e-9, "{kind:?}");
        let want = [want_x, 3.5 + 0.75 - 4.0, 2.0 - 0.3];
        for k in 0..3 {
            assert!(
                (x[k] - want[k]).abs() < 1e-9,
                "{kind:?}: {x:?} against {want:?}"
            );
        }
        assert!((v[0] - (0.7 - 1.2)).abs() < 1e-12, "{kind:?}: {v:?}");
        assert_eq!(p.image[0][1], 1, "{kind:?}");
    }
}

#[test]
fn an_oblique_inelastic_collision_across_the_sliding_face_is_md_as_emd() {
    // γ̇ = 1/3 s⁻¹, L_y = 6 m: the image above moves at 2 m/s. B's image above, at
    // (2.3, 6.5) with velocity (−2 + 2, −0.5) = (0, −0.5), meets A head on along y but
    // off-centre along x (n_x ≈ −0.3 at contact, t ≈ 0.25 s); restitution 0.5.
    let text = format!(
        "t_end = 1.0\n{}[[particles]]\nradius = 0.5\nposition = [2.0, 5.3, 3.0]\n\
         velocity = [0.0, 0.5, 0.0]\n[[particles]]\nradius = 0.5\nposition = [2.3, 0.5, 3.0]\n\
         velocity = [-2.0, -0.5, 0.0]\n[box]\nsize = [6.0, 6.0, 6.0]\n\
         shear_rate = 0.3333333333333333\n",
        material(0.5)
    );
    let velocities = |kind| {
        let mut e = engine(&text, kind);
        let sim = e.sim_mut();
        sim.advance_to(1.0).unwrap();
        sim.particles().velocity
    };
    let (md, emd) = (velocities(EngineKind::Md), velocities(EngineKind::Emd));
    // They did collide: A's velocity changed.
    assert!((emd[0][1] - 0.5).abs() > 0.3, "{emd:?}");
    for i in 0..2 {
        for k in 0..3 {
            assert!(
                (md[i][k] - emd[i][k]).abs() < 5e-3,
                "particle {i}: MD {:?}, eMD {:?}",
                md[i],
                emd[i]
            );
        }
    }
}

#[test]
fn an_oblique_inelastic_emdstar_collision_across_the_sliding_face_is_the_one_inside_the_box() {
    // The collision above, on eMD*: across the face (A near the top, B near the bottom,
    // its image above meeting A), and the same pair inside the box, 3 m lower, with B
    // at its image's place and velocity at t = 0: (2.3, 3.5), (0, −0.5). The contact
    // is resolved in the pair's frame, so both give the same outcome; across the face
    // B's real position and velocity are its image's less the slide, Δ(1 s) = 2 m
    // along x and L_y = 6 m along y, and γ̇ L_y = 2 m/s along x. MD, across the face,
    // agrees to its step's accuracy.
    let pair = |a: [f64; 3], b: [f64; 3], vb: [f64; 3]| {
        format!(
            "t_end = 1.0\n{}[[particles]]\nradius = 0.5\nposition = {a:?}\n\
             velocity = [0.0, 0.5, 0.0]\n[[particles]]\nradius = 0.5\nposition = {b:?}\n\
             velocity = {vb:?}\n[box]\nsize = [6.0, 6.0, 6.0]\n\
             shear_rate = 0.3333333333333333\n",
            material(0.5)
        )
    };
    let across = pair([2.0, 5.3, 3.0], [2.3, 0.5, 3.0], [-2.0, -0.5, 0.0]);
    let inside = pair([2.0, 2.3, 3.0], [2.3, 3.5, 3.0], [0.0, -0.5, 0.0]);
    let run = |text: &str, kind| {
        let mut e = engine(text, kind);
        let sim = e.sim_mut();
        sim.advance_to(1.0).unwrap();
        sim.particles()
    };
    let (star, star_inside) = (
        run(&across, EngineKind::EmdStar),
        run(&inside, EngineKind::EmdStar),
    );
    let md = run(&across, EngineKind::Md);
    // They did collide: A's velocity changed.
    assert!(
        (star.velocity[0][1] - 0.5).abs() > 0.3,
        "{:?}",
        star.velocity
    );
    // (position shift, x-velocity shift) from inside the box to across the face.
    let shift = [([0.0, 3.0, 0.0], 0.0), ([-2.0, -3.0, 0.0], -2.0)];
    for (i, (dx, dvx)) in shift.iter().enumerate() {
        let (x, v) = (star.position[i], star.velocity[i]);
        let (xi, vi) = (star_inside.position[i], star_inside.velocity[i]);
        let want_x: [f64; 3] = std::array::from_fn(|k| xi[k] + dx[k]);
        let want_v = [vi[0] + dvx, vi[1], vi[2]];
        for k in 0..3 {
            assert!(
                (x[k] - want_x[k]).abs() < 1e-9 && (v[k] - want_v[k]).abs() < 1e-9,
                "particle {i}: across {x:?} {v:?}, inside {want_x:?} {want_v:?}"
            );
            assert!(
                (md.velocity[i][k] - v[k]).abs() < 5e-3,
                "particle {i}: MD {:?}, eMD* {v:?}",
                md.velocity[i]
            );
        }
    }
}

/// Mean and standard error of `x`.
fn mean_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// 500 unit spheres at φ = 0.15 with restitution 0.9, from a random start of
/// `rms_speed` (m/s, peculiar) drawn with `seed`, sheared at `rate` (1/s).
fn sheared_gas(rms_speed: f64, seed: u64, rate: f64) -> String {
    format!(
        "t_end = 100.0\n{}[gas]\ncount = 500\nradius = 0.5\narrangement = \"random\"\n\
         rms_speed = {rms_speed:?}\nseed = {seed}\n[box]\nsize = [12.04, 12.04, 12.04]\n\
         shear_rate = {rate:?}\n",
        material(0.9)
    )
}

#[test]
fn md_and_emd_shear_the_same_gas_with_the_same_stress() {
    // 500 unit spheres at φ = 0.15, kT₀ = 1 J, restitution 0.9 (MD's linear dashpot,
    // eMD's kick), γ̇ = 0.2/s; P_xy ≈ −0.03 Pa. Each engine's P_xy and kT from 12
    // blocks of 1.5 s after 2 s.
    let text = sheared_gas(1.7320508, 5, 0.2);
    let run = |kind| {
        let blocks = steady_blocks(&text, kind, 2.0, 12, 1.5);
        let column = |k: usize| mean_error(&blocks.iter().map(|b| b[k]).collect::<Vec<_>>());
        (column(5), column(0).0)
    };
    let ((md, md_err), t_md) = run(EngineKind::Md);
    let ((emd, emd_err), t_emd) = run(EngineKind::Emd);
    eprintln!("P_xy: MD {md} ± {md_err}, eMD {emd} ± {emd_err}; T: MD {t_md}, eMD {t_emd}");
    assert!(
        md < -0.03 && emd < -0.03,
        "the shear stress opposes the flow"
    );
    assert!(
        (md - emd).abs() < 3.0 * md_err.hypot(emd_err),
        "P_xy: MD {md} ± {md_err}, eMD {emd} ± {emd_err}"
    );
    // Both settle where shear heating balances the dissipation, about 0.2 J (from
    // 1 J); T of 500 spheres fluctuates by some 4 % per block.
    assert!(t_md < 0.5 && t_emd < 0.5, "{t_md} {t_emd}");
    assert!(
        (t_md / t_emd - 1.0).abs() < 0.08,
        "T: MD {t_md}, eMD {t_emd}"
    );
}

/// The steady sheared state of `kind` on the gas `text` after `relax` s: per block of
/// `block` s, (kT and a₂ averaged over 5 instants, P_xx, P_yy, P_zz, P_xy over the block).
fn steady_blocks(
    text: &str,
    kind: EngineKind,
    relax: f64,
    blocks: usize,
    block: f64,
) -> Vec<[f64; 6]> {
    let mut e = engine(text, kind);
    let sim = e.sim_mut();
    sim.advance_to(relax).unwrap();
    let mut out = Vec::new();
    for b in 0..blocks {
        let from = reading(sim);
        let (mut kt, mut a2) = (0.0, 0.0);
        for k in 1..=5 {
            sim.advance_to(relax + block * (b as f64 + k as f64 / 5.0))
                .unwrap();
            kt += sim.thermo().granular_temperature / 5.0;
            a2 += since(sim, None).sonine_a2 / 5.0;
        }
        let p = since(sim, Some(&from)).tensor;
        out.push([kt, a2, p[0], p[1], p[2], p[3]]);
    }
    out
}

#[test]
fn md_and_emdstar_reach_the_same_steady_sheared_state() {
    // 500 unit spheres at φ = 0.15, restitution 0.9 (MD's linear dashpot and eMD*'s
    // matrix of restitution of the same contact, 7 ms long), γ̇ = 1/s: the steady
    // state (kT ≈ 3 J, where it starts) after 2 s, then 9 s (some 40 collisions per
    // particle), six seeds. kT, the pressure tensor and a₂ agree within three standard
    // errors of the difference, the errors of the six runs' means: the temperature of
    // 500 spheres wanders over several seconds, so blocks of one run would understate
    // them (by about half).
    let names = ["kT", "a2", "P_xx", "P_yy", "P_zz", "P_xy"];
    let run = |kind| {
        let means: Vec<[f64; 6]> = (21..27)
            .map(|seed| {
                let blocks = steady_blocks(&sheared_gas(3.0, seed, 1.0), kind, 2.0, 3, 3.0);
                std::array::from_fn(|k| blocks.iter().map(|b| b[k]).sum::<f64>() / 3.0)
            })
            .collect();
        let column = |k: usize| mean_error(&means.iter().map(|m| m[k]).collect::<Vec<_>>());
        std::array::from_fn::<_, 6, _>(column)
    };
    let (md, star) = (run(EngineKind::Md), run(EngineKind::EmdStar));
    for (k, name) in names.iter().enumerate() {
        let ((m, me), (s, se)) = (md[k], star[k]);
        eprintln!("{name}: MD {m} ± {me}, eMD* {s} ± {se}");
        assert!(
            (m - s).abs() < 3.0 * me.hypot(se),
            "{name}: MD {m} ± {me}, eMD* {s} ± {se}"
        );
    }
    // The shear stress opposes the flow, well beyond the noise.
    assert!(star[5].0 < -10.0 * star[5].1, "{:?}", star[5]);
}

/// Σ ½ m c² with c = v − γ̇ (y − L_y/2) e_x (the box from 0).
fn peculiar_energy(p: &Particles, rate: f64, ly: f64) -> f64 {
    (0..p.len())
        .map(|i| {
            let mut c = p.velocity[i];
            c[0] -= rate * (p.position[i][1] - 0.5 * ly);
            0.5 * p.mass[i] * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
        })
        .sum()
}

/// An elastic soft-sphere gas sheared hard: the boundaries' work −γ̇ V ∫P_xy dt (the
/// tensor MD sums, kinetic and virial) is the gain of the peculiar kinetic plus the
/// elastic energy, to the accuracy of the time step.
#[test]
fn md_heats_a_sheared_elastic_gas_by_the_work_of_the_boundaries() {
    let (rate, side) = (0.5, 12.04);
    let text = format!(
        "t_end = 4.0\n{}[gas]\ncount = 500\nradius = 0.5\narrangement = \"random\"\n\
         rms_speed = 1.7320508\nseed = 9\n[box]\nsize = [{side}, {side}, {side}]\n\
         shear_rate = {rate}\n",
        material(1.0)
    );
    let mut e = engine(&text, EngineKind::Md);
    let sim = e.sim_mut();
    let energy = |sim: &dyn emdstar_system::Simulation| {
        peculiar_energy(&sim.particles(), rate, side) + sim.thermo().potential_energy
    };
    let (e0, s0) = (energy(sim), sim.stress_sums());
    sim.advance_to(4.0).unwrap();
    let (e1, s1) = (energy(sim), sim.stress_sums());
    let work = -rate * (s1.kinetic[3] - s0.kinetic[3] + s1.collisional[3] - s0.collisional[3]);
    eprintln!("energy {e0} -> {e1}: gain {}, work {work}", e1 - e0);
    assert!(e1 - e0 > 0.1 * e0, "{e0} -> {e1}");
    assert!(
        ((e1 - e0) / work - 1.0).abs() < 2e-3,
        "gain {} against the work {work}",
        e1 - e0
    );
}
