//! The TOML config shared by all engines.
//!
//! ```toml
//! t_end = 0.5                      # s
//! gravity = [0.0, 0.0, -9.81]      # m/s², optional (default none)
//! [material]                       # one material for everything (or [[materials]])
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
//! # [[materials]]                  # several materials, each with a name and the keys
//! # name = "glass"                 # of [material]; particles, gas species and walls
//! # ...                            # then say material = "glass"
//! # [[interactions]]               # optional: the constants of one pair of materials
//! # materials = ["glass", "steel"]
//! # restitution = 0.7              # (keys as in a material, without name and density)
//! [[particles]]                    # an explicit list ...
//! radius = 0.1
//! position = [0.03, -0.5, 0.0]
//! velocity = [1.25, 2.5, 0.0]      # optional, default at rest
//! # angular_velocity = [0.0, 0.0, 10.0] # rad/s, optional, default no spin
//! # mass = 4.0                     # optional, overrides the density
//! # material = "glass"             # with [[materials]]
//! # [gas]                          # ... or a generated gas
//! # count = 32768
//! # radius = 0.1
//! # arrangement = "lattice"        # or "fcc" (count = 4n³), "random" (non-overlapping)
//! # packing_fraction = 0.01        # sizes a cubic periodic box (omit [box] then)
//! # rms_speed = 1.0                # m/s, √⟨v²⟩, Maxwell, zero total momentum
//! # seed = 1
//! # [[gas.species]]                # a mixture, instead of radius (and mass, material)
//! # material = "glass"
//! # radius = 0.1
//! # fraction = 0.5                 # of the count
//! # [initial]                      # ... or a state read from a file (GSD, extended
//! # file = "packing.gsd"           # XYZ or LAMMPS data; see docs/config.md)
//! # frame = -1                     # the last (GSD, XYZ)
//! # types = { 1 = "glass" }        # the material of each type of the file
//! # [box]                          # absent: free space
//! # size = [2.0, 2.0, 2.0]
//! # lo = [-1.0, -1.0, -1.0]        # default [0, 0, 0]
//! # periodic = [true, true, false] # default all periodic
//! # shear_rate = 0.1               # 1/s: Lees–Edwards shear, x flow, y gradient
//! # [[walls]]
//! # normal = [0.0, 0.0, 1.0]       # towards the particles
//! # point = [0.0, 0.0, -1.0]
//! # material = "steel"             # with [[materials]]
//! # amplitude = 1e-3               # m: a vibrated wall, A sin(2π f t + φ) along the
//! # frequency = 50.0               # Hz  normal
//! # phase = 0.0                    # rad (default 0)
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
//! # [events]                       # options of the event-driven engines (emd, emdstar)
//! # tc = 1e-5                      # s: the TC model (Luding & McNamara 1998)
//! ```
//!
//! Engines own their optional sections (`[md]`, `[events]`); the rest describes the
//! physical system and is engine-independent. Every value is checked whatever the
//! engine; a message about a value gives its line ([`KeyLines`]).

use crate::domain::Domain;
pub use crate::domain_config::{BoxConfig, WallConfig};
use crate::error::{
    Result, SystemError, finite3, invalid, num, positive, representable_energy, representable_spin,
};
use crate::gas::{self, GasConfig};
use crate::geometry::SimBox;
use crate::initial::InitialConfig;
use crate::interactions::Interactions;
use crate::key_lines::KeyLines;
use crate::material_config::{InteractionConfig, MaterialConfig, names};
use crate::materials::MaterialTable;
use crate::state::{Particles, Species};
use crate::system::System;
use crate::vibration::vibrated_walls_fit;
use emdstar_contact::Sphere;
use serde::{Deserialize, Serialize};

/// The whole config file.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// End time in s.
    pub t_end: f64,
    /// Uniform acceleration in m/s².
    pub gravity: Option<[f64; 3]>,
    /// One material for every particle and wall (or `materials`).
    pub material: Option<MaterialConfig>,
    /// Several named materials.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<MaterialConfig>,
    /// The constants of pairs of materials, where given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub interactions: Vec<InteractionConfig>,
    #[serde(default)]
    pub particles: Vec<ParticleConfig>,
    pub gas: Option<GasConfig>,
    /// The initial state from a file (instead of `particles` or `gas`).
    pub initial: Option<InitialConfig>,
    #[serde(rename = "box")]
    pub sim_box: Option<BoxConfig>,
    #[serde(default)]
    pub walls: Vec<WallConfig>,
    pub output: Option<OutputConfig>,
    /// Options of the force-based engine (see `emdstar-dem`).
    pub md: Option<MdConfig>,
    /// Options of the event-driven engines (see `emdstar-edmd`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub events: Option<EventsConfig>,
    /// Where each value of the text is (empty for a config not read from text).
    #[serde(skip)]
    pub keys: KeyLines,
    /// The directory of the config file, against which `initial.file` is read (the
    /// working directory when `None`).
    #[serde(skip)]
    pub dir: Option<std::path::PathBuf>,
    /// A thermostat feeding energy at regular ticks (see [`crate::Drive`]).
    pub driving: Option<crate::driving::DrivingConfig>,
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
    /// The material's name (required with several materials).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

fn is_zero(v: &[f64; 3]) -> bool {
    *v == [0.0; 3]
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

/// `[events]`: options of the event-driven engines (emd, emdstar).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EventsConfig {
    /// The TC model's t_c in s (Luding & McNamara 1998): a particle's collisions within
    /// t_c of its previous one are elastic. Default none.
    pub tc: Option<f64>,
}

impl Config {
    /// The largest config file read (1 GiB: ten million `[[particles]]` entries).
    pub const MAX_BYTES: u64 = 1 << 30;

    /// Parses TOML text; unknown keys are errors.
    pub fn from_toml(text: &str) -> Result<Self> {
        let mut config: Self = crate::parse::from_toml(text)?;
        config.keys = KeyLines::of(text);
        config.check_options().map_err(|e| config.locate(e))?;
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
        let mut config = Self::from_toml(&text)?;
        config.dir = path.parent().map(std::path::Path::to_path_buf);
        Ok(config)
    }

    /// A digest of the physical system the config describes (everything but `t_end`
    /// and `[output]`): a checkpoint records it, and a run resumed from it under
    /// another config is refused.
    pub fn digest(&self) -> u64 {
        let physics = Self {
            t_end: 0.0,
            output: None,
            keys: KeyLines::default(),
            ..self.clone()
        };
        let text = toml::to_string(&physics).expect("a parsed config serialises");
        u64::from(crc32fast::hash(text.as_bytes())) | (text.len() as u64) << 32
    }

    /// The materials and `[[interactions]]` entries, checked: `[material]` or
    /// `[[materials]]` (not both), unique names, entries naming known materials once.
    pub fn material_table(&self) -> Result<MaterialTable> {
        let mut table = MaterialTable::default();
        match (&self.material, self.materials.is_empty()) {
            (Some(_), false) => {
                return invalid!(
                    "give either [material] (one material for everything) or [[materials]] \
                     (several, each with a name), not both"
                );
            }
            (None, true) => {
                return invalid!(
                    "no material: add a [material] section (or [[materials]] entries with a \
                     name each)"
                );
            }
            (Some(m), true) => table.materials.push(m.material("material")?),
            (None, false) => {
                for (i, m) in self.materials.iter().enumerate() {
                    let key = format!("materials[{i}]");
                    let Some(name) = &m.name else {
                        return invalid!(
                            "{key}.name is missing: every [[materials]] entry needs a name, \
                             which particles, gas species and walls give as material = \"…\""
                        );
                    };
                    if name.trim().is_empty() {
                        return invalid!("{key}.name must not be empty");
                    }
                    if table.materials.iter().any(|t| &t.name == name) {
                        return invalid!(
                            "{key}.name = \"{name}\" is given twice: material names must be \
                             unique"
                        );
                    }
                    table.materials.push(m.material(&key)?);
                }
            }
        }
        for (i, e) in self.interactions.iter().enumerate() {
            let key = format!("interactions[{i}]");
            let entry = e.entry(&key, &table)?;
            let [a, b] = entry.materials;
            if let Some(other) = table
                .entries
                .iter()
                .find(|o| o.materials == [a, b] || o.materials == [b, a])
            {
                return invalid!(
                    "{key} gives the pair of \"{}\" and \"{}\" again ({} gives it already): \
                     give each pair of materials once",
                    e.materials[0],
                    e.materials[1],
                    other.key
                );
            }
            table.entries.push(entry);
        }
        Ok(table)
    }

    /// `t_end` and the engines' sections, whatever the engine: a bad value is refused
    /// even by an engine that does not use it.
    fn check_options(&self) -> Result<()> {
        positive("t_end", self.t_end)?;
        if let Some(md) = &self.md {
            if let Some(dt) = md.dt {
                positive("md.dt", dt)?;
            }
            if let Some(skin) = md.skin
                && !(skin.is_finite() && skin >= 0.0)
            {
                return invalid!("md.skin = {} must be a finite number ≥ 0 (m)", num(skin));
            }
        }
        if let Some(tc) = self.events.as_ref().and_then(|e| e.tc) {
            positive("events.tc", tc)?;
        }
        Ok(())
    }

    /// `e` with the line of the key it names, where the text sets it.
    pub fn locate(&self, e: SystemError) -> SystemError {
        match e {
            SystemError::Invalid(m) => SystemError::Invalid(self.keys.locate(&m)),
            e => e,
        }
    }

    /// Builds and validates the system the config describes.
    pub fn build(&self) -> Result<System> {
        self.build_system().map_err(|e| self.locate(e))
    }

    fn build_system(&self) -> Result<System> {
        let gravity = finite3("gravity", self.gravity.unwrap_or([0.0; 3]))?;
        let table = self.material_table()?;
        let mut walls = Vec::with_capacity(self.walls.len());
        let mut wall_materials = Vec::with_capacity(self.walls.len());
        for (i, w) in self.walls.iter().enumerate() {
            walls.push(w.wall(i)?);
            wall_materials.push(material_index(&table, &format!("walls[{i}]"), &w.material)?);
        }
        let mut sim_box = self.sim_box.as_ref().map(BoxConfig::sim_box).transpose()?;
        let mut species = Vec::new();
        let mut particles = Particles::default();
        let sources = [
            (!self.particles.is_empty()).then_some("[[particles]]"),
            self.gas.as_ref().map(|_| "[gas]"),
            self.initial.as_ref().map(|_| "[initial]"),
        ];
        let given: Vec<&str> = sources.into_iter().flatten().collect();
        if given.len() > 1 {
            return invalid!(
                "give either [[particles]] or [gas] or an [initial] file, not {}",
                given.join(" and ")
            );
        }
        let mut add = |what: &str, p: Inline, particles: &mut Particles| -> Result<()> {
            let s = species_of(&table, what, p.radius, p.mass, p.material)?;
            let index = species_index(&mut species, s);
            let x = finite3(&format!("{what}.position"), p.position)?;
            let v = finite3(&format!("{what}.velocity"), p.velocity)?;
            representable_energy(&format!("{what}.velocity"), s.mass, v)?;
            let w = finite3(&format!("{what}.angular_velocity"), p.angular_velocity)?;
            particles.push(&species, index, x, v);
            let i = particles.len() - 1;
            particles.angular_velocity[i] =
                representable_spin(&format!("{what}.angular_velocity"), particles.inertia(i), w)?;
            particles.image[i] = p.image;
            Ok(())
        };
        match (&self.gas, &self.initial) {
            _ if given.is_empty() => {
                return invalid!(
                    "no particles: add [[particles]] entries, a [gas] section or an [initial] \
                     file"
                );
            }
            (None, None) => {
                for (i, pc) in self.particles.iter().enumerate() {
                    let what = format!("particles[{i}]");
                    let material = material_index(&table, &what, &pc.material)?;
                    let p = Inline {
                        radius: pc.radius,
                        mass: pc.mass,
                        material,
                        position: pc.position,
                        velocity: pc.velocity,
                        angular_velocity: pc.angular_velocity,
                        image: [0; 3],
                    };
                    add(&what, p, &mut particles)?;
                }
            }
            (None, Some(init)) => {
                let file = init.read(self.dir.as_deref())?;
                if sim_box.is_none() {
                    sim_box = file.sim_box;
                }
                let path = init.path(self.dir.as_deref());
                for (i, row) in file.rows.into_iter().enumerate() {
                    let what = format!("{} particle {i}", path.display());
                    let material = init.material_of(&table, &what, &row.type_name)?;
                    let image = match &sim_box {
                        Some(b) => image_flags(&what, b, row.image)?,
                        None => [0; 3],
                    };
                    let p = Inline {
                        radius: row.radius,
                        mass: row.mass,
                        material,
                        position: row.position,
                        velocity: row.velocity,
                        angular_velocity: row.angular_velocity,
                        image,
                    };
                    add(&what, p, &mut particles)?;
                }
                if let Some(b) = &sim_box {
                    // Positions just outside a periodic box (LAMMPS keeps some there)
                    // wrapped in, counted in the image flags.
                    // (Positions inside stay as read, to the bit.)
                    let hi = b.hi();
                    for (x, image) in particles.position.iter_mut().zip(&mut particles.image) {
                        if (0..3).any(|k| b.periodic[k] && !(b.lo[k] <= x[k] && x[k] < hi[k])) {
                            *x = b.wrap_counting(*x, image);
                        }
                    }
                }
            }
            (Some(gas), _) => {
                let kinds = gas.kinds(|what, radius, mass, material| {
                    let m = material_index(&table, what, material)?;
                    species_of(&table, what, radius, mass, m)
                })?;
                species = kinds.iter().map(|k| k.species).collect();
                let b = match (sim_box, gas.packing_fraction) {
                    (Some(_), Some(_)) => {
                        return invalid!(
                            "gas.packing_fraction sizes a cubic periodic box, so it cannot be \
                             combined with [box]; drop one of them"
                        );
                    }
                    (Some(b), None) => b,
                    (None, Some(eta)) => gas::cubic_box_of(&kinds, eta)?,
                    (None, None) => {
                        return invalid!("a [gas] needs a [box] or a gas.packing_fraction");
                    }
                };
                sim_box = Some(b);
                gas::generate_gas(gas, &kinds, &species, &b, &mut particles)?;
            }
        }
        let smallest = particles
            .radius
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        vibrated_walls_fit(&walls, sim_box.as_ref(), smallest)?;
        let interactions = Interactions::build(&table, &species, &wall_materials)?;
        let shear_rate = match &self.sim_box {
            Some(b) => b.shear_rate(gravity)?,
            None => 0.0,
        };
        if let (Some(_), Some(b)) = (&self.gas, &sim_box)
            && shear_rate != 0.0
        {
            // A generated gas starts in the steady shear flow: its Maxwell velocities
            // are the peculiar ones, the streaming profile added.
            crate::LeesEdwards::new(b, -shear_rate).peculiar(&mut particles);
        }
        let system = System {
            particles,
            species,
            interactions,
            domain: Domain {
                sim_box,
                walls,
                gravity,
                shear_rate,
            },
        };
        system.validate()?;
        system.check_contacts(self.t_end)?;
        Ok(system)
    }
}

/// One particle as `[[particles]]` or a file gives it, its material known.
struct Inline {
    radius: f64,
    mass: Option<f64>,
    material: u32,
    position: [f64; 3],
    velocity: [f64; 3],
    angular_velocity: [f64; 3],
    image: [i32; 3],
}

/// A file's image flags, which must be 0 along the closed axes of `b`.
fn image_flags(what: &str, b: &SimBox, image: [i32; 3]) -> Result<[i32; 3]> {
    match (0..3).find(|&k| !b.periodic[k] && image[k] != 0) {
        Some(k) => invalid!(
            "{what} has image flag {} along {}, but the box is closed there: image flags \
             count crossings of periodic faces (set them to 0, or make the axis periodic)",
            image[k],
            ["x", "y", "z"][k]
        ),
        None => Ok(image),
    }
}

/// The material `name` names for `what` (a particle, gas species or wall): required
/// with several materials, the one material otherwise.
fn material_index(table: &MaterialTable, what: &str, name: &Option<String>) -> Result<u32> {
    match name {
        None if table.materials.len() == 1 => Ok(0),
        None => invalid!(
            "{what}.material is missing: with several [[materials]] ({}) each particle, gas \
             species and wall names its own, e.g. material = \"{}\"",
            names(table),
            table.materials[0].name
        ),
        Some(name) => match table.materials.iter().position(|m| &m.name == name) {
            Some(i) => Ok(i as u32),
            None => invalid!(
                "{what}.material = \"{name}\" is no material of this config; the materials are \
                 {}",
                names(table)
            ),
        },
    }
}

/// The species of a sphere of `material` given by radius and either its own mass or
/// the material's density.
fn species_of(
    table: &MaterialTable,
    what: &str,
    radius: f64,
    mass: Option<f64>,
    material: u32,
) -> Result<Species> {
    positive(&format!("{what}.radius"), radius)?;
    let m = &table.materials[material as usize];
    let sphere = match (mass, m.density) {
        (Some(mass), _) => {
            let sphere = Sphere::new(radius, positive(&format!("{what}.mass"), mass)?)?;
            representable_mass(&sphere, &format!("{what}.mass"), mass, "kg")?;
            sphere
        }
        (None, Some(rho)) => {
            // Blame the radius where a sphere of it would weigh too much even of water.
            let water = Sphere::from_density(radius, 1000.0)?;
            if representable_mass(&water, "", 0.0, "").is_err() {
                return invalid!(
                    "{what}.radius = {radius:e} m is out of range: a sphere of it would weigh \
                     {:.3e} kg even of water's density, and double precision cannot hold the \
                     products of masses and radii every engine forms; give a radius of a \
                     physical size",
                    water.mass
                );
            }
            let sphere = Sphere::from_density(radius, rho)?;
            representable_mass(&sphere, &format!("{}.density", m.key), rho, "kg/m³")?;
            sphere
        }
        (None, None) => {
            return invalid!("{what} has no mass: set {}.density or {what}.mass", m.key);
        }
    };
    Ok(Species {
        radius: sphere.radius,
        mass: sphere.mass,
        material,
    })
}

/// A sphere's mass is representable where products of two masses (the reduced mass
/// m₁m₂/(m₁+m₂)) and the moment of inertia (2/5)mR² are normal doubles.
fn representable_mass(sphere: &Sphere, key: &str, value: f64, unit: &str) -> Result<()> {
    let (m, r) = (sphere.mass, sphere.radius);
    if (m * m).is_normal() && (0.4 * m * r * r).is_normal() {
        return Ok(());
    }
    invalid!(
        "{key} = {value:e} {unit} is out of range: it gives a sphere of radius {r:e} m the mass \
         {m:.3e} kg, \
         which double precision cannot hold with the products of masses every engine forms; \
         give it a physical size"
    )
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
