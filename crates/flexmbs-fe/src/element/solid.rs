//! Generic isoparametric continuum element: Jacobian, strain-displacement matrix B, stiffness
//! K = sum B^T D B det J w and consistent mass M = sum rho N^T N det J w (seed 000 ch. 2.1).

use super::gauss::QuadPoint;
use crate::FeError;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};

/// Shape functions of a reference element: fills `n[a]` and `dn[a] = dN_a/d(xi, eta, zeta)`.
pub type ShapeFn = fn(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]);

/// Shape functions and their Cartesian derivatives at one point of an element.
pub struct PointEval {
    /// Shape function values N_a.
    pub n: Vec<f64>,
    /// Cartesian derivatives dN_a/dx.
    pub dndx: Vec<Vector3<f64>>,
    /// Jacobian matrix J_ij = d x_j / d xi_i.
    pub jac: Matrix3<f64>,
    /// det J.
    pub det: f64,
}

/// Jacobian matrix J_ij = sum_a dN_a/dxi_i x_a,j.
pub fn jacobian(x: &[[f64; 3]], dn: &[[f64; 3]]) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for (xa, da) in x.iter().zip(dn) {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += da[r] * xa[c];
            }
        }
    }
    j
}

/// Evaluates shape functions, Jacobian and Cartesian derivatives at `xi`. Errors with
/// [`FeError::BadJacobian`] when det J <= 1e-12 |J|_F^3 (inverted or degenerate; `element` and
/// `point` only label the error).
pub fn eval_point(
    shape: ShapeFn,
    x: &[[f64; 3]],
    xi: [f64; 3],
    element: usize,
    point: usize,
) -> Result<PointEval, FeError> {
    let nn = x.len();
    let mut n = vec![0.0; nn];
    let mut dn = vec![[0.0; 3]; nn];
    shape(xi, &mut n, &mut dn);
    let jac = jacobian(x, &dn);
    let det = jac.determinant();
    // relative threshold: a degenerate element has det J tiny compared to its size^3
    let scale = jac.norm().powi(3);
    if det.is_nan() || det <= 1e-12 * scale {
        return Err(FeError::BadJacobian {
            element,
            point,
            det,
        });
    }
    let jinv = jac.try_inverse().ok_or(FeError::BadJacobian {
        element,
        point,
        det,
    })?;
    let dndx = dn
        .iter()
        .map(|d| jinv * Vector3::new(d[0], d[1], d[2]))
        .collect();
    Ok(PointEval { n, dndx, jac, det })
}

/// Writes the 6 x 3 strain-displacement block of a node (Voigt xx, yy, zz, xy, yz, zx, engineering
/// shear) with Cartesian derivative `g` into `b` at column `col`.
pub fn b_block(b: &mut DMatrix<f64>, col: usize, g: &Vector3<f64>) {
    b[(0, col)] = g[0];
    b[(1, col + 1)] = g[1];
    b[(2, col + 2)] = g[2];
    b[(3, col)] = g[1];
    b[(3, col + 1)] = g[0];
    b[(4, col + 1)] = g[2];
    b[(4, col + 2)] = g[1];
    b[(5, col)] = g[2];
    b[(5, col + 2)] = g[0];
}

/// Full strain-displacement matrix B (6 x 3n) from Cartesian shape derivatives.
pub fn b_matrix(dndx: &[Vector3<f64>]) -> DMatrix<f64> {
    let mut b = DMatrix::zeros(6, 3 * dndx.len());
    for (a, g) in dndx.iter().enumerate() {
        b_block(&mut b, 3 * a, g);
    }
    b
}

/// Converts the fixed-size elasticity matrix to a dynamic one.
pub fn dyn_d(d: &Matrix6<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| d[(i, j)])
}

/// Stiffness K = sum_p B^T D B det J w over `rule`.
pub fn stiffness(
    shape: ShapeFn,
    x: &[[f64; 3]],
    d: &Matrix6<f64>,
    rule: &[QuadPoint],
    element: usize,
) -> Result<DMatrix<f64>, FeError> {
    let nd = 3 * x.len();
    let dd = dyn_d(d);
    let mut k = DMatrix::zeros(nd, nd);
    for (ip, p) in rule.iter().enumerate() {
        let e = eval_point(shape, x, p.xi, element, ip)?;
        let b = b_matrix(&e.dndx);
        let db = &dd * &b;
        k.gemm_tr(e.det * p.w, &b, &db, 1.0);
    }
    symmetrize(&mut k);
    Ok(k)
}

/// Consistent mass M = sum_p rho N^T N det J w over `rule`, expanded to the 3 translations
/// (node-major DOF order).
pub fn consistent_mass(
    shape: ShapeFn,
    x: &[[f64; 3]],
    rho: f64,
    rule: &[QuadPoint],
    element: usize,
) -> Result<DMatrix<f64>, FeError> {
    let nn = x.len();
    let mut m = DMatrix::zeros(3 * nn, 3 * nn);
    for (ip, p) in rule.iter().enumerate() {
        let e = eval_point(shape, x, p.xi, element, ip)?;
        let f = rho * e.det * p.w;
        for a in 0..nn {
            for b in 0..nn {
                let v = f * e.n[a] * e.n[b];
                for c in 0..3 {
                    m[(3 * a + c, 3 * b + c)] += v;
                }
            }
        }
    }
    symmetrize(&mut m);
    Ok(m)
}

/// Element volume sum det J w over `rule`.
pub fn volume(
    shape: ShapeFn,
    x: &[[f64; 3]],
    rule: &[QuadPoint],
    element: usize,
) -> Result<f64, FeError> {
    let mut v = 0.0;
    for (ip, p) in rule.iter().enumerate() {
        v += eval_point(shape, x, p.xi, element, ip)?.det * p.w;
    }
    Ok(v)
}

/// Replaces `a` by (a + a^T)/2 to remove round-off asymmetry.
pub fn symmetrize(a: &mut DMatrix<f64>) {
    let n = a.nrows();
    for i in 0..n {
        for j in (i + 1)..n {
            let v = 0.5 * (a[(i, j)] + a[(j, i)]);
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
}
