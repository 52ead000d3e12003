//! The central and elastic limit slices against exact solves just beyond the box.

use emdstar_contact::ScaledParams;
use emdstar_tablegen::{Spec, build, exact_solver};

#[test]
fn elastic_and_central_impacts_follow_the_limits() {
    let spec = Spec::parse(
        "model = \"linear\"\nbox = \"paper_table_1\"\nnodes = [6, 8, 6]\norder = [4, 4, 4]\n",
    )
    .unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    // Elastic (c_dis = 0): ε_r = 1 and ε_ṙ = −1 exactly; ε_t comes from the elastic slice.
    let b = table.bounds();
    let x = emdstar_contact::RectCoords {
        a: 0.0,
        b: table.axes()[1].node(3),
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
        ((got.eps_t - exact.eps_t) / exact.eps_t).abs() < 1e-9,
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
    assert!(rel < 1e-6, "1-eps_r: {got:?} vs {exact:?}");
    // Central (c_φ = 0): ε_φ = 0 exactly; the normal components from the central slice.
    // At grid nodes of (b, c), so only the limit itself is tested.
    let [_, bx, cx] = *table.axes();
    let p = ScaledParams {
        l_tilde: (bx.node(3) + b.m.min).exp(),
        c_phi: 0.0,
        c_dis: cx.node(2).exp(),
    };
    let got = table.lookup_scaled(&p).unwrap();
    let exact = exact_solver(spec.model, &p).unwrap();
    assert_eq!(got.eps_phi, 0.0);
    assert!(
        ((got.eps_rdot - exact.eps_rdot) / exact.eps_rdot).abs() < 1e-6,
        "{got:?} vs {exact:?}"
    );
}

/// Where strong damping makes the MoR not smooth in c_φ², the near-central extension
/// is refused (NotTabulated), not answered wrongly; elsewhere it matches exact solves.
#[test]
fn the_near_central_extension_is_refused_where_it_does_not_hold() {
    let spec = Spec::parse(
        "model = \"hertz\"\nbox = \"paper_table_2\"\nnodes = [6, 8, 8]\norder = [4, 4, 4]\n",
    )
    .unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    let [ax, bx, cx] = *table.axes();
    let (mut refused, mut answered) = (0, 0);
    for j in 0..bx.n {
        for k in 0..cx.n {
            // Grid nodes of (b, c), so only the extension in a is tested.
            let x = emdstar_contact::RectCoords {
                a: ax.min - 1.0,
                b: bx.node(j),
                c: cx.node(k),
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
                        assert!(((g - e) / e).abs() < 1e-6, "{x:?}: {got:?} vs {exact:?}");
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
