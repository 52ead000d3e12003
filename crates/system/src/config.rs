//! The TOML config shared by all engines.
//!
//! ```toml
//! t_end = 0.5                      # s
//! gravity = [0.0, 0.0, -9.81]      # m/s², optional (default none)
//! [material]
//! model = "linear"                 # or "hertz"
//! stiffness = 2000.0               # N/m  (linear)
//! damping = 0.0                    # kg/s (linear)
//! # young = 1e9                    # Pa   (hertz)
//! # poisson = 0.4                  #      (hertz)
//! # dissipation = 1e-3             # s: A of Brilliantov et al. (hertz)
//! # restitution = 0.8              # instead of damping/dissipation: central ε_n
//! # restitution_speed = 1.0        # m/s, where ε_n is matched (hertz only)
//! density = 1140.0                 # kg/m³ (or give `mass` per particle / gas)
//! # friction = 0.2                 # Coulomb µ (default 0: frictionless)
//! # tangential_stiffness = 1600.0  # N/m: k_t of the history spring
//! # tangential_damping = 0.0       # kg/s: γ_t
//! # tangential = "history"         # or "coulomb" (pure sliding, |F_t| = µ F_n)
//! # tangential_restitution = 0.4   # β₀ ∈ [-1, 1] of Walton's rule (event engines),
//! #                                # instead of the three tangential keys above (MD)
//! [[particles]]                    # an explicit list ...
//! radius = 0.1
//! position = [0.03, -0.5, 0.0]
//! velocity = [1.25, 2.5, 0.0]      # optional, default at rest
//! # angular_velocity = [0.0, 0.0, 10.0] # rad/s, optional, default no spin
//! # mass = 4.0                     # optional, overrides the density
//! # [gas]                          # ... or a generated gas
//! # count = 32768
//! # radius = 0.1
//! # arrangement = "lattice"        # or "fcc" (count = 4n³), "random" (non-overlapping)
//! # packing_fraction = 0.01        # sizes a cubic periodic box (omit [box] then)
//! # rms_speed = 1.0                # m/s, √⟨v²⟩, Maxwell, zero total momentum
//! # seed = 1
//! # [box]                          # absent: free space
//! # size = [2.0, 2.0, 2.0]
//! # lo = [-1.0, -1.0, -1.0]        # default [0, 0, 0]
//! # periodic = [true, true, false] # default all periodic
//! # [[walls]]
//! # normal = [0.0, 0.0, 1.0]       # towards the particles
//! # point = [0.0, 0.0, -1.0]
//! # [output]
//! # trajectory = "run.xyz"
//! # trajectory_interval = 0.01     # s
//! # log = "run.log"
//! # log_interval = 0.001           # s
//! # restart_interval = 0.1         # s: a checkpoint this often (with `run --checkpoint`)
//! # [md]                           # options of the MD engine only
//! # dt = 1e-5                      # s (default: a fraction of the contact time)
//! # contact_end = "force"          # or "overlap" (LAMMPS)
//! # skin = 0.02                    # m
//! ```
//!
//! Engines own their optional sections (`[md]` here); the rest describes the physical
//! system and is engine-independent.

use crate::domain::Domain;
use crate::error::{
    Result, SystemError, finite3, invalid, positive, representable_energy, representable_spin,
};
use crate::gas::{self, GasConfig};
use crate::geometry::{SimBox, Wall};
use crate::state::{Particles, Species};
use crate::system::System;
use emdstar_contact::{
    ForceLaw, Friction, LinearDashpot, Model, PairProperties, Sphere, TangentialModel,
    ViscoelasticHertz,
};
use serde::{Deserialize, Serialize};

/// The whole config file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// End time in s.
    pub t_end: f64,
    /// Uniform acceleration in m/s².
    pub gravity: Option<[f64; 3]>,
    pub material: MaterialConfig,
    #[serde(default)]
    pub particles: Vec<ParticleConfig>,
    pub gas: Option<GasConfig>,
    #[serde(rename = "box")]
    pub sim_box: Option<BoxConfig>,
    #[serde(default)]
    pub walls: Vec<WallConfig>,
    pub output: Option<OutputConfig>,
    /// Options of the force-based engine (see `emdstar-dem`).
    pub md: Option<MdConfig>,
}

/// `[material]`: the force law, the friction and the density.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    pub model: String,
    pub stiffness: Option<f64>,
    pub damping: Option<f64>,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub dissipation: Option<f64>,
    /// Normal restitution of a central impact of two reference spheres, instead of
    /// `damping` or `dissipation` (see [`MaterialConfig::force_law`]).
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

/// One `[[particles]]` entry.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleConfig {
    pub radius: f64,
    pub position: [f64; 3],
    #[serde(default)]
    pub velocity: [f64; 3],
    /// rad/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub angular_velocity: [f64; 3],
    pub mass: Option<f64>,
}

fn is_zero(v: &[f64; 3]) -> bool {
    *v == [0.0; 3]
}

/// `[box]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxConfig {
    pub size: [f64; 3],
    #[serde(default)]
    pub lo: [f64; 3],
    #[serde(default = "all_periodic")]
    pub periodic: [bool; 3],
}

fn all_periodic() -> [bool; 3] {
    [true; 3]
}

/// One `[[walls]]` entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WallConfig {
    pub normal: [f64; 3],
    pub point: [f64; 3],
}

/// `[output]`: file names and intervals (the CLI may override them).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    pub trajectory: Option<String>,
    pub trajectory_interval: Option<f64>,
    pub log: Option<String>,
    pub log_interval: Option<f64>,
    /// Time between checkpoints in s (none by default).
    pub restart_interval: Option<f64>,
}

/// `[md]`: options of the force-based engine; the command line overrides them.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MdConfig {
    /// Time step in s.
    pub dt: Option<f64>,
    /// "force" (default, Schwager & Pöschel) or "overlap" (LAMMPS).
    pub contact_end: Option<String>,
    /// Verlet-list skin in m.
    pub skin: Option<f64>,
}

impl Config {
    /// The largest config file read (1 GiB: ten million `[[particles]]` entries).
    pub const MAX_BYTES: u64 = 1 << 30;

    /// Parses TOML text; unknown keys are errors.
    pub fn from_toml(text: &str) -> Result<Self> {
        let config: Self = crate::parse::from_toml(text)?;
        positive("t_end", config.t_end)?;
        Ok(config)
    }

    /// Reads and parses a config file.
    pub fn from_file(path: &std::path::Path) -> Result<Self> {
        let bytes = crate::files::read_input(path, "config", Self::MAX_BYTES)?;
        let text = String::from_utf8(bytes).map_err(|_| SystemError::Io {
            path: path.display().to_string(),
            io: std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                "a config is UTF-8 text; this file is not",
            ),
        })?;
        Self::from_toml(&text)
    }

    /// A digest of the physical system the config describes (everything but `t_end`
    /// and `[output]`): a checkpoint records it, and a run resumed from it under
    /// another config is refused.
    pub fn digest(&self) -> u64 {
        let physics = Self {
            t_end: 0.0,
            output: None,
            ..self.clone()
        };
        let text = toml::to_string(&physics).expect("a parsed config serialises");
        u64::from(crc32fast::hash(text.as_bytes())) | (text.len() as u64) << 32
    }

    /// Builds and validates the system the config describes.
    pub fn build(&self) -> Result<System> {
        let gravity = finite3("gravity", self.gravity.unwrap_or([0.0; 3]))?;
        let walls = self
            .walls
            .iter()
            .enumerate()
            .map(|(i, w)| w.wall(i))
            .collect::<Result<Vec<_>>>()?;
        let mut sim_box = self.sim_box.as_ref().map(BoxConfig::sim_box).transpose()?;
        let mut species = Vec::new();
        let mut particles = Particles::default();
        match (&self.gas, self.particles.is_empty()) {
            (Some(_), false) => {
                return invalid!("give either [[particles]] or [gas], not both");
            }
            (None, true) => {
                return invalid!("no particles: add [[particles]] entries or a [gas] section");
            }
            (None, false) => {
                for (i, pc) in self.particles.iter().enumerate() {
                    let s = self.species_of(&format!("particles[{i}]"), pc.radius, pc.mass)?;
                    let index = species_index(&mut species, s);
                    let x = finite3(&format!("particles[{i}].position"), pc.position)?;
                    let v = finite3(&format!("particles[{i}].velocity"), pc.velocity)?;
                    representable_energy(&format!("particles[{i}].velocity"), s.mass, v)?;
                    let w = finite3(
                        &format!("particles[{i}].angular_velocity"),
                        pc.angular_velocity,
                    )?;
                    particles.push(&species, index, x, v);
                    particles.angular_velocity[i] = representable_spin(
                        &format!("particles[{i}].angular_velocity"),
                        particles.inertia(i),
                        w,
                    )?;
                }
            }
            (Some(gas), true) => {
                let s = self.species_of("gas", gas.radius, gas.mass)?;
                species.push(s);
                let b = match (sim_box, gas.packing_fraction) {
                    (Some(_), Some(_)) => {
                        return invalid!(
                            "gas.packing_fraction sizes a cubic periodic box, so it cannot be \
                             combined with [box]; drop one of them"
                        );
                    }
                    (Some(b), None) => b,
                    (None, Some(eta)) => gas::cubic_box(gas.count, gas.radius, eta)?,
                    (None, None) => {
                        return invalid!("a [gas] needs a [box] or a gas.packing_fraction");
                    }
                };
                sim_box = Some(b);
                gas::generate_gas(gas, &species, &b, &mut particles)?;
            }
        }
        // species[0]: the [gas] sphere or the first [[particles]] entry.
        let material = self.material.force_law(&species[0])?;
        let friction = self.material.friction()?;
        let system = System {
            particles,
            species,
            material,
            friction,
            domain: Domain {
                sim_box,
                walls,
                gravity,
            },
        };
        system.validate()?;
        Ok(system)
    }

    /// The species of a sphere given by radius and either its own mass or the density.
    fn species_of(&self, what: &str, radius: f64, mass: Option<f64>) -> Result<Species> {
        positive(&format!("{what}.radius"), radius)?;
        let sphere = match (mass, self.material.density) {
            (Some(m), _) => Sphere::new(radius, positive(&format!("{what}.mass"), m)?)?,
            (None, Some(rho)) => Sphere::from_density(radius, positive("material.density", rho)?)?,
            (None, None) => {
                return invalid!("{what} has no mass: set material.density or {what}.mass");
            }
        };
        Ok(Species {
            radius: sphere.radius,
            mass: sphere.mass,
        })
    }
}

fn species_index(species: &mut Vec<Species>, s: Species) -> u32 {
    match species.iter().position(|t| *t == s) {
        Some(i) => i as u32,
        None => {
            species.push(s);
            (species.len() - 1) as u32
        }
    }
}

impl MaterialConfig {
    /// The force law, refusing keys that belong to the other model.
    ///
    /// With `restitution = E` the dissipation (γ or A) is the one with which a central
    /// impact of two `reference` spheres has normal restitution E (Hertz: at normal
    /// speed `restitution_speed`), from the exact solver (`emdstar_mor::inverse`). Other
    /// pairs of a mixture, and Hertz impacts at other speeds, get other restitutions.
    pub fn force_law(&self, reference: &Species) -> Result<ForceLaw> {
        let model: Model = self.model.parse().map_err(SystemError::Invalid)?;
        let need = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                SystemError::Invalid(format!(
                    "material.{name} is required by model = \"{model}\""
                ))
            })
        };
        let refuse = |name: &str, v: Option<f64>| match v {
            Some(_) => {
                invalid!("material.{name} does not belong to model = \"{model}\"; remove it")
            }
            None => Ok(()),
        };
        let dissipation = |name: &str, v: Option<f64>| match (v, self.restitution) {
            (Some(_), Some(_)) => invalid!(
                "give either material.{name} or material.restitution, not both: restitution \
                 computes {name}"
            ),
            (v, _) => Ok(v.unwrap_or(0.0)),
        };
        let law = match model {
            Model::Linear => {
                refuse("young", self.young)?;
                refuse("poisson", self.poisson)?;
                refuse("dissipation", self.dissipation)?;
                if self.restitution_speed.is_some() {
                    return invalid!(
                        "material.restitution_speed does not belong to model = \"linear\": \
                         the linear dashpot's restitution is the same at every speed; remove it"
                    );
                }
                ForceLaw::Linear(LinearDashpot::new(
                    need("stiffness", self.stiffness)?,
                    dissipation("damping", self.damping)?,
                )?)
            }
            Model::Hertz => {
                refuse("stiffness", self.stiffness)?;
                refuse("damping", self.damping)?;
                ForceLaw::Hertz(ViscoelasticHertz::new(
                    need("young", self.young)?,
                    need("poisson", self.poisson)?,
                    dissipation("dissipation", self.dissipation)?,
                )?)
            }
        };
        let Some(e) = self.restitution else {
            if self.restitution_speed.is_some() {
                return invalid!(
                    "material.restitution_speed needs material.restitution (or remove it)"
                );
            }
            return Ok(law);
        };
        let speed = match model {
            Model::Linear => 1.0,
            Model::Hertz => self.restitution_speed.ok_or_else(|| {
                SystemError::Invalid(
                    "material.restitution needs material.restitution_speed (m/s) with \
                     model = \"hertz\": the restitution of viscoelastic spheres falls with the \
                     impact speed, so it is matched at one speed"
                        .into(),
                )
            })?,
        };
        let sphere = Sphere::new(reference.radius, reference.mass)?;
        let pair = PairProperties::spheres(&sphere, &sphere);
        emdstar_mor::with_restitution(&law, &pair, speed, e)
            .map_err(|err| SystemError::Invalid(format!("material.restitution: {err}")))
    }

    /// The friction of the material; absent keys mean no friction. Tangential keys
    /// without `friction` are refused (they would have no effect), and so is a material
    /// with both MD's tangential law (`tangential_stiffness`, `tangential_damping`,
    /// `tangential`) and Walton's rule of the event-driven engines
    /// (`tangential_restitution`): each engine runs one of them.
    pub fn friction(&self) -> Result<Friction> {
        if let (Some(mu), Some(b)) = (self.friction, self.tangential_restitution) {
            let md_keys = [
                ("tangential_stiffness", self.tangential_stiffness.is_some()),
                ("tangential_damping", self.tangential_damping.is_some()),
                ("tangential", self.tangential.is_some()),
            ];
            if let Some((name, _)) = md_keys.iter().find(|(_, set)| *set) {
                return invalid!(
                    "material.{name} belongs to force-based MD's tangential law and \
                     material.tangential_restitution to Walton's rule of the event-driven \
                     engines (emd): a material has one or the other; remove one of them"
                );
            }
            return Friction::walton(mu, b)
                .map_err(|e| SystemError::Invalid(format!("material.{e}")));
        }
        let model: TangentialModel = match &self.tangential {
            Some(t) => t
                .parse()
                .map_err(|e| SystemError::Invalid(format!("material.tangential: {e}")))?,
            None => TangentialModel::History,
        };
        let Some(mu) = self.friction else {
            let set = [
                ("tangential_stiffness", self.tangential_stiffness.is_some()),
                ("tangential_damping", self.tangential_damping.is_some()),
                ("tangential", self.tangential.is_some()),
                (
                    "tangential_restitution",
                    self.tangential_restitution.is_some(),
                ),
            ];
            if let Some((name, _)) = set.iter().find(|(_, s)| *s) {
                return invalid!(
                    "material.{name} has no effect without material.friction (Coulomb's µ); \
                     add friction = µ or remove it"
                );
            }
            return Ok(Friction::NONE);
        };
        if model == TangentialModel::Coulomb {
            for (name, v) in [
                ("tangential_stiffness", self.tangential_stiffness),
                ("tangential_damping", self.tangential_damping),
            ] {
                if v.is_some() {
                    return invalid!(
                        "material.{name} does not belong to tangential = \"coulomb\" (pure \
                         sliding has no spring or dashpot); remove it or use \"history\""
                    );
                }
            }
        }
        Friction::new(
            mu,
            self.tangential_stiffness.unwrap_or(0.0),
            self.tangential_damping.unwrap_or(0.0),
            model,
        )
        .map_err(|e| SystemError::Invalid(format!("material.{e}")))
    }

    /// One line saying which dissipation `restitution` gave `law`, for the user; `None`
    /// when the dissipation was given directly.
    pub fn restitution_note(&self, law: &ForceLaw, reference: &Species) -> Option<String> {
        let e = self.restitution?;
        let pair = format!(
            "central impacts of two spheres of radius {} m and mass {:.6e} kg",
            reference.radius, reference.mass
        );
        Some(match law {
            ForceLaw::Linear(l) => format!(
                "material.restitution = {e}: damping = {:.10e} kg/s ({pair})",
                l.damping
            ),
            ForceLaw::Hertz(h) => format!(
                "material.restitution = {e} at {} m/s: dissipation = {:.10e} s ({pair})",
                self.restitution_speed.unwrap_or(f64::NAN),
                h.dissipation
            ),
        })
    }
}

impl BoxConfig {
    fn sim_box(&self) -> Result<SimBox> {
        for k in 0..3 {
            positive(&format!("box.size[{k}]"), self.size[k])?;
        }
        let lo = finite3("box.lo", self.lo)?;
        for k in 0..3 {
            resolvable(k, lo[k], self.size[k])?;
        }
        Ok(SimBox {
            lo,
            size: self.size,
            periodic: self.periodic,
        })
    }
}

/// Positions across the box along axis `k` must be resolved: at least 2²⁴ doubles
/// between its faces (with fewer, cell faces and positions round together and a
/// particle could cross a face without moving).
fn resolvable(k: usize, lo: f64, size: f64) -> Result<()> {
    let far = lo.abs().max((lo + size).abs());
    // The gap to the next double up (NaN where `far` overflowed, which is refused too).
    let spacing = f64::from_bits(far.to_bits() + 1) - far;
    if size / spacing >= f64::from(1u32 << 24) {
        return Ok(());
    }
    invalid!(
        "box.lo[{k}] = {lo:e} is too far from the origin for box.size[{k}] = {size:e}: double \
         precision resolves positions there only to {spacing:.1e} m, fewer than 2^24 steps \
         across the box; move the box nearer the origin (or make it larger)"
    )
}

impl WallConfig {
    fn wall(&self, i: usize) -> Result<Wall> {
        let n = finite3(&format!("walls[{i}].normal"), self.normal)?;
        let point = finite3(&format!("walls[{i}].point"), self.point)?;
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len == 0.0 {
            return invalid!("walls[{i}].normal must not be the zero vector");
        }
        Ok(Wall {
            normal: n.map(|c| c / len),
            point,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(lo: f64, size: f64) -> Result<crate::System> {
        Config::from_toml(&format!(
            "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 55.0\ndensity = 2500.0\n\
             [box]\nlo = [{lo:e}, 0.0, 0.0]\nsize = [{size:e}, 10.0, 10.0]\n\
             [[particles]]\nradius = 0.1\nposition = [{x:e}, 5.0, 5.0]\n",
            x = lo + 0.5 * size
        ))?
        .build()
    }

    #[test]
    fn a_box_too_far_from_the_origin_to_resolve_is_refused() {
        // Found by fuzzing: a box 4000 m wide at x = 2e164 m, where doubles are 3e148 m
        // apart. Its cell faces all rounded to one number and the hybrid's event part
        // crossed them at one instant for ever.
        let err = build(2.066e164, 4000.0).unwrap_err().to_string();
        assert!(
            err.contains("box.lo[0]") && err.contains("nearer the origin"),
            "{err}"
        );
        // 2^24 steps across the box is the bar: 1 m at 1e9 m (0.12 µm apart) is refused,
        // at 1e6 m (0.12 nm apart) it is not.
        assert!(build(1e9, 1.0).is_err());
        build(1e6, 1.0).unwrap();
    }
}
