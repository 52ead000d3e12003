//! Which impacts of a granular gas the default Hertz table answers, and how well.
//!
//! The eMD* gas of `emdstar bench edmd` (Müller & Pöschel 2013, Sec. VI B 6): Hertz
//! spheres with Y = 1 GPa, ν = 0.4, R = 0.1 m, ρ = 1140 kg/m³, A = 0 (elastic) or a
//! given A, each particle velocity component normal with standard deviation `sigma`.
//! Colliding pairs are drawn with the collision rate's weight |g| (relative speed g),
//! and the impact parameter uniformly over the collision disk (so e = √U).
//!
//! `cargo run --release -p emdstar-tablegen --example gas_coverage -- [SIGMA] [A] [N]`

use emdstar_contact::{
    ForceLaw, Impact, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz, scale,
};
use emdstar_table::{TableError, default_table};
use emdstar_tablegen::exact_solver;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("numbers: SIGMA A N"))
        .collect();
    let sigma = args.first().copied().unwrap_or(1.0);
    let dissipation = args.get(1).copied().unwrap_or(0.0);
    let n = args.get(2).copied().unwrap_or(200_000.0) as usize;
    let table = default_table(Model::Hertz).unwrap();
    let s = Sphere::from_density(0.1, 1140.0).unwrap();
    let pair = PairProperties::spheres(&s, &s);
    let law = PairLaw::same_material(
        &ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, dissipation).unwrap()),
        pair.r_eff,
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut normal = || {
        // Box-Muller.
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let mut draws = Vec::new();
    let g_max = 12.0 * sigma;
    let mut rng2 = ChaCha8Rng::seed_from_u64(8);
    while draws.len() < n {
        // Relative velocity of two particles: each component N(0, 2σ²).
        let g = (0..3)
            .map(|_| (normal() * sigma * 2f64.sqrt()).powi(2))
            .sum::<f64>()
            .sqrt();
        if rng2.random::<f64>() * g_max > g {
            continue; // collision rate ∝ g
        }
        let e = rng2.random::<f64>().sqrt();
        if e >= 1.0 || g <= 0.0 {
            continue;
        }
        draws.push(Impact::from_speed_eccentricity(g, e).unwrap());
    }
    let (mut answered, mut worst) = (0usize, [0.0f64; 4]);
    let mut out_axis = std::collections::BTreeMap::new();
    let mut near_central = 0usize;
    for imp in &draws {
        match table.lookup(&law, &pair, imp) {
            Ok(hit) => {
                answered += 1;
                let p = scale(&law, &pair, imp).unwrap().params;
                if p.c_phi / p.l_tilde < 0.01 {
                    near_central += 1;
                }
                // Compare with the exact solve on a subsample (every 20th answered).
                if answered % 20 == 0 || p.c_phi / p.l_tilde < 0.01 {
                    let m = exact_solver(Model::Hertz, &p).unwrap();
                    let rel = |a: f64, b: f64| if a == b { 0.0 } else { ((a - b) / b).abs() };
                    let e = [
                        rel(hit.mor.one_minus_eps_r, m.one_minus_eps_r),
                        rel(hit.mor.eps_rdot, m.eps_rdot),
                        rel(hit.mor.eps_phi, m.eps_phi),
                        rel(hit.mor.eps_t, m.eps_t),
                    ];
                    for (w, x) in worst.iter_mut().zip(e) {
                        *w = w.max(x);
                    }
                }
            }
            Err(TableError::OutOfBox {
                axis,
                value,
                min,
                max,
            }) => {
                let side = if value > max {
                    "above"
                } else if value < min {
                    "below"
                } else {
                    "?"
                };
                *out_axis.entry(format!("{axis} {side}")).or_insert(0usize) += 1;
            }
            Err(e) => *out_axis.entry(format!("{e}")).or_insert(0usize) += 1,
        }
    }
    println!(
        "Hertz gas, sigma = {sigma} m/s, A = {dissipation} s: {n} impacts, {answered} answered \
         ({:.3}%), {near_central} of them near-central (e < 0.01)",
        100.0 * answered as f64 / n as f64
    );
    for (why, count) in &out_axis {
        println!(
            "  outside: {why}: {count} ({:.3}%)",
            100.0 * *count as f64 / n as f64
        );
    }
    println!(
        "  largest relative error vs exact (every 20th answered impact and all near-central \
         ones): 1-eps_r {:.2e}, eps_rdot {:.2e}, eps_phi {:.2e}, eps_t {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}
