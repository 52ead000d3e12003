//! Lookups from physical parameters (the paper's direct forms of a, b and c) against
//! the scaled route (scaling, then the rectangular map of emdstar-contact), and pair
//! tables against the exact solver and the full table, on the shipped tables.

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz,
    scale,
};
use emdstar_table::{Table, TableError};

fn table(model: Model) -> Table {
    Table::open(format!(
        "{}/../../tables/{model}.npz",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// Two equal spheres of `radius` and `density` under `law`: their pair law and
/// properties.
fn equal_spheres(law: &ForceLaw, radius: f64, density: f64) -> (PairLaw, PairProperties) {
    let s = Sphere::from_density(radius, density).unwrap();
    let pair = PairProperties::spheres(&s, &s);
    (PairLaw::same_material(law, pair.r_eff).unwrap(), pair)
}

#[test]
fn physical_and_scaled_lookups_agree() {
    for model in [Model::Linear, Model::Hertz] {
        let t = table(model);
        let mut answered = 0;
        for (radius, density) in [(0.002, 7800.0), (0.05, 1140.0)] {
            let s = Sphere::from_density(radius, density).unwrap();
            let pair = PairProperties::spheres(&s, &s);
            for damping in [0.0, 0.05] {
                let law = match model {
                    Model::Linear => ForceLaw::Linear(LinearDashpot::new(5e4, damping).unwrap()),
                    Model::Hertz => {
                        ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, damping * 1e-3).unwrap())
                    }
                };
                let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
                for v in [0.01, 0.5, 3.0] {
                    for e in [0.0, 0.005, 0.2, 0.9] {
                        let imp = Impact::from_speed_eccentricity(v, e).unwrap();
                        let sc = scale(&law, &pair, &imp).unwrap();
                        let direct = t.lookup(&law, &pair, &imp);
                        let scaled = t.lookup_scaled(&sc.params);
                        match (direct, scaled) {
                            (Ok(d), Ok(m)) => {
                                answered += 1;
                                let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs();
                                assert!(close(d.time, sc.time) && close(d.length, sc.length));
                                for (x, y) in [
                                    (d.mor.one_minus_eps_r, m.one_minus_eps_r),
                                    (d.mor.eps_rdot, m.eps_rdot),
                                    (d.mor.eps_phi, m.eps_phi),
                                    (d.mor.eps_t, m.eps_t),
                                ] {
                                    assert!(close(x, y), "{model} v={v} e={e}: {d:?} vs {m:?}");
                                }
                            }
                            (Err(a), Err(b)) => {
                                assert_eq!(std::mem::discriminant(&a), std::mem::discriminant(&b))
                            }
                            (d, m) => panic!("{model} v={v} e={e}: {d:?} vs {m:?}"),
                        }
                    }
                }
            }
        }
        assert!(answered > 20, "{model}: only {answered} lookups answered");
    }
}

#[test]
fn bad_physical_input_is_an_error() {
    let t = table(Model::Hertz);
    let hertz = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-5).unwrap());
    let (law, pair) = equal_spheres(&hertz, 0.01, 1000.0);
    let receding = Impact {
        normal_speed: -1.0,
        tangential_speed: 0.0,
    };
    assert!(matches!(
        t.lookup(&law, &pair, &receding),
        Err(TableError::Input(_))
    ));
    let linear = PairLaw::same_material(
        &ForceLaw::Linear(LinearDashpot::new(1e4, 0.1).unwrap()),
        pair.r_eff,
    )
    .unwrap();
    let hit = Impact::from_speed_eccentricity(1.0, 0.3).unwrap();
    assert!(matches!(
        t.lookup(&linear, &pair, &hit),
        Err(TableError::WrongModel { .. })
    ));
}

#[test]
fn the_fallback_solves_out_of_box_impacts_and_counts_them() {
    let t = table(Model::Linear);
    let linear = ForceLaw::Linear(LinearDashpot::new(1e5, 0.1).unwrap());
    let (law, pair) = equal_spheres(&linear, 0.005, 2500.0);
    let map = emdstar_table::PairMap::new(&law, &pair).unwrap();
    let counted = emdstar_table::WithFallback::new(&t, |m, p| {
        emdstar_mor::solve(m, p).map_err(|e| e.to_string())
    });
    let inside = Impact::from_speed_eccentricity(1.0, 0.3).unwrap();
    let (hit, source) = counted.lookup_pair(&map, &inside).unwrap();
    assert_eq!(source, emdstar_table::Source::Table);
    // Far too slow for the box: refused by the table, solved exactly by the fallback.
    let slow = Impact::from_speed_eccentricity(1e-5, 0.3).unwrap();
    assert!(matches!(
        t.lookup_pair(&map, &slow),
        Err(TableError::OutOfBox { .. })
    ));
    let (exact, source) = counted.lookup_pair(&map, &slow).unwrap();
    assert_eq!(source, emdstar_table::Source::ExactSolve);
    let sc = scale(&law, &pair, &slow).unwrap();
    assert_eq!(
        exact.mor,
        emdstar_mor::solve(Model::Linear, &sc.params).unwrap()
    );
    assert_eq!(exact.time, sc.time);
    assert_eq!(counted.fallbacks(), 1);
    assert!(hit.mor.eps_rdot < 0.0);
    // The same through the pair's own table: the same exact solve, counted again.
    let own = t.pair_table(&law, &pair).unwrap();
    let (hit, source) = counted.lookup_pair_table(&own, &inside).unwrap();
    assert_eq!(source, emdstar_table::Source::Table);
    assert_eq!(hit, own.lookup(&inside).unwrap());
    let (again, source) = counted.lookup_pair_table(&own, &slow).unwrap();
    assert_eq!((source, again), (emdstar_table::Source::ExactSolve, exact));
    assert_eq!(counted.fallbacks(), 2);
    // A pair table of another model's table is refused.
    let hertz = table(Model::Hertz);
    let law_h = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-5).unwrap());
    let law_h = PairLaw::same_material(&law_h, pair.r_eff).unwrap();
    let own_h = hertz.pair_table(&law_h, &pair).unwrap();
    assert!(matches!(
        counted.lookup_pair_table(&own_h, &inside),
        Err(TableError::WrongModel { .. })
    ));
}

/// A pair's own table (the restriction of a shipped table to one pair's impacts)
/// against the exact solver, against the full table, and at its edges.
mod pair_tables {
    use super::*;
    use emdstar_table::mor_to_logs;

    /// A seeded generator (SplitMix64): log-uniform draws over a range.
    struct Draw(u64);

    impl Draw {
        fn log_uniform(&mut self, r: [f64; 2]) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
            (r[0].ln() + (r[1].ln() - r[0].ln()) * u).exp()
        }
    }

    /// The value of the table's box parameter `name`, drawn log-uniformly.
    fn draw(t: &Table, d: &mut Draw, name: &str) -> f64 {
        let info = t.info();
        let k = info.box_names.iter().position(|n| n == name).unwrap();
        d.log_uniform(info.box_ranges[k])
    }

    /// A pair of equal spheres of the table's box, drawn at random.
    fn random_pair(t: &Table, d: &mut Draw) -> (PairLaw, PairProperties) {
        let law = match t.model() {
            Model::Linear => ForceLaw::Linear(
                LinearDashpot::new(draw(t, d, "stiffness"), draw(t, d, "damping")).unwrap(),
            ),
            Model::Hertz => ForceLaw::Hertz(
                ViscoelasticHertz::new(
                    draw(t, d, "young"),
                    draw(t, d, "poisson"),
                    draw(t, d, "dissipation"),
                )
                .unwrap(),
            ),
        };
        equal_spheres(&law, draw(t, d, "radius"), draw(t, d, "density"))
    }

    fn random_impact(t: &Table, d: &mut Draw) -> Impact {
        Impact::from_speed_eccentricity(draw(t, d, "speed"), draw(t, d, "eccentricity")).unwrap()
    }

    #[test]
    fn pair_tables_agree_with_the_exact_solver_and_the_full_table() {
        for model in [Model::Linear, Model::Hertz] {
            let t = table(model);
            let mut d = Draw(7);
            let (mut answered, mut sliced) = (0, 0);
            for _ in 0..12 {
                let (law, pair) = random_pair(&t, &mut d);
                let own = t.pair_table(&law, &pair).unwrap();
                sliced += usize::from(own.patch_count() > 0);
                for _ in 0..60 {
                    let impact = random_impact(&t, &mut d);
                    match (own.lookup(&impact), t.lookup(&law, &pair, &impact)) {
                        (Ok(hit), Ok(full)) => {
                            answered += 1;
                            assert_eq!((hit.time, hit.length), (full.time, full.length));
                            // Against the full table: the restriction is exact up to rounding.
                            let (a, b) = (mor_to_logs(&hit.mor), mor_to_logs(&full.mor));
                            for q in 0..4 {
                                assert!(
                                    (a[q] - b[q]).abs() < 1e-7,
                                    "{model} {impact:?}: {a:?} {b:?}"
                                );
                            }
                            // Against the exact solve: the table's accuracy, 1e-6 relative.
                            let s = scale(&law, &pair, &impact).unwrap();
                            let exact = emdstar_mor::solve(model, &s.params).unwrap();
                            let e = mor_to_logs(&exact);
                            for q in 0..4 {
                                let rel = (a[q] - e[q]).abs();
                                assert!(rel < 1e-6, "{model} {impact:?} component {q}: {rel:e}");
                            }
                        }
                        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
                        (a, b) => panic!("{model} {impact:?}: {a:?} against {b:?}"),
                    }
                }
            }
            assert!(
                sliced >= 8,
                "{model}: only {sliced} of 12 pairs were restricted"
            );
            assert!(answered > 500, "{model}: only {answered} impacts answered");
        }
    }

    #[test]
    fn a_pair_off_the_main_piece_looks_up_through_the_full_table() {
        // No dissipation: c = −∞, the nearly elastic extension for every impact.
        let t = table(Model::Linear);
        let elastic = ForceLaw::Linear(LinearDashpot::new(1e5, 0.0).unwrap());
        let (law, pair) = equal_spheres(&elastic, 0.01, 2500.0);
        let own = t.pair_table(&law, &pair).unwrap();
        assert_eq!(own.patch_count(), 0);
        for v in [0.1, 1.0] {
            let impact = Impact::from_speed_eccentricity(v, 0.5).unwrap();
            let full = t.lookup(&law, &pair, &impact).unwrap();
            assert_eq!(own.lookup(&impact).unwrap(), full);
            assert_eq!(full.mor.eps_r, 1.0);
        }
    }

    #[test]
    fn pair_tables_refuse_what_the_full_table_refuses() {
        let t = table(Model::Hertz);
        let hertz = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-4).unwrap());
        let (law, pair) = equal_spheres(&hertz, 0.05, 1140.0);
        let own = t.pair_table(&law, &pair).unwrap();
        assert!(own.patch_count() > 0);
        // Faster than the box allows: out of the box, named as the full table names it.
        let fast = Impact::from_speed_eccentricity(1e4, 0.5).unwrap();
        let (a, b) = (own.lookup(&fast), t.lookup(&law, &pair, &fast));
        assert!(matches!(a, Err(TableError::OutOfBox { .. })), "{a:?}");
        assert_eq!(a.unwrap_err().to_string(), b.unwrap_err().to_string());
        let bad = Impact {
            normal_speed: f64::NAN,
            tangential_speed: 0.0,
        };
        assert!(matches!(own.lookup(&bad), Err(TableError::Input(_))));
        // A table of the other model is refused when the handle is built.
        let linear = table(Model::Linear);
        assert!(matches!(
            linear.pair_table(&law, &pair),
            Err(TableError::WrongModel { .. })
        ));
    }
}
