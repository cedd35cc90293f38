//! Helpers shared by the integration tests: test data paths, a parser dispatcher by file kind
//! and a xorshift generator.
#![allow(dead_code)]

use flexmbs_fe::UnitSystem;
use flexmbs_io::calculix::{
    parse_ccx_dofs, parse_ccx_matrix, parse_dat_frequencies, parse_frd, parse_inp_with,
};
use flexmbs_io::model::{parse_fe_model, ModelError};
use flexmbs_io::seed::{parse_masses, parse_mode_shapes, parse_stiffness, parse_u0};
use flexmbs_io::IoError;
use std::path::{Path, PathBuf};

/// `tests/data/<rel>`.
pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// Parser kinds, named as the prefixes of the corpus files (`u0__...`).
pub const KINDS: [&str; 10] = [
    "u0",
    "modes",
    "mass",
    "stiffness",
    "inp",
    "sti",
    "dof",
    "dat",
    "frd",
    "fe",
];

/// Runs the `&str` parser of `kind` on `text`. `*INCLUDE` in decks resolves only to files
/// beside `file` (read from disk), as in the library default.
pub fn parse_kind(kind: &str, text: &str, file: &Path) -> Result<(), IoError> {
    match kind {
        "u0" => parse_u0(text, file).map(|_| ()),
        "modes" => parse_mode_shapes(text, file).map(|_| ()),
        "mass" => parse_masses(text, file).map(|_| ()),
        "stiffness" => parse_stiffness(text, file, 4).map(|_| ()),
        "inp" => parse_inp_with(text, file, UnitSystem::Si, &mut |p: &Path| {
            std::fs::read_to_string(p).map_err(|source| IoError::Io {
                file: p.to_path_buf(),
                source,
            })
        })
        .map(|_| ()),
        "sti" => parse_ccx_matrix(text, file).map(|_| ()),
        "dof" => parse_ccx_dofs(text, file).map(|_| ()),
        "dat" => parse_dat_frequencies(text, file).map(|_| ()),
        "frd" => parse_frd(text, file).map(|_| ()),
        "fe" => parse_fe_model(text, file)
            .map(|_| ())
            .map_err(model_error_as_io),
        _ => panic!("unknown parser kind {kind}"),
    }
}

/// An FE model-file error as an [`IoError`] (the corpus's common error type): `Invalid` when it
/// has a line, else `Inconsistent`; the message is kept whole.
pub fn model_error_as_io(e: ModelError) -> IoError {
    let file = e.file().to_path_buf();
    let what = e.to_string();
    match e.line() {
        Some(line) => IoError::Invalid { file, line, what },
        None => IoError::Inconsistent { file, what },
    }
}

/// Marsaglia xorshift64 (deterministic test randomness).
pub struct XorShift(pub u64);

impl XorShift {
    /// Next raw value.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    /// Uniform in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
