//! Matrix-of-restitution (MoR) lookup tables for eMD* (Müller & Pöschel 2013, Sec. V).
//!
//! The MoR {ε_r, ε_ṙ, ε_φ, ε_t} of a collision depends on three scaled parameters
//! (l̃, c_φ, c_dis); the paper's rectangularised coordinates (a, b, c) of
//! [`emdstar_contact::RectBounds`] map a box of physical parameters (its Tab. I or II)
//! onto a rectangle, on which this crate stores the MoR on a grid (uniform, or with the
//! nodes of an axis crowded towards its low end) and interpolates it with local
//! tensor-product Lagrange polynomials (4, 6 or 8 points per axis: tricubic to
//! tri-septic).
//!
//! The reader depends only on `emdstar-contact`; it does not solve the collision ODE.
//! Points beyond the box are an explicit [`TableError::OutOfBox`], or a counted
//! exact solve through [`WithFallback`]. Central (c_φ = 0) and elastic (c_dis = 0)
//! impacts are handled exactly by stored limit slices, see [`Table`].
//!
//! ```no_run
//! use emdstar_contact::*;
//! use emdstar_table::Table;
//! let table = Table::open("tables/linear.npz")?;
//! let s = Sphere::from_density(0.01, 1140.0)?;
//! let pair = PairProperties::spheres(&s, &s);
//! let law = PairLaw::same_material(&ForceLaw::Linear(LinearDashpot::new(2e4, 0.05)?), pair.r_eff)?;
//! let hit = table.lookup(&law, &pair, &Impact::from_speed_eccentricity(1.0, 0.3)?)?;
//! println!("eps_n = {}, tau = {} s", -hit.mor.eps_rdot, hit.mor.eps_t * hit.time);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # File format (version 2)
//!
//! An uncompressed `.npz` archive (a zip of `.npy` arrays, as `numpy.savez` writes),
//! read and written here by a small built-in codec. Members, in this order:
//!
//! | member | dtype, shape | content |
//! |---|---|---|
//! | `format_version` | int64, () | 2 |
//! | `model` | str, () | `"linear"` or `"hertz"` |
//! | `generator` | str, () | e.g. `"emdstar-tablegen 0.1.0"` |
//! | `spec` | str, () | the TOML spec the table was built from |
//! | `quantities` | str, (4,) | names of the four stored quantities |
//! | `box_names`, `box_ranges` | str (p,), float64 (p, 2) | the physical box, SI units |
//! | `bounds` | float64, (3, 2) | [g_min, g_max], [m_min, m_max], [c_min, c_max] of the rectangle |
//! | `axis_a`, `axis_b`, `axis_c` | float64, (n_a,) … | the grid nodes |
//! | `order` | int64, (3,) | interpolation points per axis |
//! | `axis_stretch` | float64, (3, 2) | [λ, d] per axis: nodes uniform in w = y + λ·ln(1 + y/d), y = x − min; λ = 0: uniform |
//! | `values` | float64, (n_a, n_b, n_c, 4) | ln(1−ε_r), ln(−ε_ṙ), ln ε_φ, ln ε_t |
//! | `elastic` | float64, (n_a, n_b, 4) | limit c_dis → 0: ln((1−ε_r)/e^c), 0, ln ε_φ, ln ε_t |
//! | `central` | float64, (n_b, n_c, 4) | limit c_φ → 0: ln(1−ε_r), ln(−ε_ṙ), ln(ε_φ/s), ln ε_t |
//! | `central_elastic` | float64, (n_b, 4) | both limits |
//! | `checksum` | uint64, () | FNV-1a-64 of the `.npy` bytes of all members above |
//!
//! with s = c_φ/l̃ = e^(a + g_min). Every member also carries the zip CRC-32; both
//! checksums are verified on load. Storing logarithms makes the relative error of each
//! component equal to the absolute interpolation error of its logarithm.
//!
//! ```python
//! import numpy as np
//! t = np.load("tables/linear.npz")
//! a, b, c = t["axis_a"], t["axis_b"], t["axis_c"]
//! one_minus_eps_r, eps_n, eps_phi, eps_t = np.exp(np.moveaxis(t["values"], -1, 0))
//! print(str(t["model"]), t["values"].shape)
//! ```

mod error;
mod format;
mod interp;
pub mod npz;
mod table;

#[cfg(feature = "embedded-defaults")]
mod defaults;

#[cfg(feature = "embedded-defaults")]
pub use defaults::{default_table, default_table_bytes};
pub use emdstar_contact::Mor;
pub use error::TableError;
pub use format::{FORMAT_VERSION, QUANTITIES, TableInfo, fnv1a64};
pub use interp::{Axis, MAX_ORDER, NQ, Stretch};
pub use table::{
    PhysicalLookup, Source, Table, TableParts, WithFallback, grid_axes, mor_from_logs, mor_to_logs,
};
