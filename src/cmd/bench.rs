//! `emdstar bench`: throughput benchmarks, one per engine.

use anyhow::Result;
use clap::{Args, Subcommand};

/// Throughput benchmarks on one core.
#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub which: BenchKind,
}

#[derive(Subcommand, Debug)]
pub enum BenchKind {
    /// The event-driven engine: elastic hard spheres (N = 32000, η = 0.10), a dilute
    /// eMD* Hertz gas (N ≈ 10⁴, η = 0.01, Y = 1 GPa) and, with --scaling, the
    /// hard-sphere rate for N from 10³ to 10⁶.
    Edmd(super::bench_edmd::BenchEdmdArgs),
}

pub fn run(args: &BenchArgs) -> Result<()> {
    match &args.which {
        BenchKind::Edmd(a) => super::bench_edmd::run(a),
    }
}
