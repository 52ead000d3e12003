//! Matrix-of-restitution (MoR) lookup tables for eMD* (Müller & Pöschel 2013, Sec. V).
//!
//! The MoR {ε_r, ε_ṙ, ε_φ, ε_t} of a collision depends on three scaled parameters
//! (l̃, c_φ, c_dis); the paper's rectangularised coordinates (a, b, c) of
//! [`emdstar_contact::RectBounds`] map a box of physical parameters (its Tab. I or II)
//! onto a rectangle. A table stores the logarithms of the four components there as a
//! piecewise polynomial: a uniform grid of top cells, each refined adaptively by
//! bisection into patches, each patch a polynomial of bounded total degree (as
//! Chebyshev coefficients in the file, evaluated in monomial form by nested Horner).
//! A lookup finds its patch in a few compares and evaluates one contiguous block of
//! coefficients for all four components at once.
//!
//! The reader depends only on `emdstar-contact`; it does not solve the collision ODE.
//! Points beyond the box are an explicit [`TableError::OutOfBox`], or a counted
//! exact solve through [`WithFallback`]. Central (c_φ = 0) and elastic (c_dis = 0)
//! impacts are handled exactly by stored limit pieces, see [`Table`].
//!
//! **Threads:** a [`Table`] is immutable once loaded; every lookup takes `&self` and
//! the table is `Send + Sync`, so share one (`&Table` or `Arc<Table>`) between threads.
//!
//! **Features:** `embedded-defaults` embeds the two shipped default tables
//! ([`default_table`]); `write` adds the serialiser ([`Table::to_bytes`]) used by the
//! generator. Without features the crate is the reader only.
//!
//! ```no_run
//! use emdstar_contact::*;
//! use emdstar_table::Table;
//! let table = Table::open("tables/linear.npz")?;
//! let s = Sphere::from_density(0.01, 1140.0)?;
//! let pair = PairProperties::spheres(&s, &s);
//! let law = PairLaw::same_material(&ForceLaw::Linear(LinearDashpot::new(2e4, 0.05)?), pair.r_eff)?;
//! // Built once per pair and law (about a millisecond): the table restricted to the
//! // pair's impacts, two-dimensional; each lookup then costs only the impact's own work.
//! let lookup = table.pair_table(&law, &pair)?;
//! let hit = lookup.lookup(&Impact::from_speed_eccentricity(1.0, 0.3)?)?;
//! println!("eps_n = {}, tau = {} s", -hit.mor.eps_rdot, hit.mor.eps_t * hit.time);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # File format (version 4)
//!
//! An uncompressed `.npz` archive (a zip of `.npy` arrays, as `numpy.savez` writes),
//! read and written here by a small built-in codec. Members, in this order:
//!
//! | member | dtype, shape | content |
//! |---|---|---|
//! | `format_version` | int64, () | 4 |
//! | `model` | str, () | `"linear"` or `"hertz"` |
//! | `generator` | str, () | e.g. `"emdstar-tablegen 0.1.0"` |
//! | `spec` | str, () | the TOML spec the table was built from |
//! | `quantities` | str, (4,) | names of the four stored quantities |
//! | `box_names`, `box_ranges` | str (p,), float64 (p, 2) | the physical box, SI units |
//! | `bounds` | float64, (3, 2) | [g_min, g_max], [m_min, m_max], [c_min, c_max] of the rectangle |
//! | `b_knee` | float64, () | d of the b axis map w = ln(1 + (b − b_min)/d) (0: w = b) |
//! | `degree` | int64, () | total degree n of every patch polynomial |
//! | `tolerance` | float64, () | the generator's error goal per patch |
//! | `quantum` | float64, () | q: the largest power of two ≤ tolerance/256 |
//! | `estimated_error` | float64, (4,) | the largest patch error estimate per quantity |
//! | `{piece}_cells` | int64, (3,) | top cells along a, b, c (1 along an axis the piece lacks) |
//! | `{piece}_roots` | int64, (cells,) | root node of each top cell, C order |
//! | `{piece}_tree` | int64, (nodes, 2) | [axis, first child] of a split, or [−1, patch] of a leaf |
//! | `{piece}_split` | float64, (nodes,) | the split coordinate (children: below, then above) |
//! | `{piece}_patches` | int64, () | number of patches (leaves) |
//! | `{piece}_coef_bits` | uint64, (words,) | the Chebyshev coefficients of every patch as packed multiples of q |
//! | `checksum` | uint64, () | FNV-1a-64 of the `.npy` bytes of all members above |
//!
//! for the pieces `main` (over a, w, c), `elastic` (a, b; limit c_dis → 0: ln((1−ε_r)/e^c),
//! 0, ln ε_φ, ln ε_t), `central` (w, c; limit c_φ → 0: ln(1−ε_r), ln(−ε_ṙ), ln(ε_φ/s),
//! ln ε_t) and `central_elastic` (w; both limits), with s = c_φ/l̃ = e^(a + g_min). A patch
//! is its leaf's box, bisected from the top cell; on it t = 2(x − centre)/width ∈ [−1, 1]
//! per axis, and its terms T_i(t_a)T_j(t_b)T_k(t_c) are those with i + j + k ≤ n (on the
//! axes of the piece), ordered by i, then j, then k. An all-NaN patch of a central piece
//! is not tabulated. Every coefficient is a multiple k·q of the quantum; the integers k
//! are bit-packed, per patch: one bit (1: tabulated, 0: an all-NaN patch, nothing
//! follows), then per quantity and per total degree d = 0, 1, …, n a 6-bit width w and
//! the terms of degree d as w-bit zigzag integers (k ≥ 0 ↦ 2k, k < 0 ↦ −2k − 1), bits
//! taken from the least significant end of each word; the unused bits of the last word
//! are zero. Rounding to q moves a patch of t terms by at most t·q/2. Every member also carries the zip CRC-32; both checksums are
//! verified on load, and so is the structure of every tree. Storing logarithms makes
//! the relative error of each component equal to the absolute error of its logarithm.
//!
//! ```python
//! import numpy as np
//! t = np.load("tables/linear.npz")
//! print(str(t["model"]), int(t["degree"]), t["main_tree"].shape, t["estimated_error"])
//! print(int(t["main_patches"]), t["main_coef_bits"].nbytes, float(t["quantum"]))
//! ```

mod error;
mod fastmath;
mod format;
pub mod npz;
mod pack;
mod pair_map;
mod pair_table;
mod patch_set;
mod physical;
mod piece;
mod poly;
mod straight;
mod table;

#[cfg(feature = "embedded-defaults")]
mod defaults;

#[cfg(feature = "embedded-defaults")]
pub use defaults::{default_table, default_table_bytes};
pub use emdstar_contact::Mor;
pub use error::TableError;
pub use format::{FORMAT_VERSION, QUANTITIES, TableInfo, fnv1a64};
pub use pair_map::PairMap;
pub use pair_table::PairTable;
pub use physical::{Source, WithFallback};
pub use piece::{LEAF, Piece, PieceParts};
pub use poly::{NQ, Terms};
pub use table::{
    BMap, PIECES, PairLookup, PhysicalLookup, SharedTable, Table, TableParts, mor_from_logs,
    mor_to_logs, piece_box,
};
