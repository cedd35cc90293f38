//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-fe --test integration <file>::`.

mod eigen_many_modes;
mod mechanism;
mod memory_guards;
mod reduction;
