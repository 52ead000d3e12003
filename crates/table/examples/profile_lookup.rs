//! Fixed-work lookup loop for instruction counts on a shared machine:
//!
//! ```sh
//! cargo build --release -p emdstar-table --example profile_lookup
//! valgrind --tool=callgrind target/release/examples/profile_lookup tables/hertz.npz 20000 table
//! ```
//!
//! MODE `table` (`Table::lookup` from physical parameters), `pair` (pair handles),
//! `own` (the pair table of the first impact's pair, for those of the impacts it
//! answers), `rect` (precomputed rectangular coordinates) or `none` (only the setup:
//! subtract its count). 4096 impacts of the table's box, cycled. A fifth argument R times R rounds
//! instead (best of R, thread CPU time; MODE `one` repeats one impact).
use emdstar_contact::scale;
use emdstar_table::Table;
use std::hint::black_box;

#[path = "../benches/support/mod.rs"]
mod support;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let table = Table::open(&args[1]).unwrap();
    let n: usize = args[2].parse().unwrap();
    let mode = args[3].as_str();
    let cases = support::impacts(&table, 4096, false);
    let handles: Vec<_> = cases
        .iter()
        .map(|(l, p, i)| (table.pair(l, p).unwrap(), *i))
        .collect();
    let own = table.pair_table(&cases[0].0, &cases[0].1).unwrap();
    let own_impacts: Vec<_> = cases
        .iter()
        .map(|c| c.2)
        .filter(|i| own.lookup(i).is_ok())
        .collect();
    let rects: Vec<_> = cases
        .iter()
        .map(|(l, p, i)| table.bounds().to_rect(&scale(l, p, i).unwrap().params))
        .collect();
    // One lookup of case `i` in `mode` (its ε_t, so that nothing is optimised away).
    let lookup = |i: usize| -> f64 {
        let i = if mode == "one" { 0 } else { i % cases.len() };
        match mode {
            "table" | "one" => {
                let (l, p, im) = &cases[i];
                black_box(table.lookup(black_box(l), p, im))
                    .unwrap()
                    .mor
                    .eps_t
            }
            "pair" => {
                let (h, im) = &handles[i];
                black_box(h.lookup(black_box(im))).unwrap().mor.eps_t
            }
            "own" => {
                let im = &own_impacts[i % own_impacts.len()];
                black_box(own.lookup(black_box(im))).unwrap().mor.eps_t
            }
            "rect" => {
                black_box(table.lookup_rect(black_box(&rects[i])))
                    .unwrap()
                    .eps_t
            }
            _ => 0.0,
        }
    };
    let mut sum = 0.0;
    let Some(rounds) = args.get(4) else {
        sum += (0..n).map(lookup).sum::<f64>();
        println!("{sum}");
        return;
    };
    let rounds: usize = rounds.parse().unwrap();
    let mut best = f64::INFINITY;
    for _ in 0..rounds {
        let t0 = support::thread_cpu_ns();
        sum += (0..n).map(lookup).sum::<f64>();
        best = best.min((support::thread_cpu_ns() - t0) as f64 / n as f64);
    }
    println!("{mode}: {best:.1} ns/lookup (best of {rounds}) {sum}");
}
