//! Solver of the scaled collision ODE (placeholder API; being implemented).

use emdstar_contact::{Model, ScaledParams};
use std::fmt;

/// The independent components of the matrix of restitution, Eq. (23).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mor {
    /// ε_r = r̃(τ̃)/l̃, Eq. (16).
    pub eps_r: f64,
    /// 1 − ε_r = ξ̃(τ̃)/l̃, computed from the overlap without cancellation.
    pub one_minus_eps_r: f64,
    /// ε_ṙ = r̃'(τ̃)/r̃'(0), Eq. (21); negative, ε_n = −ε_ṙ.
    pub eps_rdot: f64,
    /// ε_φ = φ̃(τ̃), Eq. (17), in radians (Φ = 1).
    pub eps_phi: f64,
    /// ε_t = τ̃, Eq. (20).
    pub eps_t: f64,
}

/// Tolerances and limits of the integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    pub rtol: f64,
    pub atol: f64,
    pub max_steps: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-12,
            atol: 1e-14,
            max_steps: 1_000_000,
        }
    }
}

/// Work done by one solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SolveStats {
    pub accepted_steps: usize,
    pub rejected_steps: usize,
    pub rhs_evaluations: usize,
}

/// Why a solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveError {
    InvalidParams(String),
    TooManySteps(usize),
    StepSizeUnderflow { t: f64 },
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidParams(why) => write!(f, "invalid scaled parameters: {why}"),
            Self::TooManySteps(n) => write!(f, "collision did not end within {n} steps"),
            Self::StepSizeUnderflow { t } => write!(f, "step size underflow at t = {t}"),
        }
    }
}

impl std::error::Error for SolveError {}

/// MoR of one collision with default tolerances.
pub fn solve(model: Model, p: &ScaledParams) -> Result<Mor, SolveError> {
    solve_with(model, p, &SolverOptions::default()).map(|(m, _)| m)
}

/// MoR of one collision with explicit tolerances, and the work it took.
pub fn solve_with(
    _model: Model,
    _p: &ScaledParams,
    _opts: &SolverOptions,
) -> Result<(Mor, SolveStats), SolveError> {
    Err(SolveError::InvalidParams(
        "solver not implemented yet".into(),
    ))
}
