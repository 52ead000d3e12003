//! The matrix of restitution as a value: what the exact solver (`emdstar-mor`) and
//! the tables (`emdstar-table`) both return.

/// The independent components of the matrix of restitution, Müller & Pöschel 2013,
/// Eq. (23), in the scaled variables of Eqs. (16)-(21).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mor {
    /// ε_r = r̃(τ̃)/l̃, Eq. (16).
    pub eps_r: f64,
    /// 1 − ε_r = ξ̃(τ̃)/l̃, kept apart from ε_r because it is tiny for hard contacts
    /// and would lose its digits as a difference.
    pub one_minus_eps_r: f64,
    /// ε_ṙ = r̃'(τ̃)/r̃'(0), Eq. (21); negative, ε_n = −ε_ṙ.
    pub eps_rdot: f64,
    /// ε_φ = φ̃(τ̃), Eq. (17), in radians (Φ = 1).
    pub eps_phi: f64,
    /// ε_t = τ̃, Eq. (20).
    pub eps_t: f64,
}
