//! `emdstar check`: numerical stability checks of the event engine.

use anyhow::{Result, bail};
use clap::{Args, Subcommand};
use emdstar_edmd::bouncing::BouncingBall;
use emdstar_edmd::{Engine, Physics};
use emdstar_system::fcc_gas;
use serde_json::json;

/// Numerical stability checks of the event-driven engine.
#[derive(Args, Debug)]
pub struct CheckArgs {
    #[command(subcommand)]
    pub which: CheckKind,
}

#[derive(Subcommand, Debug)]
pub enum CheckKind {
    /// Bannerman et al. 2014, Sec. 5: an inelastic ball dropped onto a plate at a
    /// random offset, for many offsets. The stable detection (Algorithm 2) must never
    /// fail; the naive quadratic formula (Eq. 12, --naive) fails on a large fraction.
    ///
    /// Example: emdstar check bouncing-ball --samples 1000000 --json
    #[command(verbatim_doc_comment)]
    BouncingBall(BouncingBallArgs),
    /// Inelastic hard spheres from an FCC start in a periodic box (Bannerman 2014,
    /// Fig. 3): the overlap at impact must never grow beyond round-off. Prints the
    /// histogram of impact separations |r| − σ in units of σ·2⁻⁵².
    ///
    /// Example: emdstar check inelastic-overlaps --cells 15 --collisions 10000000 --json
    #[command(verbatim_doc_comment)]
    InelasticOverlaps(InelasticArgs),
}

#[derive(Args, Debug)]
pub struct BouncingBallArgs {
    /// Number of plate offsets, drawn uniformly from [0, 1).
    #[arg(long, default_value_t = 1_000_000)]
    pub samples: u64,
    /// Coefficient of restitution of ball and plate, in [0, 1).
    #[arg(long, default_value_t = 0.5)]
    pub restitution: f64,
    /// Impacts per sample.
    #[arg(long, default_value_t = 1000)]
    pub impacts: u32,
    /// Use the naive event time, Bannerman 2014, Eq. (12).
    #[arg(long)]
    pub naive: bool,
    /// Seed of the plate offsets.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Args, Debug)]
pub struct InelasticArgs {
    /// FCC cells per side: N = 4·cells³ (15 gives Bannerman's N = 13500).
    #[arg(long, default_value_t = 15)]
    pub cells: usize,
    /// Number density ρσ³.
    #[arg(long, default_value_t = 0.5)]
    pub density: f64,
    /// Coefficient of restitution, in [0, 1].
    #[arg(long, default_value_t = 0.8)]
    pub restitution: f64,
    /// Collisions to run.
    #[arg(long, default_value_t = 10_000_000)]
    pub collisions: u64,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &CheckArgs) -> Result<()> {
    match &args.which {
        CheckKind::BouncingBall(a) => bouncing_ball(a),
        CheckKind::InelasticOverlaps(a) => inelastic(a),
    }
}

fn bouncing_ball(a: &BouncingBallArgs) -> Result<()> {
    if !(0.0..1.0).contains(&a.restitution) {
        bail!(
            "--restitution {} must lie in [0, 1): an elastic ball never comes to rest",
            a.restitution
        );
    }
    if a.samples == 0 || a.impacts == 0 {
        bail!("--samples and --impacts must be positive");
    }
    let bb = BouncingBall {
        restitution: a.restitution,
        impacts: a.impacts,
        naive: a.naive,
        ..Default::default()
    };
    let s = bb.run(a.samples, a.seed);
    if a.json {
        println!(
            "{}",
            json!({
                "samples": s.samples,
                "failures": s.failures,
                "max_overlap": s.max_overlap,
                "mean_events": s.mean_events,
                "algorithm": if a.naive { "naive" } else { "stable" },
            })
        );
    } else {
        println!(
            "bouncing ball ({} detection, ε = {}): {} of {} samples failed, mean {:.1} \
             impacts, largest overlap {:e} σ",
            if a.naive { "naive" } else { "stable" },
            a.restitution,
            s.failures,
            s.samples,
            s.mean_events,
            s.max_overlap
        );
    }
    Ok(())
}

fn inelastic(a: &InelasticArgs) -> Result<()> {
    if a.cells == 0 || a.density.is_nan() || a.density <= 0.0 {
        bail!("--cells and --density must be positive");
    }
    // σ = 1, m = 1, kT = 1 (rms speed √3); η = n·πσ³/6.
    let eta = a.density * std::f64::consts::PI / 6.0;
    let (particles, domain) = fcc_gas(a.cells, eta, 0.5, 1.0, 3f64.sqrt(), a.seed)?;
    let n = particles.len();
    let mut e: Engine = Engine::new(&particles, &domain, Physics::hard_spheres(a.restitution))?;
    let start = std::time::Instant::now();
    e.run_collisions(a.collisions)?;
    let wall = start.elapsed().as_secs_f64();
    let s = e.stats();
    let bins: Vec<i64> = (-8..=8).collect();
    if a.json {
        println!(
            "{}",
            json!({
                "particles": n,
                "collisions": s.collisions(),
                "stabilising": s.stabilising,
                "max_impact_overlap": s.max_impact_overlap,
                "separation_bins_ulp": bins,
                "separation_histogram": s.separation_histogram,
                "time": e.time(),
                "wall_seconds": wall,
            })
        );
    } else {
        println!(
            "N = {n}, ε = {}: {} collisions, {} stabilising, largest overlap at impact {:e} σ",
            a.restitution,
            s.collisions(),
            s.stabilising,
            s.max_impact_overlap
        );
        for (b, c) in bins.iter().zip(&s.separation_histogram) {
            println!("  (|r| − σ)/(σ·2⁻⁵²) = {b:+3}: {c}");
        }
    }
    Ok(())
}
