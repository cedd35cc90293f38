//! The FE reduction pipeline of flexmbs, between the FE front end (`flexmbs-fe`) and the model
//! files (`flexmbs-io` reads the FE body model file): builds the mesh of an FE body file (built-in
//! generators, CalculiX deck, seed folder), applies its supports, assembles or imports K and M and
//! runs the modal analysis or the reduction ([`pipeline`]); the full mass matrix for the
//! consistent mass model and node rotary inertias ([`full_mass`]); the centrifugal geometric
//! stiffness ([`geometric`]); frequency tables of modal analyses ([`report`]); modal stress fields ([`stress`]); superelement data of a Craig-Bampton
//! reduction ([`superelement`]).
#![warn(missing_docs)]

pub mod body_file;
pub mod face_load;
pub mod full_mass;
pub mod geometric;
pub mod pipeline;
pub mod report;
pub mod stress;
pub mod superelement;
