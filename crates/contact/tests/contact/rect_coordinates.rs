//! The rectangularised coordinates: forward∘inverse is the identity on the whole
//! rectangle, and every physical impact of the paper's boxes (equal spheres) lands
//! inside the rectangle, which is what the construction of Sec. V promises.

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ParameterBox, RectCoords,
    Sphere, ViscoelasticHertz, scale,
};
use proptest::prelude::*;

fn log_uniform(r: emdstar_contact::Range, u: f64) -> f64 {
    (r.min.ln() + u * (r.max.ln() - r.min.ln())).exp()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn rect_round_trip(hertz in any::<bool>(), ua in 0.0..=1.0f64, ub in 0.0..=1.0f64, uc in 0.0..=1.0f64) {
        let model = if hertz { Model::Hertz } else { Model::Linear };
        let bounds = ParameterBox::paper(model).bounds().unwrap();
        let [ra, rb, rc] = bounds.axes();
        let x = RectCoords {
            a: ra.min + ua * ra.width(),
            b: rb.min + ub * rb.width(),
            c: rc.min + uc * rc.width(),
        };
        let p = bounds.from_rect(&x);
        let y = bounds.to_rect(&p);
        prop_assert!((x.a - y.a).abs() < 1e-12, "a {} -> {}", x.a, y.a);
        prop_assert!((x.b - y.b).abs() < 1e-12, "b {} -> {}", x.b, y.b);
        prop_assert!((x.c - y.c).abs() < 1e-12, "c {} -> {}", x.c, y.c);
    }

    #[test]
    fn physical_box_maps_into_the_rectangle(
        hertz in any::<bool>(),
        u in proptest::array::uniform7(0.0..=1.0f64),
    ) {
        let pbox = if hertz { ParameterBox::paper_table_2() } else { ParameterBox::paper_table_1() };
        let bounds = pbox.bounds().unwrap();
        let ranges = pbox.ranges();
        let val = |i: usize| log_uniform(ranges[i].1, u[i]);
        let (law, radius, density, speed, ecc) = match pbox {
            ParameterBox::Linear(_) => (
                ForceLaw::Linear(LinearDashpot::new(val(0), val(3)).unwrap()),
                val(1), val(2), val(4), val(5),
            ),
            ParameterBox::Hertz(_) => (
                ForceLaw::Hertz(ViscoelasticHertz::new(val(0), val(1), val(4)).unwrap()),
                val(2), val(3), val(5), val(6),
            ),
        };
        let s = Sphere::from_density(radius, density).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let pair_law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        let imp = Impact::from_speed_eccentricity(speed, ecc).unwrap();
        let sc = scale(&pair_law, &pair, &imp).unwrap();
        let x = bounds.to_rect(&sc.params);
        let [ra, rb, rc] = bounds.axes();
        let slack = 1e-9;
        prop_assert!(x.a >= ra.min - slack && x.a <= ra.max + slack, "a = {} not in {:?}", x.a, ra);
        prop_assert!(x.b >= rb.min - slack && x.b <= rb.max + slack, "b = {} not in {:?}", x.b, rb);
        prop_assert!(x.c >= rc.min - slack && x.c <= rc.max + slack, "c = {} not in {:?}", x.c, rc);
    }
}
