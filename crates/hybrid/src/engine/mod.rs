//! The hybrid engine: state, the step loop, rebuilds and mode decisions; its event
//! part (events.rs, cells.rs, host.rs), its time-driven part (time_driven.rs), and
//! what it reports (thermo.rs, simulation.rs).

mod cells;
mod events;
mod friction;
mod host;
mod record;
mod simulation;
mod snapshot;
mod thermo;
mod time_driven;

use crate::options::{HybridError, HybridOptions, HybridStats, Mode};
use crate::phi::{DenseScratch, local_volume_fractions, region, volume_fractions_on};
use emdstar_contact::vec3::norm;
use emdstar_dem::{
    ContactScratch, MdError, NeighbourList, Rotation, check_and_wrap, prepare_system,
};
use emdstar_edmd::cells::LinkedCells;
use emdstar_edmd::collision::{RotationProbe, Rules};
use emdstar_edmd::rules::MorSource;
use emdstar_edmd::{CalendarQueue, EventQueue, Interference, Physics};
use emdstar_system::{Method, System};
use record::{EdRec, Saved};

/// A hybrid TD/ED simulation of one [`System`] (see the crate docs).
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Hybrid {
    pub(crate) system: System,
    pub(crate) opts: HybridOptions,
    pub(crate) skin: f64,
    /// The skin of the current list: `skin`, or wider while no particle is TD.
    pub(crate) list_skin: f64,
    pub(crate) mode: Vec<Mode>,
    pub(crate) steps: u64,
    pub(crate) inv_mass: Vec<f64>,
    /// TD contact accelerations at the current time (zero for ED particles).
    pub(crate) contact_acc: Vec<[f64; 3]>,
    pub(crate) new_acc: Vec<[f64; 3]>,
    /// The collision rules of the ED particles (not saved: a restored engine keeps
    /// its own).
    #[serde(skip)]
    pub(crate) rules: Rules,
    /// The time of the ED event being executed.
    pub(crate) now: f64,
    /// eMD*: exception (a) of the E^φ being executed, checked by the predictions
    /// (none between steps).
    #[serde(skip)]
    pub(crate) probe: Option<RotationProbe<Saved>>,
    pub(crate) ed: Vec<EdRec>,
    /// Each ED particle's earliest event (+∞ for the others).
    pub(crate) heap: CalendarQueue,
    /// The full layout (every pair under both particles).
    pub(crate) list: NeighbourList,
    /// The cells of the cell path (crate docs), while no particle is TD; `None` on the
    /// list path.
    pub(crate) grid: Option<LinkedCells>,
    /// Scratch of the cell path's mode check: positions and radii now, cell sums.
    #[serde(skip)]
    pub(crate) positions_now: Vec<[f64; 3]>,
    #[serde(skip)]
    pub(crate) radius_now: Vec<f64>,
    #[serde(skip)]
    pub(crate) dense: DenseScratch,
    /// Sorted indices of the TD particles.
    pub(crate) td: Vec<u32>,
    pub(crate) td_dirty: bool,
    /// Particles switched to TD at the current boundary whose forces are not yet in.
    pub(crate) converted: Vec<u32>,
    /// TD particles that may have ED neighbours in the list (the guard's work list):
    /// set at rebuilds, grown by every switch to TD.
    pub(crate) boundary: Vec<u32>,
    /// ED particles over their event budget, switched at the end of the step.
    pub(crate) deferred: Vec<u32>,
    pub(crate) drift_bound: f64,
    pub(crate) v_max_td: f64,
    pub(crate) a_max_td: f64,
    /// Bound on the speed of every ED particle (pending velocities included).
    pub(crate) v_max_ed: f64,
    /// Position jumps of eMD* E^φ events since the last rebuild, per particle.
    pub(crate) jump: Vec<f64>,
    pub(crate) max_jump: f64,
    pub(crate) stats: HybridStats,
    /// Friction: the TD part's spins and springs (`None` where every contact is
    /// frictionless).
    pub(crate) rotation: Option<Box<Rotation>>,
    /// Scratch: the TD contacts of a step.
    #[serde(skip)]
    pub(crate) contacts: ContactScratch,
}

impl Hybrid {
    /// Prepares `system`: steps of `opts.dt` (checked against the shortest contact time
    /// expected up to `t_end`, as MD does), eMD* collisions with the MoR from `mor`.
    /// Modes are decided at once (all TD if `opts.adaptive` is false; then set them
    /// with [`Hybrid::set_mode`]).
    pub fn new(
        mut system: System,
        opts: HybridOptions,
        mor: Box<dyn MorSource>,
        t_end: f64,
    ) -> Result<Self, HybridError> {
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
        system.interactions.check_runs_on(Method::Hybrid, walls)?;
        let frictional = system.interactions.is_frictional();
        // Frictional ED collisions are instantaneous, eMD's (HAET, Eqs. 1.1a-b) with
        // Walton's rule.
        let physics = if frictional {
            Physics::Emd(friction::event_contacts(&system.interactions)?)
        } else {
            Physics::EmdStar {
                interactions: system.interactions.clone(),
                mor,
                interference: Interference::HitOnly,
            }
        };
        let rules = Rules::new(physics, walls)?;
        let rotation = frictional.then(|| Box::new(Rotation::new(&system.particles)));
        let n = system.particles.len();
        let inv_mass = system.particles.mass.iter().map(|m| 1.0 / m).collect();
        let mut h = Self {
            system,
            opts,
            skin,
            list_skin: skin,
            mode: vec![Mode::Time; n],
            steps: 0,
            inv_mass,
            contact_acc: vec![[0.0; 3]; n],
            new_acc: vec![[0.0; 3]; n],
            rules,
            now: 0.0,
            probe: None,
            ed: vec![EdRec::default(); n],
            heap: CalendarQueue::new(n),
            list: NeighbourList::default(),
            grid: None,
            positions_now: Vec::new(),
            radius_now: Vec::new(),
            dense: DenseScratch::default(),
            td: Vec::new(),
            td_dirty: true,
            converted: (0..n as u32).collect(),
            boundary: Vec::new(),
            deferred: Vec::new(),
            drift_bound: 0.0,
            v_max_td: 0.0,
            a_max_td: 0.0,
            v_max_ed: 0.0,
            jump: vec![0.0; n],
            max_jump: 0.0,
            stats: HybridStats::default(),
            rotation,
            contacts: ContactScratch::default(),
        };
        // Forces at t = 0 with the velocities themselves, as MD starts.
        h.rebuild(h.opts.adaptive)?;
        h.add_converted_forces();
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
    /// with friction, whose ED collisions are eMD's).
    pub fn mor_name(&self) -> &'static str {
        self.rules.mor_name()
    }

    /// The options in use.
    pub fn options(&self) -> &HybridOptions {
        &self.opts
    }

    /// The Verlet-list skin in use, in m.
    pub fn skin(&self) -> f64 {
        self.skin
    }

    /// The system (particle states of ED particles are those of their last event; use
    /// [`Hybrid::particles`] for the state now).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Every particle's mode, in config order.
    pub fn modes(&self) -> &[Mode] {
        &self.mode
    }

    /// Number of particles in `mode`.
    pub fn count(&self, mode: Mode) -> usize {
        self.mode.iter().filter(|&&m| m == mode).count()
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

    fn step(&mut self) -> Result<(), HybridError> {
        let dt = self.opts.dt;
        let g = norm(self.system.domain.gravity);
        let v_bound = (self.v_max_td + 0.5 * self.a_max_td * dt).max(self.v_max_ed) + g * dt;
        // Written so that NaN (a blow-up) rebuilds, where it is reported. The list lasts
        // until particles may have moved half its skin; on the cell path, which has no
        // list, the modes are checked when they may have moved one event skin.
        let reach = if self.grid.is_some() { 1.0 } else { 2.0 };
        let list_holds =
            reach * (self.drift_bound + self.max_jump + v_bound * dt) <= self.list_skin;
        if !list_holds {
            if self.grid.is_some() {
                self.cell_pass()?;
            } else {
                self.rebuild(self.opts.adaptive)?;
            }
            if 2.0 * v_bound * dt > self.skin {
                return Err(MdError::SkinTooThin {
                    skin: self.skin,
                    step: v_bound * dt,
                }
                .into());
            }
        }
        self.guard();
        self.add_converted_forces();
        let t1 = (self.steps + 1) as f64 * dt;
        self.process_events(t1)?;
        self.td_step();
        self.v_max_ed += g * dt;
        self.drift_bound += v_bound.max(self.v_max_td) * dt;
        if !self.deferred.is_empty() {
            let t = self.time();
            for i in std::mem::take(&mut self.deferred) {
                let i = i as usize;
                if self.mode[i] == Mode::Event {
                    self.switch_to_td(i, t);
                    self.stats.budget_conversions += 1;
                }
            }
            if self.grid.is_some() {
                self.rebuild(false)?; // leave the cell path: a particle is TD
            }
            self.add_converted_forces();
        }
        Ok(())
    }

    /// Synchronises every particle, checks the box, rebuilds the list, decides the
    /// modes (if `decide`) and re-predicts every ED particle: on the cell path if no
    /// particle is TD then, else on the list.
    #[inline(never)]
    pub(crate) fn rebuild(&mut self, decide: bool) -> Result<(), HybridError> {
        let t = self.time();
        let n = self.mode.len();
        self.grid = None;
        for i in 0..n {
            if self.mode[i] == Mode::Event {
                self.sync(i, t);
            }
        }
        if let Some(outlet) = self.opts.outlet {
            for i in 0..n {
                let gone = outlet.distance(self.system.particles.position[i]) < 0.0;
                if gone && self.mode[i] != Mode::Removed {
                    self.remove(i, t);
                }
            }
        }
        let mode = &self.mode;
        check_and_wrap(
            &mut self.system.particles,
            self.system.domain.sim_box.as_ref(),
            t,
            |i| mode[i] == Mode::Removed,
        )?;
        // Without TD particles the list serves the events only: a wider skin means
        // fewer rebuilds (each re-predicts every ED particle). After such a period the
        // list is first built wide again, and narrowed once TD particles appear.
        let r2 = 2.0 * self.system.max_radius();
        self.refresh_td();
        let built = if self.list_skin > self.skin && (decide || self.td.is_empty()) {
            self.event_skin(&self.system.particles.position)
        } else {
            self.skin
        };
        let p = &self.system.particles;
        self.list.build_full(
            &p.position,
            &p.radius,
            self.system.domain.sim_box.as_ref(),
            r2 + built,
            built,
        )?;
        if decide {
            self.decide_modes(t, built == self.skin);
        }
        self.refresh_td();
        let cells = self.opts.cells && self.td.is_empty() && self.mode.contains(&Mode::Event);
        self.list_skin = if self.td.is_empty() {
            self.event_skin(&self.system.particles.position)
        } else {
            self.skin
        };
        if cells {
            // The list stays as built (for nothing but the next rebuild's decision).
            self.enter_cells();
        } else if self.list_skin != built {
            let p = &self.system.particles;
            self.list.build_full(
                &p.position,
                &p.radius,
                self.system.domain.sim_box.as_ref(),
                r2 + self.list_skin,
                self.list_skin,
            )?;
        }
        // Every ED particle gets a new key below; the others hold +∞ (set by the
        // switch to TD), so the queue is not reset.
        self.v_max_ed = 0.0;
        for i in 0..n {
            if self.mode[i] == Mode::Event {
                self.ed[i].frozen = false;
                self.predict(i, t);
                let v = self.system.particles.velocity[i];
                self.v_max_ed = self.v_max_ed.max(norm(v));
                if self.ed[i].pending_time.is_finite() {
                    self.v_max_ed = self.v_max_ed.max(norm(self.ed[i].pending_vel));
                }
            }
        }
        self.boundary.clear();
        for &i in &self.td {
            let mixed = self
                .list
                .of(i as usize)
                .iter()
                .any(|&e| self.mode[self.list.split(e).0] == Mode::Event);
            if mixed {
                self.boundary.push(i);
            }
        }
        self.drift_bound = 0.0;
        self.jump.iter_mut().for_each(|j| *j = 0.0);
        self.max_jump = 0.0;
        self.stats.rebuilds += 1;
        Ok(())
    }

    /// The list skin while every particle is ED: the mean particle spacing (measured
    /// best on a dilute gas: half of it rebuilt twice as often, for 25 % more time),
    /// at least the MD skin, and small enough for 3 cells along every periodic axis.
    pub(crate) fn event_skin(&self, positions: &[[f64; 3]]) -> f64 {
        let active = self.mode.iter().filter(|&&m| m != Mode::Removed).count();
        let (_, extent, periodic) = region(positions, self.system.domain.sim_box.as_ref());
        let r2 = 2.0 * self.system.max_radius();
        let volume: f64 = extent.iter().map(|e| e.max(r2)).product();
        let mut skin = self.skin.max((volume / active.max(1) as f64).cbrt());
        for k in 0..3 {
            if periodic[k] {
                skin = skin.min(extent[k] / 3.0 - r2);
            }
        }
        skin.max(self.skin)
    }

    /// Takes particle `i` out through the outlet at time `t` (a transient it shares is
    /// finished for both partners first).
    fn remove(&mut self, i: usize, t: f64) {
        if self.mode[i] == Mode::Event {
            self.switch_to_td(i, t);
            self.converted.retain(|&c| c as usize != i);
        }
        self.mode[i] = Mode::Removed;
        self.contact_acc[i] = [0.0; 3];
        self.clear_torque(i);
        self.td_dirty = true;
        self.stats.removed += 1;
    }

    /// Number of particles or walls `i` touches now (centre distance below contact).
    fn contacts_of(&self, i: usize) -> usize {
        let p = &self.system.particles;
        let xi = p.position[i];
        let mut count = 0;
        for &entry in self.list.of(i) {
            let (j, s) = self.list.split(entry);
            let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
            if norm(d) < p.radius[i] + p.radius[j] && self.mode[j] != Mode::Removed {
                count += 1;
            }
        }
        for w in &self.system.domain.walls {
            if w.distance(xi) < p.radius[i] {
                count += 1;
            }
        }
        count
    }

    /// The mode rule of the crate docs (volume fraction with hysteresis, contacts,
    /// buffer), applied at a rebuild (all particles synchronised at `t`).
    #[inline(never)]
    ///
    /// φ uses link cells of the MD cut-off 2R_max + skin: those of the list when
    /// `list_cells` (the list was built with the MD skin), else a grid of its own.
    fn decide_modes(&mut self, t: f64, list_cells: bool) {
        let p = &self.system.particles;
        let min_cell = 2.0 * self.system.max_radius() + self.skin;
        let radius: Vec<f64> = (0..p.len())
            .map(|i| {
                if self.mode[i] == Mode::Removed {
                    0.0
                } else {
                    p.radius[i]
                }
            })
            .collect();
        let phi = if list_cells {
            volume_fractions_on(&self.list.grid, &p.position, &radius, min_cell)
        } else {
            let area = region(&p.position, self.system.domain.sim_box.as_ref());
            local_volume_fractions(&p.position, &radius, area, min_cell)
        };
        let n = self.mode.len();
        let candidate: Vec<Mode> = (0..n)
            .map(|i| match self.mode[i] {
                Mode::Time => {
                    if phi[i] < self.opts.phi_event && self.contacts_of(i) == 0 {
                        Mode::Event
                    } else {
                        Mode::Time
                    }
                }
                Mode::Event => {
                    if phi[i] >= self.opts.phi_time {
                        Mode::Time
                    } else {
                        Mode::Event
                    }
                }
                Mode::Removed => Mode::Removed,
            })
            .collect();
        for i in 0..n {
            let buffered = candidate[i] == Mode::Event
                && self
                    .list
                    .of(i)
                    .iter()
                    .any(|&e| candidate[self.list.split(e).0] == Mode::Time);
            let target = if buffered { Mode::Time } else { candidate[i] };
            if target != self.mode[i] {
                match target {
                    Mode::Time => self.switch_to_td(i, t),
                    Mode::Event => self.switch_to_ed(i, t),
                    Mode::Removed => {}
                }
            }
        }
        // Switches to TD bring forces only from the next boundary on; add them now.
        self.add_converted_forces();
    }

    /// TD → ED at time `t` for a particle without contacts (no force acts on it).
    pub(crate) fn switch_to_ed(&mut self, i: usize, t: f64) {
        self.mode[i] = Mode::Event;
        self.contact_acc[i] = [0.0; 3];
        self.clear_torque(i);
        let rec = &mut self.ed[i];
        rec.stamp = t;
        rec.counter = rec.counter.wrapping_add(1);
        rec.frozen = false;
        self.td_dirty = true;
        self.stats.to_event += 1;
    }

    /// Sets the mode of particle `i` (config number) now, between steps. A switch to
    /// ED is refused while the particle touches another particle or a wall (HAET,
    /// condition (6.2)): it would start an event-driven flight inside a contact.
    pub fn set_mode(&mut self, i: usize, mode: Mode) -> Result<(), HybridError> {
        if i >= self.mode.len() {
            return Err(HybridError::Invalid(format!(
                "particle {i} does not exist: there are {} particles",
                self.mode.len()
            )));
        }
        if mode == self.mode[i] {
            return Ok(());
        }
        if mode == Mode::Removed || self.mode[i] == Mode::Removed {
            return Err(HybridError::Invalid(format!(
                "particle {i}: only the outlet removes particles, and they do not come back"
            )));
        }
        let t = self.time();
        match mode {
            Mode::Time => {
                self.switch_to_td(i, t);
                if self.grid.is_some() {
                    self.rebuild(false)?; // leave the cell path: a particle is TD
                }
                self.add_converted_forces();
            }
            Mode::Removed => unreachable!("refused above"),
            Mode::Event => {
                if self.contacts_of(i) > 0 {
                    return Err(HybridError::Invalid(format!(
                        "particle {i} touches another particle or a wall at t = {t:e} s; it \
                         can become event-driven only without contacts"
                    )));
                }
                self.switch_to_ed(i, t);
                // Its TD neighbours now have an ED neighbour: the guard must see them.
                for e in 0..self.list.of(i).len() {
                    let j = self.list.split(self.list.of(i)[e]).0;
                    if self.mode[j] == Mode::Time {
                        self.boundary.push(j as u32);
                    }
                }
                self.predict(i, t);
                let v = norm(self.system.particles.velocity[i]);
                self.v_max_ed = self.v_max_ed.max(v);
            }
        }
        Ok(())
    }
}
