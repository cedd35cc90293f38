//! 20-node serendipity hexahedron (CalculiX `C3D20` with 3x3x3 Gauss, `C3D20R` with 2x2x2).

/// Reference coordinates of the 20 nodes in Abaqus order: corners 1-8, mid-edges 9-12 (bottom
/// 1-2, 2-3, 3-4, 4-1), 13-16 (top 5-6, 6-7, 7-8, 8-5), 17-20 (vertical 1-5, 2-6, 3-7, 4-8).
pub const HEX20_NODES: [[f64; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// Serendipity shape functions and derivatives. Corner a:
/// N = (1+xi xi_a)(1+eta eta_a)(1+zeta zeta_a)(xi xi_a + eta eta_a + zeta zeta_a - 2)/8;
/// mid-edge with xi_a = 0: N = (1-xi^2)(1+eta eta_a)(1+zeta zeta_a)/4 (and cyclic).
pub fn hex20_shape(xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    for (a, r) in HEX20_NODES.iter().enumerate() {
        if a < 8 {
            let f = [1.0 + xi[0] * r[0], 1.0 + xi[1] * r[1], 1.0 + xi[2] * r[2]];
            let s = xi[0] * r[0] + xi[1] * r[1] + xi[2] * r[2] - 2.0;
            n[a] = 0.125 * f[0] * f[1] * f[2] * s;
            for c in 0..3 {
                let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
                // d/dxi_c [f_c * s] = r_c s + f_c r_c
                dn[a][c] = 0.125 * f[c1] * f[c2] * r[c] * (s + f[c]);
            }
        } else {
            // direction k with r_k = 0
            let k = (0..3).find(|&c| r[c] == 0.0).unwrap_or(0);
            let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
            let q = 1.0 - xi[k] * xi[k];
            let f1 = 1.0 + xi[k1] * r[k1];
            let f2 = 1.0 + xi[k2] * r[k2];
            n[a] = 0.25 * q * f1 * f2;
            dn[a][k] = -0.5 * xi[k] * f1 * f2;
            dn[a][k1] = 0.25 * q * r[k1] * f2;
            dn[a][k2] = 0.25 * q * f1 * r[k2];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_interpolate_and_fd_derivatives() {
        let mut n = [0.0; 20];
        let mut dn = [[0.0; 3]; 20];
        for (a, r) in HEX20_NODES.iter().enumerate() {
            hex20_shape(*r, &mut n, &mut dn);
            for (b, nb) in n.iter().enumerate() {
                assert!(
                    (nb - if a == b { 1.0 } else { 0.0 }).abs() < 1e-15,
                    "node {a} fn {b}"
                );
            }
        }
        let xi = [0.31, -0.52, 0.77];
        hex20_shape(xi, &mut n, &mut dn);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        // completeness to quadratic: sum N_a xi_a^2 = xi^2
        let s: f64 = n
            .iter()
            .zip(HEX20_NODES.iter())
            .map(|(na, r)| na * r[0] * r[0])
            .sum();
        assert!((s - xi[0] * xi[0]).abs() < 1e-14);
        for c in 0..3 {
            let (mut np, mut nm) = ([0.0; 20], [0.0; 20]);
            let mut dd = [[0.0; 3]; 20];
            let (mut xp, mut xm) = (xi, xi);
            xp[c] += 1e-6;
            xm[c] -= 1e-6;
            hex20_shape(xp, &mut np, &mut dd);
            hex20_shape(xm, &mut nm, &mut dd);
            for a in 0..20 {
                assert!(
                    ((np[a] - nm[a]) / 2e-6 - dn[a][c]).abs() < 1e-9,
                    "a {a} c {c}"
                );
            }
        }
    }
}
