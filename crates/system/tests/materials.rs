//! Several materials: what a config of `[[materials]]`, `[[interactions]]` and
//! `material = "…"` keys builds, checked against the contact mechanics it stands for
//! (Hertz's rule, a restitution solved exactly for its pair, the wall as an infinitely
//! heavy partner), and every refusal with the key it names.

use emdstar_contact::{Impact, PairLaw, PairProperties, Sphere, Tangential, scale};
use emdstar_mor::solve;
use emdstar_system::{Config, Method, System};

fn build(text: &str) -> Result<System, String> {
    Config::from_toml(text)
        .and_then(|c| c.build())
        .map_err(|e| e.to_string())
}

const GLASS: &str = "[[materials]]\nname = \"glass\"\nmodel = \"hertz\"\nyoung = 63e9\n\
                     poisson = 0.23\ndensity = 2500.0\n";
const STEEL: &str = "[[materials]]\nname = \"steel\"\nmodel = \"hertz\"\nyoung = 200e9\n\
                     poisson = 0.3\ndensity = 7800.0\n";

/// A glass and a steel sphere side by side, and a steel floor.
fn pair_on_floor(extra: &str) -> String {
    format!(
        "t_end = 1.0\n{GLASS}{STEEL}{extra}\
         [[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.05]\nmaterial = \"glass\"\n\
         [[particles]]\nradius = 0.02\nposition = [0.1, 0.0, 0.05]\nmaterial = \"steel\"\n\
         [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, 0.0]\nmaterial = \"steel\"\n"
    )
}

/// ρ_el of a Hertz pair law.
fn rho_el(law: &PairLaw) -> f64 {
    let PairLaw::Hertz { rho_el, .. } = law else {
        panic!("not Hertz: {law:?}")
    };
    *rho_el
}

/// The central restitution of `law` for `pair` at normal speed `v`, by the exact solver.
fn central(law: &PairLaw, pair: &PairProperties, v: f64) -> f64 {
    let impact = Impact::from_speed_eccentricity(v, 0.0).unwrap();
    let scaled = scale(law, pair, &impact).unwrap();
    -solve(law.model(), &scaled.params).unwrap().eps_rdot
}

#[test]
fn unlike_hertz_spheres_mix_their_moduli_by_hertzs_rule() {
    let s = build(&pair_on_floor("")).unwrap();
    let i = s.interactions();
    assert_eq!(s.species.len(), 2);
    assert_eq!((s.species[0].material, s.species[1].material), (0, 1));
    // Each sphere's mass from its own material's density.
    let volume = |r: f64| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    assert!((s.species[0].mass / (2500.0 * volume(0.01)) - 1.0).abs() < 1e-14);
    assert!((s.species[1].mass / (7800.0 * volume(0.02)) - 1.0).abs() < 1e-14);
    // Johnson, Contact Mechanics, Eq. 4.22: 1/E* = (1−ν₁²)/Y₁ + (1−ν₂²)/Y₂ and
    // ρ_el = (4/3)E*√R_eff.
    let e_star = 1.0 / ((1.0 - 0.23f64.powi(2)) / 63e9 + (1.0 - 0.3f64.powi(2)) / 200e9);
    let pair = i.pair(0, 1);
    let expected = 4.0 / 3.0 * e_star * pair.props.r_eff.sqrt();
    assert!((rho_el(pair.law()) / expected - 1.0).abs() < 1e-12);
    assert_eq!(i.pair(1, 0).law(), pair.law());
    // Glass on a steel wall: the same E*, with R_eff = R of the glass sphere.
    let wall = i.wall(0, 0);
    assert_eq!(wall.props.r_eff, 0.01);
    let expected = 4.0 / 3.0 * e_star * 0.01f64.sqrt();
    assert!((rho_el(wall.law()) / expected - 1.0).abs() < 1e-12);
    // Like pairs keep their material's E* = Y/(2(1−ν²)).
    let glass = 63e9 / (2.0 * (1.0 - 0.23f64.powi(2)));
    let gg = i.pair(0, 0);
    let expected = 4.0 / 3.0 * glass * gg.props.r_eff.sqrt();
    assert!((rho_el(gg.law()) / expected - 1.0).abs() < 1e-12);
}

#[test]
fn an_interaction_gives_its_pair_a_law_and_a_restitution_solved_for_that_pair() {
    // Young's modulus and Poisson's ratio of the pair: as two spheres of one material
    // of these constants, E* = Y/(2(1−ν²)).
    let entry = "[[interactions]]\nmaterials = [\"glass\", \"steel\"]\nmodel = \"hertz\"\n\
                 young = 1e10\npoisson = 0.25\nrestitution = 0.7\nrestitution_speed = 2.0\n";
    let s = build(&pair_on_floor(entry)).unwrap();
    let pair = s.interactions().pair(0, 1);
    let e_star = 1e10 / (2.0 * (1.0 - 0.0625));
    let expected = 4.0 / 3.0 * e_star * pair.props.r_eff.sqrt();
    assert!((rho_el(pair.law()) / expected - 1.0).abs() < 1e-12);
    // The reference pair (the two spheres here) has ε = 0.7 at 2 m/s, by the exact
    // solver, and a faster impact less.
    let e = central(pair.law(), &pair.props, 2.0);
    assert!((e - 0.7).abs() < 1e-10, "{e}");
    assert!(central(pair.law(), &pair.props, 5.0) < 0.7);
    // The pairs without an entry stay elastic (to the solver's tolerance).
    let glass = s.interactions().pair(0, 0);
    assert!((central(glass.law(), &glass.props, 1.0) - 1.0).abs() < 1e-9);
}

#[test]
fn a_restitution_for_a_wall_material_is_solved_for_a_sphere_on_the_wall() {
    // Steel only in the walls: the glass–steel entry's restitution holds for a glass
    // sphere meeting the wall (R_eff = R, m_eff = m).
    let text = format!(
        "t_end = 1.0\n{GLASS}{STEEL}[[interactions]]\nmaterials = [\"steel\", \"glass\"]\n\
         restitution = 0.6\nrestitution_speed = 1.0\n\
         [[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.05]\nmaterial = \"glass\"\n\
         [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, 0.0]\nmaterial = \"steel\"\n"
    );
    let s = build(&text).unwrap();
    let wall = s.interactions().wall(0, 0);
    let sphere = Sphere::new(0.01, s.species[0].mass).unwrap();
    assert_eq!(wall.props, PairProperties::sphere_wall(&sphere));
    let e = central(wall.law(), &wall.props, 1.0);
    assert!((e - 0.6).abs() < 1e-10, "{e}");
    let note = &s.interactions().notes()[0];
    assert!(
        note.contains("interactions[0].restitution") && note.contains("on a wall"),
        "{note}"
    );
}

#[test]
fn a_restitution_both_materials_give_is_solved_for_their_unlike_pair() {
    let with = |m: &str| {
        m.replacen(
            "density",
            "restitution = 0.8\nrestitution_speed = 1.0\ndensity",
            1,
        )
    };
    let text = format!(
        "t_end = 1.0\n{}{}\
         [[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\nmaterial = \"glass\"\n\
         [[particles]]\nradius = 0.02\nposition = [0.1, 0.0, 0.0]\nmaterial = \"steel\"\n",
        with(GLASS),
        with(STEEL)
    );
    let s = build(&text).unwrap();
    for (a, b) in [(0, 0), (1, 1), (0, 1)] {
        let i = s.interactions().pair(a, b);
        let e = central(i.law(), &i.props, 1.0);
        assert!((e - 0.8).abs() < 1e-10, "species {a}, {b}: {e}");
    }
}

#[test]
fn friction_is_a_slot_of_each_pair_and_walls_collide_by_their_pair() {
    let rough = |name: &str, mu: f64| {
        format!(
            "[[materials]]\nname = \"{name}\"\nmodel = \"linear\"\nstiffness = 1e4\n\
             density = 1000.0\nfriction = {mu}\ntangential_stiffness = 3e3\n"
        )
    };
    let entry = "[[interactions]]\nmaterials = [\"a\", \"b\"]\nfriction = 0.7\n\
                 tangential_stiffness = 2e3\ntangential_damping = 0.1\n";
    let text = format!(
        "t_end = 1.0\n{}{}{entry}\
         [[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.05]\nmaterial = \"a\"\n\
         [[particles]]\nradius = 0.01\nposition = [0.1, 0.0, 0.05]\nmaterial = \"b\"\n\
         [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, 0.0]\nmaterial = \"b\"\n",
        rough("a", 0.2),
        rough("b", 0.5)
    );
    let s = build(&text).unwrap();
    let i = s.interactions();
    let mu = |t: &Tangential| t.friction();
    assert_eq!(mu(i.pair(0, 0).tangential()), 0.2);
    assert_eq!(mu(i.pair(1, 1).tangential()), 0.5);
    assert_eq!(mu(i.pair(0, 1).tangential()), 0.7);
    // Sphere a on wall b: the pair's law; sphere b on wall b: b's own.
    assert_eq!(mu(i.wall(0, 0).tangential()), 0.7);
    assert_eq!(mu(i.wall(1, 0).tangential()), 0.5);
    assert!(i.is_frictional());
    s.interactions().check_runs_on(Method::Md, 1).unwrap();
}

#[test]
fn a_gas_of_several_species_gets_its_shares_one_temperature_and_no_momentum() {
    let text = format!(
        "t_end = 1.0\n{GLASS}{STEEL}\
         [[interactions]]\nmaterials = [\"glass\", \"steel\"]\nrestitution = 0.9\n\
         restitution_speed = 1.0\n\
         [gas]\ncount = 3001\narrangement = \"random\"\npacking_fraction = 0.05\n\
         rms_speed = 2.0\nseed = 9\n\
         [[gas.species]]\nmaterial = \"glass\"\nradius = 0.002\nfraction = 0.3\n\
         [[gas.species]]\nmaterial = \"steel\"\nradius = 0.001\nfraction = 0.7\n"
    );
    let s = build(&text).unwrap();
    let p = &s.particles;
    let count = |k: u32| p.species.iter().filter(|&&x| x == k).count();
    // 900.3 and 2100.7: the largest remainder takes the odd sphere.
    assert_eq!((count(0), count(1)), (900, 2101));
    // η = Σ N (4/3)πR³ / V.
    let volume: f64 = (0..p.len())
        .map(|i| 4.0 / 3.0 * std::f64::consts::PI * p.radius[i].powi(3))
        .sum();
    let b = s.domain.sim_box.unwrap();
    let eta = volume / b.size.iter().product::<f64>();
    assert!((eta - 0.05).abs() < 1e-12, "{eta}");
    // Zero total momentum and the rms speed over all spheres.
    let momentum = p.momentum();
    let scale = p.total_mass() * 2.0;
    assert!(
        momentum.iter().all(|c| c.abs() < 1e-12 * scale),
        "{momentum:?}"
    );
    let ms: f64 = p
        .velocity
        .iter()
        .map(|v| v.iter().map(|c| c * c).sum::<f64>())
        .sum::<f64>()
        / p.len() as f64;
    assert!((ms.sqrt() - 2.0).abs() < 1e-12);
    // One temperature: ⟨m v²⟩ of each kind agree within sampling error (~4 %).
    let temperature = |k: u32| {
        let (mut sum, mut n) = (0.0, 0.0);
        for i in 0..p.len() {
            if p.species[i] == k {
                sum += p.mass[i] * p.velocity[i].iter().map(|c| c * c).sum::<f64>();
                n += 1.0;
            }
        }
        sum / n
    };
    let (t0, t1) = (temperature(0), temperature(1));
    assert!((t0 / t1 - 1.0).abs() < 0.15, "{t0} vs {t1}");
    // No overlaps (the system validates them) and both sizes in the box.
    assert!(p.radius.contains(&0.002) && p.radius.contains(&0.001));
}

/// Each bad input and a piece of what its message must say.
#[test]
fn bad_material_input_is_refused_naming_the_key() {
    let two = format!("t_end = 1.0\n{GLASS}{STEEL}");
    let sphere = |m: &str| format!("[[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n{m}");
    let linear = "[[materials]]\nname = \"putty\"\nmodel = \"linear\"\nstiffness = 1e3\n\
                  density = 1000.0\n";
    let cases = [
        (
            format!("{two}{}", sphere("material = \"wood\"\n")),
            vec!["particles[0].material = \"wood\"", "\"glass\", \"steel\""],
        ),
        (
            format!("{two}{}", sphere("")),
            vec!["particles[0].material is missing", "material = \"glass\""],
        ),
        (
            format!(
                "t_end = 1.0\n{GLASS}{GLASS}{}",
                sphere("material = \"glass\"\n")
            ),
            vec!["materials[1].name = \"glass\" is given twice"],
        ),
        (
            format!(
                "{two}[[interactions]]\nmaterials = [\"glass\", \"gold\"]\nrestitution = 0.5\n{}",
                sphere("material = \"glass\"\n")
            ),
            vec!["interactions[0].materials names \"gold\""],
        ),
        (
            format!(
                "{two}[[interactions]]\nmaterials = [\"glass\", \"steel\"]\nfriction = 0.0\n\
                 [[interactions]]\nmaterials = [\"steel\", \"glass\"]\nfriction = 0.0\n{}",
                sphere("material = \"glass\"\n")
            ),
            vec!["interactions[1]", "again", "interactions[0]"],
        ),
        (
            format!(
                "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 1.0\n{GLASS}{}",
                sphere("")
            ),
            vec!["either [material]", "[[materials]]"],
        ),
        (format!("t_end = 1.0\n{}", sphere("")), vec!["no material"]),
        (
            format!(
                "t_end = 1.0\n[[materials]]\nmodel = \"linear\"\nstiffness = 1.0\n{}",
                sphere("")
            ),
            vec!["materials[0].name is missing"],
        ),
        (
            // A glass sphere meets a putty one: a linear and a Hertz material.
            format!(
                "t_end = 1.0\n{GLASS}{linear}{}{}",
                sphere("material = \"glass\"\n"),
                sphere("material = \"putty\"\n").replace("[0.0, 0.0, 0.0]", "[0.1, 0.0, 0.0]")
            ),
            vec![
                "\"glass\"",
                "\"putty\"",
                "[[interactions]]",
                "materials = [\"glass\", \"putty\"]",
            ],
        ),
        (
            // Different restitutions and no entry.
            format!(
                "t_end = 1.0\n{}{}{}{}",
                GLASS.replace(
                    "density",
                    "restitution = 0.9\nrestitution_speed = 1.0\ndensity"
                ),
                STEEL.replace(
                    "density",
                    "restitution = 0.7\nrestitution_speed = 1.0\ndensity"
                ),
                sphere("material = \"glass\"\n"),
                sphere("material = \"steel\"\n").replace("[0.0, 0.0, 0.0]", "[0.1, 0.0, 0.0]")
            ),
            vec![
                "dissipations differ",
                "materials = [\"glass\", \"steel\"]",
                "restitution = …",
            ],
        ),
        (
            format!(
                "{two}{}[[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.0, 0.0, -1.0]\n",
                sphere("material = \"glass\"\n")
            ),
            vec!["walls[0].material is missing"],
        ),
        (
            format!(
                "{two}[gas]\ncount = 10\narrangement = \"lattice\"\npacking_fraction = 0.01\n\
                 rms_speed = 1.0\n[[gas.species]]\nmaterial = \"glass\"\nradius = 0.01\n\
                 fraction = 0.5\n[[gas.species]]\nmaterial = \"steel\"\nradius = 0.01\n\
                 fraction = 0.4\n"
            ),
            vec!["fractions of [[gas.species]] add up to 0.9"],
        ),
        (
            format!(
                "{two}[gas]\ncount = 10\narrangement = \"lattice\"\npacking_fraction = 0.01\n\
                 rms_speed = 1.0\nradius = 0.01\n"
            ),
            vec!["gas.material is missing"],
        ),
        (
            format!(
                "{two}[gas]\ncount = 10\narrangement = \"lattice\"\npacking_fraction = 0.01\n\
                 rms_speed = 1.0\nradius = 0.01\nmaterial = \"glass\"\n[[gas.species]]\n\
                 material = \"glass\"\nradius = 0.01\nfraction = 1.0\n"
            ),
            vec!["gas.radius and [[gas.species]] exclude each other"],
        ),
    ];
    for (text, needles) in cases {
        let err = build(&text).expect_err(&text);
        for needle in needles {
            assert!(
                err.contains(needle),
                "{text}\n→ {err}\nshould say {needle:?}"
            );
        }
    }
}

#[test]
fn a_law_an_engine_cannot_run_is_refused_by_the_one_check() {
    let walton = "[[materials]]\nname = \"w\"\nmodel = \"linear\"\nstiffness = 1e4\n\
                  density = 1000.0\nfriction = 0.3\ntangential_restitution = 0.2\n\
                  [[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n";
    let s = build(&format!("t_end = 1.0\n{walton}")).unwrap();
    let i = s.interactions();
    i.check_runs_on(Method::Emd, 0).unwrap();
    for m in [Method::Md, Method::EmdStar, Method::Hybrid] {
        let err = i.check_runs_on(m, 0).unwrap_err().to_string();
        assert!(
            err.contains("material \"w\"") || err.contains("the material"),
            "{err}"
        );
        assert!(
            err.contains(m.name()) && err.contains("tangential_restitution"),
            "{err}"
        );
    }
}
