//! A fixed amount of frictional-contact work, for instruction counts and accuracy:
//! `cargo run --release -p emdstar-mor --example frictional_probe -- COUNT [MODE] [--tol X]`
//! solves COUNT impacts of the frictional Hertz gas (the `frictional` bench's) by the fast
//! solver at eMD*'s `CONTACT_OPTIONS` (or at rtol = atol = X) and prints the work per
//! solve. MODE: `pair` (default), `wall` (the same impacts at a wall), `check` (pairs, and
//! their worst distance from the reference at 1e-12), `worst` (the six worst impacts and
//! the error's percentiles), `one K` (impact K alone, and its error). Instructions per
//! contact: callgrind of COUNT = 2000 less 1000.

#[path = "../benches/shared/gas_impacts.rs"]
mod gas_impacts;

use emdstar_contact::vec3::{dot, norm, scale};
use emdstar_mor::frictional::{CONTACT_OPTIONS, HistorySpring, solve_contact, solve_wall_contact};
use gas_impacts::{errors, impacts, law, report, wall_law};

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut opts = CONTACT_OPTIONS;
    if let Some(k) = args.iter().position(|a| a == "--tol") {
        let tol = args.get(k + 1).and_then(|t| t.parse().ok());
        let tol: f64 = tol.expect("--tol takes a number, e.g. --tol 3e-9");
        (opts.rtol, opts.atol) = (tol, tol);
        args.drain(k..k + 2);
    }
    let count = args.first().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let mode = args.get(1).map_or("pair", String::as_str);
    let spring = HistorySpring::new(0.3, 1e5, 0.0).expect("a valid spring");
    let mut points = impacts(count, 7);
    if mode == "wall" {
        let wall_law = wall_law();
        let ends: Vec<_> = points
            .iter()
            .map(|i| (i.bodies[0], scale(1.0 / norm(i.r), i.r), i.v))
            .filter(|(_, n, v)| dot(*n, *v) < 0.0)
            .map(|(b, n, v)| solve_wall_contact(&wall_law, &spring, &b, n, v, &opts).unwrap())
            .collect();
        report("fast, at a wall", &ends);
        return;
    }
    let mut first = 0;
    if mode == "one" {
        first = args
            .get(2)
            .and_then(|k| k.parse().ok())
            .expect("one K: K < COUNT");
        points.drain(..first);
        points.truncate(1);
    }
    let law = law();
    let ends: Vec<_> = points
        .iter()
        .map(|i| solve_contact(&law, &spring, &i.bodies, i.r, i.v, &opts).unwrap())
        .collect();
    report("fast", &ends);
    if matches!(mode, "check" | "worst" | "one") {
        let mut errors: Vec<(f64, usize)> = errors(&law, &spring, &points, &ends)
            .into_iter()
            .enumerate()
            .map(|(k, e)| (e, first + k))
            .collect();
        errors.sort_by(|a, b| b.0.total_cmp(&a.0));
        eprintln!("against the reference at 1e-12: worst {:.2e}", errors[0].0);
        if mode == "worst" {
            for &(e, k) in errors.iter().take(6) {
                let end = &ends[k - first];
                eprintln!("  impact {k}: {e:.2e}, {} switches", end.switches);
            }
            let at = |p: f64| errors[((1.0 - p) * errors.len() as f64) as usize].0;
            eprintln!(
                "  median {:.2e}, 90 % {:.2e}, 99 % {:.2e}",
                at(0.5),
                at(0.9),
                at(0.99)
            );
        }
    }
}
