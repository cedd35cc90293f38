//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-validate --test integration <file>::`.

mod beam_rotary_ffr;
mod calculix_beam;
mod cantilever_plate;
mod ccx_consistent_ffr;
mod point_mass_on_beam_full_fe;
mod sliding_balls_arc;
mod sliding_balls_full;
