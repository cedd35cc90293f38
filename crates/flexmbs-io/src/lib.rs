//! File formats of flexmbs: the seed 4-file body format, CalculiX decks and exports,
//! reduced-body files, results files and VTK output; the FE body model file (schema in
//! [`model`], checks in [`model_check`]); what both kinds of model file share, the key-path
//! locator ([`toml_locate`]) and the file-kind classifier ([`file_kind`]); line plots ([`plot`]).
//! The FE reduction pipeline that turns an FE body model file into a reduced body is the crate
//! `flexmbs-reduce`.
#![warn(missing_docs)]

pub mod body_file;
pub mod calculix;
pub mod error;
mod fe_quantity;
pub mod file_kind;
pub mod inp_writer;
pub mod model;
pub mod model_check;
mod model_locate;
pub mod output_safety;
pub mod plot;
pub mod results;
pub mod seed;
pub mod sha256;
pub mod source_file;
pub mod test_tools;
pub mod toml_locate;
pub mod units;
pub mod vtk;

pub use error::IoError;
pub mod seed_body;
