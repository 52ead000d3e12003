//! The contact model of every kind of contact in a system: each species pair, and each
//! species against each wall (Müller & Pöschel 2013, Sec. II, for the pair properties;
//! the constants of a pair of materials come from [`crate::materials`]).

use crate::error::Result;
use crate::materials::{MaterialTable, PairMaterial, Reference};
use crate::state::Species;
use emdstar_contact::{ContactModel, ForceLaw, PairLaw, PairProperties, Sphere, Tangential};
use std::collections::HashMap;

/// The contact model and pair properties of one kind of contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interaction {
    pub model: ContactModel,
    pub props: PairProperties,
    /// The materials in contact: a sphere's, then its partner's or the wall's.
    pub materials: [u32; 2],
}

impl Interaction {
    /// The normal force law.
    #[inline]
    pub fn law(&self) -> &PairLaw {
        &self.model.normal
    }

    /// The tangential sub-model.
    #[inline]
    pub fn tangential(&self) -> &Tangential {
        &self.model.tangential
    }
}

/// Every kind of contact of a system, looked up by species (and wall).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Interactions {
    /// Material names and where the config gives them (`material`, `materials[1]`).
    names: Vec<(String, String)>,
    species: usize,
    /// `pairs[a * species + b]`.
    pairs: Vec<Interaction>,
    /// Distinct wall materials ("slots"), the slot of each wall (empty: every wall is
    /// slot 0), and `walls[a * slots + slot]`.
    slots: usize,
    wall_slot: Vec<u32>,
    walls: Vec<Interaction>,
    /// What was solved for the user (restitutions as input), one line each.
    notes: Vec<String>,
}

impl Interactions {
    /// The contacts of spheres of `species` with each other and with walls of
    /// `wall_materials` (one material per wall), from the materials of `table`.
    pub fn build(
        table: &MaterialTable,
        species: &[Species],
        wall_materials: &[u32],
    ) -> Result<Self> {
        let first_of = |m: u32| species.iter().find(|s| s.material == m).copied();
        let mut resolved: HashMap<(u32, u32, bool), PairMaterial> = HashMap::new();
        let mut notes = Vec::new();
        // A wall of a material spheres are made of too takes the spheres' constants.
        let mut resolve = |a: &Species, other: u32| -> Result<PairMaterial> {
            let first_a = first_of(a.material).unwrap_or(*a);
            let reference = match first_of(other) {
                Some(first_b) => Reference::Spheres(first_a, first_b),
                None => Reference::Wall(first_a),
            };
            let wall_only = matches!(reference, Reference::Wall(_));
            let key = (a.material.min(other), a.material.max(other), wall_only);
            if let Some(p) = resolved.get(&key) {
                return Ok(p.clone());
            }
            let p = table.resolve(a.material, other, &reference)?;
            notes.extend(p.note.clone());
            resolved.insert(key, p.clone());
            Ok(p)
        };
        let mut pairs = Vec::with_capacity(species.len() * species.len());
        for a in species {
            for b in species {
                let m = resolve(a, b.material)?;
                let props = PairProperties::spheres(&a.sphere(), &b.sphere());
                pairs.push(interaction(&m, props, [a.material, b.material])?);
            }
        }
        let mut slot_material: Vec<u32> = Vec::new();
        let wall_slot = wall_materials
            .iter()
            .map(|&m| match slot_material.iter().position(|&s| s == m) {
                Some(slot) => slot as u32,
                None => {
                    slot_material.push(m);
                    (slot_material.len() - 1) as u32
                }
            })
            .collect();
        let mut walls = Vec::with_capacity(species.len() * slot_material.len());
        for a in species {
            for &w in &slot_material {
                let m = resolve(a, w)?;
                let props = PairProperties::sphere_wall(&a.sphere());
                walls.push(interaction(&m, props, [a.material, w])?);
            }
        }
        Ok(Self {
            names: table
                .materials
                .iter()
                .map(|m| (m.name.clone(), m.key.clone()))
                .collect(),
            species: species.len(),
            pairs,
            slots: slot_material.len(),
            wall_slot,
            walls,
            notes,
        })
    }

    /// The contacts of spheres of `species` that are all of one material, `law` with
    /// `tangential`, and so are all walls.
    pub fn one_material(
        law: &ForceLaw,
        tangential: Tangential,
        species: &[Species],
    ) -> Result<Self> {
        let m = PairMaterial {
            law: *law,
            tangential: tangential.normalised(),
            note: None,
        };
        let mut pairs = Vec::with_capacity(species.len() * species.len());
        for a in species {
            for b in species {
                let props = PairProperties::spheres(&a.sphere(), &b.sphere());
                pairs.push(interaction(&m, props, [0, 0])?);
            }
        }
        let walls = species
            .iter()
            .map(|a| interaction(&m, PairProperties::sphere_wall(&a.sphere()), [0, 0]))
            .collect::<Result<_>>()?;
        Ok(Self {
            names: vec![("material".into(), "material".into())],
            species: species.len(),
            pairs,
            slots: 1,
            wall_slot: Vec::new(),
            walls,
            notes: Vec::new(),
        })
    }

    /// The contacts of `spheres` (one species each) all made of `law` with
    /// `tangential`, walls included.
    pub fn of_spheres(law: &ForceLaw, tangential: Tangential, spheres: &[Sphere]) -> Result<Self> {
        let species: Vec<Species> = spheres
            .iter()
            .map(|s| Species::new(s.radius, s.mass))
            .collect();
        Self::one_material(law, tangential, &species)
    }

    /// The same contacts with the tangential law `tangential` gives for each.
    pub fn with_tangential<E: From<emdstar_contact::ContactError>>(
        &self,
        tangential: impl Fn(&Interaction) -> std::result::Result<Tangential, E>,
    ) -> std::result::Result<Self, E> {
        let mut out = self.clone();
        for i in out.pairs.iter_mut().chain(&mut out.walls) {
            i.model.tangential = tangential(i)?.normalised();
        }
        Ok(out)
    }

    /// Species `a` against species `b`.
    #[inline]
    pub fn pair(&self, a: u32, b: u32) -> &Interaction {
        &self.pairs[a as usize * self.species + b as usize]
    }

    /// Species `a` against wall `w`.
    #[inline]
    pub fn wall(&self, a: u32, w: usize) -> &Interaction {
        &self.walls[self.wall_index(a, w) - self.pairs.len()]
    }

    /// The number of species pair (`a`, `b`) among [`Interactions::all`], for tables
    /// kept beside this one.
    #[inline]
    pub fn pair_index(&self, a: u32, b: u32) -> usize {
        a as usize * self.species + b as usize
    }

    /// The number of species `a` against wall `w` among [`Interactions::all`].
    #[inline]
    pub fn wall_index(&self, a: u32, w: usize) -> usize {
        let slot = self.wall_slot.get(w).map_or(0, |&s| s as usize);
        self.pairs.len() + a as usize * self.slots + slot
    }

    /// Every kind of contact, ordered pairs then walls, numbered as
    /// [`Interactions::pair_index`] and [`Interactions::wall_index`] say.
    pub fn all(&self) -> impl Iterator<Item = &Interaction> {
        self.pairs.iter().chain(&self.walls)
    }

    /// Number of species.
    pub fn species(&self) -> usize {
        self.species
    }

    /// Every distinct contact: each unordered species pair once, then the walls.
    pub fn distinct(&self) -> impl Iterator<Item = &Interaction> {
        self.distinct_pairs().chain(&self.walls)
    }

    /// Each unordered species pair once.
    pub fn distinct_pairs(&self) -> impl Iterator<Item = &Interaction> {
        let n = self.species;
        (0..n).flat_map(move |a| (a..n).map(move |b| &self.pairs[a * n + b]))
    }

    /// Each species against each kind of wall.
    pub fn wall_contacts(&self) -> impl Iterator<Item = &Interaction> {
        self.walls.iter()
    }

    /// True if any contact exchanges tangential forces.
    pub fn is_frictional(&self) -> bool {
        self.distinct().any(|i| i.model.is_frictional())
    }

    /// The name of material `m`.
    pub fn material_name(&self, m: u32) -> &str {
        self.names.get(m as usize).map_or("?", |n| n.0.as_str())
    }

    /// Where the config gives material `m` (`material`, `materials[1]`).
    pub fn material_key(&self, m: u32) -> &str {
        self.names
            .get(m as usize)
            .map_or("material", |n| n.1.as_str())
    }

    /// How messages name the contact of `i`: a material with itself, or a pair.
    pub fn describe(&self, i: &Interaction) -> String {
        let [a, b] = i.materials;
        if self.names.len() <= 1 {
            return "the material".into();
        }
        if a == b {
            format!("material \"{}\"", self.material_name(a))
        } else {
            format!(
                "materials \"{}\" and \"{}\"",
                self.material_name(a),
                self.material_name(b)
            )
        }
    }

    /// One line for each restitution that was solved for a pair's dissipation.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }
}

fn interaction(
    m: &PairMaterial,
    props: PairProperties,
    materials: [u32; 2],
) -> Result<Interaction> {
    Ok(Interaction {
        model: ContactModel {
            normal: PairLaw::same_material(&m.law, props.r_eff)?,
            tangential: m.tangential.normalised(),
        },
        props,
        materials,
    })
}
