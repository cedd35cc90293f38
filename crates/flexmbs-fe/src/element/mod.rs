//! Element matrices: linear elastic solids (`Hex8`, `Hex8I`, `Hex20`, `Hex20R`, `Tet10`) and
//! the two-node 3D beam (`Beam2`), with consistent or HRZ-lumped mass (seed 000 ch. 2.1).
//!
//! DOF order is node-major: node 0 (ux, uy, uz[, rx, ry, rz]), node 1, ... with 3 DOFs per
//! node for solids and 6 for beams. Node order follows Abaqus/CalculiX.
//!
//! Integration rules (stiffness / consistent mass):
//! - `Hex8`: 2x2x2 / 2x2x2 (`C3D8`);
//! - `Hex8I`: 2x2x2 with 9 condensed incompatible modes / 2x2x2 of the compatible field (`C3D8I`);
//! - `Hex20`: 3x3x3 / 3x3x3 (`C3D20`);
//! - `Hex20R`: 2x2x2 / 3x3x3;
//! - `Tet10`: 4-point / 14-point (degree 5, exact for the quartic N^T N) (`C3D10`).
//!
//! Stiffness matrices equal CalculiX 2.20 exports to 1e-13 (test `ccx_tests`), and so do the
//! `Hex8` and `Hex20` masses. CalculiX integrates the mass of `C3D20R` and `C3D10` with the
//! stiffness rule (2x2x2 and 4 points: scalar mass of rank 8 of 20 and 4 of 10 per element);
//! flexmbs uses the exact rules above (positive definite element mass, same total mass), so
//! these masses differ entry-wise from a CalculiX export (by up to 20 % and 38 % of the largest
//! entry for the test elements) while converging to the same frequencies under refinement.
//! CalculiX `C3D8I` maps its bubble derivatives with J0^{-1} but without the factor
//! det J0 / det J, so it fails the constant-strain patch test on non-parallelepiped elements;
//! `Hex8I` keeps the factor (Taylor et al. 1976) and equals the condensed `C3D8I` only on
//! parallelepipeds (0.7 % apart on the distorted test element).

pub mod beam;
pub mod gauss;
pub mod hex20;
pub mod hex8;
pub mod lumping;
pub mod solid;
pub mod tet10;

#[cfg(test)]
mod beam_tests;
#[cfg(test)]
mod ccx_tests;
#[cfg(test)]
mod solid_tests;
#[cfg(test)]
mod test_util;

use crate::mesh::{ElementKind, Mesh, Property};
use crate::FeError;
use nalgebra::DMatrix;

/// Kind of element mass matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MassKind {
    /// Consistent mass int rho N^T N dV.
    #[default]
    Consistent,
    /// Diagonal mass: HRZ scaling of the consistent diagonal for solids (never negative or zero);
    /// for beams see [`beam`] (half the mass per node plus a documented rotational inertia).
    Lumped,
}

/// Stiffness and mass matrices of one element in global coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementMatrices {
    /// Stiffness matrix (symmetric, ndof x ndof).
    pub k: DMatrix<f64>,
    /// Mass matrix (symmetric, ndof x ndof).
    pub m: DMatrix<f64>,
}

/// Stiffness and mass of element `element` of `mesh`.
///
/// DOF order node-major: node0 (ux,uy,uz\[,rx,ry,rz\]), node1, ... (6 DOFs/node for `Beam2`, 3 for
/// solids). Errors: [`FeError::Invalid`] for an out-of-range element, wrong node count, missing
/// or mismatched property or bad section; [`FeError::BadJacobian`] for det J <= 0 at an
/// integration point (inverted or degenerate element).
pub fn element_matrices(
    mesh: &Mesh,
    element: usize,
    mass: MassKind,
) -> Result<ElementMatrices, FeError> {
    let el = mesh.elements.get(element).ok_or_else(|| {
        FeError::Invalid(format!(
            "element index {element} out of range (mesh has {})",
            mesh.elements.len()
        ))
    })?;
    if el.nodes.len() != el.kind.num_nodes() {
        return Err(FeError::Invalid(format!(
            "element {element} ({:?}) has {} nodes, expected {}",
            el.kind,
            el.nodes.len(),
            el.kind.num_nodes()
        )));
    }
    let x = el
        .nodes
        .iter()
        .map(|&n| {
            mesh.nodes.get(n).copied().ok_or_else(|| {
                FeError::Invalid(format!(
                    "element {element} refers to node index {n} out of range"
                ))
            })
        })
        .collect::<Result<Vec<[f64; 3]>, FeError>>()?;
    let prop = mesh.properties.get(el.property).ok_or_else(|| {
        FeError::Invalid(format!(
            "element {element} refers to missing property {}",
            el.property
        ))
    })?;
    match (el.kind, prop) {
        (
            ElementKind::Beam2,
            Property::Beam {
                material,
                section,
                theory,
                orientation,
            },
        ) => {
            let (k, m) = beam::beam_matrices(
                x[0],
                x[1],
                material,
                section,
                *theory,
                *orientation,
                mass,
                element,
            )?;
            Ok(ElementMatrices { k, m })
        }
        (kind, Property::Solid { material }) if kind.is_solid() => {
            material.validate()?;
            solid_matrices(kind, &x, material, mass, element)
        }
        (kind, _) => Err(FeError::Invalid(format!(
            "element {element} ({kind:?}) has a property of the wrong kind"
        ))),
    }
}

/// Stiffness and mass of a solid element of `kind` with node coordinates `x` (Abaqus order).
pub fn solid_matrices(
    kind: ElementKind,
    x: &[[f64; 3]],
    material: &crate::Material,
    mass: MassKind,
    element: usize,
) -> Result<ElementMatrices, FeError> {
    use gauss::{hex_rule, tet_rule_14, tet_rule_4};
    let d = material.elasticity_matrix();
    let rho = material.rho;
    let (k, m) = match kind {
        ElementKind::Hex8 => (
            solid::stiffness(hex8::hex8_shape, x, &d, &hex_rule(2), element)?,
            solid::consistent_mass(hex8::hex8_shape, x, rho, &hex_rule(2), element)?,
        ),
        ElementKind::Hex8I => (
            hex8::hex8i_stiffness(x, &d, element)?,
            solid::consistent_mass(hex8::hex8_shape, x, rho, &hex_rule(2), element)?,
        ),
        ElementKind::Hex20 => (
            solid::stiffness(hex20::hex20_shape, x, &d, &hex_rule(3), element)?,
            solid::consistent_mass(hex20::hex20_shape, x, rho, &hex_rule(3), element)?,
        ),
        ElementKind::Hex20R => (
            solid::stiffness(hex20::hex20_shape, x, &d, &hex_rule(2), element)?,
            solid::consistent_mass(hex20::hex20_shape, x, rho, &hex_rule(3), element)?,
        ),
        ElementKind::Tet10 => (
            solid::stiffness(tet10::tet10_shape, x, &d, &tet_rule_4(), element)?,
            solid::consistent_mass(tet10::tet10_shape, x, rho, &tet_rule_14(), element)?,
        ),
        ElementKind::Beam2 => {
            return Err(FeError::Invalid(format!(
                "element {element}: Beam2 is not a solid element"
            )));
        }
    };
    let m = match mass {
        MassKind::Consistent => m,
        MassKind::Lumped => lumping::hrz_lump_solid(&m, element)?,
    };
    Ok(ElementMatrices { k, m })
}
