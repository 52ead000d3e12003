//! The running sums behind the pressure tensor and the collision rate of the thermo
//! log, and the velocity moments: what every engine accumulates as it runs, and how
//! an interval's observables follow from two readings (see docs/physics.md, "Stress,
//! collision rate and velocity moments").
//!
//! The pressure tensor over an interval Δt is the virial one (Allen & Tildesley 1987,
//! Eq. 2.60 and Sec. 2.4):
//!
//! P·V·Δt = ∫ Σ_i m_i v_i ⊗ v_i dt + Σ r_ij ⊗ Δp_ij (impulses) or ∫ Σ r_ij ⊗ F_ij dt
//! (forces),
//!
//! so each engine keeps the time integral of the kinetic tensor and the sum of its
//! collisional part, both in kg·m²/s, from the start of the run; the difference of two
//! readings over their time difference and the volume is the interval's tensor.

use crate::state::Particles;

/// A symmetric 3×3 tensor as xx, yy, zz, xy, xz, yz.
pub type Sym3 = [f64; 6];

/// The symmetric part of a ⊗ b: ½(a_k b_l + a_l b_k).
#[inline(always)]
pub fn sym_outer(a: [f64; 3], b: [f64; 3]) -> Sym3 {
    [
        a[0] * b[0],
        a[1] * b[1],
        a[2] * b[2],
        0.5 * (a[0] * b[1] + a[1] * b[0]),
        0.5 * (a[0] * b[2] + a[2] * b[0]),
        0.5 * (a[1] * b[2] + a[2] * b[1]),
    ]
}

/// `to += m · v ⊗ v` (15 flops: the kinetic tensor's share of one particle).
#[inline(always)]
pub fn add_kinetic(to: &mut Sym3, m: f64, v: [f64; 3]) {
    let (a, b, c) = (m * v[0], m * v[1], m * v[2]);
    to[0] += a * v[0];
    to[1] += b * v[1];
    to[2] += c * v[2];
    to[3] += a * v[1];
    to[4] += a * v[2];
    to[5] += b * v[2];
}

/// `to += w · t`.
#[inline(always)]
pub fn add_scaled(to: &mut Sym3, t: Sym3, w: f64) {
    for k in 0..6 {
        to[k] += w * t[k];
    }
}

/// What an engine has accumulated since its run began (a checkpoint keeps it).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StressSums {
    /// ∫ Σ m v ⊗ v dt in kg·m²/s (translation only).
    pub kinetic: Sym3,
    /// Σ r_ij ⊗ Δp_i over the pair impulses (event engines) or ∫ Σ r_ij ⊗ F_ij dt over
    /// the pair forces (MD), r_ij = x_i − x_j, in kg·m²/s. Walls and gravity are
    /// external forces and left out (see docs/physics.md).
    pub collisional: Sym3,
    /// Pair collisions (event engines) or pair contacts begun (MD).
    pub collisions: u64,
}

/// An engine's sums at a time: where the log's last interval ended (engines keep it in
/// their saved state, so that a resumed run's next line is the uninterrupted run's).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StressMark {
    pub t: f64,
    pub sums: StressSums,
}

/// The observables of one log interval, or of a whole run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Observables {
    /// tr(P)/3 in Pa.
    pub pressure: f64,
    /// The pressure tensor (kinetic plus collisional) in Pa: xx, yy, zz, xy, xz, yz.
    pub tensor: Sym3,
    /// Collisions per particle per second, 2·N_coll/(N·Δt).
    pub collision_rate: f64,
    /// The Sonine coefficient a₂ = (3/5)⟨c⁴⟩/⟨c²⟩² − 1 of the peculiar velocities.
    pub sonine_a2: f64,
}

impl Observables {
    /// Nothing known (the log's first line, which has no interval behind it).
    pub const UNKNOWN: Self = Self {
        pressure: f64::NAN,
        tensor: [f64::NAN; 6],
        collision_rate: f64::NAN,
        sonine_a2: f64::NAN,
    };

    /// The observables between the readings `from` and `to` of an engine over
    /// `dt` s, in `volume` m³ with `n` particles; `sonine_a2` as given.
    pub fn between(
        from: &StressSums,
        to: &StressSums,
        dt: f64,
        volume: f64,
        n: usize,
        sonine_a2: f64,
    ) -> Self {
        let tensor: Sym3 = std::array::from_fn(|k| {
            (to.kinetic[k] - from.kinetic[k] + to.collisional[k] - from.collisional[k])
                / (volume * dt)
        });
        Self {
            pressure: (tensor[0] + tensor[1] + tensor[2]) / 3.0,
            tensor,
            collision_rate: 2.0 * (to.collisions - from.collisions) as f64 / (n as f64 * dt),
            sonine_a2,
        }
    }
}

/// a₂ = (3/5)⟨c⁴⟩/⟨c²⟩² − 1 of the velocities c = v − u relative to the mean u (van
/// Noije & Ernst 1998 in three dimensions: ⟨c⁴⟩/⟨c²⟩² = (d + 2)/d·(1 + a₂)).
/// Unweighted by mass; NaN for fewer than two particles or all at rest.
pub fn sonine_a2(p: &Particles) -> f64 {
    let n = p.len() as f64;
    let mut u = [0.0; 3];
    for v in &p.velocity {
        for k in 0..3 {
            u[k] += v[k] / n;
        }
    }
    let (mut c2, mut c4) = (0.0, 0.0);
    for v in &p.velocity {
        let s: f64 = (0..3).map(|k| (v[k] - u[k]) * (v[k] - u[k])).sum();
        c2 += s;
        c4 += s * s;
    }
    if p.len() < 2 || c2 == 0.0 {
        return f64::NAN;
    }
    let (c2, c4) = (c2 / n, c4 / n);
    0.6 * c4 / (c2 * c2) - 1.0
}
