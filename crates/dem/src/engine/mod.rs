//! The MD engine: its system and MD's Verlet driver over all of its particles, the
//! run's clock, thermo.

mod snapshot;

use crate::driver::{All, Verlet};
use crate::options::{MdError, MdOptions, prepare_system};
use emdstar_system::{Method, Particles, System, Thermo, VelocityChange};

/// A force-based simulation of one [`System`].
pub struct Md {
    system: System,
    verlet: Verlet,
    steps: u64,
    t_start: f64,
}

impl Md {
    /// Prepares `system` for integration with `opts` up to `t_end` (which only enters
    /// the check of the time step against the shortest expected contact time).
    pub fn new(mut system: System, opts: MdOptions, t_end: f64) -> Result<Self, MdError> {
        let walls = system.domain.walls.len();
        system.interactions.check_runs_on(Method::Md, walls)?;
        let skin = prepare_system(&mut system, opts.dt, opts.skin, t_end)?;
        let mut verlet = Verlet::new(&system, opts, skin);
        if system.domain.gravity == [0.0; 3] && system.domain.shear_rate == 0.0 {
            verlet.keep_kinetic_by_particle(system.particles.len());
        }
        verlet.rebuild(&mut system, 0.0, |_| false)?;
        // Forces at t = 0 with the velocities themselves (h = 0).
        verlet.start_forces(&system, All);
        Ok(Self {
            system,
            verlet,
            steps: 0,
            t_start: 0.0,
        })
    }

    /// Time in s.
    pub fn time(&self) -> f64 {
        self.t_start + self.steps as f64 * self.verlet.opts.dt
    }

    /// Steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Neighbour-list rebuilds done (the first included).
    pub fn rebuilds(&self) -> u64 {
        self.verlet.rebuilds
    }

    /// The options in use.
    pub fn options(&self) -> &MdOptions {
        &self.verlet.opts
    }

    /// The Verlet-list skin in use, in m.
    pub fn skin(&self) -> f64 {
        self.verlet.skin
    }

    /// Keeps the stress sums now as the mark (see [`Verlet::mark_stress`]).
    pub fn mark_stress(&mut self) {
        let t = self.time();
        self.verlet.mark_stress(t, &self.system.particles);
    }

    /// The Verlet driver (its options, list and the sums of [`Verlet::stress_sums`]).
    pub fn verlet(&self) -> &Verlet {
        &self.verlet
    }

    /// The system; particles are in the engine's (cell-sorted) order, see
    /// [`Particles::id`]. Their velocities lag half a kick behind after
    /// [`Md::stride`]; [`Md::particles_in_config_order`] and [`Md::thermo`] show them
    /// in step.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The particles in config order, velocities in step with the positions.
    pub fn particles_in_config_order(&self) -> Particles {
        let mut p = self.particles_now();
        let mut order = vec![0u32; p.len()];
        for (k, &id) in p.id.iter().enumerate() {
            order[id as usize] = k as u32;
        }
        p.permute(&order);
        p
    }

    /// The particles in the engine's order, velocities and spins in step with the
    /// positions.
    fn particles_now(&self) -> Particles {
        let p = &self.system.particles;
        let mut now = Particles {
            velocity: self
                .verlet
                .velocities_now(p, All, self.system.domain.gravity),
            angular_velocity: self.verlet.spins_now(p),
            ..p.clone()
        };
        if let Some(le) = self.system.domain.lees_edwards() {
            // Between rebuilds a particle may lie beyond the sliding face: its image in
            // the box (see `LeesEdwards::wrap`).
            let t = self.time();
            for ((x, v), image) in now
                .position
                .iter_mut()
                .zip(&mut now.velocity)
                .zip(&mut now.image)
            {
                image[1] += le.wrap(x, v, t);
            }
        }
        now
    }

    /// Advances `n` steps of velocity Verlet (see the crate docs), velocities in step
    /// with the positions afterwards.
    pub fn advance(&mut self, n: u64) -> Result<(), MdError> {
        self.stride(n)?;
        self.synchronise()
    }

    /// Advances `n` steps of velocity Verlet (fewer when a stop is requested,
    /// [`emdstar_system::stop`]) leaving the last half kick pending: the
    /// trajectory does not depend on how a run is cut into strides (a run stopped,
    /// read or saved between strides goes on bitwise as one that ran through).
    pub fn stride(&mut self, n: u64) -> Result<(), MdError> {
        for _ in 0..n {
            if emdstar_system::stop::is_requested() {
                // Between steps: the state is whole, and a later stride goes on as
                // this one would have (the pending half kick is fused either way).
                break;
            }
            self.step()?;
        }
        Ok(())
    }

    /// Changes the velocities now (see [`emdstar_system::Simulation::change_velocities`]):
    /// the pending half kick first, then `change` in config order; the list's speed bound
    /// follows the new velocities.
    pub fn change_velocities(&mut self, change: &mut VelocityChange<'_>) -> Result<(), MdError> {
        self.synchronise()?;
        self.verlet.flush_kinetic(&self.system.particles);
        let p = &mut self.system.particles;
        let n = p.len();
        let (mut v, mut m) = (vec![[0.0; 3]; n], vec![0.0; n]);
        for k in 0..n {
            let id = p.id[k] as usize;
            (v[id], m[id]) = (p.velocity[k], p.mass[k]);
        }
        change(&mut v, &m);
        for k in 0..n {
            p.velocity[k] = v[p.id[k] as usize];
        }
        self.verlet.speeds_changed(p, All);
        Ok(())
    }

    /// Applies the pending half kick, if any (velocities then in step with the
    /// positions), and reports a blow-up.
    pub fn synchronise(&mut self) -> Result<(), MdError> {
        let (g, t) = (self.system.domain.gravity, self.time());
        self.verlet
            .synchronise(&mut self.system.particles, All, g, t)
    }

    /// One step: v += a·kick, x += v·dt, forces at the new positions (the first half
    /// kick fused with the last one of the previous step, if the velocities lag).
    ///
    /// The neighbour list is rebuilt *before* the drift when the particles might
    /// otherwise have moved by more than half the skin by its end; the speed bound
    /// uses the largest speed of the last sweep, the kicked particles in contact and
    /// gravity, so it holds for every particle.
    fn step(&mut self) -> Result<(), MdError> {
        let (kick, dt) = (self.verlet.next_kick(), self.verlet.opts.dt);
        let touched_v2 = self.verlet.kick(&mut self.system.particles, kick);
        let g = self.system.domain.gravity;
        let mut v_bound = self.verlet.speed_bound(touched_v2, g, kick);
        let shear = self.system.domain.lees_edwards();
        if let Some(le) = &shear {
            // The images across the sliding face move at γ̇ L_y relative to the box: a
            // pair across it closes in by up to that besides its two drifts.
            v_bound += 0.5 * le.image_speed().abs();
        }
        if !self.verlet.list_holds(self.verlet.drift_bound, v_bound, dt) {
            let t = self.time();
            self.verlet.rebuild(&mut self.system, t, |_| false)?;
            self.verlet.step_fits(v_bound, dt)?;
        }
        self.steps += 1;
        self.verlet.set_wall_time(self.time());
        if let Some(le) = &shear {
            self.verlet.list.slide(le, self.time());
        }
        self.verlet.sweep(&mut self.system, All, kick, dt);
        if let Some(le) = &shear {
            self.verlet.drift_bound += 0.5 * le.image_speed().abs() * dt;
        }
        Ok(())
    }

    /// Energies, temperature, momentum and contacts now. The potential energy is the
    /// elastic energy of the contacts, ∫F_el dξ: ½kξ² (linear) or (2/5)ρ_el ξ^{5/2}
    /// (Hertz, Müller & Pöschel 2013, Eq. 51), plus −Σ m g·x.
    pub fn thermo(&self) -> Thermo {
        let p = &self.particles_now();
        let model = crate::driver::model(&self.system, &self.verlet.opts).at(self.time());
        let interactions = &self.system.interactions;
        let mut potential = self
            .verlet
            .rotation
            .as_ref()
            .map_or(0.0, |r| r.spring_energy(interactions, p));
        let mut contacts = 0;
        let list = &self.verlet.list;
        // The list's images are those of the stored positions (not wrapped since the
        // last rebuild, which a sheared box's readout does).
        let stored = &self.system.particles.position;
        for i in 0..p.len() {
            let xi = p.position[i];
            let sums = (&mut contacts, &mut potential);
            let entries = list.of(i).iter().copied();
            model.add_elastic(i, stored[i], entries, list, stored, sums);
            let g = self.system.domain.gravity;
            potential -= p.mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: p.kinetic_energy(),
            rotational_energy: p.rotational_energy(),
            potential_energy: potential,
            granular_temperature: match self.system.domain.lees_edwards() {
                Some(le) => {
                    let mut c = p.clone();
                    le.peculiar(&mut c);
                    c.granular_temperature()
                }
                None => p.granular_temperature(),
            },
            rotational_temperature: p.rotational_temperature(),
            momentum: p.momentum(),
            contacts,
        }
    }
}
