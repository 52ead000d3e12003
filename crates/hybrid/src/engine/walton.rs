//! The event-driven collisions of [`crate::EventRule::Emd`] with friction: Walton's
//! rule with β₀ derived from the time-driven law (crate docs, "Friction and
//! rotation"; [`emdstar_contact::sticking_restitution`]).

use crate::options::HybridError;
use emdstar_contact::{LinearDashpot, PairLaw, Tangential, Walton, sticking_restitution};
use emdstar_system::{Interaction, Interactions};

/// The contacts of eMD's collisions: each frictional contact of `interactions` with
/// Walton's rule whose β₀ is that of its tangential law for the pair's reduced mass and
/// contact time (linear law only: the method's check refuses the rest first).
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
