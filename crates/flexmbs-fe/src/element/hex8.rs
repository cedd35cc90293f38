//! 8-node hexahedra: `Hex8` (trilinear, full 2x2x2 Gauss, CalculiX `C3D8`) and `Hex8I`
//! (incompatible modes of Wilson et al. with the Taylor-Beresford-Wilson correction, like `C3D8I`).
//!
//! Hex8I adds the 9 bubble displacements alpha_k (1 - xi_k^2) e_c (k, c = 1..3). Their strain
//! matrix uses the Jacobian at the element centre, B_I = (det J0 / det J) J0^{-1} dP/dxi, so that
//! int B_I dV = 0 exactly and constant strain states are reproduced on any element shape (patch
//! test). The internal DOFs are condensed statically: K = K_cc - K_ci K_ii^{-1} K_ic. The mass
//! matrix is that of the compatible trilinear field (the bubbles carry no mass after condensation).

use super::gauss::hex_rule;
use super::solid::{b_block, b_matrix, dyn_d, eval_point, jacobian, symmetrize};
use crate::FeError;
use nalgebra::{DMatrix, Matrix6, Vector3};

/// Reference coordinates of the 8 corner nodes in Abaqus order.
pub const HEX8_NODES: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Trilinear shape functions N_a = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a)/8 and derivatives.
pub fn hex8_shape(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    for (a, r) in HEX8_NODES.iter().enumerate() {
        let f = [1.0 + xi[0] * r[0], 1.0 + xi[1] * r[1], 1.0 + xi[2] * r[2]];
        n[a] = 0.125 * f[0] * f[1] * f[2];
        dn[a] = [
            0.125 * r[0] * f[1] * f[2],
            0.125 * f[0] * r[1] * f[2],
            0.125 * f[0] * f[1] * r[2],
        ];
    }
}

/// Stiffness of the incompatible-mode hexahedron with static condensation of the 9 internal DOFs.
pub fn hex8i_stiffness(
    x: &[[f64; 3]],
    d: &Matrix6<f64>,
    element: usize,
) -> Result<DMatrix<f64>, FeError> {
    hex8i_stiffness_variant(x, d, element, true)
}

/// Incompatible-mode stiffness; `det_ratio` = false omits the factor det J0 / det J in B_I (the
/// variant of CalculiX `C3D8I`, which fails the patch test on non-parallelepiped elements; kept
/// only to verify the CalculiX comparison).
pub(crate) fn hex8i_stiffness_variant(
    x: &[[f64; 3]],
    d: &Matrix6<f64>,
    element: usize,
    det_ratio: bool,
) -> Result<DMatrix<f64>, FeError> {
    // Jacobian at the element centre (Taylor correction)
    let mut n0 = [0.0; 8];
    let mut dn0 = [[0.0; 3]; 8];
    hex8_shape([0.0; 3], &mut n0, &mut dn0);
    let j0 = jacobian(x, &dn0);
    let det0 = j0.determinant();
    if det0.is_nan() || det0 <= 0.0 {
        return Err(FeError::BadJacobian {
            element,
            point: 0,
            det: det0,
        });
    }
    let j0inv = j0.try_inverse().ok_or(FeError::BadJacobian {
        element,
        point: 0,
        det: det0,
    })?;
    let dd = dyn_d(d);
    let mut kcc = DMatrix::zeros(24, 24);
    let mut kic = DMatrix::zeros(9, 24);
    let mut kii = DMatrix::zeros(9, 9);
    for (ip, p) in hex_rule(2).iter().enumerate() {
        let e = eval_point(hex8_shape, x, p.xi, element, ip)?;
        let bc = b_matrix(&e.dndx);
        // bubble derivatives dP_k/dxi = -2 xi_k e_k, mapped with J0 and scaled by det J0 / det J
        let mut bi = DMatrix::zeros(6, 9);
        for k in 0..3 {
            let mut g = Vector3::zeros();
            g[k] = -2.0 * p.xi[k];
            let gx = j0inv * g * if det_ratio { det0 / e.det } else { 1.0 };
            b_block(&mut bi, 3 * k, &gx);
        }
        let f = e.det * p.w;
        let dbc = &dd * &bc;
        let dbi = &dd * &bi;
        kcc.gemm_tr(f, &bc, &dbc, 1.0);
        kic.gemm_tr(f, &bi, &dbc, 1.0);
        kii.gemm_tr(f, &bi, &dbi, 1.0);
    }
    symmetrize(&mut kii);
    let chol = kii.clone().cholesky().ok_or_else(|| {
        FeError::Invalid(format!(
            "element {element}: Hex8I internal-mode stiffness not positive definite"
        ))
    })?;
    // K = K_cc - K_ic^T K_ii^{-1} K_ic
    let x_ic = chol.solve(&kic);
    let mut k = kcc - kic.transpose() * x_ic;
    symmetrize(&mut k);
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_partition_of_unity_and_kronecker() {
        let mut n = [0.0; 8];
        let mut dn = [[0.0; 3]; 8];
        for (a, r) in HEX8_NODES.iter().enumerate() {
            hex8_shape(*r, &mut n, &mut dn);
            for (b, nb) in n.iter().enumerate() {
                assert!((nb - if a == b { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
        hex8_shape([0.3, -0.7, 0.1], &mut n, &mut dn);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        for c in 0..3 {
            assert!(dn.iter().map(|d| d[c]).sum::<f64>().abs() < 1e-15);
        }
        // derivative by central finite differences (h = 1e-6, tolerance 1e-9)
        let xi = [0.3, -0.7, 0.1];
        for c in 0..3 {
            let (mut np, mut nm) = ([0.0; 8], [0.0; 8]);
            let mut dd = [[0.0; 3]; 8];
            let (mut xp, mut xm) = (xi, xi);
            xp[c] += 1e-6;
            xm[c] -= 1e-6;
            hex8_shape(xp, &mut np, &mut dd);
            hex8_shape(xm, &mut nm, &mut dd);
            for a in 0..8 {
                assert!(((np[a] - nm[a]) / 2e-6 - dn[a][c]).abs() < 1e-9);
            }
        }
    }
}
