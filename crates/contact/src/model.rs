//! The contact model of one kind of contact: a normal law and a tangential sub-model,
//! as LAMMPS's `GranularModel` (one per pair of types, shared by pairs and walls, with
//! frictionless contacts as the `none` tangential sub-model).

use crate::law::PairLaw;
use crate::tangential::Tangential;

/// What happens when two bodies of given materials touch: the normal force law of the
/// pair (geometry folded in) and the tangential sub-model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    pub normal: PairLaw,
    pub tangential: Tangential,
}

impl ContactModel {
    /// A frictionless contact of law `normal`.
    pub fn smooth(normal: PairLaw) -> Self {
        Self {
            normal,
            tangential: Tangential::None,
        }
    }

    /// True if the contact exchanges tangential forces.
    pub fn is_frictional(&self) -> bool {
        self.tangential.is_frictional()
    }
}
