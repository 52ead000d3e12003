//! `[material]`, `[[materials]]` and `[[interactions]]` of the config: the keys of a
//! force law, its dissipation and its friction, checked with errors that name the key.

use crate::error::{Result, SystemError, invalid, positive};
use crate::materials::{Dissipation, Elastic, Material, MaterialTable, PairEntry};
use emdstar_contact::check::non_negative;
use emdstar_contact::{HistorySpring, Model, Tangential, Walton};
use serde::{Deserialize, Serialize};

/// `[material]` or one `[[materials]]` entry: the force law, the friction and the
/// density.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    /// The name particles, gas species and walls give in `material = "…"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    pub model: String,
    pub stiffness: Option<f64>,
    pub damping: Option<f64>,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub dissipation: Option<f64>,
    /// Normal restitution of a central impact of two reference spheres, instead of
    /// `damping` or `dissipation` (solved exactly, see [`crate::materials`]).
    pub restitution: Option<f64>,
    /// Normal impact speed in m/s at which `restitution` holds (Hertz only).
    pub restitution_speed: Option<f64>,
    pub density: Option<f64>,
    /// Coulomb's friction coefficient µ (default 0: frictionless).
    pub friction: Option<f64>,
    /// k_t of the tangential history spring in N/m.
    pub tangential_stiffness: Option<f64>,
    /// γ_t of the tangential dashpot in kg/s.
    pub tangential_damping: Option<f64>,
    /// "history" (default) or "coulomb".
    pub tangential: Option<String>,
    /// β₀ ∈ [−1, 1] of Walton's rule, the event-driven engines' friction, instead of
    /// MD's tangential law.
    pub tangential_restitution: Option<f64>,
}

/// One `[[interactions]]` entry: the constants of one pair of materials, with the keys
/// of a material but `name` and `density`. Keys it leaves out come from the materials
/// (docs/config.md).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InteractionConfig {
    pub materials: [String; 2],
    /// With the elastic constants of the pair (`stiffness`, or `young` and `poisson`);
    /// absent, they follow the mixing rule.
    pub model: Option<String>,
    pub stiffness: Option<f64>,
    pub damping: Option<f64>,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub dissipation: Option<f64>,
    pub restitution: Option<f64>,
    pub restitution_speed: Option<f64>,
    pub friction: Option<f64>,
    pub tangential_stiffness: Option<f64>,
    pub tangential_damping: Option<f64>,
    pub tangential: Option<String>,
    pub tangential_restitution: Option<f64>,
}

/// The keys of a law and its friction, shared by materials and entries.
struct LawKeys<'a> {
    /// `material`, `materials[1]`, `interactions[0]`.
    key: &'a str,
    stiffness: Option<f64>,
    damping: Option<f64>,
    young: Option<f64>,
    poisson: Option<f64>,
    dissipation: Option<f64>,
    restitution: Option<f64>,
    restitution_speed: Option<f64>,
    friction: Option<f64>,
    tangential_stiffness: Option<f64>,
    tangential_damping: Option<f64>,
    tangential: Option<&'a str>,
    tangential_restitution: Option<f64>,
}

/// The [`LawKeys`] of a `[material]` or `[[interactions]]` entry (the same fields).
macro_rules! law_keys {
    ($entry:expr, $key:expr) => {
        LawKeys {
            key: $key,
            stiffness: $entry.stiffness,
            damping: $entry.damping,
            young: $entry.young,
            poisson: $entry.poisson,
            dissipation: $entry.dissipation,
            restitution: $entry.restitution,
            restitution_speed: $entry.restitution_speed,
            friction: $entry.friction,
            tangential_stiffness: $entry.tangential_stiffness,
            tangential_damping: $entry.tangential_damping,
            tangential: $entry.tangential.as_deref(),
            tangential_restitution: $entry.tangential_restitution,
        }
    };
}

fn parse_model(key: &str, model: &str) -> Result<Model> {
    model
        .parse()
        .map_err(|e| SystemError::Invalid(format!("{key}.model: {e}")))
}

impl MaterialConfig {
    /// The material `key` names (`material` or `materials[i]`), checked.
    pub fn material(&self, key: &str) -> Result<Material> {
        let model = parse_model(key, &self.model)?;
        let keys = law_keys!(self, key);
        let density = match self.density {
            Some(rho) => Some(crate::error::positive(&format!("{key}.density"), rho)?),
            None => None,
        };
        Ok(Material {
            name: self.name.clone().unwrap_or_else(|| key.to_string()),
            key: key.to_string(),
            elastic: keys.elastic(model)?,
            dissipation: keys
                .dissipation(model)?
                .unwrap_or(Dissipation::Constant(0.0)),
            tangential: keys.tangential()?.unwrap_or(Tangential::None),
            density,
        })
    }
}

impl InteractionConfig {
    /// The entry `key` names (`interactions[i]`) for the materials of `table`.
    pub fn entry(&self, key: &str, table: &MaterialTable) -> Result<PairEntry> {
        let index = |name: &str| -> Result<u32> {
            match table.materials.iter().position(|m| m.name == name) {
                Some(i) => Ok(i as u32),
                None => invalid!(
                    "{key}.materials names \"{name}\", which is no material of this config; \
                     the materials are {}",
                    names(table)
                ),
            }
        };
        let materials = [index(&self.materials[0])?, index(&self.materials[1])?];
        let model = match &self.model {
            Some(m) => Some(parse_model(key, m)?),
            None => None,
        };
        let keys = law_keys!(self, key);
        // Without a model, the pair's model is the materials' (which must agree).
        let pair_model = match model {
            Some(m) => m,
            None => {
                for name in ["stiffness", "young", "poisson"] {
                    let given = match name {
                        "stiffness" => self.stiffness,
                        "young" => self.young,
                        _ => self.poisson,
                    };
                    if given.is_some() {
                        return invalid!(
                            "{key}.{name} gives elastic constants of the pair: give {key}.model \
                             with them (\"linear\" with stiffness, \"hertz\" with young and \
                             poisson), or remove it to take them from the materials"
                        );
                    }
                }
                let [a, b] = materials.map(|m| table.materials[m as usize].elastic.model());
                if a != b && (self.dissipation.is_some() || self.damping.is_some()) {
                    return invalid!(
                        "{key} joins a {a} and a {b} material: give {key}.model and the pair's \
                         elastic constants"
                    );
                }
                a
            }
        };
        Ok(PairEntry {
            materials,
            key: key.to_string(),
            elastic: match model {
                Some(m) => Some(keys.elastic(m)?),
                None => None,
            },
            dissipation: keys.dissipation(pair_model)?,
            tangential: keys.tangential()?,
        })
    }
}

/// The names of a table's materials, quoted, for messages.
pub(crate) fn names(table: &MaterialTable) -> String {
    table
        .materials
        .iter()
        .map(|m| format!("\"{}\"", m.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl LawKeys<'_> {
    fn need(&self, name: &str, v: Option<f64>, model: Model) -> Result<f64> {
        v.ok_or_else(|| {
            SystemError::Invalid(format!(
                "{}.{name} is required by model = \"{model}\"",
                self.key
            ))
        })
    }

    fn refuse(&self, name: &str, v: Option<f64>, model: Model) -> Result<()> {
        match v {
            Some(_) => invalid!(
                "{}.{name} does not belong to model = \"{model}\"; remove it",
                self.key
            ),
            None => Ok(()),
        }
    }

    /// The elastic constants of `model`, refusing keys of the other model.
    fn elastic(&self, model: Model) -> Result<Elastic> {
        let key = self.key;
        Ok(match model {
            Model::Linear => {
                self.refuse("young", self.young, model)?;
                self.refuse("poisson", self.poisson, model)?;
                let stiffness = self.need("stiffness", self.stiffness, model)?;
                emdstar_contact::LinearDashpot::new(stiffness, 0.0)
                    .map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
                Elastic::Linear { stiffness }
            }
            Model::Hertz => {
                self.refuse("stiffness", self.stiffness, model)?;
                let young = self.need("young", self.young, model)?;
                let poisson = self.need("poisson", self.poisson, model)?;
                emdstar_contact::ViscoelasticHertz::new(young, poisson, 0.0)
                    .map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
                Elastic::Hertz { young, poisson }
            }
        })
    }

    /// The dissipation: a constant of `model` (γ or A), or a restitution; `None` if
    /// none is given.
    fn dissipation(&self, model: Model) -> Result<Option<Dissipation>> {
        let key = self.key;
        let (name, other, given) = match model {
            Model::Linear => ("damping", ("dissipation", self.dissipation), self.damping),
            Model::Hertz => ("dissipation", ("damping", self.damping), self.dissipation),
        };
        self.refuse(other.0, other.1, model)?;
        if model == Model::Linear && self.restitution_speed.is_some() {
            return invalid!(
                "{key}.restitution_speed does not belong to model = \"linear\": the linear \
                 dashpot's restitution is the same at every speed; remove it"
            );
        }
        match (given, self.restitution) {
            (Some(_), Some(_)) => invalid!(
                "give either {key}.{name} or {key}.restitution, not both: restitution computes \
                 {name}"
            ),
            (Some(c), None) => {
                non_negative(name, c).map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
                if self.restitution_speed.is_some() {
                    return invalid!(
                        "{key}.restitution_speed needs {key}.restitution (or remove it)"
                    );
                }
                Ok(Some(Dissipation::Constant(c)))
            }
            (None, Some(e)) => {
                let speed = match model {
                    Model::Linear => 1.0,
                    Model::Hertz => {
                        let v = self.restitution_speed.ok_or_else(|| {
                            SystemError::Invalid(format!(
                                "{key}.restitution needs {key}.restitution_speed (m/s) with \
                                 model = \"hertz\": the restitution of viscoelastic spheres \
                                 falls with the impact speed, so it is matched at one speed"
                            ))
                        })?;
                        positive(&format!("{key}.restitution_speed"), v)?
                    }
                };
                Ok(Some(Dissipation::Restitution { value: e, speed }))
            }
            (None, None) => {
                if self.restitution_speed.is_some() {
                    return invalid!(
                        "{key}.restitution_speed needs {key}.restitution (or remove it)"
                    );
                }
                Ok(None)
            }
        }
    }

    /// The tangential law; `None` if no friction key is given. Tangential keys without
    /// `friction` are refused (they would have no effect), and so are MD's tangential
    /// keys together with Walton's rule (each engine runs one of them).
    fn tangential(&self) -> Result<Option<Tangential>> {
        let key = self.key;
        let md_keys = [
            ("tangential_stiffness", self.tangential_stiffness.is_some()),
            ("tangential_damping", self.tangential_damping.is_some()),
            ("tangential", self.tangential.is_some()),
        ];
        let Some(mu) = self.friction else {
            let stray = md_keys
                .iter()
                .chain(&[(
                    "tangential_restitution",
                    self.tangential_restitution.is_some(),
                )])
                .find(|(_, set)| *set)
                .map(|(name, _)| *name);
            if let Some(name) = stray {
                return invalid!(
                    "{key}.{name} has no effect without {key}.friction (Coulomb's µ); add \
                     friction = µ or remove it"
                );
            }
            return Ok(None);
        };
        non_negative("friction", mu).map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
        if let Some(b) = self.tangential_restitution {
            if let Some((name, _)) = md_keys.iter().find(|(_, set)| *set) {
                return invalid!(
                    "{key}.{name} belongs to force-based MD's tangential law and \
                     {key}.tangential_restitution to Walton's rule of the event-driven engines \
                     (emd): a material has one or the other; remove one of them"
                );
            }
            let w = Walton::new(mu, b).map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
            return Ok(Some(Tangential::Walton(w).normalised()));
        }
        let coulomb = match self.tangential {
            None | Some("history") => false,
            Some("coulomb") => true,
            Some(other) => {
                return invalid!(
                    "{key}.tangential: unknown tangential model \"{other}\": use \"history\" \
                     (Cundall-Strack spring, the default) or \"coulomb\" (pure sliding friction)"
                );
            }
        };
        if coulomb {
            for (name, v) in [
                ("tangential_stiffness", self.tangential_stiffness),
                ("tangential_damping", self.tangential_damping),
            ] {
                if v.is_some() {
                    return invalid!(
                        "{key}.{name} does not belong to tangential = \"coulomb\" (pure sliding \
                         has no spring or dashpot); remove it or use \"history\""
                    );
                }
            }
            return Ok(Some(Tangential::Coulomb { friction: mu }.normalised()));
        }
        if mu == 0.0 {
            // Smooth spheres: the spring's keys are checked but unused.
            for (name, v) in [
                ("tangential_stiffness", self.tangential_stiffness),
                ("tangential_damping", self.tangential_damping),
            ] {
                if let Some(v) = v {
                    non_negative(name, v)
                        .map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
                }
            }
            return Ok(Some(Tangential::None));
        }
        let spring = HistorySpring::new(
            mu,
            self.tangential_stiffness.unwrap_or(0.0),
            self.tangential_damping.unwrap_or(0.0),
        )
        .map_err(|e| SystemError::Invalid(format!("{key}.{e}")))?;
        Ok(Some(Tangential::History(spring)))
    }
}
