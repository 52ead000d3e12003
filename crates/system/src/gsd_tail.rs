//! Reading back what [`crate::gsd::GsdWriter`] wrote, to resume a run: the header, the
//! index, and for each frame whether it is whole and its time (see the writer's module
//! documentation for the layout).

use crate::tail::KeepUntil;
use std::fs::File;
use std::io::{self, ErrorKind, Read, Seek, SeekFrom};

/// What a resumed writer keeps of an existing file.
pub(crate) struct Kept {
    pub index_location: u64,
    pub index_capacity: u64,
    /// The index entries of the frames kept, in file order.
    pub entries: Vec<[u8; 32]>,
    pub frames: u64,
    /// Where the next data chunk goes: after the kept frames' data and the index.
    pub end: u64,
    /// The first frame's box centre (fixed for free-space boxes).
    pub first_centre: Option<[f64; 3]>,
    /// Whole frames stamped after the resume time, and whether an unfinished one was
    /// left (its bytes beyond `end`).
    pub cut_frames: u64,
    pub partial_bytes: u64,
}

fn invalid(what: String) -> io::Error {
    io::Error::new(
        ErrorKind::InvalidData,
        format!("{what}; give the resumed run a new file with --trajectory"),
    )
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

fn read_at(file: &mut File, at: u64, len: u64) -> io::Result<Vec<u8>> {
    let mut b = vec![0; len as usize];
    file.seek(SeekFrom::Start(at))?;
    file.read_exact(&mut b)?;
    Ok(b)
}

/// Bytes per element of a GSD type (gsd.h, `enum gsd_type`).
fn type_size(kind: u8) -> Option<u64> {
    Some(match kind {
        1 | 5 => 1,
        2 | 6 => 2,
        3 | 7 | 9 => 4,
        4 | 8 | 10 => 8,
        _ => return None,
    })
}

/// Reads the GSD file `file`, which must be one this crate wrote (its magic, application
/// and name list `names`), and keeps its frames up to the first that is unfinished or
/// that `keep` does not keep. Errors on a frame of other than `particles` particles and
/// `species` species.
pub(crate) fn keep_until(
    file: &mut File,
    names: &[u8],
    keep: KeepUntil,
    particles: u64,
    species: u64,
) -> io::Result<Kept> {
    let len = file.metadata()?.len();
    if len < crate::gsd::HEADER_BYTES + names.len() as u64 {
        return Err(invalid("the GSD file is shorter than its header".into()));
    }
    let header = read_at(file, 0, crate::gsd::HEADER_BYTES)?;
    let namelist = read_at(file, crate::gsd::HEADER_BYTES, names.len() as u64)?;
    let magic = u64_at(&header, 0) == crate::gsd::MAGIC;
    let ours = header[48..].starts_with(b"emdstar ") && namelist == names;
    if !magic || !ours {
        return Err(invalid(
            "the file is not a GSD trajectory written by emdstar".into(),
        ));
    }
    let (index_location, index_capacity) = (u64_at(&header, 8), u64_at(&header, 16));
    let index_bytes = index_capacity
        .checked_mul(crate::gsd::ENTRY_BYTES)
        .filter(|&b| index_location.checked_add(b).is_some_and(|e| e <= len))
        .ok_or_else(|| invalid("the GSD index lies beyond the end of the file".into()))?;
    let index = read_at(file, index_location, index_bytes)?;
    let entries: Vec<[u8; 32]> = index
        .chunks_exact(crate::gsd::ENTRY_BYTES as usize)
        .map(|e| e.try_into().expect("32 bytes"))
        .take_while(|e: &[u8; 32]| u64_at(e, 16) != 0)
        .collect();
    let per_frame = crate::gsd::NAMES.len();
    let time_id = crate::gsd::name_id("log/time");
    let n_id = crate::gsd::name_id("particles/N");
    let types_id = crate::gsd::name_id("particles/types");
    let centre_id = crate::gsd::name_id("log/box_centre");
    let index_end = index_location + index_bytes;
    let mut kept = Kept {
        index_location,
        index_capacity,
        entries: Vec::new(),
        frames: 0,
        end: index_end,
        first_centre: None,
        cut_frames: 0,
        partial_bytes: 0,
    };
    // Where the data of every whole frame ends (the kept ones set `kept.end`).
    let mut whole_end = 0;
    for (frame, group) in entries.chunks(per_frame).enumerate() {
        let whole = group.len() == per_frame
            && group.iter().enumerate().all(|(k, e)| {
                u64_at(e, 0) == frame as u64
                    && usize::from(u16::from_le_bytes([e[28], e[29]])) == k
                    && chunk_end(e).is_some_and(|end| end <= len)
            });
        if !whole {
            break;
        }
        let end = group.iter().filter_map(chunk_end).max().unwrap_or(0);
        whole_end = whole_end.max(end);
        let time = f64::from_le_bytes(value::<8>(file, &group[usize::from(time_id)])?);
        let n = u32::from_le_bytes(value::<4>(file, &group[usize::from(n_id)])?);
        let types = u64_at(&group[usize::from(types_id)], 8);
        if u64::from(n) != particles || types != species {
            return Err(invalid(format!(
                "frame {frame} of the GSD file holds {n} particles of {types} species where \
                 this run has {particles} of {species}"
            )));
        }
        if !keep.keeps(time) || kept.cut_frames > 0 {
            kept.cut_frames += 1;
            continue;
        }
        if frame == 0 {
            let c = value::<24>(file, &group[usize::from(centre_id)])?;
            kept.first_centre = Some(std::array::from_fn(|k| {
                f64::from_le_bytes(c[8 * k..8 * k + 8].try_into().expect("8 bytes"))
            }));
        }
        kept.entries.extend_from_slice(group);
        kept.frames += 1;
        kept.end = index_end.max(end);
    }
    kept.partial_bytes = len.saturating_sub(index_end.max(whole_end));
    Ok(kept)
}

/// Where the data of the chunk of index entry `e` ends, if it has a known type.
fn chunk_end(e: &[u8; 32]) -> Option<u64> {
    let cols = u64::from(u32::from_le_bytes(e[24..28].try_into().expect("4 bytes")));
    let size = type_size(e[30])?
        .checked_mul(u64_at(e, 8))?
        .checked_mul(cols)?;
    u64_at(e, 16).checked_add(size)
}

/// The first `N` bytes of the chunk of index entry `e` (a value of one element).
fn value<const N: usize>(file: &mut File, e: &[u8; 32]) -> io::Result<[u8; N]> {
    if chunk_end(e).is_none_or(|end| end - u64_at(e, 16) < N as u64) {
        return Err(invalid("a GSD chunk is shorter than its value".into()));
    }
    let b = read_at(file, u64_at(e, 16), N as u64)?;
    Ok(b.try_into().expect("N bytes"))
}
