#![no_main]
//! Fuzz target `ccx_frd`: arbitrary bytes (lossy UTF-8) into the `&str` parser; must never panic.
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = flexmbs_io::calculix::parse_frd(&text, Path::new("fuzz.frd"));
});
