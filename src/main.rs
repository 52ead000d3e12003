//! `emdstar`: event-driven molecular dynamics of soft spheres (eMD*, Müller & Pöschel
//! 2013), checked against force-based MD. See `emdstar --help`.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Event-driven simulation of soft, frictionless spheres (eMD*, Müller & Pöschel 2013),
/// its matrix-of-restitution tables, and its cross-validation against force-based MD.
#[derive(Parser)]
#[command(name = "emdstar", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Matrix of restitution of one collision, solved exactly (or from a table).
    Mor(cmd::mor::MorArgs),
    /// Numerical stability checks of the event-driven engine.
    Check(cmd::check::CheckArgs),
    /// Matrix-of-restitution lookup tables: build, merge, verify, check, plot.
    Table(cmd::table::TableArgs),
    /// A few particles (typically a two-sphere collision) to t_end; prints the final state.
    Pair(cmd::pair::PairArgs),
    /// Simulate a gas: progress bar, trajectory, thermo log and a summary JSON.
    Run(cmd::run::RunArgs),
    /// Speed benchmarks (particle-steps per second), optionally against LAMMPS.
    Bench(cmd::bench::BenchArgs),
    // The help text is ValidateArgs' doc comment (its long form lists the scenarios).
    Validate(cmd::validate::ValidateArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Mor(args) => cmd::mor::run(&args),
        Command::Check(args) => cmd::check::run(&args),
        Command::Table(args) => cmd::table::run(&args),
        Command::Pair(args) => cmd::pair::run(&args),
        Command::Run(args) => cmd::run::run(&args),
        Command::Bench(args) => cmd::bench::run(&args),
        Command::Validate(args) => match cmd::validate::run(&args) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::from(1),
            Err(e) => Err(e),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(2)
        }
    }
}
