//! Trajectory (extended XYZ) and thermo-log writers.

use crate::error::{Result, SystemError};
use crate::geometry::{SimBox, bounding_box};
use crate::state::Particles;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

fn io_error(path: &str) -> impl Fn(std::io::Error) -> SystemError + '_ {
    move |source| SystemError::Io {
        path: path.to_string(),
        source,
    }
}

/// Writes frames in extended XYZ, which OVITO reads with the columns
/// `id species pos velo radius` and the `Lattice`, `Origin`, `pbc` and `Time` fields.
///
/// In free space the lattice is the particles' bounding box (grown by the largest
/// radius) and `pbc="F F F"`.
pub struct XyzWriter {
    out: BufWriter<File>,
    path: String,
}

impl XyzWriter {
    /// Creates (truncates) the file.
    pub fn create(path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let out = BufWriter::new(File::create(path).map_err(io_error(&name))?);
        Ok(Self { out, path: name })
    }

    /// Appends one frame at time `t`.
    pub fn write_frame(
        &mut self,
        t: f64,
        particles: &Particles,
        sim_box: Option<&SimBox>,
    ) -> Result<()> {
        let (lo, size, pbc) = match sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let r = particles.radius.iter().copied().fold(0.0, f64::max);
                let (lo, extent) = bounding_box(&particles.position);
                (lo.map(|c| c - r), extent.map(|e| e + 2.0 * r), [false; 3])
            }
        };
        let tf = |b: bool| if b { "T" } else { "F" };
        let err = io_error(&self.path);
        let w = &mut self.out;
        writeln!(w, "{}", particles.len()).map_err(&err)?;
        writeln!(
            w,
            "Lattice=\"{:e} 0 0 0 {:e} 0 0 0 {:e}\" Origin=\"{:e} {:e} {:e}\" \
             Properties=id:I:1:species:I:1:pos:R:3:velo:R:3:radius:R:1 Time={t:e} pbc=\"{} {} {}\"",
            size[0],
            size[1],
            size[2],
            lo[0],
            lo[1],
            lo[2],
            tf(pbc[0]),
            tf(pbc[1]),
            tf(pbc[2])
        )
        .map_err(&err)?;
        for i in 0..particles.len() {
            let (x, v) = (particles.position[i], particles.velocity[i]);
            writeln!(
                w,
                "{} {} {:e} {:e} {:e} {:e} {:e} {:e} {:e}",
                particles.id[i],
                particles.species[i],
                x[0],
                x[1],
                x[2],
                v[0],
                v[1],
                v[2],
                particles.radius[i]
            )
            .map_err(&err)?;
        }
        Ok(())
    }

    /// Flushes buffered frames to disk.
    pub fn flush(&mut self) -> Result<()> {
        self.out.flush().map_err(io_error(&self.path))
    }
}

/// One line of the thermo log.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Thermo {
    /// Time in s.
    pub t: f64,
    /// Engine steps (time steps or events) so far.
    pub step: u64,
    /// Σ ½ m v² in J.
    pub kinetic_energy: f64,
    /// Elastic contact energy plus gravitational potential energy in J.
    pub potential_energy: f64,
    /// Granular temperature in J, see [`Particles::granular_temperature`].
    pub granular_temperature: f64,
    /// Σ m v in kg m/s.
    pub momentum: [f64; 3],
    /// Pairs (and particle–wall pairs) in contact.
    pub contacts: usize,
}

impl Thermo {
    /// Kinetic plus potential energy in J.
    pub fn total_energy(&self) -> f64 {
        self.kinetic_energy + self.potential_energy
    }
}

/// A whitespace-separated thermo log with a commented header line.
pub struct ThermoLog {
    out: BufWriter<File>,
    path: String,
}

impl ThermoLog {
    /// Creates (truncates) the file and writes the header.
    pub fn create(path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let mut out = BufWriter::new(File::create(path).map_err(io_error(&name))?);
        writeln!(
            out,
            "# t[s] step kinetic_energy[J] potential_energy[J] total_energy[J] \
             granular_temperature[J] px[kg*m/s] py pz contacts"
        )
        .map_err(io_error(&name))?;
        Ok(Self { out, path: name })
    }

    /// Appends one line.
    pub fn write(&mut self, th: &Thermo) -> Result<()> {
        writeln!(
            self.out,
            "{:e} {} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {}",
            th.t,
            th.step,
            th.kinetic_energy,
            th.potential_energy,
            th.total_energy(),
            th.granular_temperature,
            th.momentum[0],
            th.momentum[1],
            th.momentum[2],
            th.contacts
        )
        .map_err(io_error(&self.path))
    }

    /// Flushes buffered lines to disk.
    pub fn flush(&mut self) -> Result<()> {
        self.out.flush().map_err(io_error(&self.path))
    }
}
