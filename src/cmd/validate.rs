//! `emdstar validate`: the cross-validation of eMD*, eMD and MD (crate emdstar-harness),
//! printed as numbered checks and written to a report directory.

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use emdstar_harness::Check;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

mod diffusion;
mod friction;
mod speed;
mod stages;
mod theory;

/// Cross-validate eMD* against eMD against force-based MD (Müller & Pöschel 2013) and
/// write a report.
///
/// Runs nine scenarios (their --only names in brackets; self-diffusion's checks are
/// numbered 4.3) and prints each check with its number, its value, its bar and
/// pass/fail:
///   1. [pairs] pair sweep: random oblique impacts over the paper's Tab. I and II
///      boxes (both force laws, equal and unequal spheres) through MD at several dt,
///      eMD, eMD* (table and exact MoR), against the exact two-body solution;
///   2. [fig6] the paper's Fig. 6: trajectories of MD against eMD and eMD*;
///   3. [fig7] the paper's Fig. 7: eMD* exception frequencies in a free elastic gas
///      against packing fraction and Young's modulus;
///   4. [cooling] freely cooling gases (viscoelastic, then linear dashpot):
///      temperature by MD, eMD and eMD* from one initial state; Haff's law and
///      T ∝ t^(-5/3);
///      [diffusion] self-diffusion of an elastic soft-sphere gas by the three
///      engines, hard spheres against Enskog's theory (checks 4.3);
///   5. [speed] wall time of MD and eMD* for the same simulated time;
///   6. [friction-pairs] random oblique frictional impacts: eMD*'s exact frictional
///      contact against MD at two fine steps, Walton's rule beside;
///   7. [friction-cooling] a freely cooling frictional gas: translational and
///      rotational temperatures by MD, frictional eMD* and Walton's eMD;
///   8. [theory] kinetic theory through the log's observables: elastic hard spheres'
///      pressure against Carnahan–Starling at η = 0.1–0.4, and a2 of the homogeneous
///      cooling state (ε = 0.8) against van Noije & Ernst; the shear viscosity of
///      hard spheres under Lees–Edwards shear against Enskog's.
///
/// The default (quick) run takes about a minute on 2 cores and uses the default
/// tables built into the program; --full runs the paper's scale (N = 10⁴ gases, 10⁴
/// impacts; about 9 CPU-minutes: 6 minutes on an idle 2-core machine, up to about 20
/// on a busy one). The report directory gets report.json, report.md and every figure
/// (PNG). The exit code is 1 when a check fails, 2 on an error.
///
/// Example:
///   emdstar validate                 # quick, writes ./validate-report/
///   emdstar validate --full --out paper-scale --threads 2
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct ValidateArgs {
    /// Run at the paper's scale instead of the quick version.
    #[arg(long)]
    pub full: bool,
    /// Directory of the report (created; files in it are overwritten).
    #[arg(long, value_name = "DIR", default_value = "validate-report")]
    pub out: PathBuf,
    /// Worker threads [default: all cores]. Results do not depend on it, except the
    /// measured wall times.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Seed of the random impacts and gases.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Run only these scenarios (repeat the flag): pairs, fig6, fig7, cooling,
    /// diffusion, speed, friction-pairs, friction-cooling, theory.
    #[arg(long, value_name = "NAME")]
    pub only: Vec<String>,
    /// Also time LAMMPS (the binary LMP, default `lmp`, with its GRANULAR package) on
    /// the speed goal's gas and report MD(LAMMPS) / eMD* beside the checks. For
    /// information: check 5a compares with this project's MD.
    #[arg(long, value_name = "LMP", num_args = 0..=1, default_missing_value = "lmp")]
    pub lammps: Option<String>,
}

/// What one scenario hands to the report.
pub struct StageOutput {
    pub checks: Vec<Check>,
    /// Markdown lines for report.md (tables, notes).
    pub markdown: Vec<String>,
    pub json: Value,
    pub figures: Vec<PathBuf>,
    /// Lines printed under the checks: measured figures that are not checks.
    pub info: Vec<String>,
}

/// A bar over `total` units of work of one scenario.
pub fn bar(title: &str, total: u64) -> ProgressBar {
    let b = ProgressBar::new(total);
    b.set_style(
        ProgressStyle::with_template("{prefix:>10} {bar:30} {pos}/{len} {elapsed} {msg}")
            .expect("valid progress template"),
    );
    b.set_prefix(title.to_string());
    b
}

const SCENARIOS: [&str; 9] = [
    "pairs",
    "fig6",
    "fig7",
    "cooling",
    "diffusion",
    "speed",
    "friction-pairs",
    "friction-cooling",
    "theory",
];

pub fn run(args: &ValidateArgs) -> Result<bool> {
    for name in &args.only {
        if !SCENARIOS.contains(&name.as_str()) {
            bail!(
                "unknown scenario '{name}' in --only: the scenarios are {}",
                SCENARIOS.join(", ")
            );
        }
    }
    if args.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    if let Some(lmp) = &args.lammps {
        crate::cmd::lammps::probe(lmp)?;
    }
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("starting the worker threads")?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create the report directory {}", args.out.display()))?;
    let start = Instant::now();
    let wanted = |s: &str| args.only.is_empty() || args.only.iter().any(|o| o == s);
    let mut outputs: Vec<(&str, StageOutput)> = Vec::new();
    for name in SCENARIOS {
        if !wanted(name) {
            continue;
        }
        let out = pool.install(|| stages::run(name, args))?;
        outputs.push((name, out));
    }
    let seconds = start.elapsed().as_secs_f64();
    let checks: Vec<&Check> = outputs.iter().flat_map(|(_, o)| &o.checks).collect();
    print_checks(&checks);
    for line in outputs.iter().flat_map(|(_, o)| &o.info) {
        println!("{line}");
    }
    let failed = checks.iter().filter(|c| !c.passed).count();
    println!(
        "{} checks, {} passed, {failed} failed, in {seconds:.0} s; report in {}",
        checks.len(),
        checks.len() - failed,
        args.out.display()
    );
    write_report(args, &outputs, seconds)?;
    Ok(failed == 0)
}

fn print_checks(checks: &[&Check]) {
    for c in checks {
        println!(
            "{:>5}  {:<4}  {:>11}  {:<11}  {}",
            c.id,
            if c.passed { "pass" } else { "FAIL" },
            c.value_text(),
            c.bar_text(),
            c.name
        );
    }
}

fn write_report(args: &ValidateArgs, outputs: &[(&str, StageOutput)], seconds: f64) -> Result<()> {
    let dir = &args.out;
    let mode = if args.full { "full" } else { "quick" };
    let mut md = vec![
        "# emdstar validate".to_string(),
        String::new(),
        format!(
            "Mode {mode}, seed {}, {} threads, {seconds:.0} s wall time, emdstar {}.",
            args.seed,
            args.threads.unwrap_or_else(rayon::current_num_threads),
            env!("CARGO_PKG_VERSION")
        ),
        String::new(),
        "| check | result | value | bar | what |".to_string(),
        "|---|---|---|---|---|".to_string(),
    ];
    for (_, o) in outputs {
        for c in &o.checks {
            md.push(format!(
                "| {} | {} | {} | {} | {} |",
                c.id,
                if c.passed { "pass" } else { "**FAIL**" },
                c.value_text(),
                c.bar_text(),
                c.name.replace('|', "\\|")
            ));
        }
    }
    let mut json_stages = serde_json::Map::new();
    for (name, o) in outputs {
        md.push(String::new());
        md.extend(o.markdown.iter().cloned());
        for f in &o.figures {
            let file = f
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            md.push(format!("\n![{file}]({file})"));
        }
        json_stages.insert(
            name.to_string(),
            json!({"checks": o.checks, "results": o.json, "figures": o.figures}),
        );
    }
    let all: Vec<&Check> = outputs.iter().flat_map(|(_, o)| &o.checks).collect();
    let report = json!({
        "mode": mode,
        "seed": args.seed,
        "wall_time_s": seconds,
        "passed": all.iter().all(|c| c.passed),
        "checks": all,
        "scenarios": json_stages,
    });
    write(
        &dir.join("report.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    write(&dir.join("report.md"), &(md.join("\n") + "\n"))
}

/// Writes a report through a temporary file renamed into place (never half a report).
fn write(path: &Path, text: &str) -> Result<()> {
    emdstar_system::write_atomically(path, text.as_bytes())
        .map_err(|e| anyhow!("cannot write the report: {e}"))
}
