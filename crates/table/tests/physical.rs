//! Lookups from physical parameters (the paper's direct forms of a, b and c) against
//! the scaled route (scaling, then the rectangular map of emdstar-contact), on the
//! shipped tables.

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
    let s = Sphere::from_density(0.01, 1000.0).unwrap();
    let pair = PairProperties::spheres(&s, &s);
    let law = PairLaw::same_material(
        &ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-5).unwrap()),
        pair.r_eff,
    )
    .unwrap();
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
    let s = Sphere::from_density(0.005, 2500.0).unwrap();
    let pair = PairProperties::spheres(&s, &s);
    let law = PairLaw::same_material(
        &ForceLaw::Linear(LinearDashpot::new(1e5, 0.1).unwrap()),
        pair.r_eff,
    )
    .unwrap();
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
}
