//! File formats of flexmbs: the seed 4-file body format, CalculiX decks and exports,
//! reduced-body files and VTK output.
#![warn(missing_docs)]

pub mod body_file;
pub mod calculix;
pub mod error;
pub mod file_kind;
pub mod inp_writer;
pub mod model;
pub mod model_check;
mod model_locate;
pub mod plot;
pub mod results;
pub mod seed;
pub mod toml_locate;
pub mod vtk;

pub use error::IoError;
pub mod seed_body;
