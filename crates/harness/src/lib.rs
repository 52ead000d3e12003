//! Cross-validation of the three engines of emdstar against each other and against the
//! exact two-body solution: eMD* (Müller & Pöschel 2013, Sec. VI B), classic eMD
//! (Sec. VI A) and force-based MD (the numerical solution of Newton's equations).
//!
//! Each scenario is a pure function from a settings struct to a result struct (no
//! printing, no files); the `emdstar validate` command runs them, prints the checks and
//! writes the report. The plots in [`plot`] write PNG files to paths the caller gives.
//!
//! - [`pairs`]: random oblique impacts over the paper's Tab. I and Tab. II boxes,
//!   through MD at several time steps, eMD and eMD* (table and exact MoR), compared with
//!   the exact two-body outcome after the collision; [`pair_summary`] gives the error
//!   distributions, their checks and figures;
//! - [`fig6`]: the two trajectories of the paper's Fig. 6 (MD against eMD and eMD*);
//! - [`exceptions`]: the exception frequencies of eMD* in a free elastic gas, Fig. 7;
//! - [`cooling`]: freely cooling gases, temperature by MD, eMD and eMD*, with the
//!   asymptotic laws of Haff (constant ε) and of viscoelastic spheres;
//! - [`speed`]: wall time of MD against eMD* for the same simulated time;
//! - [`floor`]: the cost floor of eMD*'s cell crossings on its own grid and queue;
//! - [`theory`]: elastic hard spheres against Carnahan–Starling, the cooling state's
//!   a₂ against van Noije & Ernst, through the engines' observables;
//! - [`vibrated`]: a ball on a vibrated plate against the period-1 orbit;
//! - [`shear`], [`sheared_pair`]: sheared hard spheres against Enskog's viscosity,
//!   eMD* against MD in a sheared inelastic gas;
//! - [`check`]: a numbered check with its bar and verdict;
//! - [`engines`]: building systems and driving the three engines on them.

pub mod check;
pub mod cooling;
pub mod diffusion;
pub mod driven;
pub mod engines;
pub mod exceptions;
pub mod fig6;
pub mod floor;
pub mod friction_cooling;
pub mod friction_pairs;
pub mod pair_summary;
pub mod pairs;
pub use emdstar_plot as plot;
pub mod shear;
pub mod sheared_pair;
pub mod speed;
pub mod stats;
pub mod theory;
pub mod vibrated;

mod error;

pub use check::{Check, Comparison};
pub use error::{HarnessError, Result};
