//! `emdstar bench edmd --friction`: MD against eMD* on the frictional Hertz gas of the
//! speed goals, with and without friction, each case an `emdstar run GAS --engine
//! md|emdstar` of this executable timed by its summary, as the goals are stated (N = 2000, R = 0.01 m, Y = 1 GPa, ν = 0.4, restitution 0.8 at 1 m/s,
//! µ = 0.3, k_t = 10⁵ N/m; η = 0.001, 0.01, 0.1 to t_end = 2, 0.3, 0.05 s).

use anyhow::{Result, bail};
use emdstar_engines::EngineKind;
use indicatif::ProgressBar;
use serde_json::{Value, json};

/// The packing fractions and the simulated times of the gas (about 10³ collisions each).
const GASES: [(f64, f64); 3] = [(0.001, 2.0), (0.01, 0.3), (0.1, 0.05)];
/// The goals MD / eMD* with friction at the three packing fractions.
const GOALS: [f64; 3] = [400.0, 60.0, 8.0];

/// The config of the gas at packing fraction `eta` to `t_end`, with the history spring
/// or without friction.
fn gas(eta: f64, t_end: f64, friction: bool) -> String {
    let spring = if friction {
        "friction = 0.3\ntangential_stiffness = 1e5\n"
    } else {
        ""
    };
    format!(
        "t_end = {t_end}\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
         restitution = 0.8\nrestitution_speed = 1.0\ndensity = 1140.0\n{spring}[gas]\n\
         count = 2000\nradius = 0.01\narrangement = \"random\"\npacking_fraction = {eta}\n\
         rms_speed = 1.0\nseed = 3\n"
    )
}

/// Wall seconds of one `emdstar run CONFIG --engine ENGINE` of this executable (the
/// summary's `wall_time_s`, as the goals are stated), and eMD*'s collisions and exact
/// frictional solves.
fn time(config: &std::path::Path, engine: EngineKind) -> Result<(f64, Value)> {
    let out = std::process::Command::new(std::env::current_exe()?)
        .args([
            "run",
            "--quiet",
            "--trajectory",
            "none",
            "--log",
            "none",
            "--engine",
        ])
        .arg(engine.name())
        .arg(config)
        .stderr(std::process::Stdio::null())
        .output()?;
    if !out.status.success() {
        bail!(
            "emdstar run {} --engine {} failed",
            config.display(),
            engine.name()
        );
    }
    let summary: Value = serde_json::from_slice(&out.stdout)?;
    let Some(seconds) = summary["wall_time_s"].as_f64() else {
        bail!("emdstar run printed no wall_time_s");
    };
    let stats = &summary["stats"];
    Ok((
        seconds,
        json!({"collisions": stats["collisions"], "frictional_solves": stats["frictional_solves"]}),
    ))
}

/// The best (least) of a list.
fn best(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Runs the four cases of each gas `rounds` times in turns; prints and returns the table.
pub fn run(rounds: usize, time_scale: f64, bar: &ProgressBar, json_out: bool) -> Result<Value> {
    if !(time_scale > 0.0 && time_scale <= 1.0) {
        bail!("--time-scale must be in (0, 1] (a part of the gas's simulated time)");
    }
    bar.set_length((GASES.len() * 4 * rounds) as u64);
    let mut rows = Vec::new();
    let say = |line: String| {
        if !json_out {
            bar.suspend(|| println!("{line}"));
        }
    };
    say(format!(
        "MD / eMD*, frictional Hertz gas (N = 2000, µ = 0.3, k_t = 1e5 N/m), best of {rounds} \
         round(s) in turns, wall seconds over t_end × {time_scale}; both on all {} cores (MD \
         splits its force loop, frictional eMD* solves contacts ahead on a second thread):",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    ));
    for (k, &(eta, t_end)) in GASES.iter().enumerate() {
        let t_end = t_end * time_scale;
        let dir =
            std::env::temp_dir().join(format!("emdstar-bench-friction-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let configs = [false, true].map(|f| dir.join(format!("gas-{eta}-{f}.toml")));
        for (path, f) in configs.iter().zip([false, true]) {
            std::fs::write(path, gas(eta, t_end, f))?;
        }
        // [smooth, frictional] × [md, emdstar].
        let mut walls = [[vec![], vec![]], [vec![], vec![]]];
        let mut stats = Value::Null;
        for _ in 0..rounds {
            for (f, config) in configs.iter().enumerate() {
                for (e, engine) in [EngineKind::Md, EngineKind::EmdStar]
                    .into_iter()
                    .enumerate()
                {
                    bar.set_message(format!(
                        "η = {eta}, {}, {}",
                        ["µ = 0", "µ = 0.3"][f],
                        engine.name()
                    ));
                    let (seconds, s) = time(config, engine)?;
                    walls[f][e].push(seconds);
                    if f == 1 && e == 1 {
                        stats = s;
                    }
                    bar.inc(1);
                }
            }
        }
        std::fs::remove_dir_all(&dir)?;
        let ratio = |f: usize| best(&walls[f][0]) / best(&walls[f][1]);
        let solves = stats["frictional_solves"].as_f64().unwrap_or(f64::NAN);
        // eMD*'s extra wall time with friction over its frictional solves.
        let per_collision = (best(&walls[1][1]) - best(&walls[0][1])) / solves;
        say(format!(
            "  η = {eta}: MD / eMD* {:.0} without friction, {:.1} with (goal {}; {} frictional \
             solves, {:.1} µs more per frictional collision)",
            ratio(0),
            ratio(1),
            GOALS[k],
            solves,
            per_collision * 1e6
        ));
        rows.push(json!({
            "packing_fraction": eta, "t_end": t_end, "goal": GOALS[k],
            "md_s": walls[0][0], "emdstar_s": walls[0][1],
            "md_friction_s": walls[1][0], "emdstar_friction_s": walls[1][1],
            "ratio": ratio(0), "ratio_friction": ratio(1),
            "emdstar_friction": stats,
        }));
    }
    Ok(json!(rows))
}
