//! Cutting a trajectory or thermo log back to the time of a checkpoint, before a resumed
//! run appends to it.
//!
//! A run that was killed (SIGKILL, a crash, a power cut) leaves behind what it wrote
//! after its last checkpoint: whole frames and log lines that the resumed run will write
//! again, and perhaps the start of a last one, since the kernel may cut a write short
//! when the process dies in the middle of it. Both are cut off, so that a run killed and
//! resumed leaves the same files as one that ran through.
//!
//! Only the tail is read: the scan steps back from the end of the file record by record
//! until it meets one at or before the checkpoint's time, then reads forward from there.

use std::fs::File;
use std::io::{self, BufRead, BufReader, ErrorKind, Read, Seek, SeekFrom};

/// What cutting a file back to a checkpoint took off its end.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Cut {
    /// Whole records (frames or log lines) that were written after the checkpoint.
    pub records: u64,
    /// Bytes of a last record that was left unfinished.
    pub partial_bytes: u64,
}

impl Cut {
    /// Whether nothing was cut.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// One record read from a file.
pub(crate) enum Record {
    /// A whole record of `len` bytes stamped with `time`.
    Whole { len: u64, time: f64 },
    /// The start of a record, `len` bytes, cut off by the end of the file.
    Partial { len: u64 },
}

/// A file made of records, each stamped with a time.
pub(crate) trait Records {
    /// The start of the last record that begins before byte `before`, if any.
    fn previous_start(&self, file: &mut File, before: u64) -> io::Result<Option<u64>>;

    /// Reads the record at the reader's position; `None` at the end of the file. A record
    /// that is not of this kind is an `InvalidData` error.
    fn read(&self, reader: &mut impl BufRead) -> io::Result<Option<Record>>;
}

/// Which records a resumed run keeps: those stamped before the time `t` it resumes
/// from, and the one stamped at `t` if `at_t` (a record the run writes at that time
/// anyway; one written only because a run stopped there is cut, and the resumed run
/// goes on past it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeepUntil {
    pub t: f64,
    pub at_t: bool,
}

impl KeepUntil {
    /// Whether a record stamped `time` is kept.
    pub fn keeps(&self, time: f64) -> bool {
        time < self.t || (self.at_t && time == self.t)
    }
}

/// Cuts `file` after its last whole record that `keep` keeps (everything from the first
/// record it does not keep on goes).
pub(crate) fn cut_after(
    file: &mut File,
    keep: KeepUntil,
    records: &impl Records,
) -> io::Result<Cut> {
    // Step back to the last whole record kept; read forward from its end (from the
    // start of the file if there is none).
    let mut start = file.metadata()?.len();
    let from = loop {
        let Some(s) = records.previous_start(file, start)? else {
            break 0;
        };
        start = s;
        file.seek(SeekFrom::Start(s))?;
        if let Some(Record::Whole { len, time }) = records.read(&mut BufReader::new(&mut *file))?
            && keep.keeps(time)
        {
            break s + len;
        }
    };
    // Keep whole records up to `t`, cut what follows.
    file.seek(SeekFrom::Start(from))?;
    let mut reader = BufReader::with_capacity(1 << 20, &mut *file);
    let (mut kept, mut at, mut cut) = (from, from, Cut::default());
    while let Some(record) = records.read(&mut reader)? {
        match record {
            Record::Whole { len, time } => {
                at += len;
                if cut.records == 0 && keep.keeps(time) {
                    kept = at;
                } else {
                    cut.records += 1;
                }
            }
            Record::Partial { len } => cut.partial_bytes = len,
        }
    }
    drop(reader);
    if !cut.is_empty() {
        file.set_len(kept)?;
        crate::writers::sync_data(file)?;
    }
    file.seek(SeekFrom::Start(kept))?;
    Ok(cut)
}

/// The position of the last `pattern` that lies wholly before byte `before`.
fn last_match_before(file: &mut File, before: u64, pattern: &[u8]) -> io::Result<Option<u64>> {
    const CHUNK: u64 = 1 << 16;
    let mut buf = vec![0u8; CHUNK as usize];
    let mut end = before;
    loop {
        let start = end.saturating_sub(CHUNK);
        let len = (end - start) as usize;
        if len < pattern.len() {
            return Ok(None);
        }
        file.seek(SeekFrom::Start(start))?;
        file.read_exact(&mut buf[..len])?;
        if let Some(i) = buf[..len]
            .windows(pattern.len())
            .rposition(|w| w == pattern)
        {
            return Ok(Some(start + i as u64));
        }
        if start == 0 {
            return Ok(None);
        }
        // Overlap the next chunk so that a match across the boundary is found.
        end = start + pattern.len() as u64 - 1;
    }
}

/// The start of the line that holds byte `at`.
fn line_start(file: &mut File, at: u64) -> io::Result<u64> {
    Ok(last_match_before(file, at, b"\n")?.map_or(0, |p| p + 1))
}

/// Reads one line, with its `\n`; `None` at the end of the file.
fn read_line(reader: &mut impl BufRead, line: &mut Vec<u8>) -> io::Result<Option<bool>> {
    line.clear();
    match reader.read_until(b'\n', line)? {
        0 => Ok(None),
        _ => Ok(Some(line.ends_with(b"\n"))),
    }
}

fn invalid(what: String) -> io::Error {
    io::Error::new(ErrorKind::InvalidData, what)
}

/// The lines of a thermo log: a `#` header (kept whatever the time), then one line per
/// time whose first column is the time.
pub(crate) struct LogLines;

impl Records for LogLines {
    fn previous_start(&self, file: &mut File, before: u64) -> io::Result<Option<u64>> {
        if before == 0 {
            return Ok(None);
        }
        line_start(file, before - 1).map(Some)
    }

    fn read(&self, reader: &mut impl BufRead) -> io::Result<Option<Record>> {
        let mut line = Vec::new();
        let Some(whole) = read_line(reader, &mut line)? else {
            return Ok(None);
        };
        let len = line.len() as u64;
        if !whole {
            return Ok(Some(Record::Partial { len }));
        }
        if line.starts_with(b"#") {
            return Ok(Some(Record::Whole {
                len,
                time: f64::NEG_INFINITY,
            }));
        }
        let text = String::from_utf8_lossy(&line);
        let time = text.split_whitespace().next().and_then(|c| c.parse().ok());
        match time {
            Some(time) => Ok(Some(Record::Whole { len, time })),
            None => Err(invalid(format!(
                "the line '{}' is not a line of an emdstar thermo log; give the resumed run \
                 a new file with --log",
                text.trim_end()
            ))),
        }
    }
}

/// The frames of an extended-XYZ trajectory of `particles` particles: a count line, a
/// header line with `Time=`, a line per particle.
pub(crate) struct XyzFrames {
    pub particles: usize,
}

impl Records for XyzFrames {
    fn previous_start(&self, file: &mut File, before: u64) -> io::Result<Option<u64>> {
        // The header line starts every frame's second line.
        match last_match_before(file, before, b"\nLattice=\"")? {
            Some(p) => line_start(file, p).map(Some),
            None => Ok(None),
        }
    }

    fn read(&self, reader: &mut impl BufRead) -> io::Result<Option<Record>> {
        let mut line = Vec::new();
        let Some(whole) = read_line(reader, &mut line)? else {
            return Ok(None);
        };
        let mut len = line.len() as u64;
        if !whole {
            return Ok(Some(Record::Partial { len }));
        }
        let count = String::from_utf8_lossy(&line).trim().parse::<usize>().ok();
        if count != Some(self.particles) {
            return Err(invalid(format!(
                "a frame starts with '{}' where this run's {} particles were expected; give \
                 the resumed run a new file with --trajectory",
                String::from_utf8_lossy(&line).trim_end(),
                self.particles
            )));
        }
        let mut time = None;
        for i in 0..=self.particles {
            match read_line(reader, &mut line)? {
                Some(true) => len += line.len() as u64,
                Some(false) => {
                    len += line.len() as u64;
                    return Ok(Some(Record::Partial { len }));
                }
                None => return Ok(Some(Record::Partial { len })),
            }
            if i == 0 {
                time = frame_time(&String::from_utf8_lossy(&line));
            }
        }
        match time {
            Some(time) => Ok(Some(Record::Whole { len, time })),
            None => Err(invalid(
                "a frame's header line has no Time= field; give the resumed run a new file \
                 with --trajectory"
                    .into(),
            )),
        }
    }
}

/// The `Time=` field of an extended-XYZ header line.
fn frame_time(header: &str) -> Option<f64> {
    header
        .split_whitespace()
        .find_map(|field| field.strip_prefix("Time="))
        .and_then(|t| t.parse().ok())
}
