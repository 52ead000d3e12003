//! The C ABI's open on arbitrary bytes, then its queries, lookups and close: a handle
//! or NULL with a message, never a panic across the boundary or a leak.
#![no_main]

use emdstar_table_c::*;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // SAFETY: `data` is a valid slice; every pointer passed below is live.
    unsafe {
        let t = emdstar_table_open_bytes(data.as_ptr(), data.len());
        if t.is_null() {
            assert!(!emdstar_table_last_error().is_null());
            return;
        }
        let mut info = std::mem::MaybeUninit::<EmdstarTableInfo>::uninit();
        assert_eq!(emdstar_table_info(t, info.as_mut_ptr()), EmdstarStatus::Ok);
        let info = info.assume_init();
        let mut mor = EmdstarMor::default();
        let _ = emdstar_table_lookup_scaled(t, 10.0, 1.0, 0.1, &mut mor);
        let _ = emdstar_table_lookup_scaled(t, 1e3, 0.0, 0.0, &mut mor);
        for i in 0..info.box_len.min(8) {
            let (mut name, mut lo, mut hi) = (std::ptr::null(), 0.0, 0.0);
            let _ = emdstar_table_box_parameter(t, i, &mut name, &mut lo, &mut hi);
        }
        let pair = match info.model {
            EmdstarModel::Linear => emdstar_pair_linear(t, 1e5, 0.1, 0.01, 0.01, 0.01, 0.01),
            EmdstarModel::Hertz => emdstar_pair_hertz(t, 1e9, 0.3, 1e-5, 0.01, 0.01, 0.01, 0.01),
        };
        if !pair.is_null() {
            let _ = emdstar_pair_lookup(pair, 1.0, 0.3, 0, &mut mor);
            emdstar_pair_free(pair);
        }
        emdstar_table_close(t);
    }
});
