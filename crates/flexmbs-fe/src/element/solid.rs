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
    let nn = x.len();
    let nd = 3 * nn;
    let mut k = DMatrix::zeros(nd, nd);
    // D B by node (6 x 3 each), reused across the points
    let mut db = vec![[[0.0f64; 3]; 6]; nn];
    for (ip, p) in rule.iter().enumerate() {
        let e = eval_point(shape, x, p.xi, element, ip)?;
        let f = e.det * p.w;
        for (dbb, g) in db.iter_mut().zip(&e.dndx) {
            *dbb = d_times_b_block(d, g);
        }
        let kd = k.as_mut_slice();
        for (a, ga) in e.dndx.iter().enumerate() {
            for (b, dbb) in db.iter().enumerate().skip(a) {
                let blk = bt_times(ga, dbb);
                for (i, row) in blk.iter().enumerate() {
                    for (c, v) in row.iter().enumerate() {
                        // column-major: entry (3a + i, 3b + c)
                        kd[(3 * a + i) + (3 * b + c) * nd] += f * v;
                    }
                }
            }
        }
    }
    // the blocks below the diagonal mirror those above (b >= a)
    for a in 0..nn {
        for b in (a + 1)..nn {
            for i in 0..3 {
                for c in 0..3 {
                    k[(3 * b + c, 3 * a + i)] = k[(3 * a + i, 3 * b + c)];
                }
            }
        }
    }
    symmetrize(&mut k);
    Ok(k)
}

/// `D B_b` (6 x 3) of the node block `B_b` with Cartesian derivative `g` ([`b_block`]: column 0
/// has `g_x, g_y, g_z` in rows 0, 3, 5; column 1 `g_y, g_x, g_z` in rows 1, 3, 4; column 2
/// `g_z, g_y, g_x` in rows 2, 4, 5).
fn d_times_b_block(d: &Matrix6<f64>, g: &Vector3<f64>) -> [[f64; 3]; 6] {
    let mut out = [[0.0; 3]; 6];
    for (r, row) in out.iter_mut().enumerate() {
        row[0] = d[(r, 0)] * g[0] + d[(r, 3)] * g[1] + d[(r, 5)] * g[2];
        row[1] = d[(r, 1)] * g[1] + d[(r, 3)] * g[0] + d[(r, 4)] * g[2];
        row[2] = d[(r, 2)] * g[2] + d[(r, 4)] * g[1] + d[(r, 5)] * g[0];
    }
    out
}

/// `B_a^T (D B_b)` (3 x 3) with the sparsity of `B_a` ([`d_times_b_block`]).
fn bt_times(g: &Vector3<f64>, db: &[[f64; 3]; 6]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for c in 0..3 {
        out[0][c] = g[0] * db[0][c] + g[1] * db[3][c] + g[2] * db[5][c];
        out[1][c] = g[1] * db[1][c] + g[0] * db[3][c] + g[2] * db[4][c];
        out[2][c] = g[2] * db[2][c] + g[1] * db[4][c] + g[0] * db[5][c];
    }
    out
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
