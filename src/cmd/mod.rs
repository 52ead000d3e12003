//! One module per subcommand. Each exposes `XArgs` (clap) and `run(&XArgs) -> anyhow::Result<()>`.

pub mod any_engine;
pub mod bench;
pub mod bench_edmd;
pub mod bench_friction;
pub mod bench_soak;
pub mod bench_table;
pub mod check;
pub mod cpu_time;
pub mod edmd_engine;
pub mod engine;
pub mod export;
pub mod export_lammps;
pub mod hybrid_engine;
pub mod lammps;
pub mod mor;
pub mod pair;
pub mod resources;
pub mod run;
pub mod stop;
pub mod table;
pub mod validate;
