//! `emdstar bench table`: ns per table lookup against ns per exact solve of the same
//! impacts, per model, measured in one run.

use super::cpu_time::thread_seconds;
use anyhow::{Result, anyhow, bail};
use clap::Args;
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz,
    scale,
};
use emdstar_table::Table;
use serde_json::json;
use std::hint::black_box;
use std::time::Instant;

/// Options of `emdstar bench table`.
#[derive(Args, Debug, Clone)]
pub struct BenchTableArgs {
    /// Tables to time (files or default:linear / default:hertz) [default: both defaults].
    #[arg(long = "table", value_name = "TABLE")]
    pub tables: Vec<String>,
    /// Impacts per case (cycled through, as a polydisperse gas scatters its lookups).
    #[arg(long, default_value_t = 4096)]
    pub impacts: usize,
    /// Rounds of every case; the figures are each case's best round, with the spread
    /// (worst/best − 1) of the rounds.
    #[arg(long, default_value_t = 5)]
    pub table_rounds: usize,
    /// Seed of the sampled impacts.
    #[arg(long, default_value_t = 1)]
    pub table_seed: u64,
}

type Case = (PairLaw, PairProperties, Impact);

/// A small seeded generator (SplitMix64), uniform in [0, 1).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn log_uniform(&mut self, r: [f64; 2]) -> f64 {
        (r[0].ln() + (r[1].ln() - r[0].ln()) * self.next()).exp()
    }
}

/// Impacts of the table's box (each parameter log-uniform in its range, as
/// `emdstar table check` draws them) that the table answers.
fn box_impacts(table: &Table, n: usize, seed: u64) -> Result<Vec<Case>> {
    let mut rng = Uniform(seed);
    let mut out = Vec::with_capacity(n);
    let mut tries = 0;
    while out.len() < n {
        tries += 1;
        if tries > 100 * n + 1000 {
            bail!("the table answers almost none of the impacts of its own box");
        }
        let mut draw = |r: [f64; 2]| rng.log_uniform(r);
        let case =
            emdstar_tablegen::check::physical_impact(table, &mut draw).map_err(|e| anyhow!(e))?;
        if table.lookup(&case.0, &case.1, &case.2).is_ok() {
            out.push(case);
        }
    }
    Ok(out)
}

/// Impacts of a monodisperse gas of one material: speeds log-uniform over a factor of
/// ten, eccentricities as in a gas (e = √U, so P(e) ∝ e), that the table answers.
fn gas_impacts(table: &Table, n: usize, seed: u64) -> Result<Vec<Case>> {
    let (law, sphere, speeds) = match table.model() {
        // The eMD* gas of `emdstar bench edmd` (Y = 1 GPa, R = 0.1 m), with A = 10 µs.
        Model::Hertz => (
            ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 1e-5)?),
            Sphere::from_density(0.1, 1140.0)?,
            [0.3, 3.0],
        ),
        // Glass-like beads: k = 1e5 N/m, γ = 0.5 kg/s, R = 1 cm.
        Model::Linear => (
            ForceLaw::Linear(LinearDashpot::new(1e5, 0.5)?),
            Sphere::from_density(0.01, 2500.0)?,
            [0.1, 1.0],
        ),
    };
    let pair = PairProperties::spheres(&sphere, &sphere);
    let law = PairLaw::same_material(&law, pair.r_eff)?;
    let mut rng = Uniform(seed);
    let mut out = Vec::with_capacity(n);
    for _ in 0..100 * n {
        if out.len() == n {
            break;
        }
        let speed = rng.log_uniform(speeds);
        let e = rng.next().sqrt().min(0.999_999);
        let impact = Impact::from_speed_eccentricity(speed, e)?;
        if table.lookup(&law, &pair, &impact).is_ok() {
            out.push((law, pair, impact));
        }
    }
    if out.len() < n {
        bail!("the table answers too few impacts of the benchmark gas");
    }
    Ok(out)
}

/// Pairs of the box for the pair tables' case.
const OWN_TABLE_PAIRS: usize = 8;

/// The pairs' own tables of the bench, their impacts and what building them took.
struct OwnTables<'t> {
    tables: Vec<emdstar_table::PairTable<&'t Table>>,
    /// (table, impact) pairs, cycling over the tables.
    impacts: Vec<(usize, Impact)>,
    /// Mean build time, µs, and mean bytes of a table.
    build_us: f64,
    bytes: f64,
}

/// The pairs of the first [`OWN_TABLE_PAIRS`] box impacts, each with its own table,
/// and `n` impacts cycling over them (speed and eccentricity log-uniform over the box,
/// as `box_impacts` draws them) that their tables answer.
fn own_tables<'t>(table: &'t Table, boxed: &[Case], n: usize, seed: u64) -> Result<OwnTables<'t>> {
    let mut owns = Vec::new();
    let start = now();
    for (law, pair, _) in boxed.iter().take(OWN_TABLE_PAIRS) {
        owns.push(table.pair_table(law, pair)?);
    }
    let build_us = (now() - start) * 1e6 / owns.len() as f64;
    let bytes = owns.iter().map(|o| o.bytes()).sum::<usize>() as f64 / owns.len() as f64;
    let info = table.info();
    let range = |name: &str| {
        let k = info.box_names.iter().position(|x| x == name);
        k.map(|k| info.box_ranges[k])
            .ok_or_else(|| anyhow!("the table's box lacks the parameter {name}"))
    };
    let (speed, eccentricity) = (range("speed")?, range("eccentricity")?);
    let mut rng = Uniform(seed);
    let mut out = Vec::with_capacity(n);
    for _ in 0..100 * n + 1000 {
        if out.len() == n {
            break;
        }
        let k = out.len() % owns.len();
        let impact =
            Impact::from_speed_eccentricity(rng.log_uniform(speed), rng.log_uniform(eccentricity))?;
        if owns[k].lookup(&impact).is_ok() {
            out.push((k, impact));
        }
    }
    if out.len() < n {
        bail!("the pairs' own tables answer too few impacts of the box");
    }
    Ok(OwnTables {
        tables: owns,
        impacts: out,
        build_us,
        bytes,
    })
}

/// Seconds of this thread's CPU time (wall time where the platform has no such clock).
fn now() -> f64 {
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    thread_seconds().unwrap_or_else(|| START.get_or_init(Instant::now).elapsed().as_secs_f64())
}

/// ns per call of `f` over `n` items, `laps` times over.
fn time_per_call(n: usize, laps: usize, mut f: impl FnMut(usize)) -> f64 {
    let start = now();
    for _ in 0..laps {
        for i in 0..n {
            f(i);
        }
    }
    (now() - start) * 1e9 / (n * laps) as f64
}

/// Best of the rounds and the spread worst/best − 1.
fn best(rounds: &[f64]) -> (f64, f64) {
    let lo = rounds.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = rounds.iter().copied().fold(0.0f64, f64::max);
    (lo, hi / lo - 1.0)
}

/// Runs the benchmark; `json`: one JSON line per model only (the shared `--json`).
pub fn run(args: &BenchTableArgs, json: bool) -> Result<()> {
    if args.impacts == 0 || args.table_rounds == 0 {
        bail!("--impacts and --table-rounds must be at least 1");
    }
    let sources = if args.tables.is_empty() {
        vec!["default:linear".to_string(), "default:hertz".to_string()]
    } else {
        args.tables.clone()
    };
    for source in &sources {
        let table = super::table::load(source)?;
        let bytes = match source.strip_prefix("default:") {
            Some(m) => {
                emdstar_table::default_table_bytes(m.parse().map_err(|e: String| anyhow!(e))?).len()
            }
            None => std::fs::metadata(source)?.len() as usize,
        };
        let n = args.impacts;
        let boxed = box_impacts(&table, n, args.table_seed)?;
        let gas = gas_impacts(&table, n, args.table_seed)?;
        let one = vec![gas[0]; 1];
        let handles: Vec<_> = boxed
            .iter()
            .map(|(law, pair, impact)| Ok((table.pair(law, pair)?, *impact)))
            .collect::<Result<_, emdstar_table::TableError>>()?;
        let scaled: Vec<_> = boxed
            .iter()
            .map(|(l, p, i)| Ok(scale(l, p, i)?.params))
            .collect::<Result<_, emdstar_contact::ContactError>>()?;
        let own = own_tables(&table, &boxed, n, args.table_seed)?;
        // The pair tables' own impacts, scaled, for exact solves of the same impacts.
        let own_scaled: Vec<_> = own
            .impacts
            .iter()
            .map(|(k, i)| {
                let map = own.tables[*k].map();
                Ok(scale(map.law(), map.pair(), i)?.params)
            })
            .collect::<Result<_, emdstar_contact::ContactError>>()?;
        let own_gas = table.pair_table(&gas[0].0, &gas[0].1)?;
        let exact_n = n.min(512);
        let laps = (200_000 / n).max(1);
        let lookup = |cases: &[Case], laps: usize| {
            time_per_call(cases.len(), laps, |i| {
                let (law, pair, impact) = &cases[i];
                black_box(table.lookup(black_box(law), pair, impact).ok());
            })
        };
        let model = table.model();
        let mut rounds: [Vec<f64>; 8] = Default::default();
        for _ in 0..args.table_rounds {
            rounds[0].push(lookup(&boxed, laps));
            rounds[1].push(lookup(&gas, laps));
            rounds[2].push(lookup(&one, 200_000));
            rounds[3].push(time_per_call(n, laps, |i| {
                let (h, impact) = &handles[i];
                black_box(h.lookup(black_box(impact)).ok());
            }));
            rounds[4].push(time_per_call(exact_n, 1, |i| {
                black_box(emdstar_mor::solve(model, black_box(&scaled[i])).ok());
            }));
            rounds[5].push(time_per_call(n, laps, |i| {
                let (k, impact) = &own.impacts[i];
                black_box(own.tables[*k].lookup(black_box(impact)).ok());
            }));
            rounds[6].push(time_per_call(n, laps, |i| {
                black_box(own_gas.lookup(black_box(&gas[i].2)).ok());
            }));
            rounds[7].push(time_per_call(exact_n, 1, |i| {
                black_box(emdstar_mor::solve(model, black_box(&own_scaled[i])).ok());
            }));
        }
        let [
            (box_ns, box_spread),
            (gas_ns, gas_spread),
            (one_ns, one_spread),
            (pair_ns, pair_spread),
            (exact_ns, exact_spread),
            (own_ns, own_spread),
            (own_gas_ns, own_gas_spread),
            (own_exact_ns, own_exact_spread),
        ] = rounds.each_ref().map(|r| best(r));
        let line = json!({
            "model": model.name(),
            "table": source,
            "table_bytes": bytes,
            "lookup_ns": box_ns,
            "lookup_gas_ns": gas_ns,
            "lookup_one_impact_ns": one_ns,
            "lookup_pair_handle_ns": pair_ns,
            "exact_ns": exact_ns,
            "exact_over_lookup": exact_ns / box_ns,
            "lookup_pair_table_ns": own_ns,
            "lookup_pair_table_gas_ns": own_gas_ns,
            "exact_pair_table_ns": own_exact_ns,
            "exact_over_pair_table": own_exact_ns / own_ns,
            "pair_table_build_us": own.build_us,
            "pair_table_bytes": own.bytes,
            "spread": {
                "lookup": box_spread, "gas": gas_spread, "one_impact": one_spread,
                "pair_handle": pair_spread, "exact": exact_spread,
                "pair_table": own_spread, "pair_table_gas": own_gas_spread,
                "exact_pair_table": own_exact_spread,
            },
            "impacts": n,
            "rounds": args.table_rounds,
        });
        if json {
            println!("{line}");
            continue;
        }
        println!(
            "{source}: {model} table, {:.2} MiB; best of {} rounds (spread worst/best − 1), thread CPU time",
            bytes as f64 / (1 << 20) as f64,
            args.table_rounds
        );
        for (what, ns, spread) in [
            ("lookup, random over the box", box_ns, box_spread),
            ("lookup, gas-like impacts", gas_ns, gas_spread),
            ("lookup, one impact (cache-hot)", one_ns, one_spread),
            ("lookup through pair handles (box)", pair_ns, pair_spread),
            ("pair tables, 8 pairs of the box", own_ns, own_spread),
            ("pair table, gas-like impacts", own_gas_ns, own_gas_spread),
            ("exact solve, same box impacts", exact_ns, exact_spread),
            (
                "exact solve, pair tables' impacts",
                own_exact_ns,
                own_exact_spread,
            ),
        ] {
            println!("  {what:<36} {ns:>10.1} ns  (±{:.0}%)", 100.0 * spread);
        }
        println!(
            "  exact solve / lookup of the same impacts: {:.1} (from physical parameters), {:.1} (pair tables)",
            exact_ns / box_ns,
            own_exact_ns / own_ns
        );
        println!(
            "  a pair table: built in {:.0} µs, {:.0} KiB",
            own.build_us,
            own.bytes / 1024.0
        );
        println!("{line}");
    }
    Ok(())
}
