#![no_main]
//! Fuzz target `seed_mass`: arbitrary bytes (lossy UTF-8) into the `&str` parser; must never panic.
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = flexmbs_io::seed::parse_masses(&text, Path::new("mij.dat"));
});
