//! The hybrid engine's tests, one binary: mode handling against the exact two-body
//! solution, the eMD* engine and MD (`modes`), the all-event-driven cell path
//! (`cells`), friction and rotation against frictional MD (`friction`), restarts, driven runs (`driven`).

mod bitwise;
mod cells;
mod common;
mod driven;
mod friction;
mod modes;
mod restart;
