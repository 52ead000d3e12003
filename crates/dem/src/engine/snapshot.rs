//! Saving MD's whole state and putting it back (checkpoints).

use super::Md;
use crate::frictional::Springs;
use crate::neighbour::NeighbourList;
use crate::options::ContactEnd;
use emdstar_system::Particles;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// What MD keeps from step to step, besides what its system and options give.
#[derive(Serialize, Deserialize)]
struct MdState<'a> {
    pub particles: Cow<'a, Particles>,
    pub dt: f64,
    pub contact_end: ContactEnd,
    pub skin: f64,
    pub steps: u64,
    pub t_start: f64,
    pub contact_acc: Cow<'a, [[f64; 3]]>,
    pub touched: Cow<'a, [u32]>,
    pub list: Cow<'a, NeighbourList>,
    pub drift_bound: f64,
    pub v_max: f64,
    pub rebuilds: u64,
    pub lagging: bool,
    /// Friction: the angular accelerations and the springs (empty without).
    pub angular_acc: Cow<'a, [[f64; 3]]>,
    pub springs: Cow<'a, Springs>,
}

impl Md {
    /// The state a checkpoint saves (see snapshot.rs).
    fn state(&self) -> MdState<'_> {
        MdState {
            particles: Cow::Borrowed(&self.system.particles),
            dt: self.opts.dt,
            contact_end: self.opts.contact_end,
            skin: self.skin,
            steps: self.steps,
            t_start: self.t_start,
            contact_acc: Cow::Borrowed(&self.contact_acc),
            touched: Cow::Borrowed(&self.touched),
            list: Cow::Borrowed(&self.list),
            drift_bound: self.drift_bound,
            v_max: self.v_max,
            rebuilds: self.rebuilds,
            lagging: self.lagging,
            angular_acc: match &self.rotation {
                Some(r) => Cow::Borrowed(&r.angular_acc),
                None => Cow::Owned(Vec::new()),
            },
            springs: match &self.rotation {
                Some(r) => Cow::Borrowed(&r.springs),
                None => Cow::Owned(Springs::default()),
            },
        }
    }

    /// Takes over a saved state (checked by the caller).
    fn set_state(&mut self, s: MdState<'_>) {
        self.system.particles = s.particles.into_owned();
        self.inv_mass = self.system.particles.mass.iter().map(|m| 1.0 / m).collect();
        self.skin = s.skin;
        self.steps = s.steps;
        self.t_start = s.t_start;
        self.contact_acc = s.contact_acc.into_owned();
        self.touched = s.touched.into_owned();
        self.list = s.list.into_owned();
        self.drift_bound = s.drift_bound;
        self.v_max = s.v_max;
        self.rebuilds = s.rebuilds;
        self.lagging = s.lagging;
        if let Some(rot) = self.rotation.as_mut() {
            rot.reset_inertia(&self.system.particles);
            rot.angular_acc = s.angular_acc.into_owned();
            rot.springs = s.springs.into_owned();
        }
    }

    /// The whole state in the checkpoint encoding.
    pub fn save_state(&self) -> Vec<u8> {
        postcard::to_allocvec(&self.state()).expect("an MD state serialises")
    }

    /// Replaces the state by one [`Md::save_state`] gave; this engine must have been
    /// built from the same config and options.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let state: MdState = postcard::from_bytes(bytes).map_err(|e| {
            format!(
                "the checkpoint's MD state cannot be read ({e}); it was written by another \
                 version or another engine"
            )
        })?;
        if state.particles.len() != self.system().particles.len() {
            return Err(format!(
                "the checkpoint holds {} particles, the config {}: resume with the config \
                 the checkpoint was written from",
                state.particles.len(),
                self.system().particles.len()
            ));
        }
        if state.dt != self.options().dt || state.contact_end != self.options().contact_end {
            return Err(format!(
                "the checkpoint was written with dt = {:e} s and contact end {:?}, this run has \
                 dt = {:e} s and {:?}; resume with the --dt and --contact-end of the run that \
                 wrote it",
                state.dt,
                state.contact_end,
                self.options().dt,
                self.options().contact_end
            ));
        }
        let n = self.system().particles.len();
        let whole = state.particles.same_bodies(&self.system().particles)
            && state.contact_acc.len() == n
            && state.touched.iter().all(|&i| (i as usize) < n)
            && state.springs.are_whole(n);
        state
            .list
            .check_restored(n)
            .and_then(|()| {
                whole
                    .then_some(())
                    .ok_or_else(|| "its particles differ".into())
            })
            .map_err(|why| {
                format!(
                    "the checkpoint's MD state does not fit this config ({why}); resume with \
                     the config and the version of emdstar that wrote it"
                )
            })?;
        let spins = if self.rotation.is_some() {
            self.system().particles.len()
        } else {
            0
        };
        if state.angular_acc.len() != spins {
            return Err(
                "the checkpoint was written with another friction than this config's: resume \
                 with the config the checkpoint was written from"
                    .into(),
            );
        }
        self.set_state(state);
        Ok(())
    }
}
