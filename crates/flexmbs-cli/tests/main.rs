//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-cli --test integration <file>::`.

mod common;

mod bad_models;
mod ctrl_c;
mod floating_frame_joint;
mod kill_results;
mod memory_guard;
mod output_folders;
mod reduce_geometric;
mod reduce_stress;
mod solid_node_joint;
mod source_fifo;
mod wrong_kind;
