//! The hybrid engine of emdstar: force-based, time-driven MD (TD) where the gas is
//! dense, eMD* events (ED) where it is dilute. After the HAET algorithm (Hybrid
//! Algorithm of Event- and Time-driven methods, cited in docs/physics.md), with one
//! change that removes HAET's mismatch: ED collisions are eMD*'s (Müller & Pöschel
//! 2013), whose trajectories agree with MD's, frictional ones included (the exact
//! frictional contact).
//!
//! # A composition
//! The engine holds its parts and copies neither engine:
//! - the **time-driven part** is MD's one Verlet driver ([`emdstar_dem::Verlet`]) over
//!   the TD particles: MD's fused kicks, touch correction, force kernel, neighbour list
//!   and its rebuild rule, with pairs of a TD and an ED particle left out;
//! - the **event-driven part** is the eMD* engine's event core
//!   ([`emdstar_edmd::EventEngine`] on cell crossings, over a membership): its particle
//!   records, queue, dispatch, delayed updates, wall predictions, staleness and
//!   collision rules, over the ED particles; the hybrid adds only hooks
//!   ([`emdstar_edmd::EventHooks`]): an event budget, the bounds its list relies on, and
//!   the TD particles for eMD*'s exception (a);
//! - the **modes**, the **guard** between the parts, and the hand-over of a particle
//!   from one part to the other.
//!
//! So with every particle TD the engine is MD to the bit, and with every particle ED
//! it is the eMD* engine on cell crossings to the bit, with the same collisions,
//! exceptions and exact frictional solves (tests/engine/bitwise.rs). Particles are
//! numbered as the driver sorts them at its list rebuilds (by cell); the event core is
//! renumbered alike, and readouts return them in config order.
//!
//! # Modes
//! Every particle is either [`Mode::Event`] (ED) or [`Mode::Time`] (TD). Modes are
//! decided at every list rebuild (HAET, Sec. 6, decides at its link-cell update dt_BL
//! too), and checked without a list while no particle is TD (below):
//! 1. **Local volume fraction.** φ of a particle is the solid volume of the particles
//!    in its link cell (at least 2R_max + skin wide) and the 26 (fewer at closed faces)
//!    neighbouring cells over their volume (HAET, Sec. 5 and 6). With hysteresis: a
//!    particle becomes TD when φ ≥ `phi_time`, and returns to ED only when φ <
//!    `phi_event` < `phi_time`, so it does not flicker at the boundary of a dense region.
//!    (The first decision, at the start, has no previous mode: TD from `phi_time` on.)
//! 2. **Contacts (HAET (6.1)–(6.2)).** A TD particle that touches any particle or wall
//!    (centre distance below the contact distance, so also a contact whose force has
//!    already dropped to zero) stays TD: an ED particle never starts overlapped, and
//!    multi-particle contacts are always MD's.
//! 3. **Buffer.** A particle that would be ED but lies within the list cut-off
//!    (contact distance + skin) of a TD particle becomes TD: the TD region carries a
//!    one-skin-wide buffer, so that the per-step guard (below) rarely has to act.
//!
//! # Mixed pairs: no mixed contacts
//! There are no ED–TD contacts. Every soft contact is either a full eMD* collision
//! (both ED) or a full MD contact (both TD, or a TD particle and a wall). This is
//! enforced by a **guard** at the start of every time step: an ED particle that could
//! reach a TD particle within the step (gap < 2·(|v_ij|·dt + |a_i|·dt² + v_ED,max·dt),
//! a bound on the approach in one step that allows for a velocity change of the ED
//! particle by an event within the step) becomes TD at once, before the contact
//! starts. An eMD* position jump (E^φ) may not bring an ED particle that close to a TD
//! particle either (else exception (a): the fallback kick). Guard switches that find
//! the pair already overlapping and approaching are counted
//! ([`HybridStats::late_conversions`]; none in the tests and the hopper example). A
//! pair just out of an eMD* collision overlaps by l(1 − ε_r) while it separates with
//! zero force: that is not a contact.
//!
//! # Switching without jumps
//! A switch changes only how a particle is moved, never its state. The TD velocities
//! are first brought in step with the positions (the driver's pending half kick).
//! - ED → TD: the particle leaves the event core with its state at the step boundary.
//!   If it is inside an eMD* transient (between E^φ and E^v), the pending E^v is
//!   applied first, early, for it and its partner, and the partner is switched too:
//!   this is eMD*'s own exception (b) (Müller & Pöschel 2013, Sec. VI B 5), which
//!   conserves momentum and energy exactly. The pair then sits at the end state of the
//!   contact, whose clipped force is zero and stays zero (F = max(0, …) with ξ̇ < 0), so
//!   MD takes over with no impulse. Its contact forces at the boundary are added to the
//!   step's forces ([`emdstar_dem::Verlet::add_forces_of`], as MD's first step).
//! - TD → ED: only at a rebuild, only without any contact (HAET (6.2)), so the particle
//!   carries no contact force and the switch is exact.
//! - An ED particle with more than [`HybridOptions::max_events_per_step`] events in one
//!   step (an inelastic collapse, or a particle resting on a wall under gravity, which
//!   HAET Sec. 4 and 6 also give to TD) has its further events held back (it flies on
//!   and crosses cells) and becomes TD at the end of the step.
//!
//! # Advancing both modes together
//! Time advances in steps of dt (the MD step). In each step [t, t + dt]:
//! 1. rebuild the list and decide modes when the particles may have moved by more than
//!    half the skin: MD's bound (largest speed since the rebuild, the kicked particles
//!    in contact, gravity), with the ED particles' speeds and eMD* jumps; while no
//!    particle is TD, a mode check after one event skin of flight instead (below);
//! 2. the guard converts ED particles that could reach a TD particle;
//! 3. the event core processes the ED events up to t + dt in time order (collisions
//!    among ED particles and with walls, E^v events); ED particles are updated lazily,
//!    only when they take part in an event, so a free ED particle costs nothing per
//!    step;
//! 4. the TD particles take one step of MD's driver.
//!
//! The list serves the TD forces, the mode rule, the guard and exception (a) against TD
//! particles (every neighbour of a particle: its upper part, built when both modes are
//! present). ED predictions need no list: the event core finds its pairs on its own
//! cells by crossing events (Alder & Wainwright 1959; Rapaport 1980), with stable
//! detection (Bannerman et al. 2014, Algorithms 1 and 2), so gravity (parabolic
//! flights) and inclined plane walls are handled in both modes; a list rebuild moves no
//! ED particle and predicts nothing again.
//!
//! # Phases without TD particles
//! While no particle is TD (a dilute gas; the free fall at the start of a hopper) there
//! is no list. The modes are checked when the particles may have moved one event skin
//! (the mean spacing, at least the list skin): a check moves nobody, computes every ED
//! particle's position now and asks whether any has φ ≥ `phi_time` (an O(N) pass that
//! sums only the neighbourhoods of cells dense enough on their own). Without TD
//! particles that is the only switch the mode rule can make, so "no" means "no
//! switch". If a particle is dense, is behind the outlet, left the box or blew up, the
//! check falls back to the full rebuild.
//!
//! **Walls under gravity.** A pair in free fall feels gravity only through its centre
//! of mass, so its E^v velocities gain g·τ. A wall, however, carries the normal part
//! of gravity during the contact: an elastic sphere leaves a wall under gravity with
//! its impact speed (energy balance at ξ = 0). So a wall E^v adds only the tangential
//! part of g·τ; what remains of gravity's effect on the contact is of second order in
//! g·τ/v_n (see the inclined-wall test).
//!
//! # Friction and rotation
//! A material with friction (µ > 0) runs MD's tangential law in the TD part and, by
//! default ([`EventRule::EmdStar`]), eMD*'s exact frictional contact in the ED part,
//! as the eMD* engine does: the history spring of MD's law solved exactly per
//! collision, for the linear and the Hertz law, walls included. Each TD contact keeps
//! its spring (saved in checkpoints); a spring ends when its contact ends or one of its
//! particles leaves the TD set. Spins are kept through every switch. Pure Coulomb sliding has no exact solve: it runs with
//! [`EventRule::Emd`], HAET's instantaneous collisions (Eqs. 1.1a-b: eMD's central
//! restitution with Walton's rule, β₀ derived from the TD law for each pair of species
//! and each species against a wall, [`emdstar_contact::sticking_restitution`]; linear
//! law only), chosen by the user, never substituted.
//!
//! # Thermostats
//! A thermostat's tick ([`Hybrid::change_velocities`], `[driving]`) falls on a step
//! boundary: the TD velocities are brought in step (MD's treatment of a tick), the ED
//! particles to the tick (pending E^v first, as the event engine's), the change sees
//! every velocity in config order, and the ED particles are predicted again. A driven
//! run with every particle in one mode is MD, or the eMD* engine on cell crossings, to
//! the bit (tests/engine/driven.rs).
//!
//! # Outlet
//! [`HybridOptions::outlet`] is a plane behind which particles leave the system
//! ([`Mode::Removed`], checked at rebuilds and mode checks): the discharge of a hopper.
//! Removed particles keep their last state but take no further part.
//!
//! # Limits
//! - Only the force-zero contact end (F = max(0, …)) is supported: the switch relies on
//!   the force staying zero at the end of an eMD* contact.
//! - Results are deterministic (fixed loop and event orders, ties broken by particle
//!   number) and do not depend on the number of threads (MD's driver sums its forces
//!   in fixed chunks).
//! - The event core's cells cover the box, or in open space the particles' region at
//!   the start; particles beyond crowd its border cells (as in the eMD* engine).

// Component loops `for k in 0..3` over several arrays read best as they are.
#![allow(clippy::needless_range_loop)]

mod engine;
mod options;
mod phi;

pub use engine::Hybrid;
pub use options::{EventRule, HybridError, HybridOptions, HybridStats, Mode};
pub use phi::local_volume_fractions;
