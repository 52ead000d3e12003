//! Müller & Pöschel 2013 print the bounds of the rectangularised coordinates for their
//! Tab. I and Tab. II (text around Eqs. 46, 48, 56 and 59); docs/physics.md gives them to
//! four decimals. Both must come out of the boxes, not be typed in.

use emdstar_contact::{ParameterBox, Range};

fn assert_rounds_to(x: f64, printed: f64, decimals: i32) {
    let scale = 10f64.powi(decimals);
    assert_eq!(
        (x * scale).round() / scale,
        printed,
        "{x} does not round to the printed {printed}"
    );
}

fn assert_range(r: Range, min: f64, max: f64) {
    assert!((r.min - min).abs() < 6e-5, "min {} vs {min}", r.min);
    assert!((r.max - max).abs() < 6e-5, "max {} vs {max}", r.max);
}

#[test]
fn table_1_linear_dashpot() {
    let b = ParameterBox::paper_table_1().bounds().unwrap();
    // Paper: −4.6 ≲ g ≲ 1.95, −2.3 ≲ ln(lω/v) ≲ 14.83.
    assert_rounds_to(b.g.min, -4.6, 1);
    assert_rounds_to(b.g.max, 1.95, 2);
    assert_rounds_to(b.m.min, -2.3, 1);
    assert_rounds_to(b.m.max, 14.83, 2);
    // docs/physics.md, "Rectangularised coordinates", to four decimals.
    assert_range(b.g, -4.6051, 1.9485);
    assert_range(b.m, -2.3334, 14.8322);
    assert_range(b.c, -12.4719, 4.0005);
}

#[test]
fn table_2_viscoelastic_hertz() {
    let b = ParameterBox::paper_table_2().bounds().unwrap();
    // Paper: g_min ≈ −4.6 again, 0.75 ≈ m_min, m_max ≈ 13.66, c from −18.71 to 9.84.
    assert_rounds_to(b.g.min, -4.6, 1);
    assert_rounds_to(b.m.min, 0.75, 2);
    assert_rounds_to(b.m.max, 13.66, 2);
    assert_rounds_to(b.c.min, -18.71, 2);
    assert_rounds_to(b.c.max, 9.84, 2);
    assert_range(b.g, -4.6051, 1.9485);
    assert_range(b.m, 0.7505, 13.6607);
    assert_range(b.c, -18.7084, 9.8389);
}
