//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-sim --test integration <file>::`.

mod common;

mod adaptive_contact_file;
mod consistent_body_file;
mod contact_animation;
mod contact_file;
mod contact_signals;
mod drives;
mod element_failure_run;
mod energy_work;
mod examples;
mod failure_hints;
mod flexible_arm;
mod flexible_contact_file;
mod force_elements_file;
mod guide_file;
mod initial_modal;
mod linear_solver;
mod load_stiffening;
mod mass_model;
mod model_errors;
mod motion_signals;
mod newton;
mod plausibility_warnings;
mod point_mass_file;
mod restart;
mod rotary_file;
mod run;
mod smooth_drive_arm;
mod solid_frames;
mod static_load_basis;
mod stiffening;
mod stiffening_file;
mod stress_output;
mod superelement_branches;
mod superelement_contour_file;
mod superelement_fe_file;
mod superelement_file;
