//! A minimal, dependency-free codec for uncompressed `.npz` files: a zip archive
//! (method 0, "stored") of `.npy` arrays (format 1.0), as `numpy.savez` writes and
//! `numpy.load` reads them.
//!
//! Only what the table format needs: little-endian `f64`, `f32`, `i64`, `u64` arrays of any
//! shape in C order, and unicode strings (`<U`n, 0-d or 1-d). Writing is
//! deterministic: fixed member order, fixed timestamps (1980-01-01), no extra fields.

use crate::error::TableError;

/// The payload of one array.
#[derive(Debug, Clone, PartialEq)]
pub enum Data {
    F64(Vec<f64>),
    F32(Vec<f32>),
    I64(Vec<i64>),
    U64(Vec<u64>),
    /// Strings of at most `width` code points each.
    Str(Vec<String>),
}

/// One named array: shape (C order) and data.
#[derive(Debug, Clone, PartialEq)]
pub struct Array {
    pub shape: Vec<usize>,
    pub data: Data,
}

impl Array {
    pub fn f64(shape: Vec<usize>, v: Vec<f64>) -> Self {
        Self {
            shape,
            data: Data::F64(v),
        }
    }
    pub fn f32(shape: Vec<usize>, v: Vec<f32>) -> Self {
        Self {
            shape,
            data: Data::F32(v),
        }
    }
    pub fn i64(shape: Vec<usize>, v: Vec<i64>) -> Self {
        Self {
            shape,
            data: Data::I64(v),
        }
    }
    pub fn u64(shape: Vec<usize>, v: Vec<u64>) -> Self {
        Self {
            shape,
            data: Data::U64(v),
        }
    }
    pub fn u64_scalar(x: u64) -> Self {
        Self {
            shape: vec![],
            data: Data::U64(vec![x]),
        }
    }
    pub fn str_scalar(s: &str) -> Self {
        Self {
            shape: vec![],
            data: Data::Str(vec![s.to_string()]),
        }
    }
    pub fn str_list(v: Vec<String>) -> Self {
        Self {
            shape: vec![v.len()],
            data: Data::Str(v),
        }
    }

    /// The `.npy` bytes of the array (format version 1.0, header padded to 64 bytes).
    pub fn to_npy(&self) -> Vec<u8> {
        let descr = match &self.data {
            Data::F64(_) => "<f8".to_string(),
            Data::F32(_) => "<f4".to_string(),
            Data::I64(_) => "<i8".to_string(),
            Data::U64(_) => "<u8".to_string(),
            Data::Str(v) => format!("<U{}", str_width(v)),
        };
        let shape = match self.shape.len() {
            0 => "()".to_string(),
            1 => format!("({},)", self.shape[0]),
            _ => format!(
                "({})",
                self.shape
                    .iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = Vec::with_capacity(10 + header.len() + 8 * self.len());
        out.extend_from_slice(b"\x93NUMPY\x01\x00");
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        match &self.data {
            Data::F64(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Data::F32(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Data::I64(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Data::U64(v) => v
                .iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
            Data::Str(v) => {
                let width = str_width(v);
                for s in v {
                    let mut n = 0;
                    for ch in s.chars() {
                        out.extend_from_slice(&(ch as u32).to_le_bytes());
                        n += 1;
                    }
                    out.extend(std::iter::repeat_n(0u8, 4 * (width - n)));
                }
            }
        }
        out
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Parses `.npy` bytes of one of the supported dtypes.
    pub fn from_npy(name: &str, b: &[u8]) -> Result<Self, TableError> {
        let corrupt = |why: String| TableError::Corrupt(format!("member {name}: {why}"));
        if b.len() < 10 || &b[..6] != b"\x93NUMPY" {
            return Err(corrupt("not an .npy array (bad magic)".into()));
        }
        let (hlen, start) = match b[6] {
            1 => (u16::from_le_bytes([b[8], b[9]]) as usize, 10),
            2 | 3 if b.len() >= 12 => (u32::from_le_bytes([b[8], b[9], b[10], b[11]]) as usize, 12),
            v => return Err(corrupt(format!("unsupported .npy version {v}"))),
        };
        let header = b
            .get(start..start + hlen)
            .and_then(|h| std::str::from_utf8(h).ok())
            .ok_or_else(|| corrupt("unreadable .npy header".into()))?;
        let descr = dict_value(header, "descr")
            .ok_or_else(|| corrupt("no descr in header".into()))?
            .trim_matches('\'');
        if dict_value(header, "fortran_order") != Some("False") {
            return Err(corrupt("only C-order arrays are supported".into()));
        }
        let shape_txt = dict_value(header, "shape").ok_or_else(|| corrupt("no shape".into()))?;
        let shape = shape_txt
            .trim_matches(|c| c == '(' || c == ')')
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|s| s.parse::<usize>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| corrupt(format!("bad shape {shape_txt}")))?;
        let n = shape
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .ok_or_else(|| corrupt(format!("shape {shape:?} is too large")))?;
        let body = &b[start + hlen..];
        let item = if let Some(w) = descr.strip_prefix("<U") {
            w.parse::<usize>()
                .ok()
                .and_then(|w| w.checked_mul(4))
                .ok_or_else(|| corrupt(format!("bad dtype {descr}")))?
        } else if descr == "<f4" {
            4
        } else {
            8
        };
        if n.checked_mul(item) != Some(body.len()) {
            return Err(corrupt(format!(
                "expected {} data bytes for shape {shape:?}, found {}",
                n.saturating_mul(item),
                body.len()
            )));
        }
        let words = || body.chunks_exact(8).map(|c| c.try_into().expect("8 bytes"));
        let data = match descr {
            "<f8" => Data::F64(words().map(f64::from_le_bytes).collect()),
            "<f4" => Data::F32(
                body.chunks_exact(4)
                    .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
                    .collect(),
            ),
            "<i8" => Data::I64(words().map(i64::from_le_bytes).collect()),
            "<u8" => Data::U64(words().map(u64::from_le_bytes).collect()),
            d if d.starts_with("<U") => {
                let mut v = Vec::with_capacity(n);
                for chunk in body.chunks_exact(item.max(1)).take(n) {
                    let s: Option<String> = chunk
                        .chunks_exact(4)
                        .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
                        .take_while(|&u| u != 0)
                        .map(char::from_u32)
                        .collect();
                    v.push(s.ok_or_else(|| corrupt("invalid unicode".into()))?);
                }
                if item == 0 {
                    v.resize(n, String::new());
                }
                Data::Str(v)
            }
            d => return Err(corrupt(format!("unsupported dtype {d}"))),
        };
        Ok(Self { shape, data })
    }
}

fn str_width(v: &[String]) -> usize {
    v.iter()
        .map(|s| s.chars().count())
        .max()
        .unwrap_or(0)
        .max(1)
}

/// The text after `'key':` in a numpy header dict, up to the next top-level comma.
fn dict_value<'h>(header: &'h str, key: &str) -> Option<&'h str> {
    let pat = format!("'{key}':");
    let rest = header[header.find(&pat)? + pat.len()..].trim_start();
    let mut depth = 0;
    for (i, ch) in rest.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' | '}' if depth == 0 => return Some(rest[..i].trim()),
            _ => {}
        }
    }
    None
}

/// CRC-32 (IEEE 802.3, as in zip).
pub fn crc32(bytes: &[u8]) -> u32 {
    static TABLE: std::sync::OnceLock<[u32; 256]> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let mut t = [0u32; 256];
        for (i, e) in t.iter_mut().enumerate() {
            let mut c = i as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
            *e = c;
        }
        t
    });
    let mut c = !0u32;
    for &b in bytes {
        c = table[((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8);
    }
    !c
}

/// Writes a stored (uncompressed) zip of `name.npy` members, in the given order.
#[cfg(feature = "write")]
pub fn write_npz<S: AsRef<str>>(members: &[(S, Array)]) -> Vec<u8> {
    const DOS_DATE: u16 = 33; // 1980-01-01
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, array) in members {
        let file = format!("{}.npy", name.as_ref());
        let body = array.to_npy();
        let crc = crc32(&body);
        let offset = out.len() as u32;
        let size = body.len() as u32;
        let common = |v: &mut Vec<u8>| {
            v.extend_from_slice(&20u16.to_le_bytes()); // version needed
            v.extend_from_slice(&0u16.to_le_bytes()); // flags
            v.extend_from_slice(&0u16.to_le_bytes()); // method: stored
            v.extend_from_slice(&0u16.to_le_bytes()); // time
            v.extend_from_slice(&DOS_DATE.to_le_bytes());
            v.extend_from_slice(&crc.to_le_bytes());
            v.extend_from_slice(&size.to_le_bytes());
            v.extend_from_slice(&size.to_le_bytes());
            v.extend_from_slice(&(file.len() as u16).to_le_bytes());
            v.extend_from_slice(&0u16.to_le_bytes()); // extra length
        };
        out.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        common(&mut out);
        out.extend_from_slice(file.as_bytes());
        out.extend_from_slice(&body);
        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        central.extend_from_slice(&20u16.to_le_bytes()); // version made by
        common(&mut central);
        central.extend_from_slice(&[0u8; 6]); // comment len, disk, internal attrs
        central.extend_from_slice(&0u32.to_le_bytes()); // external attrs
        central.extend_from_slice(&offset.to_le_bytes());
        central.extend_from_slice(file.as_bytes());
    }
    let cd_offset = out.len() as u32;
    let n = members.len() as u16;
    out.extend_from_slice(&central);
    out.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    out.extend_from_slice(&[0u8; 4]);
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&(central.len() as u32).to_le_bytes());
    out.extend_from_slice(&cd_offset.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out
}

/// Reads the members of a stored zip (as written by [`write_npz`] or by
/// `numpy.savez`), verifying each member's CRC-32. Returns (name without `.npy`, array).
pub fn read_npz(bytes: &[u8]) -> Result<Vec<(String, Array)>, TableError> {
    if bytes.len() < 4 || bytes[..4] != [0x50, 0x4b, 0x03, 0x04] {
        return Err(TableError::NotATable(
            "the file does not start like an .npz (zip) archive".into(),
        ));
    }
    let u16_at = |i: usize| {
        bytes
            .get(i..i + 2)
            .map(|s| u16::from_le_bytes([s[0], s[1]]))
    };
    let u32_at = |i: usize| {
        bytes
            .get(i..i + 4)
            .map(|s| u32::from_le_bytes(s.try_into().expect("4 bytes")))
    };
    let truncated = |what: &str| TableError::Truncated(what.to_string());
    // End of central directory: the last 22 bytes when there is no comment.
    let eocd = (0..bytes.len().saturating_sub(21))
        .rev()
        .take(22 + 65535)
        .find(|&i| u32_at(i) == Some(0x0605_4b50))
        .ok_or_else(|| truncated("the zip end-of-archive record"))?;
    let n = u16_at(eocd + 10).ok_or_else(|| truncated("the zip end-of-archive record"))? as usize;
    let mut p =
        u32_at(eocd + 16).ok_or_else(|| truncated("the zip end-of-archive record"))? as usize;
    let mut members = Vec::with_capacity(n);
    for _ in 0..n {
        if u32_at(p) != Some(0x0201_4b50) {
            return Err(truncated("the zip central directory"));
        }
        let method = u16_at(p + 10).ok_or_else(|| truncated("the zip central directory"))?;
        let crc = u32_at(p + 16).ok_or_else(|| truncated("the zip central directory"))?;
        let csize = u32_at(p + 20).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let usize_ = u32_at(p + 24).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let name_len =
            u16_at(p + 28).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let extra_len =
            u16_at(p + 30).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let comment_len =
            u16_at(p + 32).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let local = u32_at(p + 42).ok_or_else(|| truncated("the zip central directory"))? as usize;
        let name = bytes
            .get(p + 46..p + 46 + name_len)
            .map(|s| String::from_utf8_lossy(s).into_owned())
            .ok_or_else(|| truncated("the zip central directory"))?;
        p += 46 + name_len + extra_len + comment_len;
        if method != 0 || csize != usize_ || csize == u32::MAX as usize {
            return Err(TableError::Corrupt(format!(
                "member {name} is compressed or zip64; save tables with numpy.savez (not savez_compressed)"
            )));
        }
        let lname = u16_at(local + 26)
            .ok_or_else(|| truncated(&format!("the header of member {name}")))?
            as usize;
        let lextra = u16_at(local + 28)
            .ok_or_else(|| truncated(&format!("the header of member {name}")))?
            as usize;
        let start = local + 30 + lname + lextra;
        let body = bytes
            .get(start..start + csize)
            .ok_or_else(|| truncated(&format!("the data of member {name}")))?;
        let found = crc32(body);
        if found != crc {
            return Err(TableError::ChecksumMismatch(format!(
                "member {name}: CRC-32 stored {crc:08x}, computed {found:08x}"
            )));
        }
        let key = name.strip_suffix(".npy").unwrap_or(&name).to_string();
        members.push((key.clone(), Array::from_npy(&key, body)?));
    }
    Ok(members)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_matches_the_standard_check_value() {
        // The CRC-32 check value of "123456789" is cbf43926 (ISO 3309 / ITU-T V.42).
        assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
    }

    #[cfg(feature = "write")]
    #[test]
    fn arrays_round_trip() {
        let members = vec![
            (
                "x",
                Array::f64(vec![2, 3], vec![1.0, -2.5, 3.0, 0.0, f64::MIN, 7.0]),
            ),
            ("n", Array::i64(vec![3], vec![1, -2, 3])),
            ("h", Array::u64_scalar(u64::MAX)),
            ("s", Array::str_scalar("hertz ε")),
            ("l", Array::str_list(vec!["a".into(), "bcd".into()])),
        ];
        let bytes = write_npz(&members);
        let back = read_npz(&bytes).unwrap();
        assert_eq!(back.len(), members.len());
        for ((n1, a1), (n2, a2)) in members.iter().zip(&back) {
            assert_eq!(n1, n2);
            assert_eq!(a1, a2);
        }
        let header_len = u16::from_le_bytes([bytes[38 + 5], bytes[38 + 6]]);
        assert_eq!((10 + header_len as usize) % 64, 0);
    }
}
