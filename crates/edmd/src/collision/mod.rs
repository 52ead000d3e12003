//! The collision rules, written once for every engine that executes them: hard
//! spheres, eMD, and the three events of eMD* (Müller & Pöschel 2013, Sec. VI B) with
//! the exceptions of Sec. VI B 5 and both fallbacks (the eMD rule when a rotation is
//! impossible, the exact MoR for impacts outside a table), each counted in [`Stats`].
//!
//! A rule ([`Rule`], chosen per kind of contact in [`Rules`]) decides what a collision
//! does ([`Decision`]); the executor here applies it to an engine through [`Host`]: its
//! particle state, its transients and its predictions. The event engine of this crate
//! and the hybrid engine's event-driven part are both hosts.

mod ahead;
mod frictional;
mod probe;
mod recontact;
mod rule;
mod virial;

pub use ahead::{Predicted, SolveAhead};
pub use probe::{NONE, RotationProbe, pushes_deeper};
pub use recontact::{LastContact, recontact};
pub use rule::{
    Decision, Kick, PairImpact, Party, Restitution, Rule, RuleContext, Rules, Transient,
};

use crate::error::Result;
use crate::physics::Interference;
use crate::stats::Stats;
use emdstar_contact::vec3::{dot, sub};
use emdstar_system::{Wall, add_scaled};

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
    /// The nearest image of j for d = x_i − x_j now: the separation to it and the
    /// x-velocity it moves with relative to j (non-zero across a Lees–Edwards face).
    fn image(&self, d: [f64; 3]) -> ([f64; 3], f64) {
        (self.min_image(d), 0.0)
    }
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
    let mut v: [f64; 3] = std::array::from_fn(|k| v[k] - g[k] * early);
    if let Some(w) = (h.partner(i) as usize).checked_sub(h.particles())
        && let Some(wall) = h.walls().get(w).copied()
        && let Some(vib) = wall.vibration
    {
        // The contact ran in the frame of a vibrated wall moving at its speed u₀ at
        // the E^φ (the TC clock's stamp); the sphere leaves it where and as the
        // contact left it in the wall's frame now: shifted by the wall's departure
        // from uniform motion, with the change of the wall's velocity.
        let (t0, now) = (h.last_contact(i).time, h.now());
        let u0 = vib.speed(t0);
        let shift = vib.displacement(now) - vib.displacement(t0) - u0 * (now - t0);
        let du = vib.speed(now) - u0;
        let x = h.position(i);
        let n = wall.normal;
        h.place(i, std::array::from_fn(|k| x[k] + shift * n[k]));
        v = std::array::from_fn(|k| v[k] + du * n[k]);
    }
    h.set_velocity(i, v);
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
fn settle_transients<H: Host>(h: &mut H, rules: &Rules, parties: &[usize]) -> bool {
    let Some(interference) = rules.interference() else {
        return true;
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

/// Particle `p` as a rule sees it, at `position` with `velocity`.
fn party<H: Host>(h: &H, p: usize, position: [f64; 3], velocity: [f64; 3]) -> Party {
    Party {
        position,
        velocity,
        spin: h.spin(p),
        radius: h.radius(p),
        mass: h.mass(p),
    }
}

/// The parties of `i` and `j` meeting, as the rules see them, from their velocities
/// `v`, j's position `xj`, and r = x_i − x_j and j's image velocity along x from
/// [`Host::image`]: i unwrapped next to j, j's image moving at v_j + `image_vx`·e_x.
pub fn meeting<H: Host>(
    h: &H,
    [i, j]: [usize; 2],
    xj: [f64; 3],
    v: [[f64; 3]; 2],
    (r, image_vx): ([f64; 3], f64),
) -> [Party; 2] {
    [
        party(h, i, std::array::from_fn(|k| xj[k] + r[k]), v[0]),
        party(h, j, xj, shifted(v[1], image_vx)),
    ]
}

/// `v` with `vx` added along x (untouched, to the bit, where `vx` is 0).
#[inline(always)]
fn shifted(v: [f64; 3], vx: f64) -> [f64; 3] {
    if vx == 0.0 {
        v
    } else {
        [v[0] + vx, v[1], v[2]]
    }
}

/// Applies `kick` to the parties `who` (one for a wall).
fn apply_kick<H: Host>(h: &mut H, who: &[usize], kick: &Kick) {
    if kick.substitute {
        h.stats().frictional_fallback_kicks += 1;
    }
    for (slot, &p) in who.iter().enumerate() {
        h.set_velocity(p, kick.velocity[slot]);
        if let Some(spin) = kick.spin {
            h.set_spin(p, spin[slot]);
        }
    }
}

/// Executes the predicted collision of `i` and `j` now by their rule in `rules`.
/// Returns false if an eMD* transient had to end first and the pair then no longer
/// approached.
pub fn pair_collision<H: Host>(h: &mut H, rules: &mut Rules, i: usize, j: usize) -> Result<bool> {
    h.sync(i);
    h.sync(j);
    if !settle_transients(h, rules, &[i, j]) {
        let (r, image_vx) = h.image(sub(h.position(i), h.position(j)));
        if dot(r, sub(h.velocity(i), shifted(h.velocity(j), image_vx))) >= 0.0 {
            h.stats().interference_resolved += 1;
            h.predict(i);
            h.predict(j);
            return Ok(false);
        }
    }
    // Across a Lees–Edwards face j's image moves at v_j + image_vx·e_x: the rules act
    // on the image, and j takes the image's change of velocity.
    let d = sub(h.position(i), h.position(j));
    let (r, image_vx) = h.image(d);
    // i unwrapped next to j, so that the pair is contiguous.
    let parties = meeting(
        h,
        [i, j],
        h.position(j),
        [h.velocity(i), h.velocity(j)],
        (r, image_vx),
    );
    let v = sub(parties[0].velocity, parties[1].velocity);
    let contact = h.radius(i) + h.radius(j);
    let distance = dot(r, r).sqrt();
    let emdstar = rules.is_emdstar();
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
    let impact = PairImpact { r, distance, v };
    let (si, sj) = (h.species(i), h.species(j));
    let now = h.now();
    let since = now - h.last_contact(i).time.max(h.last_contact(j).time);
    stamp(h, &[i, j], now);
    let decision = {
        let (rule, mut ctx) = rules.pair(si, sj, since, h.stats());
        rule.pair(&mut ctx, &parties, &impact)?
    };
    let mut fallback = None;
    // eMD*: the E^v impulses, at the separation E^φ places the pair at (kept until E^v:
    // the pair moves with its centre of mass), counted once the E^φ stands.
    let mut later = [0.0; 6];
    // The velocities the pair leaves this event with, in i's frame (j's image).
    let mut after;
    match decision {
        Decision::Kick(kick) => {
            if emdstar {
                // No E^φ placed the pair: it leaves from outside contact.
                note_contact(h, i, j, 0.0);
            }
            after = kick.velocity;
            apply_kick(h, &[i, j], &in_own_frames(kick, image_vx));
        }
        Decision::Transient(t) if walls_block(h, &[i, j], &t.placed, None) => {
            h.stats().exception_rotation += 1;
            note_contact(h, i, j, 0.0);
            after = t.fallback.velocity;
            apply_kick(h, &[i, j], &in_own_frames(t.fallback, image_vx));
        }
        Decision::Transient(mut t) => {
            *h.probe() = Some(RotationProbe {
                parties: [i as u32, j as u32],
                before: [h.save(i), h.save(j)],
                old_position: [h.position(i), h.position(j)],
                blocked: false,
            });
            fallback = Some(t.fallback);
            note_contact(h, i, j, t.overlap_left);
            later = virial::velocity_events(&t, [parties[0].mass, parties[1].mass]);
            after = [t.moving; 2];
            let mut frames = [0.0; 2];
            if image_vx != 0.0 {
                // Across a Lees–Edwards face the rule placed i's image next to j (shifted
                // by −(d − r)) and gave velocities in i's frame: i goes back by d − r, and
                // j's velocities, now and at E^v, lose the image's x-velocity. The pair
                // still moves rigidly: j's image moves with the centre of mass.
                t.placed[0] = std::array::from_fn(|k| t.placed[0][k] + (d[k] - r[k]));
                frames[1] = -image_vx;
            }
            begin_transients(h, &[i, j], &t, [j as u32, i as u32], frames);
        }
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
        }
        note_contact(h, i, j, 0.0);
        if let Some(kick) = fallback {
            after = kick.velocity;
            apply_kick(h, &[i, j], &in_own_frames(kick, image_vx));
        }
        later = [0.0; 6];
        h.predict(i);
        h.predict(j);
    }
    let w = &mut h.stats().collisional_virial;
    virial::add_pair_impulse(w, r, &parties, after);
    add_scaled(w, later, 1.0);
    Ok(true)
}

/// A pair's kick from i's frame (j's image moving at v_j + `image_vx`·e_x) into each
/// particle's own: j takes its image's change of velocity.
fn in_own_frames(mut kick: Kick, image_vx: f64) -> Kick {
    kick.velocity[1] = shifted(kick.velocity[1], -image_vx);
    kick
}

/// Notes that `i` and `j` collided last with each other, left at `overlap`.
fn note_contact<H: Host>(h: &mut H, i: usize, j: usize, overlap: f64) {
    let time = h.now();
    h.set_last_contact(
        i,
        LastContact {
            partner: j as u32,
            overlap,
            time,
        },
    );
    h.set_last_contact(
        j,
        LastContact {
            partner: i as u32,
            overlap,
            time,
        },
    );
}

/// Notes that the parties `who` collide at `now` (the TC model's clock).
fn stamp<H: Host>(h: &mut H, who: &[usize], now: f64) {
    for &p in who {
        let last = h.last_contact(p);
        h.set_last_contact(p, LastContact { time: now, ..last });
    }
}

/// eMD*'s E^φ (Müller & Pöschel 2013, Sec. VI B): the parties `who` placed where the
/// contact leaves them (`t.placed`, relative to `origin`), moving with the transient
/// velocity (and, with friction, given their new spins), their E^v scheduled at t + τ
/// with the post-collision velocities plus gravity's share over τ (see
/// [`transient_gravity`]); `partners[k]` shares the transient of `who[k]`, and
/// `frames[k]` is added to the x-velocities of `who[k]` (a pair across a Lees–Edwards
/// face, 0 otherwise). The velocities are set before the placement, which takes a
/// party through the sliding face with them.
fn begin_transients<H: Host>(
    h: &mut H,
    who: &[usize],
    t: &Transient,
    partners: [u32; 2],
    frames: [f64; 2],
) {
    let end = h.now() + t.duration;
    for (slot, &p) in who.iter().enumerate() {
        let g = transient_gravity(h.gravity(), h.walls(), h.particles(), partners[slot]);
        h.set_velocity(p, shifted(t.moving, frames[slot]));
        if let Some(spins) = t.spin {
            h.set_spin(p, spins[slot]);
        }
        let post = shifted(t.after[slot], frames[slot]);
        let after = std::array::from_fn(|k| post[k] + g[k] * t.duration);
        h.begin_transient(p, end, after, partners[slot]);
        h.place(p, t.placed[slot]);
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
            let point = wall.point_at(h.now());
            let h_new = dot(wall.normal, sub(x_new, point));
            let h_old = dot(wall.normal, sub(x_old, point));
            if h_new < h.radius(p) && h_new < h_old {
                return true;
            }
        }
    }
    false
}

/// Executes the predicted collision of `i` with wall `w` now by its rule in `rules`.
///
/// A vibrated wall's collision is resolved in its frame at the impact: its position
/// and velocity u now, the rule applied to the velocity relative to u, u added back
/// (eMD*: u is taken as constant over the contact). A predicted time at which the
/// sphere does not touch it yet (see [`crate::vibrated::sphere_vibrated_wall`]) is a
/// check: the sphere is predicted again.
pub fn wall_collision<H: Host>(h: &mut H, rules: &mut Rules, i: usize, w: usize) -> Result<()> {
    h.sync(i);
    settle_transients(h, rules, &[i]);
    let wall = h.walls()[w];
    let n = wall.normal;
    if let Some(vib) = wall.vibration {
        let now = h.now();
        let point = wall.point_at(now);
        let height = dot(n, sub(h.position(i), point));
        let relative = dot(n, h.velocity(i)) - vib.speed(now);
        let (r, a) = (h.radius(i), vib.amplitude);
        let slack = 16.0 * crate::vibrated::contact_tolerance(height, r, a, relative, now);
        if height - r > slack {
            h.changed(i);
            h.predict(i);
            return Ok(());
        }
    }
    let point = wall.point_at(h.now());
    let u = wall.velocity_at(h.now());
    let vn = match wall.vibration {
        None => dot(n, h.velocity(i)),
        Some(_) => dot(n, sub(h.velocity(i), u)),
    };
    h.stats().wall_collisions += 1;
    let height = dot(n, sub(h.position(i), point));
    if height < h.radius(i) && vn >= 0.0 {
        h.stats().stabilising += 1;
    }
    if vn >= 0.0 {
        // A stabilising event at the top of a flight (Bannerman 2014, Alg. 2,
        // line 9): the sphere does not approach, so its velocity stays.
        h.changed(i);
        h.predict(i);
        return Ok(());
    }
    let mut me = party(h, i, sub(h.position(i), point), h.velocity(i));
    if wall.vibration.is_some() {
        me.velocity = sub(me.velocity, u);
    }
    let now = h.now();
    let since = now - h.last_contact(i).time;
    stamp(h, &[i], now);
    let decision = {
        let (rule, mut ctx) = rules.wall(h.species(i), w, since, h.stats());
        let decision = rule.wall(&mut ctx, &me, &wall, -vn)?;
        match wall.vibration {
            None => decision,
            Some(_) => decision.moved_by(u),
        }
    };
    let mut fallback = None;
    match decision {
        Decision::Kick(kick) => apply_kick(h, &[i], &kick),
        Decision::Transient(t) => {
            let placed = std::array::from_fn(|k| t.placed[0][k] + point[k]);
            if walls_block(h, &[i], &[placed], Some(w)) {
                h.stats().exception_rotation += 1;
                apply_kick(h, &[i], &t.fallback);
            } else {
                *h.probe() = Some(RotationProbe {
                    parties: [i as u32; 2],
                    before: [h.save(i); 2],
                    old_position: [h.position(i); 2],
                    blocked: false,
                });
                fallback = Some(t.fallback);
                let t = Transient {
                    placed: [placed; 2],
                    ..t
                };
                let partner = (h.particles() + w) as u32;
                begin_transients(h, &[i], &t, [partner; 2], [0.0; 2]);
            }
        }
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
        if let Some(kick) = fallback {
            apply_kick(h, &[i], &kick);
        }
        h.predict(i);
    }
    Ok(())
}
