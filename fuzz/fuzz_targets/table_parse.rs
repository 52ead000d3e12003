//! The table file parser on arbitrary bytes: a table or an error, never a panic, a
//! hang or an out-of-bounds access; whatever loads answers lookups without panicking.
#![no_main]

use emdstar_contact::RectCoords;
use emdstar_table::Table;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(table) = Table::from_bytes(data) else {
        return;
    };
    let [a, b, c] = table.rect();
    for (fa, fb, fc) in [
        (0.0, 0.0, 0.0),
        (0.5, 0.5, 0.5),
        (1.0, 1.0, 1.0),
        (-0.2, 0.3, -0.1),
    ] {
        let x = RectCoords {
            a: a.min + fa * (a.max - a.min),
            b: b.min + fb * (b.max - b.min),
            c: c.min + fc * (c.max - c.min),
        };
        let _ = table.logs_at(&x);
    }
    let _ = table.lookup_rect(&RectCoords {
        a: f64::NEG_INFINITY,
        b: b.min,
        c: f64::NEG_INFINITY,
    });
});
