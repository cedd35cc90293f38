//! Finite-element front end of flexmbs.
//!
//! Everything a flexible body needs before it enters a multibody model
//! (seed 000 ch. 2.1-2.3, seed 001 ch. 3): meshes, linear elastic elements,
//! sparse assembly with fixed node sets and rigid interfaces, the generalized
//! symmetric eigenproblem `K phi = omega^2 M phi`, and modal and
//! Craig-Bampton reduction.
#![warn(missing_docs)]

pub mod assembly;
pub mod constraint;
pub mod eigen;
pub mod element;
pub mod error;
pub mod geometric;
pub mod geometric_loads;
#[cfg(test)]
mod geometric_loads_tests;
#[cfg(test)]
mod geometric_tests;
pub mod material;
pub mod mechanism;
pub mod memory;
pub mod mesh;
pub mod modes;
pub mod point_load;
pub mod reduction;
pub mod static_modes;
pub mod stress;
#[cfg(test)]
mod stress_tests;
pub mod system;
pub mod units;

pub use error::FeError;
pub use material::Material;
pub use mesh::{BoxFace, ElementKind, Mesh, NodeIdx};
pub use units::UnitSystem;

/// Sparse matrix type used for assembled FE matrices (compressed sparse column, full storage).
pub type SparseMatrix = faer::sparse::SparseColMat<usize, f64>;
