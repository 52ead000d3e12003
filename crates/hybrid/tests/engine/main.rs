//! The hybrid engine's tests, one binary: mode handling against the exact two-body
//! solution, the eMD* engine and MD (`modes`), and the all-event-driven cell path
//! (`cells`).

mod cells;
mod common;
mod friction;
mod modes;
mod restart;
