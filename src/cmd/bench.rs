//! `emdstar bench md`: particle-steps per second of the MD engine, beside LAMMPS.

use super::lammps::LammpsGas;
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use emdstar_dem::{
    ContactEnd, DEFAULT_DT_FRACTION, Md, MdOptions, default_skin, shortest_contact_time,
};
use emdstar_system::Config;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to benchmark.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BenchTarget {
    /// The MD engine on a dilute Hertz gas: R = 0.1 m, ρ = 1140 kg/m³,
    /// Y = 1 GPa, ν = 0.4, A = 0, rms speed 1 m/s, simple cubic start.
    Md,
    /// The event-driven engine: elastic hard spheres (N = 32000, η = 0.10),
    /// a dilute eMD* Hertz gas (N ≈ 10⁴, η = 0.01, Y = 1 GPa) against hard spheres
    /// of the same gas and, with --scaling, both rates for N from 10³ to 10⁶. Uses
    /// only the flags under "event-driven".
    Edmd,
    /// Table lookups against exact solves (see `emdstar bench table --help`).
    Table,
    /// Long event-driven runs that must stay sound (flags under "soak"): inelastic
    /// hard spheres (N = 13 500, ε = 0.8, ρσ³ = 0.5; Bannerman et al. 2014, Figs. 3
    /// and 5) and a cooling eMD* Hertz gas (A = 10⁻⁵ s), 10⁷ collisions each by
    /// default. Reports the largest impact overlap (hard spheres: round-off, well below
    /// 10⁻¹² σ; eMD*: up to the overlap of a pair in its transient), stabilising collisions, momentum drift, eMD* exceptions and fallbacks, and
    /// memory (resident size sampled during the run and the process peak).
    /// Quick look: emdstar bench soak --soak-collisions 100000
    Soak,
}

/// Speed benchmarks (particle-steps or collisions per second), optionally against LAMMPS.
///
/// Prints one JSON object per case and a summary.
///
/// Example (MD at two densities and thread counts, LAMMPS side by side):
///   emdstar bench md --eta 0.01 --eta 0.1 --threads 1 --threads 2 --repeat 3 --lammps tools/lammps/hertz_gas.in
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct BenchArgs {
    pub target: BenchTarget,
    /// Particles (rounded to a cube, n³).
    #[arg(long, default_value_t = 32768)]
    pub n: usize,
    /// Packing fractions (repeat the flag).
    #[arg(long, default_values_t = [0.01, 0.1])]
    pub eta: Vec<f64>,
    /// Timed steps per case (after 10% warm-up).
    #[arg(long, default_value_t = 3000)]
    pub steps: u64,
    /// Thread counts (repeat the flag).
    #[arg(long, default_values_t = [1, 2])]
    pub threads: Vec<usize>,
    /// Rounds: every case runs this often, alternating with the others; the summary
    /// takes each case's best round.
    #[arg(long, default_value_t = 1)]
    pub repeat: usize,
    /// Verlet skin in units of R [default: the engine's, R at η = 0.01, R/2 at η = 0.1];
    /// LAMMPS gets the same.
    #[arg(long)]
    pub skin: Option<f64>,
    /// Also run this LAMMPS input (tools/lammps/hertz_gas.in) with `lmp` on one core.
    #[arg(long, value_name = "SCRIPT")]
    pub lammps: Option<PathBuf>,
    /// The LAMMPS binary.
    #[arg(long, default_value = "lmp")]
    pub lmp: String,
    #[command(flatten, next_help_heading = "event-driven (bench edmd)")]
    pub edmd: super::bench_edmd::BenchEdmdArgs,
    #[command(flatten, next_help_heading = "tables (bench table)")]
    pub table: super::bench_table::BenchTableArgs,
    #[command(flatten, next_help_heading = "soak (bench soak)")]
    pub soak: super::bench_soak::BenchSoakArgs,
}

const RADIUS: f64 = 0.1;
const DENSITY: f64 = 1140.0;
const RMS_SPEED: f64 = 1.0;

pub fn run(args: &BenchArgs) -> Result<()> {
    if let BenchTarget::Edmd = args.target {
        return super::bench_edmd::run(&args.edmd);
    }
    if let BenchTarget::Table = args.target {
        return super::bench_table::run(&args.table, args.edmd.json);
    }
    if let BenchTarget::Soak = args.target {
        return super::bench_soak::run(&args.soak, args.edmd.json);
    }
    let side = (args.n as f64).cbrt().round() as usize;
    if side < 3 || args.steps == 0 {
        bail!("need --n ≥ 27 and --steps ≥ 1");
    }
    let n = side * side * side;
    let mut rows = Vec::new();
    for &eta in &args.eta {
        let text = format!(
            "t_end = 1.0\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
             dissipation = 0.0\ndensity = {DENSITY}\n[gas]\ncount = {n}\nradius = {RADIUS}\n\
             arrangement = \"lattice\"\npacking_fraction = {eta}\nrms_speed = {RMS_SPEED}\nseed = 1\n"
        );
        let config = Config::from_toml(&text)?;
        let system = config.build()?;
        let tc = shortest_contact_time(&system, 0.0)?.context("the gas moves")?;
        let dt = DEFAULT_DT_FRACTION * tc;
        let skin = args
            .skin
            .map_or_else(|| default_skin(&system), |s| s * RADIUS);
        let opts = MdOptions {
            dt,
            contact_end: ContactEnd::ForceZero,
            skin: Some(skin),
        };
        let box_side = system.domain.sim_box.expect("gas has a box").size[0];
        for round in 0..args.repeat {
            for &threads in &args.threads {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()?;
                let row = pool.install(|| -> Result<Value> {
                let mut md = Md::new(system.clone(), opts, 0.0)?;
                md.advance((args.steps / 10).max(1))?;
                let (steps0, rebuilds0) = (md.steps(), md.rebuilds());
                let (start, cpu0) = (Instant::now(), super::cpu_time::process_seconds());
                md.advance(args.steps)?;
                let wall = start.elapsed().as_secs_f64();
                let cpu = super::cpu_time::process_seconds()
                    .zip(cpu0)
                    .map(|(b, a)| b - a);
                let th = md.thermo();
                Ok(json!({
                    "code": "emdstar", "eta": eta, "n": n, "threads": threads, "dt": dt, "skin": skin, "round": round,
                    "steps": md.steps() - steps0, "rebuilds": md.rebuilds() - rebuilds0,
                    "contacts_at_end": th.contacts, "wall_time_s": wall, "cpu_time_s": cpu,
                    "particle_steps_per_s": n as f64 * args.steps as f64 / wall,
                    "particle_steps_per_cpu_s": cpu.map(|c| n as f64 * args.steps as f64 / c),
                }))
            })?;
                println!("{row}");
                rows.push(row);
            }
            if let Some(script) = &args.lammps {
                let mut row =
                    run_lammps(args, script, side, box_side / side as f64, dt, skin, eta)?;
                row["round"] = json!(round);
                println!("{row}");
                rows.push(row);
            }
        }
    }
    // The best of the rounds: the least disturbed by other load on the machine.
    let rate = |code: &str, eta: f64, threads: usize, key: &str| {
        rows.iter()
            .filter(|r| r["code"] == code && r["eta"] == eta && r["threads"] == threads)
            .filter_map(|r| r[key].as_f64())
            .reduce(f64::max)
    };
    let ratios: Vec<Value> = args
        .eta
        .iter()
        .map(|&eta| {
            let best = |code, threads, key| rate(code, eta, threads, key);
            let ratio = |key| Some(best("emdstar", 1, key)? / best("lammps", 1, key)?);
            json!({
                "eta": eta,
                "emdstar_1_thread": best("emdstar", 1, "particle_steps_per_s"),
                "emdstar_2_threads": best("emdstar", 2, "particle_steps_per_s"),
                "lammps_1_core": best("lammps", 1, "particle_steps_per_s"),
                "emdstar_over_lammps_1_core_wall": ratio("particle_steps_per_s"),
                "emdstar_over_lammps_1_core_cpu": ratio("particle_steps_per_cpu_s"),
            })
        })
        .collect();
    println!("{}", json!({"summary": ratios}));
    Ok(())
}

/// Runs the LAMMPS input with the same gas, time step and skin.
fn run_lammps(
    args: &BenchArgs,
    script: &Path,
    side: usize,
    spacing: f64,
    dt: f64,
    skin: f64,
    eta: f64,
) -> Result<Value> {
    let gas = LammpsGas {
        side,
        spacing,
        radius: RADIUS,
        density: DENSITY,
        rms_speed: RMS_SPEED,
        dt,
        skin,
        warmup: (args.steps / 10).max(1),
        steps: args.steps,
    };
    let t = super::lammps::run(&args.lmp, script, &gas)?;
    let n = t.particles as f64;
    Ok(json!({
        "code": "lammps", "eta": eta, "n": t.particles, "threads": 1, "dt": dt, "skin": skin, "steps": t.steps,
        "wall_time_s": t.wall_s, "cpu_time_s": t.cpu_s, "particle_steps_per_s": n * t.steps / t.wall_s,
        "particle_steps_per_cpu_s": n * t.steps / t.cpu_s,
    }))
}
