//! File formats of flexmbs: the seed 4-file body format, CalculiX decks and exports,
//! reduced-body files and VTK output.
#![warn(missing_docs)]

pub mod inp_writer;
pub mod model;
pub mod pipeline;
pub mod plot;
pub mod report;
pub mod body_file;
pub mod vtk;
pub mod calculix;
pub mod error;
pub mod seed;

pub use error::IoError;
pub mod seed_body;
