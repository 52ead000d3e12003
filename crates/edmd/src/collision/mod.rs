//! The collision rules, written once for every engine that executes them: hard
//! spheres, eMD, and the three events of eMD* (Müller & Pöschel 2013, Sec. VI B) with
//! the exceptions of Sec. VI B 5 and both fallbacks (the eMD rule when a rotation is
//! impossible, the exact MoR for impacts outside a table), each counted in [`Stats`].
//!
//! An engine takes part through [`Host`]: its particle state, its transients and
//! its predictions. The event engine of this crate and the hybrid engine's
//! event-driven part are both hosts.

mod frictional;
mod probe;
mod recontact;
mod rough;

pub use probe::{FrictionalFallback, NONE, RotationProbe, pushes_deeper};
pub use recontact::{LastContact, recontact};

use crate::error::Result;
use crate::physics::{Interference, Physics};
use crate::rules::{HertzRestitution, restitution_kick};
use crate::stats::Stats;
use emdstar_contact::vec3::{dot, from_na, sub, to_na};
use emdstar_contact::{Friction, Impact, Walton, scale};
use emdstar_mor::rule::{Body, Outcome, resolve, resolve_wall};
use emdstar_system::Wall;

/// What the collision rules need of an engine. Particles are numbered by the host;
/// partner `n + w` (n = [`Host::particles`]) is wall w.
///
/// The host keeps each particle's state at some earlier time (a delayed update) and
/// brings it to the present on [`Host::sync`]; the rules only read and write synced
/// particles. Between E^φ and E^v a particle is in a transient: it moves with the
/// pair's centre-of-mass velocity and holds its post-collision velocity, the time of
/// its E^v and its partner.
pub trait Host {
    /// A particle's state as [`Host::restore`] puts it back (position, velocity,
    /// and whatever the host files it under).
    type Saved: Copy;

    /// The time of the event being executed.
    fn now(&self) -> f64;
    /// Number of particles.
    fn particles(&self) -> usize;
    /// Moves particle `i` on to now.
    fn sync(&mut self, i: usize);
    fn position(&self, i: usize) -> [f64; 3];
    fn velocity(&self, i: usize) -> [f64; 3];
    fn set_velocity(&mut self, i: usize, v: [f64; 3]);
    /// Angular velocity in rad/s (constant between collisions: nothing else exerts a
    /// torque).
    fn spin(&self, i: usize) -> [f64; 3];
    fn set_spin(&mut self, i: usize, w: [f64; 3]);
    fn radius(&self, i: usize) -> f64;
    fn mass(&self, i: usize) -> f64;
    fn species(&self, i: usize) -> u32;
    /// The shortest periodic image of a separation.
    fn min_image(&self, d: [f64; 3]) -> [f64; 3];
    fn gravity(&self) -> [f64; 3];
    fn walls(&self) -> &[Wall];

    /// The time of `i`'s pending E^v (+∞ outside a transient).
    fn pending_time(&self, i: usize) -> f64;
    /// The velocity `i`'s pending E^v applies (gravity over the transient included).
    fn pending_velocity(&self, i: usize) -> [f64; 3];
    /// Who shares `i`'s transient: a particle, `n + w`, or [`NONE`].
    fn partner(&self, i: usize) -> u32;
    /// Starts a transient of `i` until `end` with `partner`, applying `after` then.
    fn begin_transient(&mut self, i: usize, end: f64, after: [f64; 3], partner: u32);
    /// Ends `i`'s transient without applying anything.
    fn clear_transient(&mut self, i: usize);
    /// Notes that `i`'s trajectory jumped (predictions involving it are stale).
    fn changed(&mut self, i: usize);
    /// eMD*: `i`'s last pair collision (see [`LastContact`]).
    fn last_contact(&self, i: usize) -> LastContact;
    fn set_last_contact(&mut self, i: usize, c: LastContact);

    /// Puts `i` at `x` now (an E^φ displacement): wrapped into the box and filed
    /// where the host finds it.
    fn place(&mut self, i: usize, x: [f64; 3]);
    fn save(&self, i: usize) -> Self::Saved;
    /// Puts `i` back into a state saved before an E^φ.
    fn restore(&mut self, i: usize, saved: Self::Saved);

    /// Predicts `i`'s next events from now (it is synced).
    ///
    /// Contract: while [`Host::probe`] holds a probe naming `i` as a party, the
    /// prediction passes every particle that could lie within contact of `i`'s
    /// position (at least all within contact distance, plus any margin the host
    /// keeps) to [`RotationProbe::blocks`], and sets `blocked` if one blocks.
    fn predict(&mut self, i: usize);
    /// The running exception-(a) probe.
    fn probe(&mut self) -> &mut Option<RotationProbe<Self::Saved>>;
    fn stats(&mut self) -> &mut Stats;
    /// The collision rule and the cache of central restitution it uses.
    fn rule(&mut self) -> (&mut Physics, &mut HertzRestitution);
    /// Walton's rule if collisions are frictional (hard spheres and eMD only), `None`
    /// for smooth spheres.
    fn walton(&self) -> Option<Walton>;
    /// eMD*'s frictional spheres (the history spring solved exactly per collision), if
    /// collisions are frictional.
    fn exact_friction(&self) -> Option<Friction> {
        None
    }
}

/// The part of gravity that acts on a particle's velocity over an eMD* transient
/// with `partner` (a particle, or `n + w` for wall w among `walls`). A pair in free
/// fall feels all of g through its centre of mass. A flat wall carries the normal part
/// during the contact (an elastic sphere leaves a wall under gravity with its impact
/// speed, by energy balance at ξ = 0), so only the part along the wall acts; the
/// remaining effect of gravity on the contact is of second order in g·τ/v_n.
pub fn transient_gravity(gravity: [f64; 3], walls: &[Wall], n: usize, partner: u32) -> [f64; 3] {
    let g = gravity;
    match (partner as usize).checked_sub(n) {
        Some(w) if partner != NONE && w < walls.len() => {
            let n = walls[w].normal;
            let g_n = dot(g, n);
            std::array::from_fn(|k| g[k] - g_n * n[k])
        }
        _ => g,
    }
}

/// Applies `i`'s pending post-collision velocity now (at its E^v time, or early for
/// exception b), ending its transient.
pub fn finish_transient<H: Host>(h: &mut H, i: usize) {
    h.sync(i);
    // The stored velocity includes gravity up to the E^v time; undo the rest.
    let early = h.pending_time(i) - h.now();
    let g = transient_gravity(h.gravity(), h.walls(), h.particles(), h.partner(i));
    let v = h.pending_velocity(i);
    h.set_velocity(i, std::array::from_fn(|k| v[k] - g[k] * early));
    h.clear_transient(i);
    h.changed(i);
}

/// An E^v event at its scheduled time.
pub fn velocity_event<H: Host>(h: &mut H, i: usize) {
    h.stats().velocity_events += 1;
    finish_transient(h, i);
    h.predict(i);
}

/// Runs the pending E^v of `i` early because a third party hits it (exception b),
/// and with [`Interference::BothPartners`] that of its partner too.
fn interrupt_transient<H: Host>(h: &mut H, i: usize, interference: Interference) {
    let partner = h.partner(i) as usize;
    finish_transient(h, i);
    if interference == Interference::BothPartners
        && partner < h.particles()
        && h.pending_time(partner).is_finite()
        && h.partner(partner) == i as u32
    {
        finish_transient(h, partner);
        h.stats().early_partner_updates += 1;
        h.predict(partner);
    }
}

/// Handles exception (b) for the parties of a collision about to happen. Returns
/// false if one of them was in a transient.
fn settle_transients<H: Host>(h: &mut H, parties: &[usize]) -> bool {
    let interference = match h.rule().0 {
        Physics::EmdStar { interference, .. } => *interference,
        _ => return true,
    };
    let mut clean = true;
    for &p in parties {
        if h.pending_time(p).is_finite() {
            clean = false;
            interrupt_transient(h, p, interference);
        }
    }
    if !clean {
        h.stats().exception_interference += 1;
    }
    clean
}

/// Adds the instantaneous kick of restitution `eps` to the pair (see
/// [`restitution_kick`]), with friction by Walton's rule where the host has it.
fn kick_pair<H: Host>(h: &mut H, i: usize, j: usize, r: [f64; 3], v: [f64; 3], eps: f64) {
    if let Some(w) = h.walton() {
        return rough::pair(h, i, j, r, eps, &w);
    }
    let (di, dj) = restitution_kick(r, v, h.mass(i), h.mass(j), eps);
    let (vi, vj) = (h.velocity(i), h.velocity(j));
    h.set_velocity(i, std::array::from_fn(|k| vi[k] + di[k]));
    h.set_velocity(j, std::array::from_fn(|k| vj[k] + dj[k]));
}

/// Executes the predicted collision of `i` and `j` now. Returns false if an eMD*
/// transient had to end first and the pair then no longer approached.
pub fn pair_collision<H: Host>(h: &mut H, i: usize, j: usize) -> Result<bool> {
    h.sync(i);
    h.sync(j);
    if !settle_transients(h, &[i, j]) {
        let r = h.min_image(sub(h.position(i), h.position(j)));
        if dot(r, sub(h.velocity(i), h.velocity(j))) >= 0.0 {
            h.stats().interference_resolved += 1;
            h.predict(i);
            h.predict(j);
            return Ok(false);
        }
    }
    let r = h.min_image(sub(h.position(i), h.position(j)));
    let v = sub(h.velocity(i), h.velocity(j));
    let contact = h.radius(i) + h.radius(j);
    let distance = dot(r, r).sqrt();
    let emdstar = matches!(h.rule().0, Physics::EmdStar { .. });
    let overlap = contact - distance;
    // Only eMD* places pairs overlapping; the last contacts are read only then.
    let placed = (emdstar && overlap > 0.0)
        .then(|| recontact(i, j, [h.last_contact(i), h.last_contact(j)], overlap))
        .flatten();
    match placed {
        Some(placed) => h.stats().record_recontact(overlap, placed),
        None => h.stats().record_impact(distance, contact),
    }
    h.stats().pair_collisions += 1;
    let (si, sj) = (h.species(i), h.species(j));
    let eps = match h.rule() {
        (Physics::HardSpheres { restitution }, _) => Some(*restitution),
        (Physics::Emd(m), hertz) => {
            let vn = -dot(r, v) / distance;
            Some(m.pair(si, sj).central.at(vn, hertz)?)
        }
        (Physics::EmdStar { .. }, _) => emdstar_pair(h, i, j, r, v)?,
    };
    if emdstar && eps.is_some() {
        // No E^φ placed the pair (exception a): it leaves from outside contact.
        note_contact(h, i, j, 0.0);
    }
    if let Some(eps) = eps {
        kick_pair(h, i, j, r, v, eps);
    }
    h.changed(i);
    h.changed(j);
    h.predict(i);
    h.predict(j);
    if let Some(probe) = h.probe().take()
        && probe.blocked
    {
        // Exception (a): undo the rotation and apply the eMD rule instead.
        h.stats().exception_rotation += 1;
        for (slot, &p) in probe.parties.iter().enumerate() {
            h.restore(p as usize, probe.before[slot]);
            h.clear_transient(p as usize);
            if let Some(f) = probe.friction {
                h.set_spin(p as usize, f.spins_before[slot]);
            }
        }
        note_contact(h, i, j, 0.0);
        match probe.friction {
            Some(f) => frictional::impulse_kick(h, i, j, r, v, f.impulse, probe.fallback),
            None => kick_pair(h, i, j, r, v, probe.fallback),
        }
        h.predict(i);
        h.predict(j);
    }
    Ok(true)
}

/// Notes that `i` and `j` collided last with each other, left at `overlap`.
fn note_contact<H: Host>(h: &mut H, i: usize, j: usize, overlap: f64) {
    h.set_last_contact(
        i,
        LastContact {
            partner: j as u32,
            overlap,
        },
    );
    h.set_last_contact(
        j,
        LastContact {
            partner: i as u32,
            overlap,
        },
    );
}

/// The E^φ event of eMD* for a pair (Sec. VI B 2). Returns the eMD restitution to
/// use instead if the rotation would push a party into a wall (exception a; third
/// particles are checked by the predictions that follow, see [`RotationProbe`]).
fn emdstar_pair<H: Host>(
    h: &mut H,
    i: usize,
    j: usize,
    r: [f64; 3],
    v: [f64; 3],
) -> Result<Option<f64>> {
    if let Some(friction) = h.exact_friction() {
        return frictional::pair(h, i, j, r, v, &friction);
    }
    let (si, sj) = (h.species(i), h.species(j));
    let (m, fallback, l, tau_scale) = {
        let Physics::EmdStar { materials, mor, .. } = h.rule().0 else {
            unreachable!("eMD* event without eMD* physics")
        };
        let entry = materials.pair(si, sj).interaction;
        let impact = Impact::from_relative(&to_na(r), &to_na(v))?;
        let scaled = scale(&entry.law, &entry.props, &impact)?;
        let (m, fallback) = mor.mor(entry.law.model(), &scaled.params)?;
        (m, fallback, entry.props.l, scaled.time)
    };
    h.stats().mor_fallbacks += u64::from(fallback);
    // Unwrap i next to j so that the pair is contiguous.
    let pj = h.position(j);
    let pi: [f64; 3] = std::array::from_fn(|k| pj[k] + r[k]);
    let bodies = [
        Body {
            position: to_na(pi),
            velocity: to_na(h.velocity(i)),
            mass: h.mass(i),
        },
        Body {
            position: to_na(pj),
            velocity: to_na(h.velocity(j)),
            mass: h.mass(j),
        },
    ];
    let out = resolve(&bodies, l, &m, tau_scale);
    let new = [
        from_na(&out.rotated_positions[0]),
        from_na(&out.rotated_positions[1]),
    ];
    if walls_block(h, &[i, j], &new, None) {
        h.stats().exception_rotation += 1;
        return Ok(Some(-m.eps_rdot));
    }
    *h.probe() = Some(RotationProbe {
        parties: [i as u32, j as u32],
        before: [h.save(i), h.save(j)],
        old_position: [h.position(i), h.position(j)],
        fallback: -m.eps_rdot,
        friction: None,
        blocked: false,
    });
    // Eq. (28): the pair overlaps by l(1 − ε_r) until it has separated.
    note_contact(h, i, j, l - l * m.eps_r);
    begin_pair_transients(h, [i, j], new, &out, None);
    Ok(None)
}

/// eMD*'s E^φ for a pair (Müller & Pöschel 2013, Sec. VI B): both particles placed
/// where the contact leaves them (`new`), moving with the transient velocity (and, with
/// friction, given their new `spins`), their E^v scheduled at t + τ with the
/// post-collision velocities plus gravity's share over τ.
fn begin_pair_transients<H: Host>(
    h: &mut H,
    pair: [usize; 2],
    new: [[f64; 3]; 2],
    out: &Outcome,
    spins: Option<[[f64; 3]; 2]>,
) {
    let g = h.gravity();
    let end = h.now() + out.duration;
    let partners = [pair[1] as u32, pair[0] as u32];
    for (slot, &p) in pair.iter().enumerate() {
        h.place(p, new[slot]);
        h.set_velocity(p, from_na(&out.transient_velocity));
        if let Some(spins) = spins {
            h.set_spin(p, spins[slot]);
        }
        let post = out.post_velocities[slot];
        let after = std::array::from_fn(|k| post[k] + g[k] * out.duration);
        h.begin_transient(p, end, after, partners[slot]);
    }
}

/// Exception (a) for walls: would a party move deeper into a wall other than
/// `own_wall` than it is now?
fn walls_block<H: Host>(
    h: &H,
    parties: &[usize],
    new: &[[f64; 3]],
    own_wall: Option<usize>,
) -> bool {
    for (slot, &p) in parties.iter().enumerate() {
        let (x_new, x_old) = (new[slot], h.position(p));
        for (w, wall) in h.walls().iter().enumerate() {
            if own_wall == Some(w) {
                continue;
            }
            let h_new = dot(wall.normal, sub(x_new, wall.point));
            let h_old = dot(wall.normal, sub(x_old, wall.point));
            if h_new < h.radius(p) && h_new < h_old {
                return true;
            }
        }
    }
    false
}

/// Executes the predicted collision of `i` with wall `w` now.
pub fn wall_collision<H: Host>(h: &mut H, i: usize, w: usize) -> Result<()> {
    h.sync(i);
    settle_transients(h, &[i]);
    let wall = h.walls()[w];
    let n = wall.normal;
    let vn = dot(n, h.velocity(i));
    h.stats().wall_collisions += 1;
    let height = dot(n, sub(h.position(i), wall.point));
    if height < h.radius(i) && vn >= 0.0 {
        h.stats().stabilising += 1;
    }
    let species = h.species(i);
    let eps = if vn >= 0.0 {
        // A stabilising event at the top of a flight (Bannerman 2014, Alg. 2,
        // line 9): the sphere does not approach, so its velocity stays.
        None
    } else {
        match h.rule() {
            (Physics::HardSpheres { restitution }, _) => Some(*restitution),
            (Physics::Emd(m), hertz) => Some(m.wall(species).central.at(-vn, hertz)?),
            (Physics::EmdStar { .. }, _) => emdstar_wall(h, i, w, -vn)?,
        }
    };
    let kick_wall = |h: &mut H, eps: f64| {
        if let Some(walton) = h.walton() {
            return rough::wall(h, i, n, eps, &walton);
        }
        let kick = (1.0 + eps) * vn;
        let v = h.velocity(i);
        h.set_velocity(i, std::array::from_fn(|k| v[k] - kick * n[k]));
    };
    if let Some(eps) = eps {
        kick_wall(h, eps);
    }
    h.changed(i);
    h.predict(i);
    if let Some(probe) = h.probe().take()
        && probe.blocked
    {
        // Exception (a) by a third particle: undo the rotation, apply the eMD rule.
        h.stats().exception_rotation += 1;
        h.restore(i, probe.before[0]);
        h.clear_transient(i);
        kick_wall(h, probe.fallback);
        h.predict(i);
    }
    Ok(())
}

/// The E^φ event of eMD* against a flat wall: a central collision along the normal
/// (Sec. IV applied with R₂, m₂ → ∞; see `emdstar_mor::rule::resolve_wall`).
fn emdstar_wall<H: Host>(h: &mut H, i: usize, w: usize, v_n: f64) -> Result<Option<f64>> {
    let species = h.species(i);
    let (m, fallback, l, tau_scale) = {
        let Physics::EmdStar { materials, mor, .. } = h.rule().0 else {
            unreachable!("eMD* event without eMD* physics")
        };
        let entry = materials.wall(species).interaction;
        let impact = Impact {
            normal_speed: v_n,
            tangential_speed: 0.0,
        };
        let scaled = scale(&entry.law, &entry.props, &impact)?;
        let (m, fallback) = mor.mor(entry.law.model(), &scaled.params)?;
        (m, fallback, entry.props.l, scaled.time)
    };
    h.stats().mor_fallbacks += u64::from(fallback);
    let wall = h.walls()[w];
    let body = Body {
        position: to_na(sub(h.position(i), wall.point)),
        velocity: to_na(h.velocity(i)),
        mass: h.mass(i),
    };
    let out = resolve_wall(&body, &to_na(wall.normal), l, &m, tau_scale);
    let rel = out.rotated_positions[0];
    let new = std::array::from_fn(|k| rel[k] + wall.point[k]);
    if walls_block(h, &[i], &[new], Some(w)) {
        h.stats().exception_rotation += 1;
        return Ok(Some(-m.eps_rdot));
    }
    *h.probe() = Some(RotationProbe {
        parties: [i as u32; 2],
        before: [h.save(i); 2],
        old_position: [h.position(i); 2],
        fallback: -m.eps_rdot,
        friction: None,
        blocked: false,
    });
    h.place(i, new);
    h.set_velocity(i, from_na(&out.transient_velocity));
    // The wall carries the normal part of gravity during the contact (an elastic
    // sphere leaves it with its impact speed), so only the tangential part acts over
    // τ; see `transient_gravity`.
    let post = out.post_velocities[0];
    let partner = (h.particles() + w) as u32;
    let g = transient_gravity(h.gravity(), h.walls(), h.particles(), partner);
    let after = std::array::from_fn(|k| post[k] + g[k] * out.duration);
    h.begin_transient(i, h.now() + out.duration, after, partner);
    Ok(None)
}
