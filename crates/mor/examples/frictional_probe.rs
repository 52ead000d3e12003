//! A fixed amount of frictional-contact work, for instruction counts and accuracy:
//! `cargo run --release -p emdstar-mor --example frictional_probe -- COUNT [MODE]` solves
//! COUNT impacts of the frictional Hertz gas (the `frictional` bench's) by the fast solver
//! at eMD*'s `CONTACT_OPTIONS` and prints the work per solve. MODE: `pair` (default),
//! `wall` (the same impacts at a wall), `check` (pairs, and their worst distance from the
//! reference at 1e-12). Instructions per contact: callgrind of COUNT = 2000 less 1000.

#[path = "../benches/shared/gas_impacts.rs"]
mod gas_impacts;

use emdstar_contact::vec3::{dot, norm, scale};
use emdstar_mor::frictional::{CONTACT_OPTIONS, HistorySpring, solve_contact, solve_wall_contact};
use gas_impacts::{impacts, law, report, wall_law, worst_error};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let count = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1000);
    let mode = args.get(2).map_or("pair", String::as_str);
    let spring = HistorySpring::new(0.3, 1e5, 0.0).expect("a valid spring");
    let points = impacts(count, 7);
    if mode == "wall" {
        let wall_law = wall_law();
        let ends: Vec<_> = points
            .iter()
            .map(|i| (i.bodies[0], scale(1.0 / norm(i.r), i.r), i.v))
            .filter(|(_, n, v)| dot(*n, *v) < 0.0)
            .map(|(b, n, v)| {
                solve_wall_contact(&wall_law, &spring, &b, n, v, &CONTACT_OPTIONS).unwrap()
            })
            .collect();
        report("fast, at a wall", &ends);
        return;
    }
    let law = law();
    let ends: Vec<_> = points
        .iter()
        .map(|i| solve_contact(&law, &spring, &i.bodies, i.r, i.v, &CONTACT_OPTIONS).unwrap())
        .collect();
    report("fast (CONTACT_OPTIONS)", &ends);
    if mode == "check" {
        let worst = worst_error(&law, &spring, &points, &ends);
        eprintln!("against the reference at 1e-12: worst {worst:.2e}");
    }
}
