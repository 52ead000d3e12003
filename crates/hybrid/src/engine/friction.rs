//! Friction in the hybrid (crate docs, "Friction and rotation"): the TD part runs MD's
//! tangential law with spins and springs ([`emdstar_dem::step_subset_frictional`]),
//! the ED part Walton's rule with β₀ derived from that law
//! ([`emdstar_contact::sticking_restitution`]).

use super::Hybrid;
use crate::options::HybridError;
use emdstar_contact::{Friction, PairLaw, Walton, sticking_restitution};
use emdstar_dem::{ContactForce, Springs};
use emdstar_edmd::Materials;
use emdstar_system::{Interaction, Particles, System};

/// What friction adds to the TD part's state.
#[derive(serde::Serialize, serde::Deserialize)]
pub(crate) struct TdRotation {
    pub friction: Friction,
    pub inv_inertia: Vec<f64>,
    /// Angular accelerations of the TD contacts now (zero for the other particles).
    pub angular_acc: Vec<[f64; 3]>,
    /// The springs of the open TD contacts (a pair's ends when the contact ends or a
    /// particle leaves the TD set).
    pub springs: Springs,
    /// Scratch: the contacts of a step.
    #[serde(skip)]
    pub contacts: Vec<ContactForce>,
}

impl TdRotation {
    fn new(friction: Friction, p: &Particles) -> Self {
        Self {
            friction,
            inv_inertia: (0..p.len()).map(|i| 1.0 / p.inertia(i)).collect(),
            angular_acc: vec![[0.0; 3]; p.len()],
            springs: Springs::default(),
            contacts: Vec::new(),
        }
    }

    /// The elastic energy of the springs, Σ ½ k_t |ξ_t|² (as MD's thermo).
    pub fn spring_energy(&self) -> f64 {
        self.springs.energy(&self.friction)
    }
}

/// Walton's rule of the ED collisions, per pair of species and per species against a
/// wall (β₀ depends on the reduced mass and the contact time).
#[derive(Debug, Clone, Default)]
pub(crate) struct EdFriction {
    species: usize,
    pairs: Vec<Walton>,
    walls: Vec<Walton>,
}

impl EdFriction {
    pub fn pair(&self, a: u32, b: u32) -> Walton {
        self.pairs[a as usize * self.species + b as usize]
    }

    pub fn wall(&self, a: u32) -> Walton {
        self.walls[a as usize]
    }
}

/// The friction of `system` for both parts, or `None` for a frictionless material;
/// refuses what the hybrid cannot run, saying what to do.
pub(crate) fn set_up(
    system: &System,
    materials: &Materials,
) -> Result<Option<(TdRotation, EdFriction)>, HybridError> {
    let friction = system.friction;
    if !friction.is_active() {
        return Ok(None);
    }
    if friction.tangential_restitution.is_some() {
        return Err(HybridError::Invalid(format!(
            "material.tangential_restitution is Walton's rule alone, but the hybrid's \
             time-driven part needs MD's tangential law: give tangential_stiffness (and \
             tangential_damping) or tangential = \"coulomb\" instead; the event-driven part \
             derives β₀ from that law (friction = {})",
            friction.friction
        )));
    }
    let interactions = materials.interactions();
    let rule = |entry: &Interaction| -> Result<Walton, HybridError> {
        let PairLaw::Linear { stiffness, damping } = entry.law else {
            return Err(HybridError::Invalid(
                "friction with model = \"hertz\" cannot be run by the hybrid: the \
                 tangential restitution β₀ of its event-driven collisions is derived from \
                 the contact time, which for Hertz contacts depends on the impact speed; \
                 use model = \"linear\", or run it with --engine md"
                    .into(),
            ));
        };
        let law = emdstar_contact::LinearDashpot::new(stiffness, damping)?;
        let m_eff = entry.props.m_eff;
        let t_c = law.central_impact(m_eff)?.duration;
        let beta = sticking_restitution(&friction, m_eff, t_c);
        Ok(Walton::new(friction.friction, beta)?)
    };
    let species = interactions.species();
    let mut ed = EdFriction {
        species,
        ..EdFriction::default()
    };
    for a in 0..species as u32 {
        for b in 0..species as u32 {
            ed.pairs.push(rule(interactions.pair(a, b))?);
        }
        ed.walls.push(rule(interactions.wall(a))?);
    }
    Ok(Some((TdRotation::new(friction, &system.particles), ed)))
}

impl Hybrid {
    /// Sets Walton's rule of the ED collision about to run: of `i` with particle
    /// `partner`, or with wall `partner − n`.
    pub(crate) fn choose_walton(&mut self, i: usize, partner: usize) {
        let Some(ed) = &self.ed_friction else {
            return;
        };
        let species = &self.system.particles.species;
        let n = self.mode.len();
        self.walton_now = Some(if partner >= n {
            ed.wall(species[i])
        } else {
            ed.pair(species[i], species[partner])
        });
    }

    /// A particle that leaves the TD set keeps its spin but no longer feels torques.
    pub(crate) fn clear_torque(&mut self, i: usize) {
        if let Some(rot) = self.rotation.as_mut() {
            rot.angular_acc[i] = [0.0; 3];
        }
    }

    /// The elastic energy of the TD springs (zero without friction).
    pub(crate) fn spring_energy(&self) -> f64 {
        self.rotation.as_ref().map_or(0.0, |r| r.spring_energy())
    }
}
