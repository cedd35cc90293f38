#![no_main]
//! Fuzz target `seed_modes`: arbitrary bytes (lossy UTF-8) into the `&str` parser; must never panic.
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = flexmbs_io::seed::parse_mode_shapes(&text, Path::new("modeShapeMatrix.dat"));
});
