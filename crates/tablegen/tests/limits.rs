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
