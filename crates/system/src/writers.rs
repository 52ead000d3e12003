//! Trajectory (extended XYZ) and thermo-log writers.

use crate::error::{Result, SystemError};
use crate::files::OutputFile;
use crate::geometry::{SimBox, bounding_box};
use crate::state::Particles;
use crate::stress::Observables;
use crate::tail::{Cut, KeepUntil, LogLines, XyzFrames, cut_after};
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

fn io_error(path: &str) -> impl Fn(std::io::Error) -> SystemError + '_ {
    move |io| SystemError::Io {
        path: path.to_string(),
        io,
    }
}

/// Writes what the operating system buffers of `file` to its disk. A file that cannot
/// be synced (a device such as /dev/null, a pipe: EINVAL) has nothing to lose and
/// passes.
pub(crate) fn sync_data(file: &File) -> std::io::Result<()> {
    match file.sync_data() {
        Err(e) if e.kind() == std::io::ErrorKind::InvalidInput => Ok(()),
        other => other,
    }
}

/// Takes the claimed file `out`, emptied unless `keep` (resuming), for writing at its
/// end.
fn take(out: OutputFile, keep: bool) -> Result<(File, String)> {
    let name = out.path().display().to_string();
    let mut file = out.into_file();
    if !keep {
        file.set_len(0).map_err(io_error(&name))?;
    }
    file.seek(SeekFrom::End(0)).map_err(io_error(&name))?;
    Ok((file, name))
}

/// Writes frames in extended XYZ, which OVITO reads with the columns
/// `id species pos velo radius omega image` (omega: the angular velocity in rad/s;
/// image: the periodic image flags, so that `pos + image · box size` is the unwrapped
/// position) and the `Lattice`, `Origin`, `pbc` and `Time` fields. Numbers are written
/// in the shortest notation that reads back to the same double, so a frame read back
/// continues a run in double precision (see `[initial]`).
///
/// In free space the lattice is the particles' bounding box (grown by the largest
/// radius) and `pbc="F F F"`. Each frame is formatted in memory and written at once.
/// A run killed in the middle of that write may leave a frame unfinished;
/// [`XyzWriter::resume`] cuts it off.
pub struct XyzWriter {
    out: File,
    frame: Vec<u8>,
    path: String,
}

impl XyzWriter {
    /// Claims the file at `path` and empties it.
    pub fn create(path: &Path) -> Result<Self> {
        Self::start(OutputFile::claim(path)?)
    }

    /// Empties the claimed file `out` and writes frames to it.
    pub fn start(out: OutputFile) -> Result<Self> {
        let (out, path) = take(out, false)?;
        Ok(Self {
            out,
            frame: Vec::new(),
            path,
        })
    }

    /// Opens the trajectory of a run resumed from a checkpoint at time `t`, to add
    /// frames at its end, after cutting off what a killed run wrote after `t`: whole
    /// frames, and a last frame left unfinished. The frames must hold `particles`
    /// particles.
    pub fn resume(path: &Path, t: f64, particles: usize) -> Result<(Self, Cut)> {
        let keep = KeepUntil { t, at_t: true };
        Self::resume_in(OutputFile::claim(path)?, keep, particles)
    }

    /// [`XyzWriter::resume`] on the claimed file `out`, keeping the frames `keep` keeps.
    pub fn resume_in(out: OutputFile, keep: KeepUntil, particles: usize) -> Result<(Self, Cut)> {
        let name = out.path().display().to_string();
        let mut file = out.into_file();
        let cut = cut_after(&mut file, keep, &XyzFrames { particles }).map_err(io_error(&name))?;
        Ok((
            Self {
                out: file,
                frame: Vec::new(),
                path: name,
            },
            cut,
        ))
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
        let w = &mut self.frame;
        w.clear();
        writeln!(w, "{}", particles.len()).map_err(&err)?;
        writeln!(
            w,
            "Lattice=\"{:e} 0 0 0 {:e} 0 0 0 {:e}\" Origin=\"{:e} {:e} {:e}\" \
             Properties=id:I:1:species:I:1:pos:R:3:velo:R:3:radius:R:1:omega:R:3:image:I:3 Time={t:e} pbc=\"{} {} {}\"",
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
            let o = particles.angular_velocity[i];
            writeln!(
                w,
                "{} {} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {} {} {}",
                particles.id[i],
                particles.species[i],
                x[0],
                x[1],
                x[2],
                v[0],
                v[1],
                v[2],
                particles.radius[i],
                o[0],
                o[1],
                o[2],
                particles.image[i][0],
                particles.image[i][1],
                particles.image[i][2]
            )
            .map_err(&err)?;
        }
        self.out.write_all(&self.frame).map_err(&err)
    }

    /// Writes what the operating system still buffers to the disk.
    pub fn flush(&mut self) -> Result<()> {
        sync_data(&self.out).map_err(io_error(&self.path))
    }
}

/// One line of the thermo log.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Thermo {
    /// Time in s.
    pub t: f64,
    /// Engine steps (time steps or events) so far.
    pub step: u64,
    /// Σ ½ m v² in J (translation only).
    pub kinetic_energy: f64,
    /// Σ ½ I ω² in J.
    pub rotational_energy: f64,
    /// Elastic contact energy plus gravitational potential energy in J.
    pub potential_energy: f64,
    /// Granular temperature in J, see [`Particles::granular_temperature`].
    pub granular_temperature: f64,
    /// Rotational temperature in J, see [`Particles::rotational_temperature`].
    pub rotational_temperature: f64,
    /// Σ m v in kg m/s.
    pub momentum: [f64; 3],
    /// Pairs (and particle–wall pairs) in contact.
    pub contacts: usize,
}

impl Thermo {
    /// Kinetic (translational and rotational) plus potential energy in J.
    pub fn total_energy(&self) -> f64 {
        self.kinetic_energy + self.rotational_energy + self.potential_energy
    }
}

/// A whitespace-separated thermo log with a commented header line. Every line goes
/// to the file as it is written (nothing waits in a buffer).
pub struct ThermoLog {
    out: File,
    path: String,
}

impl ThermoLog {
    /// The header line.
    const HEADER: &str = "# t[s] step kinetic_energy[J] potential_energy[J] total_energy[J] \
                          granular_temperature[J] px[kg*m/s] py pz contacts \
                          rotational_energy[J] rotational_temperature[J] pressure[Pa] \
                          pxx[Pa] pyy[Pa] pzz[Pa] pxy[Pa] pxz[Pa] pyz[Pa] \
                          collision_rate[1/s] sonine_a2\n";

    /// Bytes a line takes at most: twenty-one numbers of up to 24 characters.
    pub const LINE_BYTES: u64 = 21 * 25;

    /// Claims the file at `path`, empties it and writes the header.
    pub fn create(path: &Path) -> Result<Self> {
        Self::start(OutputFile::claim(path)?)
    }

    /// Empties the claimed file `out` and writes the header.
    pub fn start(out: OutputFile) -> Result<Self> {
        let (mut out, path) = take(out, false)?;
        out.write_all(Self::HEADER.as_bytes())
            .map_err(io_error(&path))?;
        Ok(Self { out, path })
    }

    /// Opens the log of a run resumed from a checkpoint at time `t`, to add lines at
    /// its end, after cutting off what a killed run wrote after `t`: whole lines, and a
    /// last line left unfinished.
    pub fn resume(path: &Path, t: f64) -> Result<(Self, Cut)> {
        Self::resume_in(OutputFile::claim(path)?, KeepUntil { t, at_t: true })
    }

    /// [`ThermoLog::resume`] on the claimed file `out`, keeping the lines `keep` keeps;
    /// an empty file gets the header.
    pub fn resume_in(out: OutputFile, keep: KeepUntil) -> Result<(Self, Cut)> {
        let name = out.path().display().to_string();
        let mut file = out.into_file();
        let cut = cut_after(&mut file, keep, &LogLines).map_err(io_error(&name))?;
        let empty = file.metadata().map_err(io_error(&name))?.len() == 0;
        if empty {
            file.write_all(Self::HEADER.as_bytes())
                .map_err(io_error(&name))?;
        }
        Ok((
            Self {
                out: file,
                path: name,
            },
            cut,
        ))
    }

    /// Appends one line: `th`, then the observables of the interval it ends.
    pub fn write(&mut self, th: &Thermo, obs: &Observables) -> Result<()> {
        let mut line = format!(
            "{:e} {} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {} {:e} {:e}",
            th.t,
            th.step,
            th.kinetic_energy,
            th.potential_energy,
            th.total_energy(),
            th.granular_temperature,
            th.momentum[0],
            th.momentum[1],
            th.momentum[2],
            th.contacts,
            th.rotational_energy,
            th.rotational_temperature
        );
        for x in [obs.pressure]
            .iter()
            .chain(&obs.tensor)
            .chain(&[obs.collision_rate, obs.sonine_a2])
        {
            line.push_str(&format!(" {x:e}"));
        }
        line.push('\n');
        self.out
            .write_all(line.as_bytes())
            .map_err(io_error(&self.path))
    }

    /// Writes what the operating system still buffers to the disk.
    pub fn flush(&mut self) -> Result<()> {
        sync_data(&self.out).map_err(io_error(&self.path))
    }
}
