//! `emdstar`: event-driven molecular dynamics of soft spheres (eMD*, Müller & Pöschel
//! 2013), checked against force-based MD. See `emdstar --help`.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[global_allocator]
static ALLOCATOR: emdstar_hugepages::HugePages = emdstar_hugepages::HugePages;

/// Event-driven simulation of soft spheres, with or without friction (eMD*, Müller &
/// Pöschel 2013), its matrix-of-restitution tables, and its cross-validation against
/// force-based MD.
#[derive(Parser)]
#[command(name = "emdstar", version, about, long_about = None, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    // Each command's help is its Args' doc comment: the first paragraph is the summary
    // listed here, the rest the long help of `emdstar COMMAND --help`.
    Mor(cmd::mor::MorArgs),
    Check(cmd::check::CheckArgs),
    Table(cmd::table::TableArgs),
    Pair(cmd::pair::PairArgs),
    Run(cmd::run::RunArgs),
    Export(cmd::export::ExportArgs),
    Bench(cmd::bench::BenchArgs),
    Validate(cmd::validate::ValidateArgs),
}

fn main() -> ExitCode {
    emdstar_hugepages::configure_from_env();
    let cli = Cli::parse();
    if !matches!(cli.command, Command::Run(_)) {
        end_quietly_when_the_reader_leaves();
    }
    let result = match cli.command {
        Command::Mor(args) => cmd::mor::run(&args),
        Command::Check(args) => cmd::check::run(&args),
        Command::Table(args) => cmd::table::run(&args),
        Command::Pair(args) => cmd::pair::run(&args),
        Command::Run(args) => match cmd::run::run(&args) {
            Ok(code) => return code,
            Err(e) => Err(e),
        },
        Command::Export(args) => cmd::export::run(&args),
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

/// Restores the default action of SIGPIPE (Rust ignores it, so that printing to a pipe
/// whose reader has gone fails, and `println!` panics): `emdstar table check … | head`
/// then ends quietly, as other command-line tools do. `run` keeps it ignored, so that
/// a closed pipe cannot end a run before its files are flushed and checkpointed.
fn end_quietly_when_the_reader_leaves() {
    #[cfg(unix)]
    // SAFETY: sets a signal's disposition to its default, before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
