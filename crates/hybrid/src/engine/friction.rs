//! Friction in the hybrid (crate docs, "Friction and rotation"): the TD part runs MD's
//! tangential laws with spins and springs (`emdstar_dem::step_subset` with a
//! [`Rotation`]), the ED part Walton's rule with β₀ derived from those laws
//! ([`emdstar_contact::sticking_restitution`]).

use super::Hybrid;
use crate::options::HybridError;
use emdstar_contact::{LinearDashpot, PairLaw, Tangential, Walton, sticking_restitution};
use emdstar_dem::Rotation;
use emdstar_system::{Interaction, Interactions};

/// The contacts of the ED collisions: each frictional contact of `interactions` with
/// Walton's rule whose β₀ is that of its tangential law for the pair's reduced mass and
/// contact time (the hybrid runs friction with the linear law only: the method's check
/// refuses the rest first).
pub(crate) fn event_contacts(interactions: &Interactions) -> Result<Interactions, HybridError> {
    interactions.with_tangential(|i: &Interaction| {
        let tangential = *i.tangential();
        if !tangential.is_frictional() {
            return Ok(tangential);
        }
        let PairLaw::Linear { stiffness, damping } = *i.law() else {
            return Ok(Tangential::None);
        };
        let law = LinearDashpot::new(stiffness, damping)?;
        let m_eff = i.props.m_eff;
        let t_c = law.central_impact(m_eff)?.duration;
        let beta = sticking_restitution(&tangential, m_eff, t_c);
        Ok(Tangential::Walton(Walton::new(
            tangential.friction(),
            beta,
        )?))
    })
}

impl Hybrid {
    /// A particle that leaves the TD set keeps its spin but no longer feels torques.
    pub(crate) fn clear_torque(&mut self, i: usize) {
        if let Some(rot) = self.rotation.as_mut() {
            rot.angular_acc[i] = [0.0; 3];
        }
    }

    /// The elastic energy of the TD springs (zero without friction).
    pub(crate) fn spring_energy(&self) -> f64 {
        let p = &self.system.particles;
        self.rotation.as_deref().map_or(0.0, |r: &Rotation| {
            r.spring_energy(&self.system.interactions, p)
        })
    }
}
