//! The cost floor of eMD*'s cell crossings ([`emdstar_harness::floor`]): free spheres
//! crossing the engine's own cells and queue, with each part of a crossing left out in
//! turn, so the differences between rows give the cost of each part.
//!
//! ```text
//! cargo run --release -p emdstar-harness --example crossing_floor -- [ETA] [N] [SECONDS] [WIDTH]
//! ```
//!
//! Defaults: η = 0.001, N = 2000 (the speed goal's gas), 3 s per row, the engine's
//! automatic cell width (or WIDTH metres). The last row files the full crossing in the
//! 4-ary heap instead of the calendar queue.

use emdstar_harness::floor::{FloorGas, FloorRun, QueueKind, Variant, run};

fn row(label: &str, r: &FloorRun) {
    let cost = r
        .cost()
        .map_or("(out of order)".to_string(), |c| format!("{c:.3e}"));
    println!(
        "{label:<30} {:>12.1} {:>16.2} {cost:>22}",
        r.ns_per_crossing(),
        r.pair_tests_per_crossing()
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{e}; usage: crossing_floor [ETA] [N] [SECONDS] [WIDTH]"))?;
    let gas = FloorGas {
        packing_fraction: args.first().copied().unwrap_or(0.001),
        particles: args.get(1).copied().unwrap_or(2000.0) as usize,
        cell_width: args.get(3).copied(),
        seed: 7,
    };
    let seconds = args.get(2).copied().unwrap_or(3.0);
    let mut first = true;
    for variant in Variant::ALL {
        let r = run(&gas, variant, QueueKind::Calendar, seconds)?;
        if first {
            println!(
                "η = {}, N = {}: {}³ cells of {:.3} m",
                gas.packing_fraction, gas.particles, r.cells_per_axis, r.cell_width
            );
            println!(
                "{:<30} {:>12} {:>16} {:>22}",
                "variant", "ns/crossing", "pairs/crossing", "wall s per simulated s"
            );
            first = false;
        }
        row(variant.label(), &r);
    }
    let heap = run(&gas, Variant::Full, QueueKind::Heap, seconds)?;
    row("full, 4-ary heap queue", &heap);
    Ok(())
}
