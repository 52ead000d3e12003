//! Scenario 5 of `emdstar validate`: wall time of MD and of eMD* per simulated second,
//! and, with `--lammps`, of LAMMPS on the goal's gas (for information).

use super::{StageOutput, ValidateArgs, bar};
use crate::cmd::lammps::{self, LammpsGas, ScriptFile};
use anyhow::{Result, anyhow};
use emdstar_harness::Check;
use emdstar_harness::floor::{self, FloorGas, FloorRun, QueueKind, Variant};
use emdstar_harness::speed::{
    CLAIM_RATIO, GOAL_GAS, GOAL_RATIO, SpeedPoint, Timing, measure, plot,
};
use serde_json::{Value, json};

pub fn run(args: &ValidateArgs) -> Result<StageOutput> {
    let etas = [0.001, 0.01, 0.1];
    let youngs = [1e7, 1e9, 1e11];
    let (count, budget, rounds) = if args.full {
        (10_000, 10.0, 5)
    } else {
        (2_000, 2.0, 4)
    };
    let timing = Timing { budget, rounds };
    let b = bar("speed", (etas.len() * youngs.len() + 1) as u64);
    b.set_message(format!(
        "MD and eMD* on one thread, N = {count}, {rounds} interleaved rounds, ≥ {budget} s each"
    ));
    // One thread for both engines: a per-core comparison.
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let mut points: Vec<SpeedPoint> = Vec::new();
    for &y in &youngs {
        for &eta in &etas {
            points.push(one.install(|| measure(eta, y, count, timing, args.seed))?);
            b.inc(1);
        }
    }
    b.set_message(format!(
        "bare cell crossings (no collisions) at η = {}, N = {count}",
        GOAL_GAS.0
    ));
    let floor_gas = FloorGas {
        packing_fraction: GOAL_GAS.0,
        particles: count,
        cell_width: None,
        seed: args.seed,
    };
    let floor_run =
        one.install(|| floor::run(&floor_gas, Variant::Full, QueueKind::Calendar, budget))?;
    b.finish();
    let path = args.out.join("speed_ratio.png");
    plot(&points, &path).map_err(|e| anyhow!(e))?;
    let auto = emdstar_edmd::BroadPhaseKind::AUTO_EPOCHS_BELOW;
    let mut markdown = vec![
        format!(
            "## 5. Speed: MD against eMD* (table), elastic Hertz gas, N = {count}, one thread each"
        ),
        String::new(),
        format!(
            "Wall seconds per simulated second. The engines take turns in {rounds} rounds of \
             {:.2} s wall each, continuing the same gases, and each engine's cost is its best round \
             (the least disturbed by other load). MD's cost is the rate of its steps (not a run over \
             the whole simulated time eMD* covers); eMD* runs ≥ 1 collision per particle over the rounds. \
             The ratio is a ratio of measured rates on this (shared) machine. eMD* finds its candidate \
             pairs by epochs below η = {auto} (swept boxes filed once per epoch, `BroadPhaseKind::Epochs`) and \
             by cell crossings above, where crossings are most of its events in a dilute gas (see the \
             note below the table).",
            budget / rounds as f64
        ),
        String::new(),
        "| η | Y (Pa) | MD dt (s) | MD steps | MD cost | eMD* broad phase | eMD* collisions | eMD* crossings / events | eMD* ns / event | eMD* cost | ratio |"
            .into(),
        "|---|---|---|---|---|---|---|---|---|---|---|".into(),
    ];
    for p in &points {
        markdown.push(format!(
            "| {} | {:.0e} | {:.2e} | {} | {:.3e} | {} | {} | {:.3} | {:.0} | {:.3e} | {:.3e} |",
            p.packing_fraction,
            p.young,
            p.md_dt,
            p.md_steps,
            p.md_cost,
            p.broad_phase(),
            p.emdstar_collisions,
            p.crossing_share(),
            p.emdstar_ns_per_event(),
            p.emdstar_cost,
            p.ratio
        ));
    }
    let goal_point = points
        .iter()
        .find(|p| (p.packing_fraction, p.young) == GOAL_GAS);
    let goal = goal_point.map_or(f64::NAN, |p| p.ratio);
    let goal_met = if goal >= GOAL_RATIO { "met" } else { "not met" };
    let checks = vec![Check::at_least(
        "5a",
        format!(
            "speed: wall-time ratio MD / eMD* at η = 0.001, Y = 1 GPa (the paper: orders of \
             magnitude; the project's goal 2·10³, for information: {goal_met})"
        ),
        goal,
        CLAIM_RATIO,
    )];
    let mut info = Vec::new();
    if let Some(p) = goal_point {
        let line = goal_line(p, rounds);
        markdown.extend([String::new(), line.clone()]);
        info.push(line);
    }
    if let Some(p) = goal_point {
        let line = floor_line(p, &floor_run);
        markdown.extend([String::new(), line.clone()]);
        info.push(line);
    }
    let mut peer = Value::Null;
    if let (Some(lmp), Some(p)) = (&args.lammps, goal_point) {
        let (line, json) = lammps_peer(lmp, p, budget)?;
        markdown.extend([String::new(), line.clone()]);
        info.push(line);
        peer = json;
    }
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({
            "points": points, "threads": 1, "timing": timing, "claim_ratio": CLAIM_RATIO,
            "goal_ratio": GOAL_RATIO, "lammps": peer, "crossing_floor": floor_run,
        }),
        figures: vec![path],
        info,
    })
}

/// The project's goal beside the check's bar, with the rounds behind the ratio.
fn goal_line(p: &SpeedPoint, rounds: usize) -> String {
    let list = |v: &[f64]| {
        v.iter()
            .map(|c| format!("{c:.3e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "For information: the project's goal is MD / eMD* ≥ {GOAL_RATIO:.0} at η = {}, Y = {:.0e} Pa \
         (check 5a's bar is the paper's claim, ≥ {CLAIM_RATIO:.0}); this run: {:.0}, {}. Best of \
         {rounds} interleaved rounds, wall s per simulated s: MD {:.3e} (rounds {}), eMD* {:.3e} \
         (rounds {}).",
        GOAL_GAS.0,
        GOAL_GAS.1,
        p.ratio,
        if p.ratio >= GOAL_RATIO {
            "met"
        } else {
            "not met"
        },
        p.md_cost,
        list(&p.md_rounds),
        p.emdstar_cost,
        list(&p.emdstar_rounds),
    )
}

/// What eMD* spends at the goal's gas, set against bare cell crossings (the floor of
/// the crossing broad phase) in the same run.
fn floor_line(p: &SpeedPoint, floor: &FloorRun) -> String {
    let floor_cost = floor.cost().unwrap_or(f64::NAN);
    format!(
        "For information: at η = {}, Y = {:.0e} Pa eMD* runs on {} ({:.0} ns per event, \
         {:.3e} wall s per simulated s). Bare cell crossings on the crossing engine's cells and \
         queue (free flight, no collisions; `cargo run --release -p emdstar-harness --example \
         crossing_floor` breaks them down) cost {:.0} ns each, {floor_cost:.3e} wall s per \
         simulated s: MD / bare crossings = {:.0} is the most an engine on cell crossings could \
         reach here; eMD* costs {:.2} of bare crossings.",
        GOAL_GAS.0,
        GOAL_GAS.1,
        p.broad_phase(),
        p.emdstar_ns_per_event(),
        p.emdstar_cost,
        floor.ns_per_crossing(),
        p.md_cost / floor_cost,
        p.emdstar_cost / floor_cost
    )
}

/// Times LAMMPS on the goal's gas (simple cubic, the cube nearest to N, the same
/// spacing, rms speed, MD time step and Verlet skin) for about `budget` seconds, and
/// compares its cost per particle and simulated second with eMD*'s at `p`.
fn lammps_peer(lmp: &str, p: &SpeedPoint, budget: f64) -> Result<(String, Value)> {
    use emdstar_harness::exceptions::{DENSITY, RADIUS, RMS_SPEED};
    let b = bar("lammps", 1);
    b.set_message(format!(
        "{lmp} on one core, η = {}, Y = {:.0e} Pa",
        GOAL_GAS.0, GOAL_GAS.1
    ));
    let side = (p.particles as f64).cbrt().round() as usize;
    let volume = 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
    // About 5e7 particle-steps per second for LAMMPS on this gas.
    let steps = ((budget * 5e7 / side.pow(3) as f64) as u64).max(1000);
    let gas = LammpsGas {
        side,
        spacing: (volume / GOAL_GAS.0).cbrt(),
        radius: RADIUS,
        density: DENSITY,
        rms_speed: RMS_SPEED,
        dt: p.md_dt,
        skin: p.md_skin,
        warmup: steps / 10,
        steps,
    };
    let script = ScriptFile::new()?;
    let t = lammps::run(lmp, script.path(), &gas)?;
    b.finish();
    let per_particle = |cost: f64, n: usize| cost / n as f64;
    let lammps_cost = t.cost(gas.dt);
    let ratio = per_particle(lammps_cost, t.particles) / per_particle(p.emdstar_cost, p.particles);
    let line = format!(
        "For information (not a check): LAMMPS ({lmp}, one core, N = {}, same dt {:.2e} s) costs \
         {lammps_cost:.3e} wall s per simulated s; per particle, LAMMPS / eMD* = {ratio:.0} at \
         η = {}, Y = {:.0e} Pa (check 5a compares with this project's MD: {:.0}).",
        t.particles, gas.dt, GOAL_GAS.0, GOAL_GAS.1, p.ratio
    );
    let json = json!({
        "binary": lmp, "particles": t.particles, "dt": gas.dt, "skin": gas.skin, "steps": t.steps,
        "wall_time_s": t.wall_s, "cpu_time_s": t.cpu_s, "cost": lammps_cost,
        "lammps_over_emdstar_per_particle": ratio,
    });
    Ok((line, json))
}
