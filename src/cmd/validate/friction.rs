//! The frictional scenarios of `emdstar validate`: random frictional impacts (eMD*'s
//! exact frictional contact against MD and Walton's rule) and a freely cooling
//! frictional gas (MD, frictional eMD*, Walton's eMD).

use super::{StageOutput, ValidateArgs, bar};
use anyhow::{Result, anyhow};
use emdstar_harness::Check;
use emdstar_harness::friction_cooling::{FrictionCoolingSettings, plot as plot_cooling};
use emdstar_harness::friction_pairs::{
    FrictionImpact, FrictionPairSettings, StateError, plot as plot_pairs,
};
use serde_json::json;

/// One engine's errors of an impact.
type Engine<'a> = dyn Fn(&FrictionImpact) -> &StateError + 'a;

fn worst(e: &StateError) -> f64 {
    e.position.max(e.velocity).max(e.spin)
}

pub fn pairs(args: &ValidateArgs) -> Result<StageOutput> {
    let settings = FrictionPairSettings {
        impacts: if args.full { 400 } else { 48 },
        seed: args.seed,
        ..FrictionPairSettings::quick()
    };
    let b = bar("fric-pairs", 1);
    b.set_message(format!(
        "{} frictional impacts: exact contact, MD at τ/400 and τ/800, Walton, eMD*",
        settings.impacts
    ));
    let out = emdstar_harness::friction_pairs::run(&settings)?;
    b.inc(1);
    b.finish();
    let path = args.out.join("friction_pairs.png");
    plot_pairs(&out, &path).map_err(|e| anyhow!(e))?;
    let (engine_median, engine_worst) = out.summary(|i| worst(&i.emdstar));
    let (ratio_median, ratio_worst) =
        out.summary(|i| worst(&i.md_fine) / worst(&i.md_truncation).max(1e-300));
    let (walton_median, walton_worst) = out.summary(|i| worst(&i.walton));
    let checks = vec![
        Check::at_most(
            "6a",
            "frictional impacts: eMD* engine against the exact contact, worst of positions/l, \
             velocities and spins·R/|v_rel|",
            engine_worst,
            1e-7,
        ),
        Check::at_most(
            "6b",
            "frictional impacts: |MD(τ/800) − eMD*| / |MD(τ/400) − MD(τ/800)|, median (MD \
             converges to eMD*: ≈ 1 at first order)",
            ratio_median,
            1.5,
        ),
        Check::at_least(
            "6c",
            "frictional impacts: Walton's rule against eMD*, median (misses)",
            walton_median,
            1e-2,
        ),
    ];
    let mut markdown = vec![
        "## 6. Frictional impacts".to_string(),
        String::new(),
        format!(
            "{} random oblique impacts (linear and Hertz, damped or not; µ from 0.05 to 1; \
             history spring, damped or not; random spins; equal and unequal radii). Errors \
             against the exact frictional contact after the collision: positions in units of \
             l, velocities and spins (times R) in units of |v_rel|.",
            settings.impacts
        ),
        String::new(),
        "| engine | quantity | median | worst |".to_string(),
        "|---|---|---|---|".to_string(),
    ];
    let rows: [(&str, &Engine); 5] = [
        ("eMD* engine", &|i| &i.emdstar),
        ("MD dt = τ/400", &|i| &i.md_coarse),
        ("MD dt = τ/800", &|i| &i.md_fine),
        ("MD(τ/400) − MD(τ/800)", &|i| &i.md_truncation),
        ("Walton's rule (eMD)", &|i| &i.walton),
    ];
    for (name, of) in rows {
        for (q, pick) in [
            (
                "position",
                &(|e: &StateError| e.position) as &dyn Fn(&StateError) -> f64,
            ),
            ("velocity", &|e: &StateError| e.velocity),
            ("spin", &|e: &StateError| e.spin),
        ] {
            let (m, w) = out.summary(|i| pick(of(i)));
            markdown.push(format!("| {name} | {q} | {m:.2e} | {w:.2e} |"));
        }
    }
    markdown.push(String::new());
    markdown.push(format!(
        "eMD* engine median {engine_median:.1e}; MD's distance to eMD* over its own step \
         change: median {ratio_median:.2}, worst {ratio_worst:.2}; Walton worst {walton_worst:.2e}."
    ));
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({"impacts": out.impacts}),
        figures: vec![path],
        info: Vec::new(),
    })
}

pub fn cooling(args: &ValidateArgs) -> Result<StageOutput> {
    let settings = FrictionCoolingSettings {
        gases: if args.full { 64 } else { 16 },
        seed: args.seed,
        ..FrictionCoolingSettings::quick()
    };
    let b = bar("fric-cool", (3 * settings.samples * settings.gases) as u64);
    b.set_message(format!(
        "{} frictional gases, N = {}: MD, eMD* (exact), eMD (Walton)",
        settings.gases, settings.particles
    ));
    let g = emdstar_harness::friction_cooling::run(&settings, &|_| b.inc(1))?;
    b.finish();
    let path = args.out.join("friction_cooling.png");
    plot_cooling(&g, &path).map_err(|e| anyhow!(e))?;
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let checks = vec![
        Check::at_most(
            "7a",
            "frictional gas: eMD* |T − T_MD|/T_MD, worst of t_end/4, t_end/2, t_end",
            max(&g.translational[0]),
            0.05,
        ),
        Check::at_most(
            "7b",
            "frictional gas: eMD* |T_rot − T_rot,MD|/T_rot,MD, worst of t_end/4, t_end/2, t_end",
            max(&g.rotational[0]),
            0.05,
        ),
    ];
    let mut markdown = vec![
        "## 7. Freely cooling frictional gas".to_string(),
        String::new(),
        format!(
            "{} gases of N = {} (averaged), η = {}, linear dashpot k = {} N/m, γ = {} kg/s, \
             µ = {}, k_t = {:.1} N/m, γ_t = {} kg/s, spins start at rest; t_end = {} s, MD dt \
             = {:.3e} s. Walton's eMD with e = {:.4}, β₀ = {:.4}.",
            settings.gases,
            settings.particles,
            settings.packing_fraction,
            settings.stiffness,
            settings.damping,
            settings.friction,
            settings.tangential_stiffness,
            settings.tangential_damping,
            settings.t_end,
            g.md_dt,
            g.walton.0,
            g.walton.1
        ),
        String::new(),
        "| engine | T: t_end/4 | t_end/2 | t_end | T_rot: t_end/4 | t_end/2 | t_end | collisions | wall s |"
            .to_string(),
        "|---|---|---|---|---|---|---|---|---|".to_string(),
    ];
    for (k, c) in g.curves.iter().enumerate() {
        let cells = |v: &[f64]| -> Vec<String> {
            g.picks.iter().map(|&p| format!("{:.4e}", v[p])).collect()
        };
        let mut row = vec![c.engine.clone()];
        row.extend(cells(&c.temperature));
        row.extend(cells(&c.rotational));
        row.push(c.collisions.to_string());
        row.push(format!("{:.1}", c.wall_seconds));
        markdown.push(format!("| {} |", row.join(" | ")));
        if k > 0 {
            markdown.push(format!(
                "| {} vs MD | {} | {} | |",
                c.engine,
                g.translational[k - 1]
                    .iter()
                    .map(|x| format!("{:.3}", x))
                    .collect::<Vec<_>>()
                    .join(" | "),
                g.rotational[k - 1]
                    .iter()
                    .map(|x| format!("{:.3}", x))
                    .collect::<Vec<_>>()
                    .join(" | ")
            ));
        }
    }
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({"settings": settings, "times": g.times, "curves": g.curves,
            "translational": g.translational, "rotational": g.rotational, "walton": g.walton}),
        figures: vec![path],
        info: Vec::new(),
    })
}
