//! C ABI of the emdstar matrix-of-restitution table reader.
//!
//! - **Tables:** open a file or the embedded default of a model (parsed once per
//!   process and shared, never copied), query its model, box and accuracy, close it.
//! - **Pairs:** a handle for one pair of spheres (or a sphere and a wall) and one law,
//!   built and checked once; lookups through it take only the impact.
//! - **Lookups:** the MoR of an impact, from the table, or — when the caller asks for
//!   it — from the exact solver where the table does not answer (counted per pair).
//! - **Collisions:** the eMD* lab-frame collision rule (Müller & Pöschel 2013, Sec. IV):
//!   positions and velocities after the collision, its duration, and the E^φ/E^v split.
//!
//! Functions returning a status return [`EmdstarStatus::Ok`] (0) on success; on failure
//! [`emdstar_table_last_error`] gives the message (per thread). No panic crosses the
//! boundary: a panic becomes [`EmdstarStatus::Panic`]. Tables and pairs may be used
//! from any number of threads at once (lookups do not modify them; the fallback
//! counter is atomic).
//!
//! The header `include/emdstar_table.h` is generated from this file by cbindgen.

mod collide;
mod pair;

pub use collide::*;
pub use pair::*;

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ScaledParams, Sphere,
    ViscoelasticHertz,
};
use emdstar_table::{Mor, SharedTable, Table, TableError};
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

/// Force model of a table.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmdstarModel {
    /// Linear spring-dashpot.
    Linear = 0,
    /// Viscoelastic Hertz.
    Hertz = 1,
}

impl From<Model> for EmdstarModel {
    fn from(m: Model) -> Self {
        match m {
            Model::Linear => Self::Linear,
            Model::Hertz => Self::Hertz,
        }
    }
}

impl From<EmdstarModel> for Model {
    fn from(m: EmdstarModel) -> Self {
        match m {
            EmdstarModel::Linear => Model::Linear,
            EmdstarModel::Hertz => Model::Hertz,
        }
    }
}

/// Outcome of a call.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmdstarStatus {
    Ok = 0,
    /// The impact lies outside the table's box (ask for the exact fallback instead).
    OutOfBox = 1,
    /// A near-central impact where the table has no central limit.
    NotTabulated = 2,
    /// Bad arguments (null pointer, non-finite or negative value, ...).
    InvalidInput = 3,
    /// The table is for the other model.
    WrongModel = 4,
    /// The file could not be read or is not a valid table.
    BadFile = 5,
    /// The exact solver did not finish.
    SolveFailed = 6,
    /// An internal error (a bug): please report it.
    Panic = 99,
}

/// Where a MoR came from.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EmdstarSource {
    #[default]
    Table = 0,
    /// The exact solver (the caller asked for the fallback).
    Exact = 1,
}

/// The matrix of restitution of one impact, Müller & Pöschel 2013, Eqs. (16)-(21).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EmdstarMor {
    pub eps_r: f64,
    pub one_minus_eps_r: f64,
    /// Negative; the normal coefficient of restitution is -eps_rdot.
    pub eps_rdot: f64,
    /// Rotation of the inter-particle unit vector during contact, radians.
    pub eps_phi: f64,
    /// Scaled duration; the contact lasts eps_t * time_scale seconds.
    pub eps_t: f64,
    /// Time scale T in s (0 for scaled lookups).
    pub time_scale: f64,
    /// Table or exact solve.
    pub source: EmdstarSource,
}

impl EmdstarMor {
    fn new(m: &Mor, time_scale: f64, source: EmdstarSource) -> Self {
        Self {
            eps_r: m.eps_r,
            one_minus_eps_r: m.one_minus_eps_r,
            eps_rdot: m.eps_rdot,
            eps_phi: m.eps_phi,
            eps_t: m.eps_t,
            time_scale,
            source,
        }
    }

    fn mor(&self) -> Mor {
        Mor {
            eps_r: self.eps_r,
            one_minus_eps_r: self.one_minus_eps_r,
            eps_rdot: self.eps_rdot,
            eps_phi: self.eps_phi,
            eps_t: self.eps_t,
        }
    }
}

/// An open table (opaque).
pub struct EmdstarTable {
    table: TableRef,
}

/// A default table (shared for the whole process) or one read from a file (shared
/// with the pairs built on it, so closing the table first is safe).
type TableRef = SharedTable;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(msg: &str) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

fn status_of(e: &TableError) -> EmdstarStatus {
    match e {
        TableError::OutOfBox { .. } => EmdstarStatus::OutOfBox,
        TableError::NotTabulated(_) => EmdstarStatus::NotTabulated,
        TableError::WrongModel { .. } => EmdstarStatus::WrongModel,
        TableError::Input(_) => EmdstarStatus::InvalidInput,
        TableError::Fallback(_) => EmdstarStatus::SolveFailed,
        _ => EmdstarStatus::BadFile,
    }
}

type Failure = (EmdstarStatus, String);

/// Runs `f`, converting errors and panics into a status and the last-error message.
fn guarded(f: impl FnOnce() -> Result<(), Failure>) -> EmdstarStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => EmdstarStatus::Ok,
        Ok(Err((status, msg))) => {
            set_error(&msg);
            status
        }
        Err(_) => {
            set_error("internal error (panic) in emdstar_table");
            EmdstarStatus::Panic
        }
    }
}

fn table_err(e: TableError) -> Failure {
    (status_of(&e), e.to_string())
}

fn input_err(msg: impl ToString) -> Failure {
    (EmdstarStatus::InvalidInput, msg.to_string())
}

/// Runs a constructor: a boxed handle, or NULL with the last error set.
fn make<T>(f: impl FnOnce() -> Result<T, Failure>) -> *mut T {
    let mut out = std::ptr::null_mut();
    guarded(|| {
        out = Box::into_raw(Box::new(f()?));
        Ok(())
    });
    out
}

/// Drops a handle made by [`make`]; NULL is ignored.
///
/// # Safety
/// `p` must be NULL or come from [`make`] and not be freed yet.
unsafe fn free<T>(p: *mut T) {
    if !p.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `make`.
            drop(unsafe { Box::from_raw(p) })
        }));
    }
}

/// The table behind a handle, or an error for NULL.
///
/// # Safety
/// `table` must be NULL or a live handle from an open function.
unsafe fn table_of<'a>(table: *const EmdstarTable) -> Result<&'a TableRef, Failure> {
    if table.is_null() {
        return Err(input_err("table is NULL"));
    }
    // SAFETY: non-null, live by the caller's contract.
    Ok(unsafe { &(*table).table })
}

/// Writes `value` to `out`, or fails for NULL.
///
/// # Safety
/// `out` must be NULL or point to writable memory for a `T`.
unsafe fn put<T>(out: *mut T, value: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(input_err("the output pointer is NULL"));
    }
    // SAFETY: non-null and writable by the caller's contract.
    unsafe { out.write(value) };
    Ok(())
}

/// Opens a table file. Returns NULL on failure (see `emdstar_table_last_error`).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_open(path: *const c_char) -> *mut EmdstarTable {
    make(|| {
        if path.is_null() {
            return Err(input_err("path is NULL"));
        }
        // SAFETY: non-null and NUL-terminated by the caller's contract.
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| input_err("path is not UTF-8"))?;
        let table = Table::open(path).map_err(table_err)?;
        Ok(EmdstarTable {
            table: TableRef::Owned(Arc::new(table)),
        })
    })
}

/// Reads a table from `len` bytes at `data` (e.g. a table embedded in the caller's own
/// binary); the bytes are parsed, not kept. NULL on failure.
///
/// # Safety
/// `data` must be NULL or point to `len` readable bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_open_bytes(
    data: *const u8,
    len: usize,
) -> *mut EmdstarTable {
    make(|| {
        if data.is_null() {
            return Err(input_err("data is NULL"));
        }
        // SAFETY: non-null with `len` readable bytes by the caller's contract.
        let bytes = unsafe { std::slice::from_raw_parts(data, len) };
        let table = Table::from_bytes(bytes).map_err(table_err)?;
        Ok(EmdstarTable {
            table: TableRef::Owned(Arc::new(table)),
        })
    })
}

/// Opens the default table of `model`, embedded in the library: parsed once per
/// process, then shared by every handle (no copy). NULL on failure.
#[unsafe(no_mangle)]
pub extern "C" fn emdstar_table_open_default(model: EmdstarModel) -> *mut EmdstarTable {
    make(|| {
        let table = emdstar_table::default_table(model.into()).map_err(table_err)?;
        Ok(EmdstarTable {
            table: TableRef::Static(table),
        })
    })
}

/// Closes a table; NULL is ignored. Pairs built on it stay valid.
///
/// # Safety
/// `table` must be NULL or a pointer returned by an open function, not yet closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_close(table: *mut EmdstarTable) {
    // SAFETY: by the caller's contract.
    unsafe { free(table) }
}

/// The last error message of this thread (empty if none). Valid until the next call.
#[unsafe(no_mangle)]
pub extern "C" fn emdstar_table_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// What a table covers and how accurate it is.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmdstarTableInfo {
    pub model: EmdstarModel,
    /// [min, max] of the rectangular coordinates a, b, c (Müller & Pöschel 2013, Sec. V).
    pub rect: [[f64; 2]; 3],
    /// The generator's error goal per stored quantity (relative error of each component).
    pub tolerance: f64,
    /// The largest error estimate per component: 1-eps_r, eps_rdot, eps_phi, eps_t.
    pub estimated_error: [f64; 4],
    /// Number of physical parameters of the box (see `emdstar_table_box_parameter`).
    pub box_len: usize,
}

/// Fills `out` with the table's model, rectangle and accuracy.
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarTableInfo`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_info(
    table: *const EmdstarTable,
    out: *mut EmdstarTableInfo,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let t = unsafe { table_of(table) }?;
        let info = t.info();
        let value = EmdstarTableInfo {
            model: t.model().into(),
            rect: t.rect().map(|r| [r.min, r.max]),
            tolerance: info.tolerance,
            estimated_error: info.estimated_error,
            box_len: info.box_names.len(),
        };
        // SAFETY: by the caller's contract.
        unsafe { put(out, value) }
    })
}

/// The `index`-th physical parameter of the table's box: its name (NUL-terminated,
/// valid while the table is open: e.g. "young") and its [min, max] range in SI units.
///
/// # Safety
/// `table` from an open function; `name`, `min`, `max` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_box_parameter(
    table: *const EmdstarTable,
    index: usize,
    name: *mut *const c_char,
    min: *mut f64,
    max: *mut f64,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let t = unsafe { table_of(table) }?;
        let info = t.info();
        let (Some(n), Some(r)) = (box_name(t, index), info.box_ranges.get(index)) else {
            return Err(input_err(format!(
                "box parameter {index} does not exist (the box has {})",
                info.box_names.len()
            )));
        };
        // SAFETY: by the caller's contract.
        unsafe {
            put(name, n)?;
            put(min, r[0])?;
            put(max, r[1])
        }
    })
}

/// The NUL-terminated names of the box parameters, kept for the life of the process
/// (a handful of short strings per table).
fn box_name(t: &Table, index: usize) -> Option<*const c_char> {
    use std::collections::HashMap;
    use std::sync::Mutex;
    static NAMES: Mutex<Option<HashMap<String, &'static CStr>>> = Mutex::new(None);
    let name = t.info().box_names.get(index)?;
    let mut guard = NAMES.lock().unwrap_or_else(|e| e.into_inner());
    let map = guard.get_or_insert_with(HashMap::new);
    let c = map.entry(name.clone()).or_insert_with(|| {
        let owned = CString::new(name.replace('\0', " ")).unwrap_or_default();
        Box::leak(owned.into_boxed_c_str())
    });
    Some(c.as_ptr())
}

/// MoR at scaled parameters l̃ > 0, c_φ ≥ 0, c_dis ≥ 0 (time_scale is set to 0).
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_scaled(
    table: *const EmdstarTable,
    l_tilde: f64,
    c_phi: f64,
    c_dis: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let t = unsafe { table_of(table) }?;
        let p = ScaledParams::new(l_tilde, c_phi, c_dis).map_err(input_err)?;
        let m = t.lookup_scaled(&p).map_err(table_err)?;
        // SAFETY: by the caller's contract.
        unsafe { put(out, EmdstarMor::new(&m, 0.0, EmdstarSource::Table)) }
    })
}

/// The exact MoR at scaled parameters (the solver of emdstar-mor, no table).
///
/// # Safety
/// `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_mor_exact_scaled(
    model: EmdstarModel,
    l_tilde: f64,
    c_phi: f64,
    c_dis: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    guarded(|| {
        let p = ScaledParams::new(l_tilde, c_phi, c_dis).map_err(input_err)?;
        let m = emdstar_mor::solve(model.into(), &p)
            .map_err(|e| (EmdstarStatus::SolveFailed, e.to_string()))?;
        // SAFETY: by the caller's contract.
        unsafe { put(out, EmdstarMor::new(&m, 0.0, EmdstarSource::Exact)) }
    })
}

fn physical(
    t: &Table,
    law: Result<ForceLaw, emdstar_contact::ContactError>,
    spheres: [f64; 4],
    speeds: [f64; 2],
) -> Result<EmdstarMor, Failure> {
    let [r1, m1, r2, m2] = spheres;
    let pair = PairProperties::spheres(
        &Sphere::new(r1, m1).map_err(input_err)?,
        &Sphere::new(r2, m2).map_err(input_err)?,
    );
    let law = PairLaw::same_material(&law.map_err(input_err)?, pair.r_eff).map_err(input_err)?;
    let impact = Impact {
        normal_speed: speeds[0],
        tangential_speed: speeds[1],
    };
    let hit = t.lookup(&law, &pair, &impact).map_err(table_err)?;
    Ok(EmdstarMor::new(&hit.mor, hit.time, EmdstarSource::Table))
}

/// MoR of two linear spring-dashpot spheres of one material (k in N/m, γ in kg/s),
/// radii in m, masses in kg, normal and tangential speed at contact in m/s. For many
/// impacts of one pair, build an `EmdstarPair` once instead.
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_linear(
    table: *const EmdstarTable,
    stiffness: f64,
    damping: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
    normal_speed: f64,
    tangential_speed: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let t = unsafe { table_of(table) }?;
        let law = LinearDashpot::new(stiffness, damping).map(ForceLaw::Linear);
        let m = physical(
            t,
            law,
            [radius1, mass1, radius2, mass2],
            [normal_speed, tangential_speed],
        )?;
        // SAFETY: by the caller's contract.
        unsafe { put(out, m) }
    })
}

/// MoR of two viscoelastic Hertz spheres of one material (Young's modulus in Pa,
/// Poisson ratio, dissipative constant A in s), radii in m, masses in kg, speeds in m/s.
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_hertz(
    table: *const EmdstarTable,
    young: f64,
    poisson: f64,
    dissipation: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
    normal_speed: f64,
    tangential_speed: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let t = unsafe { table_of(table) }?;
        let law = ViscoelasticHertz::new(young, poisson, dissipation).map(ForceLaw::Hertz);
        let m = physical(
            t,
            law,
            [radius1, mass1, radius2, mass2],
            [normal_speed, tangential_speed],
        )?;
        // SAFETY: by the caller's contract.
        unsafe { put(out, m) }
    })
}
