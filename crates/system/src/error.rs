//! The one error type of system set-up and output.

use emdstar_contact::ContactError;

/// Why a system could not be built, read or written.
///
/// Every message names what was wrong and how to fix it.
#[derive(Debug, thiserror::Error)]
pub enum SystemError {
    /// The config text is not valid TOML, or has unknown or mistyped keys.
    #[error("config: {0}")]
    Parse(String),
    /// A value in the config is out of range or inconsistent with another.
    #[error("config: {0}")]
    Invalid(String),
    /// A material or sphere parameter was rejected by the pair physics.
    #[error("config: {0}")]
    Contact(#[from] ContactError),
    /// Two particles overlap at the start.
    #[error(
        "particles {i} and {j} overlap at the start: centre distance {distance:.6e} m < \
         R_{i} + R_{j} = {contact:.6e} m; move them apart (particles are numbered from 0 in \
         config order)"
    )]
    Overlap {
        i: usize,
        j: usize,
        distance: f64,
        contact: f64,
    },
    /// A particle lies outside the box (along a non-periodic axis) or behind a wall.
    #[error("particle {i} at {position:?} {why}")]
    Misplaced {
        i: usize,
        position: [f64; 3],
        why: String,
    },
    /// A checkpoint could not be read or does not belong to this run.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// A path that a run may not read or write (not a regular file, an input, locked
    /// by another run); the message says which and what to do.
    #[error("{0}")]
    File(String),
    /// A file could not be read or written.
    #[error("{path}: {io}{}", io_hint(io))]
    Io { path: String, io: std::io::Error },
}

/// What to do about an I/O error of a kind users meet.
fn io_hint(e: &std::io::Error) -> &'static str {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded => {
            "; free space on that disk or write the file elsewhere (what was written before \
             is kept)"
        }
        ErrorKind::FileTooLarge => {
            "; the file reached the largest size allowed here (`ulimit -f`, or the file \
             system's limit): write less (longer output intervals) or elsewhere (what was \
             written before is kept)"
        }
        ErrorKind::PermissionDenied | ErrorKind::ReadOnlyFilesystem => {
            "; choose a path you may write to"
        }
        ErrorKind::NotFound => "; check the path (does its directory exist?)",
        _ => "",
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, SystemError>;

/// `Err(Invalid)` with a formatted message.
macro_rules! invalid {
    ($($arg:tt)*) => { Err($crate::error::SystemError::Invalid(format!($($arg)*))) };
}
pub(crate) use invalid;

/// Each component finite, else an error naming the quantity.
pub fn finite3(name: &str, v: [f64; 3]) -> Result<[f64; 3]> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(v)
    } else {
        invalid!("{name} = {v:?} must have finite components (no NaN or infinity)")
    }
}

/// `value` if finite and > 0, else an error naming the quantity.
pub fn positive(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        invalid!(
            "{name} = {} must be a finite number greater than zero",
            num(value)
        )
    }
}

/// `v` if the kinetic energy ½ m v² of a particle of mass `m` is a finite double (every
/// engine squares speeds), else an error naming the quantity.
pub fn representable_energy(name: &str, m: f64, v: [f64; 3]) -> Result<[f64; 3]> {
    if (0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])).is_finite() {
        Ok(v)
    } else {
        invalid!(
            "{name} = {v:?} m/s is too large: the particle's kinetic energy overflows double \
             precision; give a speed of a physical size"
        )
    }
}

/// `w` if the rotational energy ½ I ω² of a particle of moment of inertia `inertia` is a
/// finite double (energies and the torques of friction square spins), else an error
/// naming the quantity.
pub fn representable_spin(name: &str, inertia: f64, w: [f64; 3]) -> Result<[f64; 3]> {
    if (0.5 * inertia * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])).is_finite() {
        Ok(w)
    } else {
        invalid!(
            "{name} = {w:?} rad/s is too large: the particle's rotational energy overflows \
             double precision; give a spin of a physical size"
        )
    }
}

/// A number for a message: as written where that is short (0.25, -1, 1500), in
/// scientific notation otherwise (1e308, 2.5e-7), never as hundreds of digits.
pub fn num(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
