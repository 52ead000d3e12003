//! Shards of a table build and their merge: shard `i/n` refines the contiguous unit
//! range `[U·i/n, U·(i+1)/n)`, and [`merge`] joins the parts into exactly the bytes of a
//! single run.

use crate::generate::{Solver, UnitTree, assemble, generator_version, refine, unit_count, units};
use crate::spec::Spec;
use emdstar_table::npz::{Array, Data, read_npz, write_npz};
use emdstar_table::{NQ, Table};

/// Unit range of shard `i` of `n` (0-based i).
pub fn shard_range(spec: &Spec, i: usize, n: usize) -> std::ops::Range<usize> {
    let total = unit_count(spec);
    total * i / n..total * (i + 1) / n
}

/// Builds shard `i` of `n` as a part file (bytes).
pub fn build_shard(
    spec: &Spec,
    solve: &Solver,
    i: usize,
    n: usize,
    progress: bool,
) -> Result<Vec<u8>, String> {
    if n == 0 || i >= n {
        return Err(format!(
            "shard {i}/{n} is invalid: use --shard I/N with 0 <= I < N"
        ));
    }
    let range = shard_range(spec, i, n);
    let trees = refine(spec, solve, &units(spec)[range.clone()], progress)?;
    let sizes: Vec<i64> = trees
        .iter()
        .flat_map(|t| [t.tree.len() as i64, t.cheb.len() as i64])
        .collect();
    Ok(write_npz(&[
        ("part_of", Array::str_scalar(&generator_version())),
        ("spec", Array::str_scalar(&spec.text)),
        ("shard", Array::i64(vec![2], vec![i as i64, n as i64])),
        (
            "range",
            Array::i64(vec![2], vec![range.start as i64, range.end as i64]),
        ),
        ("sizes", Array::i64(vec![trees.len(), 2], sizes)),
        (
            "tree",
            Array::i64(
                vec![trees.iter().map(|t| t.tree.len()).sum(), 2],
                trees
                    .iter()
                    .flat_map(|t| t.tree.iter().flatten())
                    .copied()
                    .collect(),
            ),
        ),
        (
            "split",
            Array::f64(
                vec![trees.iter().map(|t| t.split.len()).sum()],
                trees.iter().flat_map(|t| t.split.iter()).copied().collect(),
            ),
        ),
        (
            "coef",
            Array::f64(
                vec![trees.iter().map(|t| t.cheb.len()).sum(), NQ],
                trees
                    .iter()
                    .flat_map(|t| t.cheb.iter().flatten())
                    .copied()
                    .collect(),
            ),
        ),
        (
            "error",
            Array::f64(
                vec![trees.len(), NQ],
                trees.iter().flat_map(|t| t.error).collect(),
            ),
        ),
    ]))
}

/// Merges the part files of all shards (any order) into the table.
pub fn merge(parts: &[Vec<u8>]) -> Result<Table, String> {
    let mut pieces = Vec::new();
    let mut spec_text: Option<String> = None;
    for (p, bytes) in parts.iter().enumerate() {
        let members = read_npz(bytes).map_err(|e| format!("part {}: {e}", p + 1))?;
        let find = |name: &str| {
            members
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, a)| &a.data)
                .ok_or_else(|| format!("part {} is not a shard file (no {name})", p + 1))
        };
        let (
            Data::Str(spec),
            Data::I64(shard),
            Data::I64(range),
            Data::I64(sizes),
            Data::I64(tree),
            Data::F64(split),
            Data::F64(coef),
            Data::F64(error),
        ) = (
            find("spec")?,
            find("shard")?,
            find("range")?,
            find("sizes")?,
            find("tree")?,
            find("split")?,
            find("coef")?,
            find("error")?,
        )
        else {
            return Err(format!("part {} has malformed members", p + 1));
        };
        match &spec_text {
            None => spec_text = Some(spec[0].clone()),
            Some(s) if *s != spec[0] => {
                return Err(format!("part {} was built from a different spec", p + 1));
            }
            _ => {}
        }
        let malformed = || format!("part {} has inconsistent sizes", p + 1);
        let mut trees = Vec::new();
        let (mut n0, mut c0) = (0usize, 0usize);
        for (u, s) in sizes.chunks_exact(2).enumerate() {
            let (nn, nc) = (s[0] as usize, s[1] as usize);
            let t = UnitTree {
                tree: tree
                    .get(2 * n0..2 * (n0 + nn))
                    .ok_or_else(malformed)?
                    .chunks_exact(2)
                    .map(|c| [c[0], c[1]])
                    .collect(),
                split: split.get(n0..n0 + nn).ok_or_else(malformed)?.to_vec(),
                cheb: coef
                    .get(NQ * c0..NQ * (c0 + nc))
                    .ok_or_else(malformed)?
                    .chunks_exact(NQ)
                    .map(|c| [c[0], c[1], c[2], c[3]])
                    .collect(),
                error: error
                    .get(NQ * u..NQ * (u + 1))
                    .ok_or_else(malformed)?
                    .try_into()
                    .expect("four values"),
            };
            n0 += nn;
            c0 += nc;
            trees.push(t);
        }
        pieces.push((
            shard[0],
            shard[1],
            range[0] as usize,
            range[1] as usize,
            trees,
        ));
    }
    let spec = Spec::parse(spec_text.as_deref().ok_or("no parts given")?)?;
    pieces.sort_by_key(|p| p.0);
    let n = pieces[0].1;
    let mut next = 0;
    let mut trees = Vec::with_capacity(unit_count(&spec));
    for (k, (i, nn, start, end, t)) in pieces.into_iter().enumerate() {
        if nn != n || i != k as i64 || start != next || t.len() != end - start {
            return Err(format!(
                "the parts do not form shards 0..{n} of one run: shard {k} is missing, \
                 duplicated or inconsistent"
            ));
        }
        next = end;
        trees.extend(t);
    }
    if next != unit_count(&spec) {
        return Err(format!(
            "the parts stop at unit {next} of {}: a shard is missing",
            unit_count(&spec)
        ));
    }
    assemble(&spec, trees)
}
