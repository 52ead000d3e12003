//! The coefficients of a piece as the file stores them: every Chebyshev coefficient
//! rounded to a multiple k·q of the table's quantum q, and the integers k bit-packed,
//! each group of a patch with the width its largest member needs.
//!
//! Stream (64-bit little-endian words, bits taken from the least significant end), per
//! patch: one bit, 1 when the patch is tabulated (0: an all-NaN patch, nothing else
//! follows); then per quantity and per total degree d = 0, 1, …, n of the terms: a
//! 6-bit width w and the terms of degree d (in storage order) as w-bit zigzag integers
//! (k ≥ 0 ↦ 2k, k < 0 ↦ −2k − 1). The high-degree coefficients of a smooth patch are
//! small, so they take few bits. Unused bits of the last word are zero.

use crate::error::TableError;
use crate::poly::{NQ, Terms};

/// Width of a group at most: the integers k stay below 2^53 in magnitude (exact in
/// float64), their zigzag codes below 2^54.
const MAX_BITS: u32 = 54;

/// The quantum of a table with error goal `tolerance`: the largest power of two not
/// above tolerance/256. A patch of t terms then moves by at most t·q/2 (below 0.24 of
/// the goal for the 120 terms of degree 7, 0.56 for the 286 of degree 10), typically by
/// about √t·q/3.5.
pub fn quantum(tolerance: f64) -> f64 {
    let target = tolerance / 256.0;
    let mut q = 1.0f64;
    while q > target {
        q *= 0.5;
    }
    while q * 2.0 <= target {
        q *= 2.0;
    }
    q
}

/// `x` rounded to the nearest multiple of `q` (a power of two: the product is exact).
#[inline]
pub fn quantize(x: f64, q: f64) -> f64 {
    (x / q).round() * q
}

/// Whether `x` (a multiple of q) packs: finite, |x/q| < 2^53.
pub fn packable(x: f64, q: f64) -> bool {
    x.is_finite() && (x / q).abs() < (1u64 << (MAX_BITS - 1)) as f64
}

/// The term indices of each total degree 0..=n, in storage order.
fn shells(terms: &Terms) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new(); terms.degree + 1];
    for (k, p) in terms.powers.iter().enumerate() {
        out[p.iter().sum::<usize>()].push(k);
    }
    out
}

#[cfg(feature = "write")]
struct Writer {
    words: Vec<u64>,
    bits: u64,
}

#[cfg(feature = "write")]
impl Writer {
    fn push(&mut self, value: u64, width: u32) {
        if width == 0 {
            return;
        }
        let used = (self.bits % 64) as u32;
        if used == 0 {
            self.words.push(0);
        }
        let last = self.words.len() - 1;
        self.words[last] |= value << used;
        if used + width > 64 {
            self.words.push(value >> (64 - used));
        }
        self.bits += width as u64;
    }
}

struct Reader<'a> {
    words: &'a [u64],
    bits: u64,
}

impl Reader<'_> {
    fn take(&mut self, width: u32) -> Option<u64> {
        if width == 0 {
            return Some(0);
        }
        let (word, used) = ((self.bits / 64) as usize, (self.bits % 64) as u32);
        let mut v = *self.words.get(word)? >> used;
        if used + width > 64 {
            v |= *self.words.get(word + 1)? << (64 - used);
        }
        self.bits += width as u64;
        Some(if width == 64 {
            v
        } else {
            v & ((1u64 << width) - 1)
        })
    }
}

#[cfg(feature = "write")]
fn zigzag(k: i64) -> u64 {
    ((k << 1) ^ (k >> 63)) as u64
}

fn unzigzag(z: u64) -> i64 {
    (z >> 1) as i64 ^ -((z & 1) as i64)
}

/// Packs `cheb` (`[patch][term][quantity]`, every value a packable multiple of `q`, or
/// a whole patch NaN).
#[cfg(feature = "write")]
#[allow(clippy::needless_range_loop)] // i indexes the quantity of each term, not `block`
pub fn pack(cheb: &[[f64; NQ]], terms: &Terms, q: f64) -> Vec<u64> {
    let shells = shells(terms);
    let mut w = Writer {
        words: Vec::new(),
        bits: 0,
    };
    for block in cheb.chunks_exact(terms.len()) {
        let tabulated = !block.iter().flatten().all(|x| x.is_nan());
        w.push(tabulated as u64, 1);
        if !tabulated {
            continue;
        }
        for i in 0..NQ {
            for shell in &shells {
                let z: Vec<u64> = shell
                    .iter()
                    .map(|&k| zigzag((block[k][i] / q) as i64))
                    .collect();
                let width = 64 - z.iter().fold(0, |m, &x| m | x).leading_zeros();
                w.push(width as u64, 6);
                for x in z {
                    w.push(x, width);
                }
            }
        }
    }
    w.words
}

/// Unpacks `patches` patches of `terms` (the inverse of [`pack`]).
#[allow(clippy::needless_range_loop)] // as in `pack`
pub fn unpack(
    words: &[u64],
    terms: &Terms,
    patches: usize,
    q: f64,
) -> Result<Vec<[f64; NQ]>, TableError> {
    let short = || TableError::Corrupt("the packed coefficients are cut short".into());
    let shells = shells(terms);
    let nt = terms.len();
    let mut r = Reader { words, bits: 0 };
    let mut out = Vec::with_capacity(patches.saturating_mul(nt).min(words.len() * 64));
    for _ in 0..patches {
        let start = out.len();
        out.extend(std::iter::repeat_n([f64::NAN; NQ], nt));
        if r.take(1).ok_or_else(short)? == 0 {
            continue;
        }
        let block = &mut out[start..];
        for i in 0..NQ {
            for shell in &shells {
                let width = r.take(6).ok_or_else(short)? as u32;
                if width > MAX_BITS {
                    return Err(TableError::Corrupt(format!(
                        "a packed coefficient group is {width} bits wide (at most {MAX_BITS})"
                    )));
                }
                for &k in shell {
                    block[k][i] = unzigzag(r.take(width).ok_or_else(short)?) as f64 * q;
                }
            }
        }
    }
    let rest = words.len() as u64 * 64 - r.bits;
    if rest >= 64 || (rest > 0 && words[words.len() - 1] >> (64 - rest) != 0) {
        return Err(TableError::Corrupt(format!(
            "{rest} bits follow the packed coefficients"
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantum_is_the_largest_power_of_two_within_the_goal() {
        assert_eq!(quantum(7e-7), 2f64.powi(-29));
        assert_eq!(quantum(1e-3), 2f64.powi(-18));
        assert_eq!(quantum(256.0), 1.0);
        assert!(quantum(7e-7) <= 7e-7 / 256.0 && 2.0 * quantum(7e-7) > 7e-7 / 256.0);
    }

    #[test]
    fn packing_round_trips_and_rejects_damage() {
        let terms = Terms::new(3, [3, 3, 3]);
        let q = quantum(1e-6);
        let nt = terms.len();
        let mut cheb: Vec<[f64; NQ]> = (0..3 * nt)
            .map(|k| {
                std::array::from_fn(|i| {
                    let x = ((k * 37 + i * 11) % 29) as f64 - 14.0;
                    quantize(x * 10f64.powi(-((k % nt) as i32)), q)
                })
            })
            .collect();
        cheb[nt..2 * nt].fill([f64::NAN; NQ]);
        cheb[5][2] = quantize(-3.5e9 * q, q);
        let words = pack(&cheb, &terms, q);
        let back = unpack(&words, &terms, 3, q).unwrap();
        for (a, b) in cheb.iter().flatten().zip(back.iter().flatten()) {
            assert!(a == b || (a.is_nan() && b.is_nan()), "{a} {b}");
        }
        assert!(unpack(&words[..words.len() - 1], &terms, 3, q).is_err());
        let mut extra = words.clone();
        extra.push(0);
        assert!(unpack(&extra, &terms, 3, q).is_err());
        assert!(unpack(&words, &terms, 2, q).is_err());
    }
}
