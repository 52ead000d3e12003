use crate::common::*;
use emdstar_contact::{Model, ScaledParams};
use emdstar_mor::{SolverOptions, solve_with};

#[test]
#[ignore]
fn explore() {
    let tight = SolverOptions {
        rtol: 1e-14,
        atol: 1e-14,
        max_steps: 1_000_000,
    };
    for model in [Model::Linear, Model::Hertz] {
        let mut pts = corners(model);
        pts.extend(uniform_in_rect(model, 2000, 1));
        for rtol in [1e-10, 1e-11, 1e-12, 1e-13] {
            let o = SolverOptions {
                rtol,
                atol: rtol,
                max_steps: 1_000_000,
            };
            let mut worst = [(
                0.0f64,
                ScaledParams {
                    l_tilde: 0.0,
                    c_phi: 0.0,
                    c_dis: 0.0,
                },
            ); 4];
            let mut steps = 0usize;
            let mut evals = 0usize;
            for p in &pts {
                let (m, s) = solve_with(model, p, &o).unwrap_or_else(|e| panic!("{p:?}: {e}"));
                let (r, _) = solve_with(model, p, &tight).unwrap();
                steps += s.accepted_steps + s.rejected_steps;
                evals += s.rhs_evaluations;
                let e = [
                    rel(m.one_minus_eps_r, r.one_minus_eps_r),
                    rel(m.eps_rdot, r.eps_rdot),
                    rel(m.eps_phi, r.eps_phi),
                    rel(m.eps_t, r.eps_t),
                ];
                for i in 0..4 {
                    if e[i] > worst[i].0 {
                        worst[i] = (e[i], *p);
                    }
                }
            }
            println!(
                "{model} rtol {rtol:e}: steps/solve {:.1} evals/solve {:.1}",
                steps as f64 / pts.len() as f64,
                evals as f64 / pts.len() as f64
            );
            for (i, n) in ["1-eps_r", "eps_rdot", "eps_phi", "eps_t"]
                .iter()
                .enumerate()
            {
                println!("   {n}: {:.2e} at {:?}", worst[i].0, worst[i].1);
            }
        }
    }
}
