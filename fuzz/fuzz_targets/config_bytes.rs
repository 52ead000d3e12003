//! Arbitrary bytes as a config: parsed, built and set up by every engine. A config or
//! an error, never a panic, a hang or unbounded memory.
#![no_main]

#[allow(dead_code)] // each target uses part of it
mod common;

use emdstar_system::Config;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(config) = Config::from_toml(text) else {
        return;
    };
    let _ = config.digest();
    if !common::small_enough(&config) {
        return;
    }
    let Ok(system) = config.build() else {
        return;
    };
    for kind in common::KINDS {
        let _ = common::build(kind, &config, system.clone());
    }
});
