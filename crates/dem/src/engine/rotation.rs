//! MD's two tangential slots as kinds the engine's sweeps are generic over
//! ([`SlotKind`]: the frictionless [`Smooth`] and the [`Frictional`] slot over MD's spins
//! and springs), and the spins' kicks.

use super::Md;
use crate::forces::{ContactRecord, PairForce, Smooth, TangentialSlot};
use crate::frictional::{ContactForce, Frictional};
use crate::verlet::kick_contacts;

/// The contacts a sweep found, per chunk of particles, for either slot.
#[derive(Default)]
pub(crate) struct Buffers {
    pub(crate) smooth: Vec<Vec<PairForce>>,
    pub(crate) frictional: Vec<Vec<ContactForce>>,
}

/// A tangential slot as MD builds it from its own state.
pub(crate) trait SlotKind {
    type Contact: ContactRecord;
    type Slot<'a>: TangentialSlot<Contact = Self::Contact>;
    /// The slot over `md`'s state.
    fn slot(md: &Md) -> Self::Slot<'_>;
    /// The chunk buffers of this slot's contacts.
    fn chunks(b: &mut Buffers) -> &mut Vec<Vec<Self::Contact>>;
}

/// Frictionless MD: spins are never touched.
pub(crate) struct SmoothKind;

impl SlotKind for SmoothKind {
    type Contact = PairForce;
    type Slot<'a> = Smooth;

    fn slot(_: &Md) -> Smooth {
        Smooth
    }

    fn chunks(b: &mut Buffers) -> &mut Vec<Vec<PairForce>> {
        &mut b.smooth
    }
}

/// Frictional MD: the spins, angular accelerations and springs of [`Md::rotation`].
pub(crate) struct FrictionalKind;

impl SlotKind for FrictionalKind {
    type Contact = ContactForce;
    type Slot<'a> = Frictional<'a>;

    fn slot(md: &Md) -> Frictional<'_> {
        let rot = md.rotation.as_deref().expect("a frictional run has spins");
        let p = &md.system.particles;
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

impl Md {
    /// ω += α_contact·`by` for the particles in contact (nothing without friction).
    pub(super) fn kick_spins(&mut self, by: f64) {
        if let Some(rot) = &self.rotation {
            kick_contacts(
                &mut self.system.particles.angular_velocity,
                &rot.angular_acc,
                &self.touched,
                by,
            );
        }
    }

    /// The spins now, in the engine's order: the stored ones with the pending half
    /// kick applied.
    pub(super) fn spins_now(&self) -> Vec<[f64; 3]> {
        let mut w = self.system.particles.angular_velocity.clone();
        if let (Some(rot), true) = (&self.rotation, self.lagging) {
            kick_contacts(&mut w, &rot.angular_acc, &self.touched, 0.5 * self.opts.dt);
        }
        w
    }
}
