//! The hybrid engine of emdstar: force-based, time-driven MD (TD) where the gas is
//! dense, eMD* events (ED) where it is dilute. After the HAET algorithm (Hybrid
//! Algorithm of Event- and Time-driven methods, cited in docs/physics.md), with one
//! change that removes HAET's mismatch: ED collisions use the matrix
//! of restitution of Müller & Pöschel 2013 (eMD*), whose trajectories agree with MD's.
//!
//! # Modes
//! Every particle is either [`Mode::Event`] (ED) or [`Mode::Time`] (TD). Modes are
//! decided at every neighbour-list rebuild, when all particles are synchronised
//! (HAET, Sec. 6, decides at its link-cell update dt_BL too), and checked on the
//! cell path (below) while no particle is TD:
//! 1. **Local volume fraction.** φ of a particle is the solid volume of the particles
//!    in its link cell and the 26 (fewer at closed faces) neighbouring cells over
//!    their volume (HAET, Sec. 5 and 6). With hysteresis: a particle becomes TD when
//!    φ ≥ `phi_time`, and returns to ED only when φ < `phi_event` < `phi_time`, so it
//!    does not flicker at the boundary of a dense region.
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
//! particle either (else exception (a): the eMD rule). Guard switches that find the
//! pair already overlapping and approaching are counted
//! ([`HybridStats::late_conversions`]; none in the tests and the hopper example). A
//! pair just out of an eMD* collision overlaps by l(1 − ε_r) while it separates with
//! zero force: that is not a contact.
//!
//! # Switching without jumps
//! A switch changes only how a particle is moved, never its state:
//! - ED → TD: the particle is moved (parabolic flight) to the step boundary. If it is
//!   inside an eMD* transient (between E^φ and E^v), the pending E^v is applied first,
//!   early, for it and its partner, and the partner is switched too: this is eMD*'s own
//!   exception (b) (Müller & Pöschel 2013, Sec. VI B 5), which conserves momentum and
//!   energy exactly. The pair then sits at the end state of the contact, whose clipped
//!   force is zero and stays zero (F = max(0, …) with ξ̇ < 0), so MD takes over with
//!   no impulse. Its contact forces at the boundary are added to the step's forces.
//! - TD → ED: only at a rebuild, only without any contact (HAET (6.2)), so the particle
//!   carries no contact force and the switch is exact.
//! - An ED particle with more than [`HybridOptions::max_events_per_step`] events in one
//!   step (an inelastic collapse, or a particle resting on a wall under gravity, which
//!   HAET Sec. 4 and 6 also give to TD) flies on freely to the end of the step and
//!   becomes TD there.
//!
//! # Advancing both modes together
//! Time advances in steps of dt (the MD step). In each step [t, t + dt]:
//! 1. rebuild the list and decide modes when the particles may have moved by more than
//!    half the skin (bound: Σ v_max·dt plus the largest eMD* jump of any particle; on
//!    the cell path, a mode check after one event skin instead, see below);
//! 2. the guard converts ED particles that could reach a TD particle;
//! 3. ED events up to t + dt are processed in time order (collisions among ED
//!    particles and with walls, E^v events); ED particles are updated lazily, only when
//!    they take part in an event, so a free ED particle costs nothing per step;
//! 4. TD particles take one velocity-Verlet step: [`emdstar_dem::step_subset`] on the
//!    TD particles (with friction its frictional counterpart, see below), MD's own step (predictor, touch correction and force kernel; see
//!    that crate's docs) with pairs of a TD and an ED particle left out, so an all-TD
//!    run is MD. Particles that switch to TD get their forces from MD's kernel with
//!    their velocities at the switch, as MD's first step.
//!
//! The list is [`emdstar_dem::NeighbourList`] in its full layout (each pair under both
//! particles), on link cells at least as wide as its cut-off 2R_max + skin, which also serve
//! the local volume fractions. ED predictions use the same list (pairs closer than
//! contact + skin at the rebuild): the drift bound guarantees that no other pair can
//! touch before the next rebuild, when every ED particle is re-predicted. (While no particle is TD, the cell path
//! below replaces the list.) Detection is Bannerman et al. 2014
//! (Algorithms 1 and 2, via [`emdstar_edmd::detect`]), so gravity (parabolic flights)
//! and inclined plane walls are handled in both modes. Collisions follow eMD* with
//! its exceptions (a) (rotation into a third body: eMD rule) and (b) (a third particle
//! hits a particle in its transient: that E^v runs early), from
//! [`emdstar_mor::rule`]. The queue holds one key per particle (its earliest event),
//! in `emdstar_edmd`'s calendar queue, ties to the smaller particle number.
//!
//! # All-ED phases: the cell path
//! While no particle is TD (a dilute gas; the free fall at the start of a hopper), a
//! list and its global rebuilds (each re-predicts every ED particle) are not needed:
//! the ED particles are handled as in the eMD* engine of `emdstar_edmd`. They live in
//! the linked-list cells of [`emdstar_edmd::cells`] (as wide as the eMD* engine makes
//! them: ≥ 2R_max, about half the mean spacing) and move between cells by
//! cell-crossing events: a full prediction scans the 27 neighbour cells, a crossing
//! only the 9 cells of the new layer (Alder & Wainwright 1959; Rapaport 1980).
//! Particles stay lazily updated; E^φ jumps re-bin the particle.
//! - **Entering.** A rebuild that leaves no particle TD bins the ED particles and
//!   predicts them on the cells. The grid covers the box, or in open space the
//!   particles' bounding box with half its extent to spare on each side (a particle
//!   beyond it makes the next mode check rebuild, which re-grids).
//! - **Mode checks** come when the particles may have moved one event skin (the mean
//!   spacing, at least the MD skin; the list would be rebuilt after half of it) since
//!   the last check. A check moves nobody: it computes every ED particle's position
//!   now and asks whether any has φ ≥ `phi_time` (the same φ on the same link cells as
//!   the list path: 2R_max + skin; an O(N) pass that sums only the neighbourhoods of
//!   cells dense enough on their own). Without TD particles that is the only switch
//!   the rule above can make, so the answer "no" means "no switch". It also updates
//!   the speed bound and the event skin.
//! - **Leaving.** If a particle is dense, is behind the outlet, left the box or blew
//!   up, the check falls back to the full rebuild, which decides the modes on the list
//!   as before (and returns to the cell path if nobody became TD). A switch to TD by
//!   hand ([`Hybrid::set_mode`]) or by the event budget rebuilds the list too (without
//!   a mode decision) before the TD particle's forces are added. So the mixed regime
//!   always runs on the list, unchanged.
//! - A particle frozen by the event budget still crosses cells until the end of the
//!   step (others must find it in its cell).
//!
//! While no particle is TD, the time steps only pace the mode checks and the event
//! budget; events run in time order across them.
//!
//! **Walls under gravity.** A pair in free fall feels gravity only through its centre
//! of mass, so its E^v velocities gain g·τ. A wall, however, carries the normal part
//! of gravity during the contact: an elastic sphere leaves a wall under gravity with
//! its impact speed (energy balance at ξ = 0). So a wall E^v adds only the tangential
//! part of g·τ; what remains of gravity's effect on the contact is of second order in
//! g·τ/v_n (see the inclined-wall test).
//!
//! # Friction and rotation
//! A material with friction (µ > 0) runs MD's tangential law (history spring and
//! dashpot, or pure Coulomb sliding) in the TD part and Walton's rule in the ED part:
//! - **TD**: [`emdstar_dem::step_subset_frictional`], MD's frictional kernel and spin
//!   kicks on the TD particles, so an all-TD run is frictional MD. Each TD contact keeps
//!   its spring (saved in checkpoints); a spring ends when its contact ends or one of
//!   its particles leaves the TD set (there are no mixed contacts, and a particle
//!   becomes ED only without contacts). Spins are kept through every switch.
//! - **ED**: eMD*'s three events have no frictional rule, so frictional ED collisions
//!   are instantaneous, as HAET's (Eqs. 1.1a-b): eMD's central restitution of the
//!   law, with Walton's rule for the tangential part. Its β₀ is derived from the TD
//!   law for each pair of species and each species against a wall, as the tangential
//!   restitution of a sticking contact that lasts the normal contact time
//!   ([`emdstar_contact::sticking_restitution`]; β₀ = 0 for pure Coulomb sliding).
//!   That needs a contact time independent of the impact speed: the linear dashpot.
//!   Hertz contacts with friction, and materials that give β₀ alone
//!   (`tangential_restitution`, no TD law), are refused at set-up.
//!
//! # Outlet
//! [`HybridOptions::outlet`] is a plane behind which particles leave the system
//! ([`Mode::Removed`], checked at rebuilds): the discharge of a hopper. Removed
//! particles keep their last state but take no further part.
//!
//! # Limits
//! - Only the force-zero contact end (F = max(0, …)) is supported: the switch relies on
//!   the force staying zero at the end of an eMD* contact.
//! - One thread; results are deterministic (fixed loop and event orders, ties broken by
//!   particle number).

// Component loops `for k in 0..3` over several arrays read best as they are.
#![allow(clippy::needless_range_loop)]

mod engine;
mod options;
mod phi;

pub use engine::Hybrid;
pub use options::{EventRule, HybridError, HybridOptions, HybridStats, Mode};
pub use phi::local_volume_fractions;
