//! MD's one Verlet driver: velocity Verlet with fused half kicks, the touch correction
//! and the neighbour list (see the crate docs), over the particles of a
//! [`Members`] set. MD ([`crate::Md`]) is the driver over all particles; the hybrid
//! engine's time-driven part is the driver over its time-driven particles.

mod joining;
mod members;
mod slots;
mod snapshot;
mod stress;
mod sync;

pub use stress::LazyKinetic;

pub use members::{All, Members};

use crate::forces::{Accelerations, ContactRecord, ForceKernel, ForceModel, WALL, apply_contacts};
use crate::frictional::Rotation;
use crate::neighbour::{INDEX_MASK, NeighbourList};
use crate::options::{MdError, MdOptions};
use crate::verlet::{kick_contacts, kick_drift, max_nan};
use emdstar_system::{
    Particles, SimBox, StressMark, StressSums, Sym3, System, add_kinetic, permute,
};
use rayon::prelude::*;
use slots::{Buffers, FrictionalKind, SlotKind, SmoothKind};

/// Particles per chunk of the force loop. Fixed, so that the order in which forces are
/// summed does not depend on the number of threads.
const CHUNK: usize = 1024;
/// Particles per cell the neighbour grid aims at (cells never get smaller than the
/// list cut-off).
const PER_CELL: f64 = 2.0;

/// What velocity Verlet keeps per particle and from step to step, apart from the
/// particles themselves: contact accelerations, the neighbour list, the bounds that
/// decide its rebuilds, spins and springs with friction. Its particles are a
/// [`System`]'s, in the order of its last rebuild (sorted by cell). Saved whole in
/// checkpoints but for its scratch (see [`Verlet::check_restored`]).
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Verlet {
    pub(crate) opts: MdOptions,
    pub(crate) skin: f64,
    #[serde(skip)]
    pub(crate) inv_mass: Vec<f64>,
    /// Contact (pair and wall) accelerations at the current time; gravity is added
    /// where they are used. Non-zero only for the particles listed in `touched`.
    pub(crate) contact_acc: Vec<[f64; 3]>,
    pub(crate) touched: Vec<u32>,
    pub(crate) list: NeighbourList,
    /// Scratch of the sweeps: one buffer per chunk of particles, and a flag per
    /// particle (all false between uses).
    #[serde(skip)]
    buffers: Buffers,
    #[serde(skip)]
    flags: Vec<bool>,
    pub(crate) drift_bound: f64,
    /// Largest speed of a member after the last sweep.
    pub(crate) v_max: f64,
    pub(crate) rebuilds: u64,
    /// The members' velocities lag half a kick (contacts and gravity) behind the
    /// positions: the first half kick of the next step is fused with the last one of
    /// the previous (see [`Verlet::synchronise`]).
    pub(crate) lagging: bool,
    /// Friction: torques and springs. `None` where every contact is frictionless: the
    /// steps then never touch the spins.
    pub(crate) rotation: Option<Box<Rotation>>,
    /// The sums behind the pressure tensor and the collision rate (see
    /// [`Verlet::stress_sums`]).
    pub(crate) stress: StressSums,
    /// The sums at the time of the last mark (see [`Verlet::mark_stress`]).
    pub(crate) stress_mark: Option<StressMark>,
    /// MD without gravity: the kinetic tensor kept by particle, added when a velocity
    /// changes (see [`LazyKinetic`]); `None`: summed at every step.
    pub(crate) lazy: Option<LazyKinetic>,
    /// The time the next force evaluation is at, where vibrated walls are (set by the
    /// engine before each; a function of the step count, so not saved).
    #[serde(skip)]
    pub(crate) wall_time: f64,
}

impl Verlet {
    /// The driver of `system`'s particles with `opts` and the list skin `skin` (see
    /// [`crate::prepare_system`]), with neither a list nor forces yet: [`Verlet::rebuild`],
    /// then [`Verlet::start_forces`].
    pub fn new(system: &System, opts: MdOptions, skin: f64) -> Self {
        let n = system.particles.len();
        Self {
            opts,
            skin,
            inv_mass: system.particles.mass.iter().map(|m| 1.0 / m).collect(),
            contact_acc: vec![[0.0; 3]; n],
            touched: Vec::new(),
            list: NeighbourList::default(),
            buffers: Buffers::for_particles(n),
            flags: Vec::new(),
            drift_bound: 0.0,
            v_max: 0.0,
            rebuilds: 0,
            lagging: false,
            rotation: system
                .interactions
                .is_frictional()
                .then(|| Box::new(Rotation::new(&system.particles))),
            stress: StressSums::default(),
            stress_mark: None,
            lazy: None,
            wall_time: 0.0,
        }
    }

    /// Sets the time of the next force evaluations (where vibrated walls are then).
    pub fn set_wall_time(&mut self, t: f64) {
        self.wall_time = t;
    }

    /// The options in use.
    pub fn options(&self) -> &MdOptions {
        &self.opts
    }

    /// The list skin in m.
    pub fn skin(&self) -> f64 {
        self.skin
    }

    /// The neighbour list of the last rebuild.
    pub fn list(&self) -> &NeighbourList {
        &self.list
    }

    /// Builds the list's upper part (every neighbour of every particle; see
    /// [`NeighbourList::build_upper`]) unless it is there.
    pub fn complete_list(&mut self) {
        if !self.list.has_upper() {
            self.list.build_upper();
        }
    }

    /// The contact acceleration of particle `i` now.
    pub fn contact_acc(&self, i: usize) -> [f64; 3] {
        self.contact_acc[i]
    }

    /// How far the members may have moved since the last rebuild (a bound), in m.
    pub fn drift_bound(&self) -> f64 {
        self.drift_bound
    }

    /// Largest speed of a member after the last step.
    pub fn v_max(&self) -> f64 {
        self.v_max
    }

    /// Whether the members' velocities lag half a kick behind their positions.
    pub fn is_lagging(&self) -> bool {
        self.lagging
    }

    /// Friction: torques and springs (`None` without friction).
    pub fn rotation(&self) -> Option<&Rotation> {
        self.rotation.as_deref()
    }

    /// The contact half kick of the next step: a whole step while the velocities lag
    /// (two half kicks fused), else half of one.
    pub fn next_kick(&self) -> f64 {
        if self.lagging {
            self.opts.dt
        } else {
            0.5 * self.opts.dt
        }
    }

    /// v += a_contact·`kick` for the particles in contact, and their spins likewise;
    /// returns their largest |v|² (NaN passes).
    pub fn kick(&mut self, p: &mut Particles, kick: f64) -> f64 {
        if let Some(lazy) = self.lazy.as_mut() {
            lazy.flush(&self.touched, p, self.opts.dt, &mut self.stress.kinetic);
        }
        let v2 = kick_contacts(&mut p.velocity, &self.contact_acc, &self.touched, kick);
        if let Some(rot) = &self.rotation {
            kick_contacts(
                &mut p.angular_velocity,
                &rot.angular_acc,
                &self.touched,
                kick,
            );
        }
        v2
    }

    /// A bound on every member's speed over the next step, after a kick by `kick` whose
    /// particles' largest |v|² is `touched_v2`: the largest speed of the last sweep, the
    /// kicked particles and gravity's kick `g`·`kick`.
    pub fn speed_bound(&self, touched_v2: f64, g: [f64; 3], kick: f64) -> f64 {
        let g_kick = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * kick;
        max_nan(self.v_max, touched_v2.sqrt()) + g_kick
    }

    /// Whether the list holds through the next step of `dt` at speeds up to `v_bound`
    /// after moving `drift` (written so that NaN, a blow-up, says no).
    pub fn list_holds(&self, drift: f64, v_bound: f64, dt: f64) -> bool {
        2.0 * (drift + v_bound * dt) <= self.skin
    }

    /// Errors unless a step of `dt` at speeds up to `v_bound` fits in the skin.
    pub fn step_fits(&self, v_bound: f64, dt: f64) -> Result<(), MdError> {
        if 2.0 * v_bound * dt <= self.skin {
            Ok(())
        } else {
            Err(MdError::SkinTooThin {
                skin: self.skin,
                step: v_bound * dt,
            })
        }
    }

    /// Checks the state at time `t` (but of the particles `skip` names), wraps periodic
    /// positions, sorts the particles by cell and rebuilds the list. Returns the order
    /// the particles (and the driver's records) were sorted by: new k is old `order[k]`;
    /// whoever keeps records of its own per particle renumbers them alike.
    pub fn rebuild(
        &mut self,
        system: &mut System,
        t: f64,
        skip: impl Fn(usize) -> bool,
    ) -> Result<Vec<u32>, MdError> {
        let min_cell = 2.0 * system.max_radius() + self.skin;
        let sim_box = system.domain.sim_box;
        let shear = system.domain.lees_edwards();
        if let Some(le) = &shear {
            // Through the sliding y face x and v_x shift with the image (before the
            // plain wrap, which then has nothing left to do).
            let p = &mut system.particles;
            for ((x, v), image) in p.position.iter_mut().zip(&mut p.velocity).zip(&mut p.image) {
                image[1] += le.wrap(x, v, t);
            }
        }
        check_and_wrap(&mut system.particles, sim_box.as_ref(), t, skip)?;
        let p = &mut system.particles;
        let order = self
            .list
            .sort_order(&p.position, sim_box.as_ref(), min_cell, PER_CELL)?;
        p.permute(&order);
        permute(&mut self.inv_mass, &order);
        permute(&mut self.contact_acc, &order);
        if let Some(lazy) = self.lazy.as_mut() {
            permute(&mut lazy.since, &order);
        }
        if let Some(rot) = self.rotation.as_mut() {
            rot.permute(&order);
        }
        self.touched.clear();
        for (i, a) in self.contact_acc.iter().enumerate() {
            let spun = self
                .rotation
                .as_ref()
                .is_some_and(|r| r.angular_acc[i] != [0.0; 3]);
            if *a != [0.0; 3] || spun {
                self.touched.push(i as u32);
            }
        }
        let shear = shear.as_ref().map(|le| (le, t));
        self.list
            .build_half_sheared(&p.position, &p.radius, self.skin, shear);
        self.drift_bound = 0.0;
        self.rebuilds += 1;
        Ok(order)
    }

    /// The forces on the members at their positions with their velocities as they are
    /// (h = 0), as at the start of a run; the velocities are then in step.
    pub fn start_forces<M: Members>(&mut self, system: &System, members: M) {
        if self.rotation.is_some() {
            self.find_contacts_parallel::<FrictionalKind, M>(system, members, 0.0);
            self.apply::<FrictionalKind>();
        } else {
            self.find_contacts_parallel::<SmoothKind, M>(system, members, 0.0);
            self.apply::<SmoothKind>();
        }
        let p = &system.particles;
        self.v_max = (0..p.len())
            .filter(|&i| members.contains(i))
            .map(|i| {
                let v = p.velocity[i];
                v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
            })
            .fold(0.0, max_nan)
            .sqrt();
        self.lagging = false;
    }

    /// The rest of a step of `dt` after its contact kick by `kick` ([`Verlet::kick`]):
    /// gravity's kick and the drift of the members, the forces at their new positions
    /// (predictor and touch correction) between members and with walls, applied; the
    /// velocities then lag half a kick.
    pub fn sweep<M: Members>(&mut self, system: &mut System, members: M, kick: f64, dt: f64) {
        let g = system.domain.gravity;
        let gk = [g[0] * kick, g[1] * kick, g[2] * kick];
        let h = 0.5 * self.opts.dt;
        let v2 = if self.rotation.is_some() {
            self.sweep_kind::<FrictionalKind, M>(system, members, gk, dt, h)
        } else {
            self.sweep_kind::<SmoothKind, M>(system, members, gk, dt, h)
        };
        if let Some(le) = system.domain.lees_edwards() {
            self.add_streaming_kinetic(&system.particles, &le, dt);
        }
        self.v_max = v2.sqrt();
        self.drift_bound += self.v_max * dt;
        self.lagging = true;
        if let Some(lazy) = self.lazy.as_mut() {
            lazy.drifts += 1;
        }
    }

    /// The drift and the contacts of one step, in one pass on one thread or in two
    /// parallel passes over fixed chunks (the same numbers in the same order), then the
    /// contacts applied. Returns max |v|².
    fn sweep_kind<K: SlotKind, M: Members>(
        &mut self,
        system: &mut System,
        members: M,
        gk: [f64; 3],
        dt: f64,
        h: f64,
    ) -> f64 {
        let tight = self.lazy.is_none();
        let v2 = if rayon::current_num_threads() == 1 || system.particles.len() <= CHUNK {
            self.sweep_fused::<K, M>(system, members, gk, dt, h)
        } else {
            let (v2, kinetic) = drift_all(&mut system.particles, members, gk, dt, tight);
            self.add_chunk_kinetics(&kinetic, dt);
            self.find_contacts_parallel::<K, M>(system, members, h);
            v2
        };
        self.apply::<K>();
        self.add_virial::<K>(system, dt);
        v2
    }

    /// One pass in particle order: kick and drift member i, then find its contacts (its
    /// listed partners j < i have already moved). Returns max |v|².
    fn sweep_fused<K: SlotKind, M: Members>(
        &mut self,
        system: &mut System,
        members: M,
        gk: [f64; 3],
        dt: f64,
        h: f64,
    ) -> f64 {
        let p = &mut system.particles;
        let mut position = std::mem::take(&mut p.position);
        let mut velocity = std::mem::take(&mut p.velocity);
        let mut buffers = std::mem::take(K::chunks(&mut self.buffers));
        let kernel = self.kernel::<K>(system, h);
        let start = &self.list.start;
        let walls = !system.domain.walls.is_empty();
        let mut v2_max: f64 = 0.0;
        let n = position.len();
        // Without gravity the velocities need not be written back (less memory traffic).
        let gravity = gk != [0.0; 3];
        let mass = &system.particles.mass;
        let tight = self.lazy.is_none();
        let mut kinetic = vec![[0.0; 6]; buffers.len()];
        for (c, buf) in buffers.iter_mut().enumerate() {
            buf.clear();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                if !members.contains(i) {
                    continue;
                }
                let (y, w) = kick_drift(position[i], velocity[i], gk, dt, gravity);
                if gravity {
                    velocity[i] = w;
                }
                position[i] = y;
                let w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                // NaN is ignored here; a blown-up particle is caught at the next rebuild.
                if w2 > v2_max {
                    v2_max = w2;
                }
                if walls || start[i] != start[i + 1] {
                    let entries = kernel.list.of(i).iter().copied();
                    if M::ALL {
                        kernel.particle(i, y, w, entries, &position, &velocity, buf);
                    } else {
                        let entries = entries.filter(|&e| members.contains(partner(e)));
                        kernel.particle(i, y, w, entries, &position, &velocity, buf);
                    }
                }
            }
            // The drift velocities (stored now), while the chunk is in the cache: a tight
            // loop (the force kernel's calls would spill the sums).
            if !tight {
                continue;
            }
            let range = c * CHUNK..((c + 1) * CHUNK).min(n);
            let mut k = [0.0; 6];
            for (i, (v, &m)) in velocity[range.clone()].iter().zip(&mass[range]).enumerate() {
                if members.contains(c * CHUNK + i) {
                    add_kinetic(&mut k, m, *v);
                }
            }
            kinetic[c] = k;
        }
        drop(kernel);
        self.add_chunk_kinetics(&kinetic, dt);
        let p = &mut system.particles;
        p.position = position;
        p.velocity = velocity;
        *K::chunks(&mut self.buffers) = buffers;
        v2_max
    }

    /// The contacts of the members at the current positions, in parallel over fixed
    /// chunks (the second pass of a parallel sweep).
    fn find_contacts_parallel<K: SlotKind, M: Members>(
        &mut self,
        system: &System,
        members: M,
        h: f64,
    ) {
        let mut buffers = std::mem::take(K::chunks(&mut self.buffers));
        let kernel = self.kernel::<K>(system, h);
        let (position, velocity) = (&system.particles.position, &system.particles.velocity);
        let n = position.len();
        let (start, walls) = (&self.list.start, !system.domain.walls.is_empty());
        buffers.par_iter_mut().enumerate().for_each(|(c, buf)| {
            buf.clear();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                if members.contains(i) && (walls || start[i] != start[i + 1]) {
                    let (x, v, entries) = (position[i], velocity[i], kernel.list.of(i).iter());
                    if M::ALL {
                        kernel.particle(i, x, v, entries.copied(), position, velocity, buf);
                    } else {
                        let entries = entries.copied().filter(|&e| members.contains(partner(e)));
                        kernel.particle(i, x, v, entries, position, velocity, buf);
                    }
                }
            }
        });
        drop(kernel);
        *K::chunks(&mut self.buffers) = buffers;
    }

    /// The force kernel over `system`'s particles with the driver's contact
    /// accelerations and the slot of kind `K`, predicting over `h` (0: the velocities
    /// as they are).
    pub(crate) fn kernel<'a, K: SlotKind>(
        &'a self,
        system: &'a System,
        h: f64,
    ) -> ForceKernel<'a, K::Slot<'a>> {
        ForceKernel {
            model: model(system, &self.opts).at(self.wall_time),
            list: &self.list,
            contact_acc: &self.contact_acc,
            h,
            slot: K::slot(self.rotation.as_deref(), &system.particles),
        }
    }

    /// Replaces the contact accelerations (and angular accelerations and springs, with
    /// friction) by those of the contacts just found, chunk by chunk and contact by
    /// contact (a fixed order).
    fn apply<K: SlotKind>(&mut self) {
        let mut rotation = self.rotation.as_deref_mut();
        for &i in &self.touched {
            self.contact_acc[i as usize] = [0.0; 3];
            if let Some(rot) = rotation.as_deref_mut() {
                rot.angular_acc[i as usize] = [0.0; 3];
            }
        }
        self.touched.clear();
        let buffers = K::chunks(&mut self.buffers);
        let mut to = Accelerations {
            inv_mass: &self.inv_mass,
            acc: &mut self.contact_acc,
            angular: rotation
                .as_deref_mut()
                .map(|r| (&r.inv_inertia[..], &mut r.angular_acc[..])),
        };
        apply_contacts(buffers.iter().flatten(), &mut to, None);
        // The particles in contact in increasing order, each once. Where contacts are
        // many, flagged and then collected (sorting the parties of every contact cost a
        // fifth of a dense step); where they are few, sorted (the scan over every
        // particle cost 7 % of a dilute step).
        let parties = buffers.iter().flatten().map(|c| c.parties());
        let n = self.contact_acc.len();
        if 32 * buffers.iter().map(Vec::len).sum::<usize>() < n {
            for (i, j) in parties {
                self.touched.push(i);
                if j != WALL {
                    self.touched.push(j);
                }
            }
            self.touched.sort_unstable();
            self.touched.dedup();
        } else {
            let flags = &mut self.flags;
            flags.resize(n, false);
            for (i, j) in parties {
                flags[i as usize] = true;
                if j != WALL {
                    flags[j as usize] = true;
                }
            }
            for (i, flag) in flags.iter_mut().enumerate() {
                if std::mem::take(flag) {
                    self.touched.push(i as u32);
                }
            }
        }
        if let Some(rot) = rotation {
            let records = buffers.iter().flatten().filter_map(ContactRecord::spring);
            rot.springs.replace(records);
        }
    }

    /// Particles `ids` stop being members now: they carry no contact forces or torques
    /// any more, and their springs go. (Their velocities must be in step:
    /// [`Verlet::synchronise`] first.)
    pub fn release(&mut self, ids: &[u32]) {
        if ids.is_empty() {
            return;
        }
        let mut gone = vec![false; self.contact_acc.len()];
        for &i in ids {
            gone[i as usize] = true;
            self.contact_acc[i as usize] = [0.0; 3];
        }
        self.touched.retain(|&i| !gone[i as usize]);
        if let Some(rot) = self.rotation.as_mut() {
            for &i in ids {
                rot.angular_acc[i as usize] = [0.0; 3];
            }
        }
    }
}

/// What the forces depend on besides the motion.
pub(crate) fn model<'a>(system: &'a System, opts: &MdOptions) -> ForceModel<'a> {
    let p = &system.particles;
    ForceModel::new(
        &p.radius,
        &p.species,
        &system.interactions,
        &system.domain,
        opts.contact_end,
    )
}

/// The partner a list entry names.
#[inline(always)]
fn partner(entry: u32) -> usize {
    (entry & INDEX_MASK) as usize
}

/// The gravity kick and the drift of every member, in parallel over fixed chunks.
/// Returns max |v|² and each chunk's Σ m v ⊗ v of the drift's velocities.
fn drift_all<M: Members>(
    p: &mut Particles,
    members: M,
    gk: [f64; 3],
    dt: f64,
    tight: bool,
) -> (f64, Vec<Sym3>) {
    let gravity = gk != [0.0; 3];
    let mass = &p.mass;
    let chunks: Vec<(f64, Sym3)> = p
        .position
        .par_chunks_mut(CHUNK)
        .zip(p.velocity.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(c, (x, v))| {
            let mut v2_max: f64 = 0.0;
            let mut kinetic = [0.0; 6];
            for (k, (x, v)) in x.iter_mut().zip(v.iter_mut()).enumerate() {
                let i = c * CHUNK + k;
                if !members.contains(i) {
                    continue;
                }
                // Copies: re-reading just-stored components stalls the CPU.
                let w;
                (*x, w) = kick_drift(*x, *v, gk, dt, gravity);
                if gravity {
                    *v = w;
                }
                if tight {
                    add_kinetic(&mut kinetic, mass[i], w);
                }
                let w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                if w2 > v2_max {
                    v2_max = w2;
                }
            }
            (v2_max, kinetic)
        })
        .collect();
    let v2 = chunks.iter().map(|c| c.0).fold(0.0, f64::max);
    (v2, chunks.into_iter().map(|c| c.1).collect())
}

/// Checks that every particle (but those `skip` names) has a finite state and stays
/// inside the closed axes of `sim_box`, and wraps positions along the periodic ones.
pub fn check_and_wrap(
    p: &mut Particles,
    sim_box: Option<&SimBox>,
    t: f64,
    skip: impl Fn(usize) -> bool,
) -> Result<(), MdError> {
    for i in 0..p.len() {
        if skip(i) {
            continue;
        }
        let (x, v) = (p.position[i], p.velocity[i]);
        if !x.iter().chain(&v).all(|c| c.is_finite()) {
            return Err(MdError::BlewUp { id: p.id[i], t });
        }
        if let Some(b) = sim_box {
            if let Some(k) = b.outside_closed_axis(x) {
                return Err(MdError::LeftBox {
                    id: p.id[i],
                    axis: ["x", "y", "z"][k],
                    t,
                    position: x,
                });
            }
            p.position[i] = b.wrap_counting(x, &mut p.image[i]);
        }
    }
    Ok(())
}
