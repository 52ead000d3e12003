//! Collisions of rough spheres by Walton's rule (`emdstar_contact::rough_pair` and
//! `rough_wall`; docs/physics.md, "Walton's rule"): velocities and spins of the parties
//! change together, instantaneously, at contact.

use super::Host;
use emdstar_contact::vec3::{norm, scale};
use emdstar_contact::{Rough, Walton, rough_pair, rough_wall};

fn rough_of<H: Host>(h: &H, i: usize) -> Rough {
    Rough {
        velocity: h.velocity(i),
        spin: h.spin(i),
        radius: h.radius(i),
        mass: h.mass(i),
    }
}

/// The collision of `i` and `j` now, `r` = x_i − x_j (minimum image), with normal
/// restitution `e`.
pub(super) fn pair<H: Host>(h: &mut H, i: usize, j: usize, r: [f64; 3], e: f64, w: &Walton) {
    let n = scale(1.0 / norm(r), r);
    let out = rough_pair(n, &rough_of(h, i), &rough_of(h, j), e, w);
    for (slot, p) in [i, j].into_iter().enumerate() {
        h.set_velocity(p, out.velocity[slot]);
        h.set_spin(p, out.spin[slot]);
    }
}

/// The collision of `i` with a wall of unit normal `n` now, with normal restitution `e`.
pub(super) fn wall<H: Host>(h: &mut H, i: usize, n: [f64; 3], e: f64, w: &Walton) {
    let out = rough_wall(n, &rough_of(h, i), e, w);
    h.set_velocity(i, out.velocity[0]);
    h.set_spin(i, out.spin[0]);
}
