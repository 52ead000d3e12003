//! The counted exact fallback of physical lookups ([`WithFallback`]).

use crate::error::TableError;
use crate::pair_map::PairMap;
use crate::pair_table::PairTable;
use crate::table::{PhysicalLookup, Table};
use emdstar_contact::{Impact, Model, Mor, ScaledParams};
use std::ops::Deref;

/// Where a [`WithFallback`] answer came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    Table,
    ExactSolve,
}

/// A table plus a caller-chosen exact solver for points outside the box.
///
/// The reader cannot solve the collision ODE itself (it does not depend on the solver);
/// the caller passes one, e.g. `|m, p| emdstar_mor::solve(m, p).map_err(|e| e.to_string())`.
/// Every fallback is counted in [`WithFallback::fallbacks`].
pub struct WithFallback<'t, F> {
    table: &'t Table,
    solve: F,
    fallbacks: std::sync::atomic::AtomicU64,
}

impl<'t, F> WithFallback<'t, F>
where
    F: Fn(Model, &ScaledParams) -> Result<Mor, String>,
{
    pub fn new(table: &'t Table, solve: F) -> Self {
        Self {
            table,
            solve,
            fallbacks: 0.into(),
        }
    }

    /// Table lookup, or the exact solve when the point lies outside the box.
    pub fn lookup_scaled(&self, p: &ScaledParams) -> Result<(Mor, Source), TableError> {
        match self.table.lookup_scaled(p) {
            Ok(m) => Ok((m, Source::Table)),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) => {
                self.fallbacks
                    .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let m = (self.solve)(self.table.model, p).map_err(TableError::Fallback)?;
                Ok((m, Source::ExactSolve))
            }
            Err(e) => Err(e),
        }
    }

    /// Table lookup of a physical impact of the pair of `map`, or the exact solve when
    /// it lies outside the box.
    pub fn lookup_pair(
        &self,
        map: &PairMap,
        impact: &Impact,
    ) -> Result<(PhysicalLookup, Source), TableError> {
        let hit = self.table.lookup_pair(map, impact);
        self.or_solve(hit, map, impact)
    }

    /// [`WithFallback::lookup_pair`] through a pair table (of this fallback's table:
    /// the exact solves use its model).
    pub fn lookup_pair_table<T: Deref<Target = Table>>(
        &self,
        own: &PairTable<T>,
        impact: &Impact,
    ) -> Result<(PhysicalLookup, Source), TableError> {
        self.table.expect_model(own.table().model)?;
        self.or_solve(own.lookup(impact), own.map(), impact)
    }

    /// A table's answer, or the counted exact solve where the table does not answer.
    fn or_solve(
        &self,
        hit: Result<PhysicalLookup, TableError>,
        map: &PairMap,
        impact: &Impact,
    ) -> Result<(PhysicalLookup, Source), TableError> {
        match hit {
            Ok(hit) => Ok((hit, Source::Table)),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) => {
                self.fallbacks
                    .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let s = emdstar_contact::scale(map.law(), map.pair(), impact)?;
                let mor =
                    (self.solve)(self.table.model, &s.params).map_err(TableError::Fallback)?;
                Ok((
                    PhysicalLookup {
                        mor,
                        time: s.time,
                        length: s.length,
                    },
                    Source::ExactSolve,
                ))
            }
            Err(e) => Err(e),
        }
    }

    /// Number of exact solves so far.
    pub fn fallbacks(&self) -> u64 {
        self.fallbacks.load(std::sync::atomic::Ordering::Relaxed)
    }
}
