//! `emdstar table`: build, merge, verify, check and plot matrix-of-restitution tables.

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use emdstar_contact::Model;
use emdstar_table::Table;
use emdstar_tablegen::{Region, Spec, exact_solver};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Matrix-of-restitution lookup tables: build, merge, verify, check, plot.
///
/// The tables of Müller & Pöschel 2013, Sec. V.
///
/// Examples:
///   emdstar table build tables/linear.toml
///   emdstar table build tables/hertz.toml --shard 3/16        # one job of a job array
///   emdstar table merge tables/hertz.part-*-of-16.npz --out tables/hertz.npz
///   emdstar table verify tables/linear.toml
///   emdstar table check tables/hertz.npz --samples 20000
///   emdstar table plot default:linear --out plots
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct TableArgs {
    #[command(subcommand)]
    pub action: Action,
}

#[derive(Subcommand, Debug)]
pub enum Action {
    /// Solve every node of a spec and write the table (or one shard of it).
    Build {
        /// The TOML spec (see tables/README.md).
        spec: PathBuf,
        /// Output file; default: the spec's path with extension .npz
        /// (.part-I-of-N.npz for a shard).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Build only shard I of N (0-based), e.g. the array index of a batch job.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Worker threads (default: all cores). The output does not depend on it.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Merge the part files of all shards into the table (same bytes as one run).
    Merge {
        /// The part files, in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output table file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Regenerate a spec and compare with the committed table, byte for byte.
    Verify {
        spec: PathBuf,
        /// The table to compare with; default: the spec's path with extension .npz.
        #[arg(long)]
        table: Option<PathBuf>,
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Compare lookups with exact solves at random points: largest and 99th-percentile
    /// relative error of each component.
    Check {
        /// A table file, or default:linear / default:hertz.
        table: String,
        #[arg(long, default_value_t = 10_000)]
        samples: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Where to sample: physical impacts of the table's box (each parameter
        /// log-uniform in its range), the whole (a, b, c) rectangle, near-central impacts
        /// (a < 0) or nearly elastic ones (c < c_min).
        #[arg(long, value_enum, default_value = "physical")]
        region: RegionArg,
        #[arg(long)]
        threads: Option<usize>,
    },
    /// PNG heatmaps of the four components over (a, b) at fixed c (Figs. 4 and 5).
    Plot {
        /// A table file, or default:linear / default:hertz.
        table: String,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// c values of the slices; default: four evenly spaced over the c axis.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        c: Vec<f64>,
        /// Pixels (cells) per axis of each heatmap.
        #[arg(long, default_value_t = 120)]
        res: usize,
        /// TrueType font for the labels [default: the embedded DejaVu Sans subset].
        #[arg(long)]
        font: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum RegionArg {
    Physical,
    Rect,
    Central,
    Elastic,
}

pub fn run(args: &TableArgs) -> Result<()> {
    match &args.action {
        Action::Build {
            spec,
            out,
            shard,
            threads,
        } => build(spec, out.as_deref(), shard.as_deref(), *threads),
        Action::Merge { parts, out } => {
            let bytes = parts
                .iter()
                .map(|p| std::fs::read(p).with_context(|| format!("cannot read {}", p.display())))
                .collect::<Result<Vec<_>>>()?;
            let table = emdstar_tablegen::merge(&bytes).map_err(|e| anyhow!(e))?;
            write(out, &table.to_bytes())
        }
        Action::Verify {
            spec,
            table,
            threads,
        } => verify(spec, table.as_deref(), *threads),
        Action::Check {
            table,
            samples,
            seed,
            region,
            threads,
        } => {
            let t = load(table)?;
            check(table, &t, *samples, *seed, *region, *threads)
        }
        Action::Plot {
            table,
            out,
            c,
            res,
            font,
        } => {
            let table = load(table)?;
            let cx = table.rect()[2];
            let slices = if c.is_empty() {
                (0..4)
                    .map(|i| cx.min + (cx.max - cx.min) * i as f64 / 3.0)
                    .collect()
            } else {
                c.clone()
            };
            if let Some(font) = font {
                emdstar_plot::register_font_file(font).map_err(|e| anyhow!(e))?;
            }
            for path in
                emdstar_tablegen::plot::plot(&table, &slices, out, *res).map_err(|e| anyhow!(e))?
            {
                println!("wrote {}", path.display());
            }
            Ok(())
        }
    }
}

/// A table file or `default:MODEL`.
pub fn load(source: &str) -> Result<std::borrow::Cow<'static, Table>> {
    if let Some(model) = source.strip_prefix("default:") {
        let model: Model = model
            .parse()
            .map_err(|_| anyhow!("use default:linear or default:hertz, not {source}"))?;
        return Ok(std::borrow::Cow::Borrowed(emdstar_table::default_table(
            model,
        )?));
    }
    Table::open(source)
        .map(std::borrow::Cow::Owned)
        .with_context(|| format!("cannot load table {source}"))
}

fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        b = b.num_threads(n);
    }
    Ok(b.build()?)
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    // Through a temporary file renamed into place: never a table cut short.
    emdstar_system::write_atomically(path, bytes).context("cannot write the table")?;
    println!("wrote {} ({} bytes)", path.display(), bytes.len());
    Ok(())
}

fn parse_shard(s: &str) -> Result<(usize, usize)> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| anyhow!("--shard must look like I/N, e.g. 3/16, got {s}"))?;
    let (i, n): (usize, usize) = (
        i.trim().parse().context("--shard I must be an integer")?,
        n.trim().parse().context("--shard N must be an integer")?,
    );
    if n == 0 || i >= n {
        bail!("--shard {s}: need 0 <= I < N");
    }
    Ok((i, n))
}

fn build(
    spec_path: &Path,
    out: Option<&Path>,
    shard: Option<&str>,
    threads: Option<usize>,
) -> Result<()> {
    let spec = Spec::read(spec_path).map_err(|e| anyhow!(e))?;
    let progress = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let start = Instant::now();
    let units = emdstar_tablegen::unit_count(&spec);
    let (bytes, default_out) = match shard {
        Some(s) => {
            let (i, n) = parse_shard(s)?;
            let bytes = pool(threads)?
                .install(|| emdstar_tablegen::build_shard(&spec, &exact_solver, i, n, progress))
                .map_err(|e| anyhow!(e))?;
            (
                bytes,
                spec_path.with_extension(format!("part-{i}-of-{n}.npz")),
            )
        }
        None => {
            let table = pool(threads)?
                .install(|| emdstar_tablegen::build(&spec, &exact_solver, progress))
                .map_err(|e| anyhow!(e))?;
            (table.to_bytes(), spec_path.with_extension("npz"))
        }
    };
    let secs = start.elapsed().as_secs_f64();
    eprintln!("fitted {units} top cells in {secs:.1} s");
    write(out.unwrap_or(&default_out), &bytes)
}

fn verify(spec_path: &Path, table: Option<&Path>, threads: Option<usize>) -> Result<()> {
    let spec = Spec::read(spec_path).map_err(|e| anyhow!(e))?;
    let path = table
        .map(Path::to_path_buf)
        .unwrap_or_else(|| spec_path.with_extension("npz"));
    let committed =
        std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let progress = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let fresh = pool(threads)?
        .install(|| emdstar_tablegen::build(&spec, &exact_solver, progress))
        .map_err(|e| anyhow!(e))?
        .to_bytes();
    if fresh != committed {
        let first = fresh.iter().zip(&committed).position(|(a, b)| a != b);
        bail!(
            "{} does not match its spec {}: {} vs {} bytes, first difference at byte {:?}; \
             regenerate it with `emdstar table build {}`",
            path.display(),
            spec_path.display(),
            committed.len(),
            fresh.len(),
            first,
            spec_path.display()
        );
    }
    println!(
        "{} matches {} ({} bytes)",
        path.display(),
        spec_path.display(),
        fresh.len()
    );
    Ok(())
}

fn check(
    source: &str,
    table: &Table,
    samples: usize,
    seed: u64,
    region: RegionArg,
    threads: Option<usize>,
) -> Result<()> {
    if samples == 0 {
        bail!("--samples must be at least 1");
    }
    let region = match region {
        RegionArg::Physical => Region::Physical,
        RegionArg::Rect => Region::Rect,
        RegionArg::Central => Region::Central,
        RegionArg::Elastic => Region::Elastic,
    };
    let start = Instant::now();
    let report = pool(threads)?
        .install(|| emdstar_tablegen::check(table, &exact_solver, samples, seed, region))
        .map_err(|e| anyhow!(e))?;
    println!(
        "{source}: {} table, {samples} samples ({region:?} region, seed {seed}), {:.1} s",
        table.model(),
        start.elapsed().as_secs_f64()
    );
    if report.outside > 0 {
        println!(
            "{} of {samples} samples ({:.3}%) lie outside the table (exact-solve fallback \
             region), the errors below are over the other {}",
            report.outside,
            100.0 * report.outside as f64 / samples as f64,
            samples - report.outside
        );
    }
    println!(
        "{:<10} {:>12} {:>12}   worst at (a, b, c)",
        "component", "max rel", "p99 rel"
    );
    for c in &report.components {
        println!(
            "{:<10} {:>12.3e} {:>12.3e}   ({:.4}, {:.4}, {:.4})",
            c.name, c.max, c.p99, c.worst_at.a, c.worst_at.b, c.worst_at.c
        );
    }
    println!(
        "largest relative error per 1/{} of each axis (low to high):",
        emdstar_tablegen::check::BINS
    );
    for (name, bins) in ["a", "b", "c"].iter().zip(&report.by_axis) {
        let cells: Vec<String> = bins.iter().map(|v| format!("{v:.1e}")).collect();
        println!("  {name}: {}", cells.join(" "));
    }
    Ok(())
}
