//! Errors of the scenarios: whatever an engine or the physics refused.

/// Why a scenario could not run.
#[derive(Debug, thiserror::Error)]
pub enum HarnessError {
    #[error("MD engine: {0}")]
    Md(#[from] emdstar_dem::MdError),
    #[error("event engine: {0}")]
    Edmd(#[from] emdstar_edmd::EngineError),
    #[error("pair physics: {0}")]
    Contact(#[from] emdstar_contact::ContactError),
    #[error("exact collision: {0}")]
    Collision(#[from] emdstar_mor::rule::CollisionError),
    #[error("system: {0}")]
    System(#[from] emdstar_system::SystemError),
    #[error("table: {0}")]
    Table(#[from] emdstar_table::TableError),
    #[error("{0}")]
    Invalid(String),
}

pub type Result<T> = std::result::Result<T, HarnessError>;
