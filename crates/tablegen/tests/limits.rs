//! The central and elastic limit slices against exact solves just beyond the box.

use emdstar_contact::ScaledParams;
use emdstar_tablegen::{Spec, build, exact_solver};

#[test]
fn elastic_and_central_impacts_follow_the_limits() {
    let spec = Spec::parse(
        "model = \"linear\"\ncells = [1, 1, 1]\ndegree = 6\ntolerance = 1e-8\nmax_depth = 4\n\
         [box]\nstiffness = [1e4, 2e4]\nradius = [0.01, 0.02]\ndensity = [1000.0, 2000.0]\n\
         damping = [0.1, 0.2]\nspeed = [0.5, 1.0]\neccentricity = [0.01, 0.03]\n",
    )
    .unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    // Elastic (c_dis = 0): ε_r = 1 and ε_ṙ = −1 exactly; ε_t comes from the elastic slice.
    let b = table.bounds();
    let x = emdstar_contact::RectCoords {
        a: 0.0,
        b: 0.37 * table.rect()[1].max,
        c: 0.0,
    };
    let p = ScaledParams {
        c_dis: 0.0,
        ..b.from_rect(&x)
    };
    let got = table.lookup_scaled(&p).unwrap();
    let exact = exact_solver(spec.model, &p).unwrap();
    assert_eq!((got.eps_r, got.eps_rdot), (1.0, -1.0));
    assert!(
        ((got.eps_t - exact.eps_t) / exact.eps_t).abs() < 1e-5,
        "{got:?} {exact:?}"
    );
    // Just below the box in c_dis: interpolation in u between the elastic slice and the face.
    let p = ScaledParams {
        c_dis: 0.5
            * b.from_rect(&emdstar_contact::RectCoords { c: b.c.min, ..x })
                .c_dis,
        ..p
    };
    let got = table.lookup_scaled(&p).unwrap();
    let exact = exact_solver(spec.model, &p).unwrap();
    let rel = ((got.one_minus_eps_r - exact.one_minus_eps_r) / exact.one_minus_eps_r).abs();
    assert!(rel < 1e-5, "1-eps_r: {got:?} vs {exact:?}");
    // Central (c_φ = 0): ε_φ = 0 exactly; the normal components from the central piece.
    let [_, bx, cx] = table.rect();
    let p = ScaledParams {
        l_tilde: (0.4 * bx.max + b.m.min).exp(),
        c_phi: 0.0,
        c_dis: (0.5 * (cx.min + cx.max)).exp(),
    };
    let got = table.lookup_scaled(&p).unwrap();
    let exact = exact_solver(spec.model, &p).unwrap();
    assert_eq!(got.eps_phi, 0.0);
    assert!(
        ((got.eps_rdot - exact.eps_rdot) / exact.eps_rdot).abs() < 1e-5,
        "{got:?} vs {exact:?}"
    );
}

/// Where strong damping makes the MoR not smooth in c_φ², the near-central extension
/// is refused (NotTabulated), not answered wrongly; elsewhere it matches exact solves.
#[test]
fn the_near_central_extension_is_refused_where_it_does_not_hold() {
    let spec = Spec::parse(
        "model = \"hertz\"\nbox = \"paper_table_2\"\ncells = [1, 2, 2]\ndegree = 4\n\
         tolerance = 1e-3\nmax_depth = 1\n",
    )
    .unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    let [ax, bx, cx] = table.rect();
    let bound = table
        .info()
        .estimated_error
        .iter()
        .fold(0.0f64, |m, e| m.max(*e));
    let (mut refused, mut answered) = (0, 0);
    for j in 0..8 {
        for k in 0..8 {
            let x = emdstar_contact::RectCoords {
                a: ax.min - 1.0,
                b: bx.min + (bx.max - bx.min) * (j as f64 + 0.5) / 8.0,
                c: cx.min + (cx.max - cx.min) * (k as f64 + 0.5) / 8.0,
            };
            let p = table.bounds().from_rect(&x);
            let exact = exact_solver(spec.model, &p);
            match table.lookup_scaled(&p) {
                Ok(got) => {
                    answered += 1;
                    let exact = exact.unwrap();
                    for (g, e) in [
                        (got.one_minus_eps_r, exact.one_minus_eps_r),
                        (got.eps_rdot, exact.eps_rdot),
                        (got.eps_phi, exact.eps_phi),
                        (got.eps_t, exact.eps_t),
                    ] {
                        assert!(
                            (g / e).ln().abs() < 3.0 * bound + 1e-6,
                            "{x:?}: {got:?} vs {exact:?}"
                        );
                    }
                }
                Err(emdstar_table::TableError::NotTabulated(_)) => refused += 1,
                Err(e) => panic!("{x:?}: {e}"),
            }
        }
    }
    // The paper's box reaches c_dis√ξ ≫ 1: the strongly damped part must be refused.
    assert!(
        refused > 0 && answered > 0,
        "{refused} refused, {answered} answered"
    );
}
