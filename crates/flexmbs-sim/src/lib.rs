//! Multibody model files of flexmbs: the TOML schema ([`schema`]), its compilation into the
//! engine's [`flexmbs_core::ModelSpec`] with names, output signals and animation geometry
//! ([`compile`]), and the run driver writing results, CSV, plots and a ParaView animation
//! ([`run`]). Reference of the file format: `docs/model-file.md`, "Multibody models".
#![warn(missing_docs)]

mod animation_points;
pub mod bodies;
mod body_loading;
pub mod compile;
pub mod config;
mod contact_drawing;
pub mod contacts;
pub mod drives;
pub mod error;
pub mod failure_hint;
pub mod fe_frames;
mod flexible_contours;
pub mod forces;
mod guides;
pub mod initial;
pub mod locate;
pub mod mass_model;
pub mod motion_signals;
pub mod plausibility;
mod point_mass_body;
pub mod provenance;
pub mod restart;
pub mod run;
pub mod schema;
pub mod signals;
pub mod stiffening;
pub mod stress;
pub use flexmbs_reduce::superelement as superelement_fe;
mod superelement_fe_body;
mod superelement_output;
pub mod superelements;
pub use flexmbs_io::units;

pub use compile::{compile_model, is_multibody_model, load_model, CompiledModel, SolverConfig};
pub use error::SimError;
