//! MD's two tangential slots as kinds the driver's sweeps are generic over
//! ([`SlotKind`]: the frictionless [`Smooth`] and the [`Frictional`] slot over the
//! spins and springs of a [`Rotation`]).

use crate::forces::{ContactRecord, PairForce, Smooth, TangentialSlot};
use crate::frictional::{ContactForce, Frictional, Rotation};
use emdstar_system::Particles;

/// The contacts a sweep found, per chunk of particles, for either slot.
#[derive(Default)]
pub(crate) struct Buffers {
    pub(crate) smooth: Vec<Vec<PairForce>>,
    pub(crate) frictional: Vec<Vec<ContactForce>>,
}

impl Buffers {
    /// One buffer per chunk of `n` particles.
    pub(crate) fn for_particles(n: usize) -> Self {
        let chunks = n.div_ceil(super::CHUNK);
        Self {
            smooth: vec![Vec::new(); chunks],
            frictional: vec![Vec::new(); chunks],
        }
    }
}

/// A tangential slot as the driver builds it from its own state.
pub(crate) trait SlotKind {
    type Contact: ContactRecord;
    type Slot<'a>: TangentialSlot<Contact = Self::Contact>;
    /// The slot over the spins of `p` and the springs of `rotation`.
    fn slot<'a>(rotation: Option<&'a Rotation>, p: &'a Particles) -> Self::Slot<'a>;
    /// The chunk buffers of this slot's contacts.
    fn chunks(b: &mut Buffers) -> &mut Vec<Vec<Self::Contact>>;
}

/// Frictionless MD: spins are never touched.
pub(crate) struct SmoothKind;

impl SlotKind for SmoothKind {
    type Contact = PairForce;
    type Slot<'a> = Smooth;

    fn slot<'a>(_: Option<&'a Rotation>, _: &'a Particles) -> Smooth {
        Smooth
    }

    fn chunks(b: &mut Buffers) -> &mut Vec<Vec<PairForce>> {
        &mut b.smooth
    }
}

/// Frictional MD: the spins of the particles, the angular accelerations and springs of
/// the driver's [`Rotation`].
pub(crate) struct FrictionalKind;

impl SlotKind for FrictionalKind {
    type Contact = ContactForce;
    type Slot<'a> = Frictional<'a>;

    fn slot<'a>(rotation: Option<&'a Rotation>, p: &'a Particles) -> Frictional<'a> {
        let rot = rotation.expect("a frictional run has spins");
        Frictional {
            id: &p.id,
            angular_velocity: &p.angular_velocity,
            angular_acc: &rot.angular_acc,
            springs: &rot.springs,
        }
    }

    fn chunks(b: &mut Buffers) -> &mut Vec<Vec<ContactForce>> {
        &mut b.frictional
    }
}
