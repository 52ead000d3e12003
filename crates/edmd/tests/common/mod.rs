//! Starting states shared by the integration tests.

use emdstar_system::{Domain, Particles, fcc_gas};

/// 4·cells³ spheres of diameter `sigma` and mass `mass` on an fcc lattice in a periodic
/// cube at number density `density` (in the units of `sigma`), Maxwell velocities with
/// kT = `kt`.
pub fn fcc(
    cells: usize,
    density: f64,
    sigma: f64,
    mass: f64,
    kt: f64,
    seed: u64,
) -> (Particles, Domain) {
    let eta = density * std::f64::consts::PI / 6.0 * sigma.powi(3);
    // Σ ½mv² = (3/2)NkT: the rms speed is √(3kT/m).
    fcc_gas(
        cells,
        eta,
        0.5 * sigma,
        mass,
        (3.0 * kt / mass).sqrt(),
        seed,
    )
    .expect("a valid fcc gas")
}
