#![no_main]
//! Fuzz target `ccx_inp`: arbitrary bytes (lossy UTF-8) into the `&str` parser; must never panic.
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = flexmbs_io::calculix::parse_inp_with(&text, Path::new("fuzz.inp"), flexmbs_fe::UnitSystem::Si, &mut |p: &Path| {
        Err(flexmbs_io::IoError::Inconsistent { file: p.to_path_buf(), what: "no includes while fuzzing".into() })
    });
});
