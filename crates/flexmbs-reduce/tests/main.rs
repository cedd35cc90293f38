//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-reduce --test integration <file>::`.

mod stress_cantilever;
