#![no_main]
//! Fuzz target: `flexmbs_io::seed::parse_stiffness`; the first byte picks the node count 1..=64.
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let (n, rest) = match data.split_first() {
        Some((b, rest)) => (*b as usize % 64 + 1, rest),
        None => (1, data),
    };
    let text = String::from_utf8_lossy(rest);
    let _ = flexmbs_io::seed::parse_stiffness(&text, Path::new("stiffnessMatrix.dat"), n);
});
