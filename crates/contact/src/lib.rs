//! Pair physics of soft spheres for event-driven and force-based
//! simulation, after Müller & Pöschel, "Event-driven molecular dynamics of soft
//! particles" (2013).
//!
//! Pure functions and small value types, no I/O:
//! - [`ForceLaw`] (per material) and [`PairLaw`] (per pair): the linear dashpot and the
//!   viscoelastic Hertz law, clipped so they never attract, with the analytic
//!   central-impact helpers of Schwager & Pöschel 2007;
//! - [`Sphere`] and [`PairProperties`]: l, m_eff and R_eff;
//! - [`Impact`]: the normal and tangential speed at contact;
//! - [`Mor`]: the matrix of restitution of one collision, as the solver and the tables
//!   return it;
//! - [`scale`]: the dimensionless collision parameters (l̃, c_φ, c_dis) and scales T, X;
//! - [`ContactModel`]: the normal law and the [`Tangential`] sub-model of one kind of
//!   contact (none, the Cundall–Strack [`HistorySpring`], pure Coulomb sliding or
//!   Walton's rule), with the slip velocity, the spring's turning and the torques;
//! - [`Walton`]: Walton's three-parameter rule for instantaneous collisions of rough
//!   spheres (e, µ, β₀), [`rough_pair`] and [`rough_wall`];
//! - [`vec3`]: the `[f64; 3]` operations the engines share;
//! - [`ParameterBox`] and [`RectBounds`]: the rectangularised coordinates (a, b, c) in
//!   both directions, with the paper's Tab. I and Tab. II as presets.
//!
//! ```
//! use emdstar_contact::*;
//! let sphere = Sphere::from_density(0.1, 1140.0)?;
//! let pair = PairProperties::spheres(&sphere, &sphere);
//! let law = PairLaw::same_material(&ForceLaw::Linear(LinearDashpot::new(2000.0, 0.0)?), pair.r_eff)?;
//! let impact = Impact::from_speed_eccentricity(5.0, 0.3)?;
//! let scaled = scale(&law, &pair, &impact)?;
//! assert!(scaled.params.l_tilde > 1.0);
//! # Ok::<(), ContactError>(())
//! ```

mod error;
mod impact;
mod law;
mod model;
mod mor;
mod pair;
mod rect;
mod scaled;
mod sticking;
mod tangential;
pub mod vec3;
mod walton;

pub use error::{ContactError, Result};
pub use impact::Impact;
pub use law::{
    CentralImpact, ForceLaw, LinearDashpot, Model, PairLaw, ViscoelasticHertz,
    hertz_elastic_scaled_duration,
};
pub use model::ContactModel;
pub use mor::Mor;
pub use pair::{PairProperties, Sphere};
pub use rect::{HertzBox, LinearBox, ParameterBox, Range, RectBounds, RectCoords};
pub use scaled::{ScaledImpact, ScaledParams, l_tilde_exponent, scale};
pub use sticking::sticking_restitution;
pub use tangential::{
    HistorySpring, SOLID_SPHERE_INERTIA, Tangential, TangentialForce, lever_arm, slip_velocity,
    torque, turn_spring,
};
pub use walton::{Rough, RoughOutcome, Walton, rough_pair, rough_wall};

/// A 3-vector in the laboratory frame.
pub type Vec3 = nalgebra::Vector3<f64>;

/// Input checks shared with the other crates of the workspace.
pub mod check {
    pub use crate::error::{finite, non_negative, positive};
}
