//! Pair handles: one law and one pair of bodies, checked once, for many lookups.

use crate::{
    EmdstarMor, EmdstarSource, EmdstarStatus, EmdstarTable, Failure, TableRef, guarded, input_err,
    make, put, table_err, table_of,
};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, PairLaw, PairProperties, Sphere, ViscoelasticHertz, scale,
};
use emdstar_table::{PairTable, TableError};
use std::sync::atomic::{AtomicU64, Ordering};

/// A pair of bodies and their force law on one table (opaque): the table restricted to
/// the pair's impacts (`emdstar_table::PairTable`).
pub struct EmdstarPair {
    pub(crate) own: PairTable<TableRef>,
    /// Exact solves done for this pair's lookups.
    pub(crate) fallbacks: AtomicU64,
}

/// Two spheres, or (radius2 = mass2 = 0) a sphere against a flat wall.
fn pair_of(r1: f64, m1: f64, r2: f64, m2: f64) -> Result<PairProperties, Failure> {
    let a = Sphere::new(r1, m1).map_err(input_err)?;
    if r2 == 0.0 && m2 == 0.0 {
        return Ok(PairProperties::sphere_wall(&a));
    }
    Ok(PairProperties::spheres(
        &a,
        &Sphere::new(r2, m2).map_err(input_err)?,
    ))
}

fn new_pair(
    table: *const EmdstarTable,
    law: Result<ForceLaw, emdstar_contact::ContactError>,
    bodies: [f64; 4],
) -> *mut EmdstarPair {
    make(|| {
        // SAFETY: the caller passes NULL or a live table.
        let t = unsafe { table_of(table) }?.clone();
        let [r1, m1, r2, m2] = bodies;
        let pair = pair_of(r1, m1, r2, m2)?;
        let law =
            PairLaw::same_material(&law.map_err(input_err)?, pair.r_eff).map_err(input_err)?;
        Ok(EmdstarPair {
            own: PairTable::new(t, &law, &pair).map_err(table_err)?,
            fallbacks: AtomicU64::new(0),
        })
    })
}

/// A pair of linear spring-dashpot spheres of one material (k in N/m, γ in kg/s; radii
/// in m, masses in kg; radius2 = mass2 = 0 for a flat wall). NULL on failure. Free it
/// with `emdstar_pair_free`; it keeps its table alive.
///
/// A pair holds the table restricted to its impacts (built here in about a
/// millisecond, some 100-200 KiB), so that each of its lookups costs about half a
/// lookup from physical parameters: build one per pair of materials and keep it.
///
/// # Safety
/// `table` must be NULL or a live table handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_linear(
    table: *const EmdstarTable,
    stiffness: f64,
    damping: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
) -> *mut EmdstarPair {
    let law = LinearDashpot::new(stiffness, damping).map(ForceLaw::Linear);
    new_pair(table, law, [radius1, mass1, radius2, mass2])
}

/// A pair of viscoelastic Hertz spheres of one material (Y in Pa, Poisson ratio, A in s;
/// radii in m, masses in kg; radius2 = mass2 = 0 for a flat wall). NULL on failure.
///
/// # Safety
/// `table` must be NULL or a live table handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_hertz(
    table: *const EmdstarTable,
    young: f64,
    poisson: f64,
    dissipation: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
) -> *mut EmdstarPair {
    let law = ViscoelasticHertz::new(young, poisson, dissipation).map(ForceLaw::Hertz);
    new_pair(table, law, [radius1, mass1, radius2, mass2])
}

/// Frees a pair; NULL is ignored.
///
/// # Safety
/// `pair` must be NULL or a pair handle not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_free(pair: *mut EmdstarPair) {
    // SAFETY: by the caller's contract.
    unsafe { crate::free(pair) }
}

/// Number of exact solves the pair's lookups have made (with `exact_fallback` set).
///
/// # Safety
/// `pair` must be NULL (gives 0) or a live pair handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_fallbacks(pair: *const EmdstarPair) -> u64 {
    if pair.is_null() {
        return 0;
    }
    // SAFETY: non-null and live by the caller's contract.
    unsafe { &*pair }.fallbacks.load(Ordering::Relaxed)
}

/// # Safety
/// `pair` must be NULL or a live pair handle.
pub(crate) unsafe fn pair_of_ptr<'a>(pair: *const EmdstarPair) -> Result<&'a EmdstarPair, Failure> {
    if pair.is_null() {
        return Err(input_err("pair is NULL"));
    }
    // SAFETY: non-null and live by the caller's contract.
    Ok(unsafe { &*pair })
}

impl EmdstarPair {
    /// The MoR of an impact: the table, or with `exact_fallback` the exact solver where
    /// the table does not answer (counted).
    pub(crate) fn mor(&self, impact: &Impact, exact_fallback: bool) -> Result<EmdstarMor, Failure> {
        match self.own.lookup(impact) {
            Ok(hit) => Ok(EmdstarMor::new(&hit.mor, hit.time, EmdstarSource::Table)),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) if exact_fallback => {
                self.fallbacks.fetch_add(1, Ordering::Relaxed);
                let map = self.own.map();
                let scaled = scale(map.law(), map.pair(), impact).map_err(input_err)?;
                let m = emdstar_mor::solve(self.own.table().model(), &scaled.params)
                    .map_err(|e| (EmdstarStatus::SolveFailed, e.to_string()))?;
                Ok(EmdstarMor::new(&m, scaled.time, EmdstarSource::Exact))
            }
            Err(e) => Err(table_err(e)),
        }
    }
}

/// MoR of an impact of the pair: normal and tangential speed at contact in m/s. With
/// `exact_fallback` nonzero, impacts the table does not answer are solved exactly
/// (`out->source` says which, `emdstar_pair_fallbacks` counts them); with 0 they fail
/// with `EMDSTAR_STATUS_OUT_OF_BOX` or `EMDSTAR_STATUS_NOT_TABULATED`.
///
/// # Safety
/// `pair` from a pair constructor; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_lookup(
    pair: *const EmdstarPair,
    normal_speed: f64,
    tangential_speed: f64,
    exact_fallback: i32,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let p = unsafe { pair_of_ptr(pair) }?;
        let impact = Impact {
            normal_speed,
            tangential_speed,
        };
        let m = p.mor(&impact, exact_fallback != 0)?;
        // SAFETY: by the caller's contract.
        unsafe { put(out, m) }
    })
}
