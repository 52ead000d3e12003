//! `emdstar export lammps CONFIG DIR`: the LAMMPS deck of a config (see
//! `export_lammps` for the mapping of each contact law).

use super::export_lammps::{Run, data_file, input_script};
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use emdstar_dem::{ContactEnd, DEFAULT_DT_FRACTION, default_skin};
use emdstar_engines::{MdChoice, md_options};
use std::path::{Path, PathBuf};

/// Write a config as input for another code: a LAMMPS deck for runs beyond one machine.
///
/// `emdstar export lammps CONFIG DIR` writes DIR/emdstar.data (the state, atom_style
/// sphere, with velocities, spins and image flags) and DIR/in.emdstar (the input
/// script): pair_style granular with one pair_coeff per pair of species (hooke with
/// damping velocity for the linear law; hertz with damping viscoelastic, its
/// coefficients exact for the pair's reduced mass, for Hertz; tangential
/// linear_history for the history spring; limit_damping for contact_end "force"),
/// fix wall/gran per wall and species, gravity, the box's periodicity, the time step
/// and length of `emdstar run --engine md`. The script writes emdstar.log in
/// emdstar's thermo-log format and emdstar.lammpstrj, a dump OVITO reads. A config
/// whose laws have no exact LAMMPS counterpart (Coulomb sliding, Walton's rule,
/// tangential damping with Hertz, walls not normal to an axis) is refused, naming the
/// contact; nothing is approximated.
///
/// Example:
///   emdstar export lammps examples/configs/cooling_hertz_gas.toml deck/
///   cd deck && mpirun -np 4 lmp -in in.emdstar
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct ExportArgs {
    #[command(subcommand)]
    pub target: ExportTarget,
}

#[derive(Subcommand, Debug)]
pub enum ExportTarget {
    /// A LAMMPS data file and input script reproducing CONFIG (see `emdstar export --help`).
    Lammps(LammpsArgs),
}

#[derive(Args, Debug)]
pub struct LammpsArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// The directory to write emdstar.data and in.emdstar to (created if missing).
    pub dir: PathBuf,
    #[command(flatten)]
    pub md: MdChoice,
    /// Stop at this time (s) instead of the config's t_end.
    #[arg(long, value_name = "S")]
    pub t_end: Option<f64>,
    /// Replace emdstar.data and in.emdstar if DIR holds them already.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: &ExportArgs) -> Result<()> {
    match &args.target {
        ExportTarget::Lammps(a) => lammps(a),
    }
}

fn lammps(args: &LammpsArgs) -> Result<()> {
    let (config, system) = super::engine::load(&args.config, false)?;
    let md = md_options(&config, &system, &args.md, DEFAULT_DT_FRACTION)?;
    let t_end = args.t_end.unwrap_or(config.t_end);
    if !(t_end.is_finite() && t_end >= 0.0) {
        bail!("--t-end {t_end} must be a finite time of at least 0 s");
    }
    let steps = (t_end / md.dt).round() as u64;
    let output = config.output.clone().unwrap_or_default();
    let every = |interval: Option<f64>, parts: f64| {
        let dt = interval.unwrap_or(config.t_end / parts);
        ((dt / md.dt).round() as u64).max(1)
    };
    let source = args.config.display().to_string();
    let run = Run {
        source: source.clone(),
        dt: md.dt,
        steps,
        skin: md.skin.unwrap_or_else(|| default_skin(&system)),
        limit_damping: md.contact_end == ContactEnd::ForceZero,
        log_every: every(output.log_interval, 100.0),
        dump_every: every(output.trajectory_interval, 20.0),
    };
    let script = input_script(&system, &run)
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("{source} has no exact LAMMPS counterpart"))?;
    let data = data_file(&system, &source);
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("cannot create {}", args.dir.display()))?;
    let files = [("emdstar.data", data), ("in.emdstar", script)];
    for (name, _) in &files {
        let path = args.dir.join(name);
        if path.exists() && !args.force {
            bail!(
                "{} exists; give another DIR, or --force to replace it",
                path.display()
            );
        }
        refuse_input(&path, &args.config)?;
    }
    for (name, text) in &files {
        let path = args.dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    eprintln!(
        "wrote {} ({} atoms of {} types, {} steps of {:e} s); run it with: cd {} && lmp -in in.emdstar",
        args.dir.display(),
        system.particles.len(),
        system.species.len(),
        steps,
        md.dt,
        args.dir.display()
    );
    Ok(())
}

/// Refuses to write over the config.
fn refuse_input(path: &Path, config: &Path) -> Result<()> {
    let same = emdstar_system::FileIdentity::of(path)? == emdstar_system::FileIdentity::of(config)?;
    if same {
        bail!("{} is the config; give another DIR", path.display());
    }
    Ok(())
}
