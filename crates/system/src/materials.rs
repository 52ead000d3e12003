//! Materials and the contact constants of every pair of them: a material's own, an
//! `[[interactions]]` entry's, or those both materials agree on (docs/physics.md,
//! "Materials and their pairs").
//!
//! A pair of materials a, b collides as two spheres of one material with the pair's
//! constants would. Without an entry for the pair:
//! - Hertz moduli follow Hertz's rule, 1/E* = (1−ν_a²)/Y_a + (1−ν_b²)/Y_b (Johnson,
//!   *Contact Mechanics*, Eq. 4.22), the one standard mixing rule of the elastic
//!   constants;
//! - every other constant (the linear stiffness, the dissipation as given — a constant
//!   or a restitution — and the tangential law) is the pair's only where both
//!   materials give the same value; otherwise the pair is refused, with the entry to add.

use crate::error::{Result, SystemError};
use crate::state::Species;
use emdstar_contact::{ForceLaw, LinearDashpot, PairProperties, Sphere, Tangential};
use emdstar_contact::{Model, ViscoelasticHertz};

/// The elastic part of a normal law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Elastic {
    /// The linear spring k in N/m.
    Linear { stiffness: f64 },
    /// Young's modulus and Poisson's ratio.
    Hertz { young: f64, poisson: f64 },
}

impl Elastic {
    pub fn model(&self) -> Model {
        match self {
            Self::Linear { .. } => Model::Linear,
            Self::Hertz { .. } => Model::Hertz,
        }
    }
}

/// How a law's dissipation is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dissipation {
    /// The dashpot γ (linear, kg/s) or the dissipative constant A (Hertz, s).
    Constant(f64),
    /// The normal restitution of a central impact of the pair's reference bodies at the
    /// normal speed `speed` (the linear dashpot's does not depend on it: 1 m/s).
    Restitution { value: f64, speed: f64 },
}

/// A material as the config gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// Where the config gives it, for messages: `material` or `materials[2]`.
    pub key: String,
    pub elastic: Elastic,
    pub dissipation: Dissipation,
    pub tangential: Tangential,
    /// kg/m³ (needed by spheres without their own mass).
    pub density: Option<f64>,
}

/// An `[[interactions]]` entry: the constants it gives for one pair of materials.
#[derive(Debug, Clone, PartialEq)]
pub struct PairEntry {
    pub materials: [u32; 2],
    /// `interactions[3]`, for messages.
    pub key: String,
    pub elastic: Option<Elastic>,
    pub dissipation: Option<Dissipation>,
    pub tangential: Option<Tangential>,
}

/// The materials of a config and its `[[interactions]]` entries.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MaterialTable {
    pub materials: Vec<Material>,
    pub entries: Vec<PairEntry>,
}

/// The reference bodies of a pair of materials: where a restitution given for it is
/// solved exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reference {
    /// Two spheres (the first species of each material).
    Spheres(Species, Species),
    /// A sphere against a flat wall (a material only walls are made of).
    Wall(Species),
}

impl Reference {
    fn props(&self) -> Result<PairProperties> {
        Ok(match self {
            Self::Spheres(a, b) => PairProperties::spheres(
                &Sphere::new(a.radius, a.mass)?,
                &Sphere::new(b.radius, b.mass)?,
            ),
            Self::Wall(a) => PairProperties::sphere_wall(&Sphere::new(a.radius, a.mass)?),
        })
    }

    fn describe(&self) -> String {
        match self {
            Self::Spheres(a, b) if a == b => format!(
                "central impacts of two spheres of radius {} m and mass {:.6e} kg",
                a.radius, a.mass
            ),
            Self::Spheres(a, b) => format!(
                "central impacts of spheres of radius {} m, mass {:.6e} kg and radius {} m, \
                 mass {:.6e} kg",
                a.radius, a.mass, b.radius, b.mass
            ),
            Self::Wall(a) => format!(
                "central impacts of a sphere of radius {} m and mass {:.6e} kg on a wall",
                a.radius, a.mass
            ),
        }
    }
}

/// What a pair of materials resolves to: the law of two spheres of one material with
/// the pair's constants, the tangential law, and a line for the user where a
/// restitution was solved.
#[derive(Debug, Clone, PartialEq)]
pub struct PairMaterial {
    pub law: ForceLaw,
    pub tangential: Tangential,
    pub note: Option<String>,
}

impl MaterialTable {
    /// The constants of materials `a` and `b` (in either order), with a restitution
    /// solved for `reference`.
    pub fn resolve(&self, a: u32, b: u32, reference: &Reference) -> Result<PairMaterial> {
        let (ma, mb) = (&self.materials[a as usize], &self.materials[b as usize]);
        let entry = self
            .entries
            .iter()
            .find(|e| e.materials == [a, b] || e.materials == [b, a]);
        let elastic = match entry.and_then(|e| e.elastic) {
            Some(e) => e,
            None if a == b => ma.elastic,
            None => self.elastic(ma, mb)?,
        };
        let dissipation = match entry.and_then(|e| e.dissipation) {
            Some(d) => d,
            None => self.agreed(ma, mb, "dissipation", |m| m.dissipation)?,
        };
        let tangential = match entry.and_then(|e| e.tangential) {
            Some(t) => t,
            None => self.agreed(ma, mb, "tangential law", |m| m.tangential)?,
        };
        let key = match entry {
            Some(e) if e.dissipation.is_some() => e.key.clone(),
            _ if a == b => ma.key.clone(),
            _ => format!("{} and {}", ma.key, mb.key),
        };
        let (law, note) = law_of(elastic, dissipation, reference)
            .map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
        let note =
            note.map(|solved| format!("{key}.restitution {solved} ({})", reference.describe()));
        Ok(PairMaterial {
            law,
            tangential,
            note,
        })
    }

    /// The elastic constants of two materials by the mixing rule (see the module docs).
    fn elastic(&self, a: &Material, b: &Material) -> Result<Elastic> {
        match (a.elastic, b.elastic) {
            (Elastic::Linear { stiffness: x }, Elastic::Linear { stiffness: y }) if x == y => {
                Ok(a.elastic)
            }
            (
                Elastic::Hertz {
                    young: ya,
                    poisson: na,
                },
                Elastic::Hertz {
                    young: yb,
                    poisson: nb,
                },
            ) => {
                let e_star = 1.0 / ((1.0 - na * na) / ya + (1.0 - nb * nb) / yb);
                // Two spheres of one material with Y = 2E*, ν = 0 have this E*.
                Ok(Elastic::Hertz {
                    young: 2.0 * e_star,
                    poisson: 0.0,
                })
            }
            (Elastic::Linear { .. }, Elastic::Linear { .. }) => Err(self.undetermined(
                a,
                b,
                "their linear stiffnesses differ, and the linear model has no mixing rule",
                "stiffness = … (with model = \"linear\")",
            )),
            _ => Err(self.undetermined(
                a,
                b,
                "one is a linear dashpot and the other a Hertz material",
                "model = \"hertz\" (or \"linear\") with its elastic constants",
            )),
        }
    }

    /// A constant both materials must agree on (`what`: its name in messages).
    fn agreed<T: PartialEq>(
        &self,
        a: &Material,
        b: &Material,
        what: &str,
        get: impl Fn(&Material) -> T,
    ) -> Result<T> {
        let (x, y) = (get(a), get(b));
        if x == y {
            return Ok(x);
        }
        let keys = if what == "dissipation" {
            "restitution = … (or dissipation / damping = …)"
        } else {
            "friction = … with its tangential keys (or friction = 0.0 for a smooth pair)"
        };
        Err(self.undetermined(
            a,
            b,
            &format!("their {what}s differ, and there is no standard mixing rule for them"),
            keys,
        ))
    }

    fn undetermined(&self, a: &Material, b: &Material, why: &str, keys: &str) -> SystemError {
        SystemError::Invalid(format!(
            "materials \"{}\" ({}) and \"{}\" ({}) touch, but the constants of their contact \
             are not determined: {why}. Give the pair its own constants:\n\n[[interactions]]\n\
             materials = [\"{}\", \"{}\"]\n{keys}\n",
            a.name, a.key, b.name, b.key, a.name, b.name
        ))
    }
}

/// The force law of `elastic` with `dissipation`, its restitution solved exactly for
/// `reference` (Müller & Pöschel 2013's exact collision; `emdstar_mor::with_restitution`),
/// and what was solved, for the user. An error names the key without its section.
fn law_of(
    elastic: Elastic,
    dissipation: Dissipation,
    reference: &Reference,
) -> std::result::Result<(ForceLaw, Option<String>), String> {
    let constant = match dissipation {
        Dissipation::Constant(c) => c,
        Dissipation::Restitution { .. } => 0.0,
    };
    let law = match elastic {
        Elastic::Linear { stiffness } => {
            LinearDashpot::new(stiffness, constant).map(ForceLaw::Linear)
        }
        Elastic::Hertz { young, poisson } => {
            ViscoelasticHertz::new(young, poisson, constant).map(ForceLaw::Hertz)
        }
    }
    .map_err(|e| e.to_string())?;
    let Dissipation::Restitution { value, speed } = dissipation else {
        return Ok((law, None));
    };
    let props = reference.props().map_err(|e| e.to_string())?;
    let law = emdstar_mor::with_restitution(&law, &props, speed, value)
        .map_err(|err| format!("restitution: {err}"))?;
    let note = match law {
        ForceLaw::Linear(l) => format!("= {value}: damping = {:.10e} kg/s", l.damping),
        ForceLaw::Hertz(h) => format!(
            "= {value} at {speed} m/s: dissipation = {:.10e} s",
            h.dissipation
        ),
    };
    Ok((law, Some(note)))
}
