//! `emdstar bench soak`: long event-driven runs that must stay sound: impact overlaps at
//! round-off, momentum conserved, exceptions and fallbacks counted, memory flat.

use super::cpu_time::thread_seconds;
use super::engine::progress_bar;
use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use emdstar_contact::Tangential;
use emdstar_contact::{ForceLaw, Model, Sphere, ViscoelasticHertz};
use emdstar_edmd::rules::TableMorSource;
use emdstar_edmd::{Engine, Interference, Physics, Stats};
use emdstar_system::Interactions;
use emdstar_system::{Domain, Particles, fcc_gas};
use serde_json::{Value, json};
use std::time::Instant;

/// Which soak runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SoakCase {
    /// Inelastic hard spheres (Bannerman et al. 2014, Figs. 3 and 5).
    HardSpheres,
    /// A cooling viscoelastic Hertz gas on eMD*.
    Emdstar,
    /// Both, one after the other.
    Both,
}

/// Options of `emdstar bench soak`.
#[derive(Args, Debug)]
pub struct BenchSoakArgs {
    /// Which soak runs.
    #[arg(long, value_enum, default_value_t = SoakCase::Both)]
    pub soak_case: SoakCase,
    /// Collisions per soak (10⁷ takes minutes per soak; 10⁵ is a quick look).
    #[arg(long, default_value_t = 10_000_000)]
    pub soak_collisions: u64,
    /// FCC cells per side of both gases: N = 4·cells³ (15 gives Bannerman's N = 13 500).
    #[arg(long, default_value_t = 15)]
    pub soak_cells: usize,
    /// Coefficient of restitution of the hard spheres, in (0, 1].
    #[arg(long, default_value_t = 0.8)]
    pub soak_restitution: f64,
    /// Number density ρσ³ of the hard spheres (0.5: η ≈ 0.26).
    #[arg(long, default_value_t = 0.5)]
    pub soak_density: f64,
    /// Dissipation constant A of the Hertz gas in seconds (Y = 1 GPa, ν = 0.4,
    /// R = 0.1 m, ρ = 1140 kg/m³, η = 0.01, rms speed 2 m/s at the start).
    #[arg(long, default_value_t = 1e-5)]
    pub soak_dissipation: f64,
    /// Hide the progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Progress updates (and momentum and memory samples) per soak.
const SAMPLES: u64 = 200;

pub fn run(a: &BenchSoakArgs, json_out: bool) -> Result<()> {
    if a.soak_collisions == 0 || a.soak_cells == 0 {
        bail!("--soak-collisions and --soak-cells must be at least 1");
    }
    if !(a.soak_restitution > 0.0 && a.soak_restitution <= 1.0) {
        bail!("--soak-restitution must lie in (0, 1]");
    }
    if a.soak_density.is_nan() || a.soak_density <= 0.0 {
        bail!("--soak-density must be positive");
    }
    if a.soak_dissipation.is_nan() || a.soak_dissipation < 0.0 {
        bail!("--soak-dissipation must be ≥ 0 (seconds)");
    }
    let mut out = json!({});
    if a.soak_case != SoakCase::Emdstar {
        // σ = 1, m = 1, kT = 1 (rms speed √3); η = ρσ³·π/6.
        let eta = a.soak_density * std::f64::consts::PI / 6.0;
        let gas = fcc_gas(a.soak_cells, eta, 0.5, 1.0, 3f64.sqrt(), 1)?;
        let physics = Physics::hard_spheres(a.soak_restitution);
        let title = format!(
            "inelastic hard spheres, ε = {}, ρσ³ = {}",
            a.soak_restitution, a.soak_density
        );
        out["hard_spheres"] = soak(&title, gas, physics, a, json_out)?;
    }
    if a.soak_case != SoakCase::HardSpheres {
        let sphere = Sphere::from_density(0.1, 1140.0)?;
        let gas = fcc_gas(a.soak_cells, 0.01, 0.1, sphere.mass, 2.0, 1)?;
        let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, a.soak_dissipation)?);
        let physics = Physics::EmdStar {
            interactions: Interactions::of_spheres(&law, Tangential::None, &[sphere])?,
            mor: Box::new(TableMorSource::new(
                emdstar_table::default_table(Model::Hertz)?,
                true,
            )),
            interference: Interference::HitOnly,
        };
        let title = format!(
            "eMD* Hertz gas, A = {} s, η = 0.01, Y = 1 GPa",
            a.soak_dissipation
        );
        out["emdstar_hertz"] = soak(&title, gas, physics, a, json_out)?;
    }
    if json_out {
        println!("{out}");
    }
    Ok(())
}

/// |p| of a momentum vector.
fn norm(p: [f64; 3]) -> f64 {
    p.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Runs one soak and prints (or returns as JSON) its figures.
fn soak(
    title: &str,
    (particles, domain): (Particles, Domain),
    physics: Physics,
    a: &BenchSoakArgs,
    json_out: bool,
) -> Result<Value> {
    let rss_before = memory_kib("VmRSS");
    let mut e: Engine = Engine::new(&particles, &domain, physics)?;
    let n = e.len();
    let total_mass: f64 = e.masses().iter().sum();
    let (k0, p0) = (e.kinetic_energy(), e.momentum());
    // The thermal momentum scale M·√(2K/M), at the start and (cooling gases) now.
    let scale = |k: f64| total_mass * (2.0 * k / total_mass).sqrt();
    let rss_start = memory_kib("VmRSS");
    let bar = progress_bar(
        a.quiet || json_out,
        a.soak_collisions,
        "{prefix} {bar:30} {pos}/{len} collisions {elapsed}/{duration} {msg}",
    );
    bar.set_prefix(title.to_string());
    let (start, cpu_start) = (Instant::now(), thread_seconds());
    let chunk = a.soak_collisions.div_ceil(SAMPLES);
    let (mut done, mut largest_drift, mut rss_peak_run) = (0, 0.0f64, 0u64);
    // Resident size after each tenth of the run: flat once the engine has warmed up.
    let mut rss_tenths = Vec::new();
    while done < a.soak_collisions {
        let step = chunk.min(a.soak_collisions - done);
        e.run_collisions(step)?;
        done += step;
        let p = e.momentum();
        let drift = norm(std::array::from_fn(|k| p[k] - p0[k]));
        largest_drift = largest_drift.max(drift / scale(k0));
        let rss = memory_kib("VmRSS").unwrap_or(0);
        rss_peak_run = rss_peak_run.max(rss);
        if done * 10 / a.soak_collisions > (done - step) * 10 / a.soak_collisions {
            rss_tenths.push(rss);
        }
        bar.set_position(done);
        bar.set_message(format!(
            "K/K₀ = {:.2e}, max overlap {:.1e}, re-contacts {}",
            e.kinetic_energy() / k0,
            e.stats().max_impact_overlap,
            e.stats().recontacts
        ));
    }
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let cpu = thread_seconds().zip(cpu_start).map(|(b, a)| b - a);
    let (k1, p1) = (e.kinetic_energy(), e.momentum());
    let drift = norm(std::array::from_fn(|k| p1[k] - p0[k]));
    let s = *e.stats();
    let contact = 2.0 * e.radii()[0];
    let rss_end = memory_kib("VmRSS");
    let v = json!({
        "case": title,
        "particles": n,
        "broad_phase": format!("{:?}", e.broad_phase()).to_lowercase(),
        "collisions": s.collisions(),
        "events": s.events,
        "simulated_time": e.time(),
        "kinetic_energy_ratio": k1 / k0,
        "max_impact_overlap_over_contact": s.max_impact_overlap / contact,
        "recontacts": s.recontacts,
        "max_recontact_overlap_over_contact": s.max_recontact_overlap / contact,
        "max_recontact_overlap_over_placed": s.max_recontact_overlap_ratio,
        "separation_bins_ulp": (-8..=8).collect::<Vec<i64>>(),
        "separation_histogram": s.separation_histogram,
        "stabilising_collisions": s.stabilising,
        "stabilising_per_event": s.stabilising as f64 / s.events.max(1) as f64,
        "momentum_drift": drift,
        "momentum_drift_over_initial_scale": drift / scale(k0),
        "momentum_drift_over_final_scale": drift / scale(k1),
        "largest_sampled_drift_over_initial_scale": largest_drift,
        "exceptions_rotation": s.exception_rotation,
        "exceptions_interference": s.exception_interference,
        "interference_resolved": s.interference_resolved,
        "fallbacks_emd_rule": s.exception_rotation,
        "fallbacks_exact_mor": s.mor_fallbacks,
        "stale_events": s.stale,
        "resorts": s.resorts,
        "wall_seconds": wall,
        "cpu_seconds": cpu,
        "collisions_per_cpu_second": cpu.map(|c| s.collisions() as f64 / c),
        "memory_kib": {
            "rss_before_engine": rss_before,
            "rss_at_start": rss_start,
            "rss_peak_during_run": rss_peak_run,
            "rss_after_each_tenth": rss_tenths,
            "rss_at_end": rss_end,
            "process_peak_vmhwm": memory_kib("VmHWM"),
        },
    });
    if !json_out {
        print_soak(&v, &s);
    }
    Ok(v)
}

fn print_soak(v: &Value, s: &Stats) {
    let m = &v["memory_kib"];
    let mib = |x: &Value| {
        x.as_f64()
            .map_or("?".into(), |k| format!("{:.1}", k / 1024.0))
    };
    println!(
        "{}, N = {}: {} collisions ({} events) in {:.1} s",
        v["case"].as_str().unwrap_or(""),
        v["particles"],
        s.collisions(),
        s.events,
        v["wall_seconds"].as_f64().unwrap_or(0.0),
    );
    println!(
        "  largest impact overlap {:.2e} σ; {} stabilising collisions ({:.1e} per event)",
        v["max_impact_overlap_over_contact"].as_f64().unwrap_or(0.0),
        s.stabilising,
        v["stabilising_per_event"].as_f64().unwrap_or(0.0),
    );
    if s.recontacts > 0 {
        println!(
            "  {} re-contacts of pairs that eMD* left overlapping (at most {:.2e} σ, {:.10} of \
             the overlap the pair was left at)",
            s.recontacts,
            v["max_recontact_overlap_over_contact"]
                .as_f64()
                .unwrap_or(0.0),
            s.max_recontact_overlap_ratio,
        );
    }
    println!(
        "  momentum drift {:.2e} (relative to the initial thermal momentum {:.2e}, \
         to the final {:.2e}); kinetic energy K/K₀ = {:.3e}",
        v["momentum_drift"].as_f64().unwrap_or(0.0),
        v["momentum_drift_over_initial_scale"]
            .as_f64()
            .unwrap_or(0.0),
        v["momentum_drift_over_final_scale"].as_f64().unwrap_or(0.0),
        v["kinetic_energy_ratio"].as_f64().unwrap_or(0.0),
    );
    println!(
        "  exceptions: {} rotations refused (eMD rule used), {} interferences ({} no longer \
         approaching); {} exact MoR fallbacks",
        s.exception_rotation, s.exception_interference, s.interference_resolved, s.mor_fallbacks,
    );
    println!(
        "  memory (MiB): {} before the engine, {} at start, {} peak during the run, {} at end; \
         process peak (VmHWM) {}",
        mib(&m["rss_before_engine"]),
        mib(&m["rss_at_start"]),
        mib(&m["rss_peak_during_run"]),
        mib(&m["rss_at_end"]),
        mib(&m["process_peak_vmhwm"]),
    );
    let tenths: Vec<String> = m["rss_after_each_tenth"]
        .as_array()
        .map(|t| t.iter().map(mib).collect())
        .unwrap_or_default();
    println!(
        "  resident size after each tenth of the run (MiB): {}",
        tenths.join(", ")
    );
    let separations: Vec<String> = s
        .separation_histogram
        .iter()
        .zip(-8..=8)
        .filter(|(c, _)| **c > 0)
        .map(|(c, b)| format!("{b:+}: {c}"))
        .collect();
    println!(
        "  impact separations (|r| − σ)/(σ·2⁻⁵²), outer bins open: {}",
        separations.join(", ")
    );
}

/// A memory figure of this process in KiB from /proc/self/status (`None` where there
/// is none, e.g. off Linux).
fn memory_kib(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(field)?.strip_prefix(':')?;
        rest.split_whitespace().next()?.parse().ok()
    })
}
