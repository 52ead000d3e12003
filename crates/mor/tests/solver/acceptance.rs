//! Acceptance run (ignored in CI; run it with
//! `cargo test -p emdstar-mor --test solver -- --ignored --nocapture acceptance`, ~15 s):
//! worst relative MoR error of the default options per component and per box, against
//! (1) the solver at rtol = atol = 1e-14, (2) the overlap-form oracle and (3) the Cartesian
//! oracle (τ̃ and ε_φ only where it resolves them), over 10^4 impacts log-uniform in the
//! physical ranges of Tab. I / Tab. II and 10^4 points uniform in each rectangle.

use crate::common::*;
use crate::oracle::{cartesian_time_resolution, oracle_errors, overlap_form_errors};
use emdstar_contact::{Model, ScaledParams};
use emdstar_mor::{SolverOptions, solve_with};

const NAMES: [&str; 4] = ["1-eps_r", "eps_rdot", "eps_phi", "eps_t"];

struct Worst {
    what: &'static str,
    err: [(f64, Option<ScaledParams>); 4],
}

impl Worst {
    fn new(what: &'static str) -> Self {
        Self {
            what,
            err: [(0.0, None); 4],
        }
    }

    fn add(&mut self, e: [f64; 4], p: &ScaledParams, keep: [bool; 4]) {
        for i in 0..4 {
            if keep[i] && e[i] > self.err[i].0 {
                self.err[i] = (e[i], Some(*p));
            }
        }
    }

    fn print(&self) -> f64 {
        println!("  vs {}:", self.what);
        for (name, (e, p)) in NAMES.iter().zip(&self.err) {
            println!("    {name:9} {e:.2e} at {p:?}");
        }
        self.err.iter().map(|e| e.0).fold(0.0, f64::max)
    }
}

#[test]
#[ignore]
fn acceptance_worst_errors_over_both_boxes() {
    let default = SolverOptions::default();
    let mut overall = 0.0f64;
    for model in [Model::Linear, Model::Hertz] {
        for (label, points) in [
            (
                "log-uniform physical",
                log_uniform_physical(model, 10_000, 2026),
            ),
            ("uniform rectangle", uniform_in_rect(model, 10_000, 2027)),
        ] {
            let (mut vs_tight, mut vs_overlap, mut vs_cart) = (
                Worst::new("rtol 1e-14"),
                Worst::new("overlap-form oracle"),
                Worst::new("Cartesian oracle"),
            );
            let (mut steps, mut rejected, mut evals, mut unresolved) = (0, 0, 0, 0);
            for p in points.iter().chain(corners(model).iter()) {
                let (m, s) =
                    solve_with(model, p, &default).unwrap_or_else(|e| panic!("{p:?}: {e}"));
                steps += s.accepted_steps;
                rejected += s.rejected_steps;
                evals += s.rhs_evaluations;
                let (r, _) = solve_with(model, p, &tight()).unwrap();
                vs_tight.add(mor_errors(&m, &r), p, [true; 4]);
                vs_overlap.add(overlap_form_errors(model, p, &m), p, [true; 4]);
                let resolved = cartesian_time_resolution(p, &m) < 1e-10;
                unresolved += usize::from(!resolved);
                vs_cart.add(
                    oracle_errors(model, p, &m),
                    p,
                    [true, true, resolved, resolved],
                );
            }
            let n = (points.len() + 8) as f64;
            println!(
                "{model}, {label} ({} points + 8 corners): {:.1} accepted + {:.2} rejected steps, {:.0} rhs evaluations per solve",
                points.len(),
                steps as f64 / n,
                rejected as f64 / n,
                evals as f64 / n
            );
            overall = overall.max(vs_tight.print()).max(vs_overlap.print());
            vs_cart.print();
            println!("    (Cartesian τ̃/ε_φ not resolved at {unresolved} points)");
        }
    }
    assert!(overall <= 1e-9, "worst relative error {overall:e}");
}
