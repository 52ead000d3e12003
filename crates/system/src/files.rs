//! The files of a run: inputs read only from regular files, whole and bounded by their
//! size; outputs written only to regular files or new paths, each held under a lock
//! for as long as the run writes it.
//!
//! A path names the same file as another when both exist and are one file (the same
//! device and inode, whatever links or spellings lead there), or when neither exists
//! and both lie in the same directory under the same name.

use crate::error::{Result, SystemError};
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> SystemError + '_ {
    move |io| SystemError::Io {
        path: path.display().to_string(),
        io,
    }
}

fn refused(message: String) -> SystemError {
    SystemError::File(message)
}

/// What a file is, beyond the name that leads to it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum FileIdentity {
    /// An existing file: its device and inode.
    Existing { device: u64, inode: u64 },
    /// A path that does not exist yet: its directory (canonical) and name.
    New {
        directory: PathBuf,
        name: std::ffi::OsString,
    },
}

impl FileIdentity {
    /// The identity of `path` (which need not exist; its directory must).
    pub fn of(path: &Path) -> Result<Self> {
        match std::fs::metadata(path) {
            Ok(meta) => Ok(Self::existing(&meta)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let directory = match path.parent() {
                    Some(p) if !p.as_os_str().is_empty() => p,
                    _ => Path::new("."),
                };
                let name = path.file_name().ok_or_else(|| {
                    refused(format!(
                        "{} names no file (it ends in '..' or '/'); give a file name",
                        path.display()
                    ))
                })?;
                Ok(Self::New {
                    directory: directory.canonicalize().map_err(io_error(path))?,
                    name: name.to_owned(),
                })
            }
            Err(e) => Err(io_error(path)(e)),
        }
    }

    #[cfg(unix)]
    fn existing(meta: &std::fs::Metadata) -> Self {
        use std::os::unix::fs::MetadataExt;
        Self::Existing {
            device: meta.dev(),
            inode: meta.ino(),
        }
    }

    #[cfg(not(unix))]
    fn existing(_meta: &std::fs::Metadata) -> Self {
        Self::Existing {
            device: 0,
            inode: 0,
        }
    }
}

/// What a run's output may not be: refuses `path` unless it is a regular file or does
/// not exist yet.
pub fn check_writable(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => Ok(()),
        Ok(meta) => Err(refused(format!(
            "{} is {}, not a regular file: emdstar writes its outputs only to regular files \
             or new paths; give another path",
            path.display(),
            kind_of(&meta)
        ))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(io_error(path)(e)),
    }
}

/// "a directory", "a device", … for messages.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let kind = meta.file_type();
    if kind.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_fifo() {
            return "a pipe (FIFO)";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// An output file claimed by this run: a regular file (or one created now) opened for
/// reading and writing, without truncation, and locked so that no second run writes it
/// at the same time. A file created by the claim is removed again if it is dropped
/// unused (see [`OutputFile::into_file`]).
#[derive(Debug)]
pub struct OutputFile {
    file: Option<File>,
    path: PathBuf,
    created: bool,
}

impl OutputFile {
    /// Claims `path`: refuses anything but a regular file or a new path, and a file that
    /// another process holds locked (another run writing it).
    pub fn claim(path: &Path) -> Result<Self> {
        check_writable(path)?;
        let existed = path.exists();
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(io_error(path))?;
        let mut out = Self {
            file: Some(file),
            path: path.to_path_buf(),
            created: !existed,
        };
        let meta = out.file().metadata().map_err(io_error(path))?;
        if !meta.is_file() {
            // Replaced between the check and the opening.
            out.created = false;
            return Err(refused(format!(
                "{} is {}, not a regular file; give another path",
                path.display(),
                kind_of(&meta)
            )));
        }
        if !lock(out.file()).map_err(io_error(path))? {
            out.created = false;
            return Err(refused(format!(
                "{} is being written by another emdstar run (it holds the file's lock); wait \
                 for it to end, or give this run other files",
                path.display()
            )));
        }
        Ok(out)
    }

    /// The path it was claimed under.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open file.
    pub fn file(&self) -> &File {
        self.file
            .as_ref()
            .expect("an output file is open until it is taken")
    }

    /// Whether the claim created the file.
    pub fn created(&self) -> bool {
        self.created
    }

    /// The file, to write it; from now on it stays even if unused. The lock lasts as
    /// long as the file is open.
    pub fn into_file(mut self) -> File {
        self.created = false;
        self.file
            .take()
            .expect("an output file is open until it is taken")
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if self.created
            && let Some(file) = self.file.take()
        {
            // Created by this claim and never used: leave no empty file behind.
            if file.metadata().is_ok_and(|m| m.len() == 0) {
                let _ = std::fs::remove_file(&self.path);
            }
        }
    }
}

/// Takes an exclusive advisory lock on `file` without waiting: `false` if another open
/// file description holds it.
#[cfg(unix)]
fn lock(file: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock on a file descriptor this process owns.
    let rc = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if rc == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    if e.kind() == std::io::ErrorKind::WouldBlock {
        Ok(false)
    } else {
        Err(e)
    }
}

#[cfg(not(unix))]
fn lock(_file: &File) -> std::io::Result<bool> {
    Ok(true)
}

/// Opens the input file `path` for reading: only a regular file (a device, a pipe or a
/// directory could be endless or block; `what` names the input in the message: "config",
/// "checkpoint"). Returns it with its size.
pub fn open_input(path: &Path, what: &str) -> Result<(File, u64)> {
    let regular = |meta: &std::fs::Metadata| {
        if meta.is_file() {
            Ok(())
        } else {
            Err(refused(format!(
                "{} is {}: a {what} is read only from a regular file",
                path.display(),
                kind_of(meta)
            )))
        }
    };
    // Looked at before it is opened: opening a pipe blocks until someone writes to it.
    regular(&std::fs::metadata(path).map_err(io_error(path))?)?;
    let file = File::open(path).map_err(io_error(path))?;
    let meta = file.metadata().map_err(io_error(path))?;
    regular(&meta)?;
    Ok((file, meta.len()))
}

/// Reads the input file `path` whole (see [`open_input`]), if it has at most
/// `max_bytes`; reads no more than the size the file had when opened.
pub fn read_input(path: &Path, what: &str, max_bytes: u64) -> Result<Vec<u8>> {
    let (file, len) = open_input(path, what)?;
    if len > max_bytes {
        return Err(refused(format!(
            "{} has {len} bytes, more than a {what} can have ({max_bytes}); is it the right \
             file?",
            path.display()
        )));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(len)
        .read_to_end(&mut bytes)
        .map_err(io_error(path))?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("emdstar-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_claimed_file_is_locked_and_an_unused_new_one_is_removed() {
        let dir = scratch("claim");
        let path = dir.join("run.log");
        let first = OutputFile::claim(&path).unwrap();
        assert!(first.created() && path.exists());
        // A second claim (another open file description) is refused while the first
        // holds the lock.
        let err = OutputFile::claim(&path).unwrap_err().to_string();
        assert!(err.contains("another emdstar run"), "{err}");
        drop(first);
        assert!(!path.exists(), "an unused new file stays");
        // Used, it stays; its lock goes with the file.
        let file = OutputFile::claim(&path).unwrap().into_file();
        assert!(OutputFile::claim(&path).is_err());
        drop(file);
        assert!(path.exists() && OutputFile::claim(&path).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn devices_and_directories_are_neither_claimed_nor_read() {
        let dir = scratch("devices");
        for path in [
            Path::new("/dev/null"),
            Path::new("/dev/zero"),
            dir.as_path(),
        ] {
            assert!(OutputFile::claim(path).is_err(), "{}", path.display());
            let err = read_input(path, "config", 1 << 20).unwrap_err().to_string();
            assert!(err.contains("regular file"), "{err}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn one_file_has_one_identity_whatever_the_path() {
        let dir = scratch("identity");
        let (a, b) = (dir.join("a.toml"), dir.join("sub/../a.toml"));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        // New paths: the same directory and name.
        assert_eq!(FileIdentity::of(&a).unwrap(), FileIdentity::of(&b).unwrap());
        std::fs::write(&a, "t_end = 1").unwrap();
        std::fs::hard_link(&a, dir.join("link.toml")).unwrap();
        let id = FileIdentity::of(&a).unwrap();
        assert_eq!(id, FileIdentity::of(&b).unwrap());
        assert_eq!(id, FileIdentity::of(&dir.join("link.toml")).unwrap());
        assert_ne!(id, FileIdentity::of(&dir.join("other.toml")).unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
