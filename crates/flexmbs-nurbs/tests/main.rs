//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-nurbs --test integration <file>::`.

mod common;
// the engine crate's counting allocator (one copy for both crates' allocation tests)
#[path = "../../flexmbs-core/tests/support/counting_alloc.rs"]
mod counting_alloc;

mod basis;
mod field;
mod fuzz;
mod interp;
mod no_alloc;
mod search;
