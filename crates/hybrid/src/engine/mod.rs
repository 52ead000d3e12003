//! The hybrid engine as a composition of its parts: the system, the modes, the
//! time-driven part (MD's Verlet driver over the TD particles), the event-driven part
//! (the event core of emdstar-edmd over the ED particles) and the guard between them;
//! here the step loop, in the other files the mode switches (modes.rs), the list
//! rebuilds and mode checks (upkeep.rs), what the events report back (events.rs), the
//! guard (guard.rs), velocities changed from outside (drive.rs) and what the engine
//! shows (readout.rs, simulation.rs, snapshot.rs).

mod drive;
mod events;
mod guard;
mod modes;
mod readout;
mod simulation;
mod snapshot;
mod upkeep;
mod walton;

use crate::options::{EventRule, HybridError, HybridOptions, HybridStats, Mode};
use crate::phi::{PhiScratch, local_volume_fractions, region};
use emdstar_contact::vec3::norm;
use emdstar_dem::{All, ContactEnd, MdError, MdOptions, Verlet, prepare_system};
use emdstar_edmd::rules::MorSource;
use emdstar_edmd::{Crossings, EventEngine, Physics};
use emdstar_system::{Method, System};
use events::EventBook;
use modes::Modes;
use upkeep::Upkeep;

/// A hybrid TD/ED simulation of one [`System`] (see the crate docs).
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Hybrid {
    /// The particles, in the order of the last list rebuild (sorted by cell, see
    /// [`emdstar_dem::Verlet::rebuild`]; `id` gives the config order). An ED particle's
    /// entry holds its state at its last switch or list rebuild: the event core holds
    /// it now.
    system: System,
    opts: HybridOptions,
    modes: Modes,
    /// The time-driven part: MD's Verlet driver over the TD particles.
    td: Verlet,
    /// The event-driven part: the event core over the ED particles, numbered as the
    /// particles.
    ed: EventEngine<Crossings>,
    /// What the events report back to the rest: speeds, jumps, budgets.
    book: EventBook,
    /// TD particles that may have ED neighbours in the list (the guard's work list):
    /// set at rebuilds, grown by every switch to TD.
    boundary: Vec<u32>,
    upkeep: Upkeep,
    /// The contact kick of the current step, once the TD velocities have taken it (as
    /// MD, before the list check); `None` between steps.
    td_kick: Option<f64>,
    steps: u64,
    stats: HybridStats,
    #[serde(skip)]
    scratch: Scratch,
}

/// Scratch kept between steps.
#[derive(Default)]
struct Scratch {
    /// Particles switched to TD at the current boundary whose forces are not yet in.
    fresh: Vec<u32>,
    /// The mode checks' positions and radii now, and cell sums.
    positions: Vec<[f64; 3]>,
    radius: Vec<f64>,
    phi: PhiScratch,
}

impl Hybrid {
    /// Prepares `system`: steps of `opts.dt` (checked against the shortest contact time
    /// expected up to `t_end`, as MD does), eMD* collisions with the MoR from `mor`
    /// (unused with [`EventRule::Emd`]). Modes are decided at once (all TD if
    /// `opts.adaptive` is false; then set them with [`Hybrid::set_mode`]).
    pub fn new(
        mut system: System,
        opts: HybridOptions,
        mor: Box<dyn MorSource>,
        t_end: f64,
    ) -> Result<Self, HybridError> {
        if system.domain.shear_rate != 0.0 {
            return Err(MdError::Sheared(system.domain.shear_rate).into());
        }
        let skin = prepare_system(&mut system, opts.dt, opts.skin, t_end)?;
        if skin == 0.0 {
            // Event-driven particles only see partners within the skin.
            return Err(MdError::BadSkin(skin).into());
        }
        let finite_fraction = |x: f64| x.is_finite() && (0.0..=1.0).contains(&x);
        if !(finite_fraction(opts.phi_event)
            && finite_fraction(opts.phi_time)
            && opts.phi_event <= opts.phi_time)
        {
            return Err(HybridError::Invalid(format!(
                "phi_event = {} and phi_time = {} must be volume fractions in [0, 1] with \
                 phi_event ≤ phi_time (the hysteresis band)",
                opts.phi_event, opts.phi_time
            )));
        }
        if opts.max_events_per_step == 0 {
            return Err(HybridError::Invalid(
                "max_events_per_step must be at least 1".into(),
            ));
        }
        let walls = system.domain.walls.len();
        let interactions = &system.interactions;
        let physics = match opts.events {
            EventRule::EmdStar => {
                interactions.check_runs_on(Method::Hybrid, walls)?;
                Physics::EmdStar {
                    interactions: interactions.clone(),
                    mor,
                    interference: opts.interference,
                }
            }
            EventRule::Emd => {
                interactions.check_runs_on(Method::HybridEmd, walls)?;
                Physics::Emd(walton::event_contacts(interactions)?)
            }
        };
        // Every particle event-driven from the start if none is dense (no particle
        // overlaps another or a wall in a valid state, so none is in contact; the first
        // decision has no hysteresis): as the event engine starts, in config order.
        let p = &system.particles;
        let min_cell = 2.0 * system.max_radius() + skin;
        let area = region(&p.position, system.domain.sim_box.as_ref());
        let phi = local_volume_fractions(&p.position, &p.radius, area, min_cell);
        let all_events = opts.adaptive && phi.iter().all(|&f| f < opts.phi_time);
        let ed = EventEngine::over_members(p, &system.domain, physics, |_| all_events)?;
        let md = MdOptions {
            dt: opts.dt,
            contact_end: ContactEnd::ForceZero,
            skin: Some(skin),
        };
        let td = Verlet::new(&system, md, skin);
        let n = p.len();
        let mode = if all_events { Mode::Event } else { Mode::Time };
        let mut h = Self {
            modes: Modes::new(n, mode),
            td,
            ed,
            book: EventBook::new(n),
            boundary: Vec::new(),
            upkeep: Upkeep::default(),
            td_kick: None,
            steps: 0,
            stats: HybridStats::default(),
            scratch: Scratch::default(),
            system,
            opts,
        };
        if all_events {
            h.events_only();
        } else {
            // Forces at t = 0 with the velocities themselves, as MD starts.
            h.rebuild(h.opts.adaptive)?;
            h.scratch.fresh.clear();
            h.td.start_forces(&h.system, h.modes.time_driven());
        }
        h.stats.ed = *h.ed.stats();
        Ok(h)
    }

    /// Time in s.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.opts.dt
    }

    /// Steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Counters.
    pub fn stats(&self) -> &HybridStats {
        &self.stats
    }

    /// The name of the source of the matrix of restitution ("table+exact", …; empty
    /// with eMD events).
    pub fn mor_name(&self) -> &'static str {
        self.ed.rules().mor_name()
    }

    /// The options in use.
    pub fn options(&self) -> &HybridOptions {
        &self.opts
    }

    /// The Verlet-list skin in use, in m.
    pub fn skin(&self) -> f64 {
        self.td.skin()
    }

    /// The system (particles in the engine's order, see [`Hybrid::particles`] for
    /// their state now in config order).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Every particle's mode, in config order.
    pub fn modes(&self) -> Vec<Mode> {
        let mut out = vec![Mode::Time; self.modes.len()];
        for (k, &id) in self.system.particles.id.iter().enumerate() {
            out[id as usize] = self.modes.of(k);
        }
        out
    }

    /// Number of particles in `mode`.
    pub fn count(&self, mode: Mode) -> usize {
        self.modes.count(mode)
    }

    /// Advances `n` steps of dt, fewer when a stop is requested
    /// ([`emdstar_system::stop`]). Velocities are synchronous with positions at step
    /// boundaries.
    pub fn advance(&mut self, n: u64) -> Result<(), HybridError> {
        for _ in 0..n {
            if emdstar_system::stop::is_requested() {
                break;
            }
            self.step()?;
        }
        Ok(())
    }

    /// One step [t, t + dt] (crate docs, "Advancing both modes together").
    fn step(&mut self) -> Result<(), HybridError> {
        let dt = self.opts.dt;
        let g = self.system.domain.gravity;
        // Forces of particles that join the TD ones now take vibrated walls where
        // they are now; the sweep's, at t + dt.
        self.td.set_wall_time(self.time());
        if self.upkeep.list {
            // MD's step: the contact kick, then the list check with its speed bound.
            let kick = self.td.next_kick();
            let kicked = self.td.kick(&mut self.system.particles, kick);
            self.td_kick = Some(kick);
            let v_td = self.td.speed_bound(kicked, g, kick);
            let v_ed = self.ed_speed_bound();
            let v_bound = max_nan(v_td, v_ed);
            let drift = self
                .td
                .drift_bound()
                .max(self.upkeep.ed_drift + self.book.max_jump);
            if !self.td.list_holds(drift, v_bound, dt) {
                self.rebuild(self.opts.adaptive)?;
                self.td.step_fits(v_bound, dt)?;
            }
        } else if self
            .upkeep
            .check_due(self.ed_speed_bound(), self.book.max_jump, dt)
        {
            self.mode_check()?;
        }
        self.guard()?;
        self.add_fresh_forces();
        let t1 = (self.steps + 1) as f64 * dt;
        self.run_events(t1)?;
        if self.modes.any(Mode::Time) {
            let kick = match self.td_kick.take() {
                Some(kick) => kick,
                None => {
                    let kick = self.td.next_kick();
                    self.td.kick(&mut self.system.particles, kick);
                    kick
                }
            };
            self.td.set_wall_time(t1);
            if self.modes.count(Mode::Time) == self.modes.len() {
                // Every particle TD: MD's sweep itself, without a test per pair.
                self.td.sweep(&mut self.system, All, kick, dt);
            } else {
                self.td
                    .sweep(&mut self.system, self.modes.time_driven(), kick, dt);
            }
            self.stats.td_particle_steps += self.modes.count(Mode::Time) as u64;
        }
        self.upkeep.ed_drift += self.ed_speed_bound() * dt;
        self.book.v_max += norm(g) * dt;
        self.steps += 1;
        self.stats.steps += 1;
        self.switch_deferred()
    }

    /// A bound on the speed of every ED particle over the next step (pending E^v
    /// velocities included), 0 without ED particles.
    fn ed_speed_bound(&self) -> f64 {
        if self.modes.any(Mode::Event) {
            self.book.v_max + norm(self.system.domain.gravity) * self.opts.dt
        } else {
            0.0
        }
    }
}

/// max(a, b) that lets a NaN through (so that a blow-up is noticed).
#[inline]
fn max_nan(a: f64, b: f64) -> f64 {
    if b > a || b.is_nan() { b } else { a }
}
