//! One module per subcommand. Each exposes `XArgs` (clap) and `run(&XArgs) -> anyhow::Result<()>`.

pub mod mor;
pub mod table;
