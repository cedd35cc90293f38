//! The crate's integration tests in one test binary (one link, one binary on disk instead of
//! one per file); each file is a module: `cargo test -p flexmbs-core --test integration <file>::`.

mod chain;
mod common;
#[path = "support/counting_alloc.rs"]
mod counting_alloc;
#[path = "support/plate.rs"]
mod plate;
#[path = "support/spring_element.rs"]
mod spring_element;

mod adaptive_weights;
mod algebra;
mod assembly;
mod constraints;
mod contact_flexible;
mod contact_friction_genalpha;
mod contact_genalpha;
mod contact_genalpha_adaptive;
mod contact_rigid;
mod curve_guide;
mod divergence;
mod element_errors;
mod external_work;
mod ffr_contour;
mod ffr_double_pendulum_energy;
mod ffr_element;
mod ffr_load_stiffening;
mod ffr_load_stiffening_dopri5;
mod ffr_load_stiffening_slider_crank;
mod ffr_load_tangent;
mod ffr_newton;
mod ffr_node_frames;
mod force_elements;
mod free_body;
mod initial_spec;
mod joint_reaction;
mod local_tangents;
mod moreau_joints;
mod moreau_penalty_step;
mod no_alloc;
mod no_alloc_many_modes;
mod pendulum;
mod scattered_nodes;
mod shared_nodes;
mod slider_crank;
mod sparse_nodes;
mod spring_statics;
mod stepper;
mod superelement_contour;
mod superelement_contour_model;
mod superelement_dynamics;
mod superelement_newton;
mod superelement_no_alloc;
mod superelement_statics;
