//! Prints the rectangle bounds derived from the paper's Tab. I and Tab. II.
//!
//! `cargo run -p emdstar-contact --example paper_bounds`

use emdstar_contact::ParameterBox;

fn main() {
    for pbox in [ParameterBox::paper_table_1(), ParameterBox::paper_table_2()] {
        let b = pbox.bounds().expect("the paper's boxes are valid");
        println!(
            "{:<6}  g = [{:.4}, {:.4}]  m = [{:.4}, {:.4}]  c = [{:.4}, {:.4}]",
            b.model.name(),
            b.g.min,
            b.g.max,
            b.m.min,
            b.m.max,
            b.c.min,
            b.c.max
        );
    }
}
