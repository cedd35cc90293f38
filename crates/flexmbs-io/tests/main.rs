//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-io --test integration <file>::`.

mod body_file_support;
mod common;
mod results_support;

mod bad_corpus;
mod body_file_consistency;
mod body_file_errors;
mod body_file_inertia;
mod body_file_python;
mod body_file_roundtrip;
mod body_file_stress;
mod calculix_ccx;
mod calculix_files;
mod fe_units;
mod fuzz_smoke;
mod geometric_ccx;
mod inp_writer;
mod results;
mod results_python;
mod seed_format;
mod vtk_reader;
mod vtk_writer;
