//! The bytes of emdstar's two default matrix-of-restitution tables, `linear.npz` and
//! `hertz.npz` of this directory (each generated from the spec beside it). Read them
//! with `emdstar-table` (its `embedded-defaults` feature does so, parsing each once).

/// The default linear spring-dashpot table (Tab. I of Müller & Pöschel 2013).
pub static LINEAR: &[u8] = include_bytes!("../linear.npz");

/// The default viscoelastic Hertz table (Tab. II of Müller & Pöschel 2013).
pub static HERTZ: &[u8] = include_bytes!("../hertz.npz");
