//! 10-node quadratic tetrahedron (CalculiX `C3D10`): stiffness with the 4-point rule (exact for
//! the quadratic B^T D B of a straight-edged element), consistent mass with the 14-point rule
//! (degree 5, exact for the quartic N^T N).

/// Reference coordinates of the 10 nodes: corners 1-4 at (0,0,0), (1,0,0), (0,1,0), (0,0,1);
/// mid-edges 5:(1-2), 6:(2-3), 7:(3-1), 8:(1-4), 9:(2-4), 10:(3-4).
pub const TET10_NODES: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

/// Corner pairs of the mid-edge nodes 5..10 (0-based corner indices).
const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// Quadratic shape functions in volume coordinates L1 = 1 - xi - eta - zeta, L2 = xi, L3 = eta,
/// L4 = zeta: corners N = L_i (2 L_i - 1), mid-edges N = 4 L_i L_j.
pub fn tet10_shape(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    // dL_i/dxi
    let dl: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for c in 0..3 {
            dn[i][c] = (4.0 * l[i] - 1.0) * dl[i][c];
        }
    }
    for (e, &(i, j)) in EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[i] * l[j];
        for c in 0..3 {
            dn[4 + e][c] = 4.0 * (dl[i][c] * l[j] + l[i] * dl[j][c]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_interpolate_and_fd_derivatives() {
        let mut n = [0.0; 10];
        let mut dn = [[0.0; 3]; 10];
        for (a, r) in TET10_NODES.iter().enumerate() {
            tet10_shape(*r, &mut n, &mut dn);
            for (b, nb) in n.iter().enumerate() {
                assert!(
                    (nb - if a == b { 1.0 } else { 0.0 }).abs() < 1e-15,
                    "node {a} fn {b}"
                );
            }
        }
        let xi = [0.21, 0.33, 0.17];
        tet10_shape(xi, &mut n, &mut dn);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        for c in 0..3 {
            let (mut np, mut nm) = ([0.0; 10], [0.0; 10]);
            let mut dd = [[0.0; 3]; 10];
            let (mut xp, mut xm) = (xi, xi);
            xp[c] += 1e-6;
            xm[c] -= 1e-6;
            tet10_shape(xp, &mut np, &mut dd);
            tet10_shape(xm, &mut nm, &mut dd);
            for a in 0..10 {
                assert!(((np[a] - nm[a]) / 2e-6 - dn[a][c]).abs() < 1e-9);
            }
        }
    }
}
