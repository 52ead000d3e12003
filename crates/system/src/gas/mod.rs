//! Generated gases (`[gas]` of the config): lattice, fcc or random placement, Maxwell
//! velocities.

use crate::domain::Domain;
use crate::error::{Result, invalid, positive};
use crate::geometry::SimBox;
use crate::state::{Particles, Species};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

mod placement;
use placement::{fcc, lattice, maxwell_velocities, random_placement};

/// How a generated gas is placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Arrangement {
    /// Simple cubic lattice filling the box.
    Lattice,
    /// Face-centred cubic lattice of `count` = 4n³ sites, n unit cells per axis.
    Fcc,
    /// Uniformly random, without overlaps (random sequential addition).
    #[default]
    Random,
}

/// `[gas]`: `count` spheres with Maxwell velocities: equal spheres of `radius` (and
/// `mass`, `material`), or a mixture of `species`.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GasConfig {
    pub count: usize,
    pub radius: Option<f64>,
    pub mass: Option<f64>,
    /// The material's name (required with several materials).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// A mixture: each kind of sphere with its share of `count`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub species: Vec<GasSpeciesConfig>,
    pub arrangement: Arrangement,
    pub packing_fraction: Option<f64>,
    /// Root-mean-square speed √⟨v²⟩ in m/s.
    pub rms_speed: f64,
    #[serde(default)]
    pub seed: u64,
}

/// One `[[gas.species]]` entry: a kind of sphere of a mixture.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GasSpeciesConfig {
    pub radius: f64,
    pub mass: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// The share of the gas's `count`, in (0, 1]; the fractions add up to 1.
    pub fraction: f64,
}

/// A kind of sphere of a gas and how many there are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GasKind {
    pub species: Species,
    pub count: usize,
}

/// The densest packing fraction of equal spheres, π/(3√2) (Kepler; Hales 2005).
const CLOSE_PACKING: f64 = 0.740_480_489_693_061;
/// The cubic periodic box holding `count` spheres of radius `radius` at packing
/// fraction η = N·(4/3)πR³/V.
pub fn cubic_box(count: usize, radius: f64, eta: f64) -> Result<SimBox> {
    positive("gas.radius", radius)?;
    box_of_volume(count as f64 * 4.0 / 3.0 * PI * radius.powi(3), eta, count)
}

/// The cubic periodic box holding the spheres of `kinds` at packing fraction
/// η = Σ N (4/3)πR³/V.
pub fn cubic_box_of(kinds: &[GasKind], eta: f64) -> Result<SimBox> {
    if let [one] = kinds {
        return cubic_box(one.count, one.species.radius, eta);
    }
    let volume = kinds
        .iter()
        .map(|k| k.count as f64 * 4.0 / 3.0 * PI * k.species.radius.powi(3))
        .sum();
    box_of_volume(volume, eta, kinds.iter().map(|k| k.count).sum())
}

/// The cube in which `count` spheres of total volume `spheres` (m³) fill the fraction
/// `eta`.
fn box_of_volume(spheres: f64, eta: f64, count: usize) -> Result<SimBox> {
    if !(eta > 0.0 && eta < CLOSE_PACKING) {
        return invalid!(
            "gas.packing_fraction = {eta} is impossible: it must lie in (0, {CLOSE_PACKING:.4}) \
             (close packing)"
        );
    }
    let side = (spheres / eta).cbrt();
    if !(side.is_finite() && side > 0.0) {
        return invalid!(
            "gas.packing_fraction = {eta:e} with {count} spheres of {spheres:e} m³ in all gives \
             a box side of {side:e} m, which double precision cannot hold; give a packing \
             fraction and radii of a physical size"
        );
    }
    Ok(SimBox {
        lo: [0.0; 3],
        size: [side; 3],
        periodic: [true; 3],
    })
}

impl GasConfig {
    /// The kinds of sphere of this gas: one of `radius` (`mass`, `material`), or the
    /// `species`, each made a [`Species`] by `species_of(what, radius, mass, material)`
    /// with its count (the fractions of `count`, rounded so that they add up to it).
    pub fn kinds(
        &self,
        mut species_of: impl FnMut(&str, f64, Option<f64>, &Option<String>) -> Result<Species>,
    ) -> Result<Vec<GasKind>> {
        if self.count == 0 {
            return invalid!("gas.count must be at least 1");
        }
        if self.species.is_empty() {
            let Some(radius) = self.radius else {
                return invalid!(
                    "gas.radius is missing: give the spheres' radius (or a mixture as \
                     [[gas.species]] entries, each with radius, material and fraction)"
                );
            };
            let species = species_of("gas", radius, self.mass, &self.material)?;
            return Ok(vec![GasKind {
                species,
                count: self.count,
            }]);
        }
        for (key, set) in [
            ("radius", self.radius.is_some()),
            ("mass", self.mass.is_some()),
            ("material", self.material.is_some()),
        ] {
            if set {
                return invalid!(
                    "gas.{key} and [[gas.species]] exclude each other: give the {key} of each \
                     species in its entry"
                );
            }
        }
        let mut kinds = Vec::with_capacity(self.species.len());
        let mut total = 0.0;
        for (i, s) in self.species.iter().enumerate() {
            let what = format!("gas.species[{i}]");
            if !(s.fraction > 0.0 && s.fraction <= 1.0) {
                return invalid!("{what}.fraction = {} must lie in (0, 1]", s.fraction);
            }
            total += s.fraction;
            let species = species_of(&what, s.radius, s.mass, &s.material)?;
            if kinds.iter().any(|k: &GasKind| k.species == species) {
                return invalid!(
                    "{what} repeats the radius, mass and material of an earlier species; merge \
                     their fractions"
                );
            }
            kinds.push(GasKind { species, count: 0 });
        }
        if (total - 1.0).abs() > 1e-9 {
            return invalid!(
                "the fractions of [[gas.species]] add up to {total}, not 1; give each species \
                 its share of gas.count"
            );
        }
        // Largest remainders: the counts add up to `count` and each is within one of
        // fraction·count.
        let exact: Vec<f64> = self
            .species
            .iter()
            .map(|s| s.fraction / total * self.count as f64)
            .collect();
        for (k, x) in kinds.iter_mut().zip(&exact) {
            k.count = x.floor() as usize;
        }
        let mut order: Vec<usize> = (0..kinds.len()).collect();
        order.sort_by(|&a, &b| {
            (exact[b] - exact[b].floor()).total_cmp(&(exact[a] - exact[a].floor()))
        });
        let assigned: usize = kinds.iter().map(|k| k.count).sum();
        for &k in order.iter().take(self.count - assigned) {
            kinds[k].count += 1;
        }
        Ok(kinds)
    }

    /// The particles of this gas of one kind of sphere, `species[0]`, in `sim_box`,
    /// with Maxwell velocities of zero total momentum and root-mean-square speed
    /// `rms_speed`, reproducibly from `seed` (ChaCha8).
    pub fn generate(&self, species: &[Species], sim_box: &SimBox) -> Result<Particles> {
        let kinds = [GasKind {
            species: species[0],
            count: self.count,
        }];
        let mut particles = Particles::default();
        generate_gas(self, &kinds, species, sim_box, &mut particles)?;
        Ok(particles)
    }
}

/// `4·cells³` equal spheres of `radius` and `mass` on an fcc lattice filling a periodic
/// cube at packing fraction `eta`, with Maxwell velocities of root-mean-square speed
/// `rms_speed` and zero total momentum (seeded): the standard start of hard-sphere
/// benchmarks (Bannerman et al. 2014, Sec. 6).
pub fn fcc_gas(
    cells: usize,
    eta: f64,
    radius: f64,
    mass: f64,
    rms_speed: f64,
    seed: u64,
) -> Result<(Particles, Domain)> {
    let gas = GasConfig {
        count: 4 * cells * cells * cells,
        radius: Some(radius),
        mass: Some(mass),
        arrangement: Arrangement::Fcc,
        packing_fraction: Some(eta),
        rms_speed,
        seed,
        ..GasConfig::default()
    };
    positive("mass", mass)?;
    let sim_box = cubic_box(gas.count, radius, eta)?;
    let particles = gas.generate(&[Species::new(radius, mass)], &sim_box)?;
    Ok((particles, Domain::periodic(sim_box)))
}

/// Places the spheres of `kinds` (species numbered as in `species`) in `sim_box` and
/// gives them Maxwell velocities with zero total momentum and root-mean-square speed
/// `gas.rms_speed`, at one temperature for every kind, reproducibly from `gas.seed`
/// (ChaCha8). A mixture is placed largest spheres first (random placement) or spread
/// over the sites at random (lattices).
pub(crate) fn generate_gas(
    gas: &GasConfig,
    kinds: &[GasKind],
    species: &[Species],
    sim_box: &SimBox,
    particles: &mut Particles,
) -> Result<()> {
    let count: usize = kinds.iter().map(|k| k.count).sum();
    if count == 0 {
        return invalid!("gas.count must be at least 1");
    }
    let rms = gas.rms_speed;
    if !(rms.is_finite() && rms >= 0.0) {
        return invalid!("gas.rms_speed = {rms} must be a finite number ≥ 0");
    }
    // Maxwell speeds reach a few times the rms; every engine squares them.
    let heaviest = kinds.iter().map(|k| k.species.mass).fold(0.0, f64::max);
    let energy = 0.5 * count as f64 * heaviest * (10.0 * rms).powi(2);
    if !energy.is_finite() {
        return invalid!(
            "gas.rms_speed = {rms:e} m/s is too large: the gas's kinetic energy overflows double \
             precision; give a speed of a physical size"
        );
    }
    if count == 1 && rms > 0.0 {
        return invalid!(
            "a single particle with zero total momentum cannot move: set gas.rms_speed = 0 or count > 1"
        );
    }
    // The lattice's spacing and the packing fraction divide by the volume.
    let volume = sim_box.volume();
    if !(volume.is_finite() && volume > 0.0) {
        return invalid!(
            "the gas's box of {:?} m has a volume of {volume:e} m³, which double precision \
             cannot hold; give box.size (or gas.packing_fraction) of a physical size",
            sim_box.size
        );
    }
    let spheres: f64 = kinds
        .iter()
        .map(|k| k.count as f64 * 4.0 / 3.0 * PI * k.species.radius.powi(3))
        .sum();
    let eta = spheres / volume;
    let largest = kinds.iter().map(|k| k.species.radius).fold(0.0, f64::max);
    if eta >= CLOSE_PACKING {
        return invalid!(
            "{count} spheres of radius up to {largest} m do not fit in the box (packing \
             fraction {eta:.3})"
        );
    }
    // Each sphere's species number, largest spheres first.
    let number = |s: &Species| species.iter().position(|t| t == s).unwrap_or(0) as u32;
    let mut by_size: Vec<&GasKind> = kinds.iter().collect();
    by_size.sort_by(|a, b| b.species.radius.total_cmp(&a.species.radius));
    let mut kind_of: Vec<u32> = by_size
        .iter()
        .flat_map(|k| std::iter::repeat_n(number(&k.species), k.count))
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(gas.seed);
    let positions = match gas.arrangement {
        Arrangement::Lattice => lattice(count, largest, sim_box)?,
        Arrangement::Fcc => fcc(count, largest, sim_box)?,
        Arrangement::Random => {
            let radii: Vec<f64> = kind_of
                .iter()
                .map(|&k| species[k as usize].radius)
                .collect();
            random_placement(&radii, sim_box, &mut rng)?
        }
    };
    if kinds.len() > 1 && gas.arrangement != Arrangement::Random {
        // Fisher–Yates: the kinds spread over the lattice sites.
        for i in (1..count).rev() {
            let j = rng.random_range(0..=i);
            kind_of.swap(i, j);
        }
    }
    let masses: Vec<f64> = kind_of.iter().map(|&k| species[k as usize].mass).collect();
    let velocities = maxwell_velocities(&masses, rms, &mut rng);
    for ((x, v), k) in positions.into_iter().zip(velocities).zip(kind_of) {
        particles.push(species, k, x, v);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::placement::grid_dims;
    use super::*;

    #[test]
    fn a_dilute_random_gas_needs_a_small_grid() {
        // 8 spheres of radius 1 µm in a 10 km box: 5e9 cells of 2 µm per axis.
        let b = SimBox {
            lo: [0.0; 3],
            size: [1e4; 3],
            periodic: [true; 3],
        };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let x = random_placement(&[1e-6; 8], &b, &mut rng).unwrap();
        assert_eq!(x.len(), 8);
        // A long thin box: cells grow along the long axis only.
        let long = grid_dims([1e9, 1e-9, 1e-9], 1e-10, 128.0);
        assert!(
            long[1] == 1 && long[2] == 1 && (64..=128).contains(&long[0]),
            "{long:?}"
        );
        for (size, d, limit) in [
            ([1e4; 3], 2e-6, 128.0),
            ([1e9, 1e-9, 1e-9], 1e-10, 128.0),
            ([1.0; 3], 0.1, 1e6),
        ] {
            let dims = grid_dims(size, d, limit);
            let total: f64 = dims.iter().map(|&n| n as f64).product();
            assert!(total <= limit, "{dims:?}");
            for k in 0..3 {
                assert!(dims[k] == 1 || size[k] / dims[k] as f64 >= d, "{dims:?}");
            }
        }
        // A dense box keeps cells of width d.
        assert_eq!(grid_dims([1.0; 3], 0.1, 1e6), [10; 3]);
    }

    #[test]
    fn boxes_whose_volume_double_precision_cannot_hold_are_refused() {
        // Found by fuzzing: 2 spheres of radius 1.23e5 m at a packing fraction of 7.6e-307
        // ask for a cube of side 3e107 m; the side overflowed to infinity and the lattice's
        // search for a spacing (narrowing an infinite one) never ended.
        let err = cubic_box(2, 1.23e5, 7.565504946218844e-307)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("gas.packing_fraction") && err.contains("inf"),
            "{err}"
        );
        // A side that underflows to zero.
        let err = cubic_box(2, 1e-120, 0.1).unwrap_err().to_string();
        assert!(err.contains("gas.packing_fraction"), "{err}");
        // A [box] of finite sides whose volume overflows (1e300 m³) or underflows.
        let species = [Species::new(1.0, 1.0)];
        for (size, radius) in [(1e150, 1.0), (1e-120, 1e-130)] {
            let gas = GasConfig {
                count: 2,
                radius: Some(radius),
                mass: Some(1.0),
                arrangement: Arrangement::Lattice,
                rms_speed: 1.0,
                seed: 1,
                ..GasConfig::default()
            };
            let b = SimBox {
                lo: [0.0; 3],
                size: [size; 3],
                periodic: [true; 3],
            };
            let err = gas.generate(&species, &b).unwrap_err().to_string();
            assert!(err.contains("box.size") && err.contains("volume"), "{err}");
        }
        // The largest cube double precision holds still gets its lattice: 2 sites half a
        // side apart.
        let side = 5e102;
        let b = SimBox {
            lo: [0.0; 3],
            size: [side; 3],
            periodic: [true; 3],
        };
        let x = lattice(2, 1.0, &b).unwrap();
        assert_eq!(
            x,
            vec![
                [side / 4.0, side / 4.0, side / 4.0],
                [3.0 * side / 4.0, side / 4.0, side / 4.0]
            ]
        );
    }

    #[test]
    fn a_box_thin_enough_for_countless_sites_along_two_axes_gets_its_lattice() {
        // Found by fuzzing: 60 spheres of 2e-308 m in a box of 8e7 × 5.5e8 × 1.3e-138 m.
        // The first spacing tried (1e-41 m) gives more than usize::MAX sites along x and
        // y, and their product overflowed (a panic). The sites now fill the first row.
        let b = SimBox {
            lo: [0.0; 3],
            size: [8e7, 5.5e8, 1.2596808811821924e-138],
            periodic: [true; 3],
        };
        let x = lattice(60, 2.1149108880615016e-308, &b).unwrap();
        assert_eq!(x.len(), 60);
        let dx = 8e7 / usize::MAX as f64;
        for (i, p) in x.iter().enumerate() {
            assert_eq!(
                *p,
                [
                    (i as f64 + 0.5) * dx,
                    0.5 * 5.5e8 / usize::MAX as f64,
                    0.5 * b.size[2]
                ]
            );
        }
    }

    #[test]
    fn maxwell_velocities_have_zero_momentum_and_the_rms_speed() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let v = maxwell_velocities(&[1.5; 1000], 2.0, &mut rng);
        let p: [f64; 3] = std::array::from_fn(|k| v.iter().map(|x| x[k]).sum::<f64>());
        assert!(p.iter().all(|c| c.abs() < 1e-12), "{p:?}");
        let ms = v
            .iter()
            .map(|x| x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
            .sum::<f64>()
            / 1000.0;
        assert!((ms.sqrt() - 2.0).abs() < 1e-12);
        // Gaussian components: kurtosis ⟨v⁴⟩/⟨v²⟩² = 3 within sampling error (~0.3 here).
        let m2 = v.iter().map(|x| x[0] * x[0]).sum::<f64>() / 1000.0;
        let m4 = v.iter().map(|x| x[0].powi(4)).sum::<f64>() / 1000.0;
        assert!((m4 / (m2 * m2) - 3.0).abs() < 0.6, "{}", m4 / (m2 * m2));
    }
}
