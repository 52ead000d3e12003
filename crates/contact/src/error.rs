//! The one error type of the pair physics.

use std::fmt;

/// Why a pair-physics computation refused its input.
///
/// Every message names the offending quantity and what would be accepted, so that
/// a command-line user can fix the input without reading the source.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactError {
    /// A value was NaN or infinite.
    NotFinite { name: &'static str, value: f64 },
    /// A value that must be strictly positive was zero or negative.
    NotPositive { name: &'static str, value: f64 },
    /// A value that must not be negative was negative.
    Negative { name: &'static str, value: f64 },
    /// A value lay outside its allowed interval.
    OutOfRange {
        name: &'static str,
        value: f64,
        allowed: &'static str,
    },
    /// A parameter lay outside a [`crate::ParameterBox`].
    OutsideBox {
        name: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
    /// Two materials that no standard mixing rule can combine.
    IncompatibleMaterials(String),
    /// The pair is not approaching at contact, so no collision starts.
    NotApproaching { normal_speed: f64 },
}

impl fmt::Display for ContactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite { name, value } => {
                write!(f, "{name} must be a finite number, got {value}")
            }
            Self::NotPositive { name, value } => {
                write!(f, "{name} must be greater than zero, got {value}")
            }
            Self::Negative { name, value } => {
                write!(f, "{name} must not be negative, got {value}")
            }
            Self::OutOfRange {
                name,
                value,
                allowed,
            } => write!(f, "{name} = {value} is outside the allowed range {allowed}"),
            Self::OutsideBox {
                name,
                value,
                min,
                max,
            } => write!(
                f,
                "{name} = {value:e} lies outside the parameter box [{min:e}, {max:e}]"
            ),
            Self::IncompatibleMaterials(why) => write!(f, "incompatible materials: {why}"),
            Self::NotApproaching { normal_speed } => write!(
                f,
                "the spheres are not approaching at contact (normal speed {normal_speed:e} m/s must be > 0)"
            ),
        }
    }
}

impl std::error::Error for ContactError {}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, ContactError>;

/// `value` if it is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(ContactError::NotPositive { name, value })
    }
}

/// `value` if it is finite and not negative.
pub fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(ContactError::Negative { name, value })
    }
}

/// `value` if it is finite.
pub fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ContactError::NotFinite { name, value })
    }
}
