//! The pair physics of every kind of contact in a system: each species pair, and each
//! species against a wall, with the force law of the one material and the pair's
//! properties (Müller & Pöschel 2013, Sec. II).

use crate::error::Result;
use crate::state::Species;
use emdstar_contact::{ForceLaw, PairLaw, PairProperties};

/// The law and properties of one kind of contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interaction {
    pub law: PairLaw,
    pub props: PairProperties,
}

/// Every kind of contact of a system, looked up by species.
#[derive(Debug, Clone, PartialEq)]
pub struct Interactions {
    species: usize,
    /// `pairs[a * species + b]`.
    pairs: Vec<Interaction>,
    walls: Vec<Interaction>,
}

impl Interactions {
    /// The contacts of spheres of `species`, all made of `material` (walls included).
    pub fn of(material: &ForceLaw, species: &[Species]) -> Result<Self> {
        let mut pairs = Vec::with_capacity(species.len() * species.len());
        for a in species {
            for b in species {
                let props = PairProperties::spheres(&a.sphere(), &b.sphere());
                pairs.push(Interaction {
                    law: PairLaw::same_material(material, props.r_eff)?,
                    props,
                });
            }
        }
        let walls = species
            .iter()
            .map(|s| {
                let props = PairProperties::sphere_wall(&s.sphere());
                Ok(Interaction {
                    law: PairLaw::same_material(material, props.r_eff)?,
                    props,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            species: species.len(),
            pairs,
            walls,
        })
    }

    /// Species `a` against species `b`.
    #[inline]
    pub fn pair(&self, a: u32, b: u32) -> &Interaction {
        &self.pairs[a as usize * self.species + b as usize]
    }

    /// Species `a` against a wall.
    #[inline]
    pub fn wall(&self, a: u32) -> &Interaction {
        &self.walls[a as usize]
    }

    /// Number of species.
    pub fn species(&self) -> usize {
        self.species
    }

    /// Every distinct contact: each unordered species pair once, then the walls.
    pub fn distinct(&self) -> impl Iterator<Item = &Interaction> {
        let n = self.species;
        (0..n)
            .flat_map(move |a| (a..n).map(move |b| &self.pairs[a * n + b]))
            .chain(&self.walls)
    }
}
