//! Errors of the event engine. Every message says what was wrong and how to fix it.

use emdstar_contact::ContactError;
use emdstar_mor::SolveError;

/// Why the engine refused its input or stopped.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    #[error("invalid input: {0}")]
    Invalid(String),
    #[error(
        "particles {i} and {j} overlap at the start (distance {distance:e} < contact distance \
         {contact:e}); event-driven dynamics needs a valid (non-overlapping) initial state, \
         so move them apart"
    )]
    Overlap {
        i: usize,
        j: usize,
        distance: f64,
        contact: f64,
    },
    #[error(
        "packing fraction η = {eta:.4} is impossible for this box (spheres of total volume \
         {spheres:e} in a box of volume {volume:e}; random close packing is η ≈ 0.64 and no \
         packing exceeds π/√18 ≈ 0.7405): enlarge the box or use fewer or smaller particles"
    )]
    Packing { eta: f64, spheres: f64, volume: f64 },
    #[error(
        "wall {wall} cuts through particle {i} (centre {distance:e} from the plane, radius \
         {radius:e}); place every particle on the side the wall normal points to, at least \
         one radius away"
    )]
    WallCut {
        wall: usize,
        i: usize,
        distance: f64,
        radius: f64,
    },
    #[error(transparent)]
    System(#[from] emdstar_system::SystemError),
    // Not `#[from]`: a source would print its message a second time in an error chain.
    #[error("pair physics: {0}")]
    Contact(ContactError),
    #[error("matrix of restitution: {0}")]
    Solve(SolveError),
    #[error(
        "collision parameters {what} lie outside the table's box; `--mor table-or-exact` (the \
         default) solves such collisions exactly and counts them, `--mor exact` solves every \
         collision exactly, or give a table that covers them"
    )]
    OutsideTable { what: String },
}

/// Shorthand for engine results.
pub type Result<T> = std::result::Result<T, EngineError>;

impl From<ContactError> for EngineError {
    fn from(e: ContactError) -> Self {
        Self::Contact(e)
    }
}

impl From<SolveError> for EngineError {
    fn from(e: SolveError) -> Self {
        Self::Solve(e)
    }
}
