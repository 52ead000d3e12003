//! Particle state as a structure of arrays, and the species it refers to.

use emdstar_contact::vec3::{cross, norm2};
use emdstar_contact::{SOLID_SPHERE_INERTIA, Sphere};

/// One kind of sphere: every particle of a species has its radius, mass and material.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Species {
    /// Radius in m.
    pub radius: f64,
    /// Mass in kg.
    pub mass: f64,
    /// The material, by its number in [`crate::Interactions`] (0 with one material).
    #[serde(default)]
    pub material: u32,
}

impl Species {
    /// A species of the first (or only) material.
    pub const fn new(radius: f64, mass: f64) -> Self {
        Self {
            radius,
            mass,
            material: 0,
        }
    }

    /// The sphere of the pair physics.
    pub fn sphere(&self) -> Sphere {
        Sphere {
            radius: self.radius,
            mass: self.mass,
        }
    }
}

/// Particle state, one array per field (structure of arrays).
///
/// `radius` and `mass` duplicate the species' values so that engines read them
/// without an indirection; [`Particles::push`] keeps them consistent. `id` is the
/// particle's number in the config (engines may reorder particles for locality and use
/// it to report in the original order). `angular_velocity` is in rad/s; every particle
/// is a solid sphere, I = (2/5) m R². `image` counts the periodic crossings of each
/// particle (HOOMD's and LAMMPS's image flags): its unwrapped position is
/// `position + image · box size` along periodic axes.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "ParticleColumns")]
pub struct Particles {
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
    pub angular_velocity: Vec<[f64; 3]>,
    pub species: Vec<u32>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub id: Vec<u32>,
    pub image: Vec<[i32; 3]>,
}

/// [`Particles`] as decoded, before the check that makes them particles.
#[derive(serde::Deserialize)]
struct ParticleColumns {
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
    species: Vec<u32>,
    radius: Vec<f64>,
    mass: Vec<f64>,
    id: Vec<u32>,
    image: Vec<[i32; 3]>,
}

impl TryFrom<ParticleColumns> for Particles {
    type Error = String;

    /// Decoded particles (a checkpoint's) need one entry per particle in every column
    /// and each number `0..n` once in `id`.
    fn try_from(c: ParticleColumns) -> Result<Self, String> {
        let n = c.position.len();
        let lengths = [
            c.velocity.len(),
            c.angular_velocity.len(),
            c.species.len(),
            c.radius.len(),
            c.mass.len(),
            c.id.len(),
            c.image.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Err(format!(
                "particle columns of {lengths:?} entries for {n} positions"
            ));
        }
        let mut seen = vec![false; n];
        for &id in &c.id {
            if id as usize >= n || std::mem::replace(&mut seen[id as usize], true) {
                return Err(format!("particle number {id} is out of range or repeated"));
            }
        }
        Ok(Self {
            position: c.position,
            velocity: c.velocity,
            angular_velocity: c.angular_velocity,
            species: c.species,
            radius: c.radius,
            mass: c.mass,
            id: c.id,
            image: c.image,
        })
    }
}

impl Particles {
    /// Whether `self` holds the bodies of `other` (each particle number with the same
    /// species, radius and mass), in any order: a decoded state against the config's.
    pub fn same_bodies(&self, other: &Particles) -> bool {
        let n = other.len();
        let mut at = vec![usize::MAX; n];
        for (k, &id) in other.id.iter().enumerate() {
            match at.get_mut(id as usize) {
                Some(slot) => *slot = k,
                None => return false,
            }
        }
        self.len() == n
            && self.id.iter().enumerate().all(|(k, &id)| {
                let Some(&b) = at.get(id as usize).filter(|&&b| b != usize::MAX) else {
                    return false;
                };
                self.species[k] == other.species[b]
                    && self.radius[k].to_bits() == other.radius[b].to_bits()
                    && self.mass[k].to_bits() == other.mass[b].to_bits()
            })
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True if there are no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Particles from one column per field, numbered in order (`id` = 0, 1, …). Errors
    /// unless every column has one entry per position.
    pub fn from_columns(
        position: Vec<[f64; 3]>,
        velocity: Vec<[f64; 3]>,
        radius: Vec<f64>,
        mass: Vec<f64>,
        species: Vec<u32>,
    ) -> crate::Result<Self> {
        let n = position.len();
        let lens = [velocity.len(), radius.len(), mass.len(), species.len()];
        if lens.iter().any(|&l| l != n) {
            return Err(crate::SystemError::Invalid(format!(
                "position, velocity, radius, mass and species need one entry per particle; \
                 got {n}, {}, {}, {} and {}",
                lens[0], lens[1], lens[2], lens[3]
            )));
        }
        Ok(Self {
            position,
            velocity,
            angular_velocity: vec![[0.0; 3]; n],
            species,
            radius,
            mass,
            id: (0..n as u32).collect(),
            image: vec![[0; 3]; n],
        })
    }

    /// Appends a particle of species number `species_index` (see `species`), without
    /// spin.
    pub fn push(
        &mut self,
        species: &[Species],
        species_index: u32,
        position: [f64; 3],
        velocity: [f64; 3],
    ) {
        let s = species[species_index as usize];
        self.id.push(self.position.len() as u32);
        self.position.push(position);
        self.velocity.push(velocity);
        self.angular_velocity.push([0.0; 3]);
        self.species.push(species_index);
        self.radius.push(s.radius);
        self.mass.push(s.mass);
        self.image.push([0; 3]);
    }

    /// Reorders every array so that new index k holds old particle `order[k]`.
    pub fn permute(&mut self, order: &[u32]) {
        permute(&mut self.position, order);
        permute(&mut self.velocity, order);
        permute(&mut self.angular_velocity, order);
        permute(&mut self.species, order);
        permute(&mut self.radius, order);
        permute(&mut self.mass, order);
        permute(&mut self.id, order);
        permute(&mut self.image, order);
    }

    /// The unwrapped position of particle `i` in `sim_box` (its position where there is
    /// no box).
    pub fn unwrapped(&self, i: usize, sim_box: Option<&crate::SimBox>) -> [f64; 3] {
        let x = self.position[i];
        match sim_box {
            Some(b) => std::array::from_fn(|k| x[k] + f64::from(self.image[i][k]) * b.size[k]),
            None => x,
        }
    }

    /// Total mass Σm in kg.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Total momentum Σ m v in kg m/s.
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for (m, v) in self.mass.iter().zip(&self.velocity) {
            for k in 0..3 {
                p[k] += m * v[k];
            }
        }
        p
    }

    /// Kinetic energy Σ ½ m v² in J.
    pub fn kinetic_energy(&self) -> f64 {
        self.mass
            .iter()
            .zip(&self.velocity)
            .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
            .sum()
    }

    /// The moment of inertia of particle `i` in kg m², (2/5) m R² (a solid sphere).
    #[inline]
    pub fn inertia(&self, i: usize) -> f64 {
        SOLID_SPHERE_INERTIA * self.mass[i] * self.radius[i] * self.radius[i]
    }

    /// Rotational kinetic energy Σ ½ I ω² in J.
    pub fn rotational_energy(&self) -> f64 {
        (0..self.len())
            .map(|i| 0.5 * self.inertia(i) * norm2(self.angular_velocity[i]))
            .sum()
    }

    /// Total angular momentum about the origin, Σ m x × v + I ω, in kg m²/s.
    pub fn angular_momentum(&self) -> [f64; 3] {
        let mut l = [0.0; 3];
        for i in 0..self.len() {
            let orbital = cross(self.position[i], self.velocity[i]);
            let spin = self.angular_velocity[i];
            for k in 0..3 {
                l[k] += self.mass[i] * orbital[k] + self.inertia(i) * spin[k];
            }
        }
        l
    }

    /// Rotational temperature T_rot = Σ I ω² / (3N) in J: the rotational kinetic energy
    /// is (3/2) N T_rot (Brilliantov & Pöschel, Kinetic Theory of Granular Gases, with
    /// k_B = 1; three rotational degrees of freedom per sphere).
    pub fn rotational_temperature(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        2.0 * self.rotational_energy() / (3.0 * self.len() as f64)
    }

    /// Granular temperature T = Σ m |v − V|² / (3N) in J, with V the centre-of-mass
    /// velocity (Brilliantov & Pöschel, Kinetic Theory of Granular Gases, Eq. 1.2 with
    /// k_B = 1): the kinetic energy of the peculiar motion is (3/2) N T.
    pub fn granular_temperature(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let p = self.momentum();
        let m = self.total_mass();
        let v_cm = [p[0] / m, p[1] / m, p[2] / m];
        let sum: f64 = self
            .mass
            .iter()
            .zip(&self.velocity)
            .map(|(m, v)| {
                let d = [v[0] - v_cm[0], v[1] - v_cm[1], v[2] - v_cm[2]];
                m * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            })
            .sum();
        sum / (3.0 * self.len() as f64)
    }
}

/// Reorders `v` so that new index k holds old element `order[k]`.
pub fn permute<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
    debug_assert_eq!(v.len(), order.len());
    let old = std::mem::take(v);
    v.extend(order.iter().map(|&i| old[i as usize]));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoded_particles_need_whole_columns_and_each_number_once() {
        let whole = Particles::from_columns(
            vec![[0.0; 3], [1.0; 3], [2.0; 3]],
            vec![[0.5; 3]; 3],
            vec![0.1; 3],
            vec![1.0; 3],
            vec![0; 3],
        )
        .unwrap();
        let decode =
            |p: &Particles| postcard::from_bytes::<Particles>(&postcard::to_allocvec(p).unwrap());
        assert_eq!(decode(&whole).unwrap(), whole);
        let mut short = whole.clone();
        short.angular_velocity.pop();
        // (postcard keeps no message: the caller says the state cannot be read.)
        assert!(decode(&short).is_err());
        let mut repeated = whole.clone();
        repeated.id[2] = 0;
        assert!(decode(&repeated).is_err());
        let mut beyond = whole;
        beyond.id[2] = 3;
        assert!(decode(&beyond).is_err());
    }

    #[test]
    fn temperature_ignores_the_centre_of_mass_motion() {
        let species = [Species::new(0.1, 2.0)];
        let mut p = Particles::default();
        p.push(&species, 0, [0.0; 3], [1.0, 0.0, 0.0]);
        p.push(&species, 0, [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]);
        // V = 2, peculiar speeds ±1: T = (2 + 2)/(3·2).
        assert!((p.granular_temperature() - 4.0 / 6.0).abs() < 1e-15);
        assert_eq!(p.momentum(), [8.0, 0.0, 0.0]);
        assert_eq!(p.kinetic_energy(), 10.0);
        assert_eq!(p.rotational_energy(), 0.0);
        // I = 0.4·2·0.01 = 0.008 kg m²: ½ I ω² = 0.016 J, T_rot = 2·0.016/6.
        p.angular_velocity[1] = [0.0, 0.0, 2.0];
        assert!((p.rotational_energy() - 0.016).abs() < 1e-15);
        assert!((p.rotational_temperature() - 0.032 / 6.0).abs() < 1e-15);
        // L = m x × v + I ω: particle 1 at x = (1, 0, 0) moves along x, so only its spin counts.
        assert!((p.angular_momentum()[2] - 0.016).abs() < 1e-15);
        p.permute(&[1, 0]);
        assert_eq!(p.id, vec![1, 0]);
        assert_eq!(p.angular_velocity[0], [0.0, 0.0, 2.0]);
        assert_eq!(p.velocity[0], [3.0, 0.0, 0.0]);
    }
}
