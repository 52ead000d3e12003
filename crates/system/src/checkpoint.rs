//! Checkpoint files: an engine's saved state (see [`crate::Simulation`]) with what
//! identifies the run it belongs to, a version and a checksum.
//!
//! Layout (little endian): the magic `EMDSTAR\x00`, the format version (u32), the
//! engine name and the options tag (each u32 length + UTF-8), the config digest (u64),
//! the time (f64), the state (u64 length + bytes), and the CRC-32 of everything before
//! it (u32). Files are written to a temporary name and renamed, so a crash never leaves
//! a half-written file under the real name ([`CheckpointFile`], which also locks it
//! against a second run).

use crate::error::{Result, SystemError};
use std::io::{Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"EMDSTAR\x00";

/// The version of the layout and of every engine's state encoding (2: particles carry
/// angular velocities, MD its tangential springs; 3: the event engines keep each
/// particle's last pair collision; 4: a cell grid holds
/// each particle's cell, not its per-cell index; 5: the hybrid keeps spins' angular
/// accelerations and the springs of its time-driven contacts; 6: the event engines keep
/// their counts of frictional eMD* solves and fallback kicks; 7: each particle's last
/// collision time for the TC model; 8: every engine keeps the sums behind the pressure
/// tensor and the collision rate, and the thermo log's mark).
pub const CHECKPOINT_VERSION: u32 = 8;

/// A saved run.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    /// The engine ("md", "emd", "emdstar", "hybrid").
    pub engine: String,
    /// The options a resumed run must share (e.g. the MoR source).
    pub options: String,
    /// Digest of the physical system the run started from (see
    /// [`crate::Config::digest`]).
    pub config_digest: u64,
    /// Simulated time of the state, in s.
    pub time: f64,
    /// The engine's state.
    pub state: Vec<u8>,
}

fn put_str(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// A reader over the bytes of a checkpoint that names the file in its errors.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    path: &'a str,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(corrupt(
                self.path,
                &format!("it ends inside the {what} (truncated?)"),
            ));
        };
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(
            self.take(4, what)?.try_into().expect("4 bytes"),
        ))
    }

    fn u64(&mut self, what: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(
            self.take(8, what)?.try_into().expect("8 bytes"),
        ))
    }

    fn string(&mut self, what: &str) -> Result<String> {
        let n = self.u32(what)? as usize;
        String::from_utf8(self.take(n, what)?.to_vec())
            .map_err(|_| corrupt(self.path, &format!("its {what} is not UTF-8")))
    }
}

fn corrupt(path: &str, why: &str) -> SystemError {
    SystemError::Checkpoint(format!(
        "{path} is not a valid emdstar checkpoint: {why}; use a checkpoint written by \
         `emdstar run --checkpoint`"
    ))
}

impl Checkpoint {
    /// The file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.state.len() + 64);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&CHECKPOINT_VERSION.to_le_bytes());
        put_str(&mut out, &self.engine);
        put_str(&mut out, &self.options);
        out.extend_from_slice(&self.config_digest.to_le_bytes());
        out.extend_from_slice(&self.time.to_bits().to_le_bytes());
        out.extend_from_slice(&(self.state.len() as u64).to_le_bytes());
        out.extend_from_slice(&self.state);
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Parses a checkpoint; `path` names it in the errors.
    pub fn from_bytes(bytes: &[u8], path: &str) -> Result<Self> {
        let mut c = Cursor { bytes, at: 0, path };
        if c.take(MAGIC.len(), "magic number")? != MAGIC {
            return Err(corrupt(path, "it does not start with the checkpoint magic"));
        }
        let version = c.u32("format version")?;
        if version != CHECKPOINT_VERSION {
            return Err(SystemError::Checkpoint(format!(
                "{path} is a checkpoint of format version {version}, but this emdstar reads \
                 version {CHECKPOINT_VERSION} only; resume it with the emdstar version that \
                 wrote it"
            )));
        }
        let engine = c.string("engine name")?;
        let options = c.string("options")?;
        let config_digest = c.u64("config digest")?;
        let time = f64::from_bits(c.u64("time")?);
        let n = c.u64("state length")?;
        let n = usize::try_from(n).map_err(|_| corrupt(path, "its state length is absurd"))?;
        let state = c.take(n, "state")?.to_vec();
        let body = c.at;
        let crc = c.u32("checksum")?;
        if c.at != bytes.len() {
            return Err(corrupt(path, "it has bytes after its checksum"));
        }
        if crc32fast::hash(&bytes[..body]) != crc {
            return Err(corrupt(
                path,
                "its checksum does not match (the file is damaged)",
            ));
        }
        Ok(Self {
            engine,
            options,
            config_digest,
            time,
            state,
        })
    }

    /// Writes the checkpoint to `path`, through a temporary file in the same directory
    /// renamed into place.
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomically(path, &self.to_bytes())
    }

    /// Reads a checkpoint file: a regular file whose size is the one its header
    /// declares (read before the rest).
    pub fn read(path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let io = |io| SystemError::Io {
            path: name.clone(),
            io,
        };
        let (file, len) = crate::files::open_input(path, "checkpoint")?;
        let mut head = Vec::new();
        (&file)
            .take(HEAD_BYTES.min(len))
            .read_to_end(&mut head)
            .map_err(io)?;
        let declared = Self::declared_len(&head, &name)?;
        if declared != len {
            return Err(corrupt(
                &name,
                &format!("its header declares {declared} bytes, the file has {len}"),
            ));
        }
        let mut bytes = head;
        bytes.reserve((len - bytes.len() as u64) as usize);
        (&file)
            .take(len - bytes.len() as u64)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        Self::from_bytes(&bytes, &name)
    }

    /// The size of the file whose first bytes are `head`, as its header declares it.
    fn declared_len(head: &[u8], path: &str) -> Result<u64> {
        let mut c = Cursor {
            bytes: head,
            at: 0,
            path,
        };
        if c.take(MAGIC.len(), "magic number")? != MAGIC {
            return Err(corrupt(path, "it does not start with the checkpoint magic"));
        }
        c.u32("format version")?;
        c.string("engine name")?;
        c.string("options")?;
        c.u64("config digest")?;
        c.u64("time")?;
        let state = c.u64("state length")?;
        (c.at as u64)
            .checked_add(state)
            .and_then(|n| n.checked_add(4))
            .ok_or_else(|| corrupt(path, "its state length is absurd"))
    }
}

/// How much of a checkpoint is read before its declared size is known: the header,
/// whose names are short.
const HEAD_BYTES: u64 = 4096;

/// Where a run writes its checkpoints, held for the run: the checkpoint's path and its
/// temporary file `PATH.partial`, claimed and locked, so that no second run writes the
/// same checkpoint. Each checkpoint is written whole to the temporary file, synced, and
/// renamed over the path; a fresh temporary file is then claimed for the next one.
#[derive(Debug)]
pub struct CheckpointFile {
    path: std::path::PathBuf,
    partial: Option<crate::files::OutputFile>,
}

impl CheckpointFile {
    /// The temporary file of the checkpoint at `path`.
    pub fn partial_path(path: &Path) -> std::path::PathBuf {
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".partial");
        tmp.into()
    }

    /// Claims `path` (a regular file or a new path) and its temporary file.
    pub fn claim(path: &Path) -> Result<Self> {
        crate::files::check_writable(path)?;
        let partial = crate::files::OutputFile::claim(&Self::partial_path(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            partial: Some(partial),
        })
    }

    /// The checkpoint's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `checkpoint` (see the type); `last` leaves no temporary file behind.
    pub fn write(&mut self, checkpoint: &Checkpoint, last: bool) -> Result<()> {
        let io = |io| SystemError::Io {
            path: self.path.display().to_string(),
            io,
        };
        crate::files::check_writable(&self.path)?;
        let partial = self
            .partial
            .take()
            .expect("the temporary file is claimed between checkpoints");
        let tmp = partial.path().to_path_buf();
        let mut file = partial.into_file();
        let written = file
            .set_len(0)
            .and_then(|()| file.write_all(&checkpoint.to_bytes()))
            .and_then(|()| file.sync_all());
        if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, &self.path)) {
            // A full disk: no part-file left behind, the old checkpoint (if any) kept.
            let _ = std::fs::remove_file(&tmp);
            return Err(io(e));
        }
        if !last {
            // The renamed file keeps its lock until `file` closes: claim the next one
            // first, so that the checkpoint is never left unlocked.
            self.partial = Some(crate::files::OutputFile::claim(&tmp)?);
        }
        drop(file);
        Ok(())
    }
}

/// Writes `bytes` to `path` through a temporary file next to it, synced and renamed into
/// place: readers see the old file or the whole new one, never a part.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |io| SystemError::Io {
        path: path.display().to_string(),
        io,
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = std::path::PathBuf::from(tmp);
    let written = std::fs::File::create(&tmp).and_then(|mut file| {
        file.write_all(bytes)?;
        file.sync_all()
    });
    if let Err(e) = written.and_then(|()| std::fs::rename(&tmp, path)) {
        // A full disk: no part-file left behind, the old file (if any) kept.
        let _ = std::fs::remove_file(&tmp);
        return Err(io(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Checkpoint {
        Checkpoint {
            engine: "emdstar".into(),
            options: "table+exact".into(),
            config_digest: 0x0123_4567_89ab_cdef,
            time: 0.1 + 0.2,
            state: (0..=255).collect(),
        }
    }

    #[test]
    fn round_trip_and_every_damage_is_refused() {
        let c = sample();
        let bytes = c.to_bytes();
        assert_eq!(Checkpoint::from_bytes(&bytes, "x").unwrap(), c);
        // Every truncation and every flipped bit is refused.
        for n in 0..bytes.len() {
            assert!(
                Checkpoint::from_bytes(&bytes[..n], "x").is_err(),
                "truncated at {n}"
            );
        }
        for k in 0..bytes.len() * 8 {
            let mut b = bytes.clone();
            b[k / 8] ^= 1 << (k % 8);
            assert!(Checkpoint::from_bytes(&b, "x").is_err(), "bit {k}");
        }
        for other in [CHECKPOINT_VERSION - 1, CHECKPOINT_VERSION + 1] {
            let mut b = bytes.clone();
            b[8..12].copy_from_slice(&other.to_le_bytes());
            let err = Checkpoint::from_bytes(&b, "c.ckpt")
                .unwrap_err()
                .to_string();
            assert!(err.contains(&format!("version {other}")), "{err}");
        }
    }

    #[test]
    fn writing_replaces_the_file_whole() {
        let dir = std::env::temp_dir().join(format!("emdstar-ckpt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("run.ckpt");
        sample().write(&path).unwrap();
        assert_eq!(Checkpoint::read(&path).unwrap(), sample());
        assert!(!dir.join("run.ckpt.partial").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
