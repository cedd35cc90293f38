//! Integration rules on the reference hexahedron [-1, 1]^3, the reference tetrahedron
//! (0 <= xi, eta, zeta, xi + eta + zeta <= 1) and the interval [-1, 1].

/// A quadrature point: reference coordinates and weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadPoint {
    /// Reference coordinates (xi, eta, zeta).
    pub xi: [f64; 3],
    /// Weight (the weights of a rule sum to the reference volume: 8 for the cube, 1/6 for the tetrahedron).
    pub w: f64,
}

/// Gauss-Legendre points and weights on [-1, 1] with `n` = 1, 2 or 3 points (exact to degree 2n-1).
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    // +-1/sqrt(3)
    const G2: [(f64, f64); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    // +-sqrt(3/5), weights 5/9, 8/9
    const G3: [(f64, f64); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    // 4-point rule: +-sqrt(3/7 -+ 2/7 sqrt(6/5)), weights (18 +- sqrt 30)/36
    const G4: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    match n {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        _ => &G4,
    }
}

/// Tensor-product Gauss rule with `n` points per direction on the reference cube (n^3 points).
/// Point order: xi fastest, then eta, then zeta.
pub fn hex_rule(n: usize) -> Vec<QuadPoint> {
    let g = gauss_legendre(n);
    let mut v = Vec::with_capacity(g.len().pow(3));
    for &(z, wz) in g {
        for &(y, wy) in g {
            for &(x, wx) in g {
                v.push(QuadPoint {
                    xi: [x, y, z],
                    w: wx * wy * wz,
                });
            }
        }
    }
    v
}

/// 4-point rule on the reference tetrahedron, exact for polynomials of degree 2 (stiffness of the
/// 10-node tetrahedron, CalculiX `C3D10`): points (a,a,a,b) with a = (5 - sqrt 5)/20, b = 1 - 3a.
pub fn tet_rule_4() -> Vec<QuadPoint> {
    let a = 0.138_196_601_125_010_5;
    let b = 0.585_410_196_624_968_5;
    let w = 1.0 / 24.0;
    [[a, a, a], [b, a, a], [a, b, a], [a, a, b]]
        .into_iter()
        .map(|xi| QuadPoint { xi, w })
        .collect()
}

/// 14-point rule on the reference tetrahedron with positive weights, exact for polynomials of
/// degree 5 (Walkington's rule; used for the consistent mass of the 10-node tetrahedron, whose
/// integrand is of degree 4). Values refined by Newton iteration on the moment equations.
pub fn tet_rule_14() -> Vec<QuadPoint> {
    // (orbit parameter, weight) for the two 4-point orbits (a, a, a, 1 - 3a)
    let orbits4 = [
        (0.092_735_250_310_891_25, 0.012_248_840_519_393_676),
        (0.310_885_919_263_301_1, 0.018_781_320_953_002_827),
    ];
    // 6-point orbit (b, b, 1/2 - b, 1/2 - b)
    let (b, wb) = (0.045_503_704_125_649_136, 0.007_091_003_462_846_771_6);
    let mut v = Vec::with_capacity(14);
    for (a, w) in orbits4 {
        for k in 0..4 {
            let mut l = [a; 4];
            l[k] = 1.0 - 3.0 * a;
            v.push(QuadPoint {
                xi: [l[1], l[2], l[3]],
                w,
            });
        }
    }
    for i in 0..4 {
        for j in (i + 1)..4 {
            let mut l = [0.5 - b; 4];
            l[i] = b;
            l[j] = b;
            v.push(QuadPoint {
                xi: [l[1], l[2], l[3]],
                w: wb,
            });
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fact(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    /// Exact integral of xi^i eta^j zeta^k over the unit tetrahedron: i! j! k! / (i+j+k+3)!.
    fn tet_monomial(i: u32, j: u32, k: u32) -> f64 {
        fact(i) * fact(j) * fact(k) / fact(i + j + k + 3)
    }

    fn integrate(rule: &[QuadPoint], i: i32, j: i32, k: i32) -> f64 {
        rule.iter()
            .map(|p| p.w * p.xi[0].powi(i) * p.xi[1].powi(j) * p.xi[2].powi(k))
            .sum()
    }

    #[test]
    fn tet_rules_integrate_monomials_exactly() {
        for (rule, deg) in [(tet_rule_4(), 2), (tet_rule_14(), 5)] {
            assert!(rule.iter().all(|p| p.w > 0.0));
            for i in 0..=deg {
                for j in 0..=(deg - i) {
                    for k in 0..=(deg - i - j) {
                        let q = integrate(&rule, i as i32, j as i32, k as i32);
                        let e = tet_monomial(i, j, k);
                        assert!(
                            (q - e).abs() < 1e-15,
                            "deg {deg}: x^{i} y^{j} z^{k}: {q} vs {e}"
                        );
                    }
                }
            }
        }
        // and the 4-point rule is not exact at degree 3 (sanity of the check itself)
        assert!((integrate(&tet_rule_4(), 3, 0, 0) - tet_monomial(3, 0, 0)).abs() > 1e-6);
    }

    #[test]
    fn hex_rules_integrate_monomials_exactly() {
        for n in 1..=4 {
            let rule = hex_rule(n);
            let deg = 2 * n as i32 - 1;
            for i in 0..=deg {
                for j in 0..=deg {
                    // int_{-1}^{1} x^i dx = 2/(i+1) for even i, 0 for odd
                    let ex = |p: i32| {
                        if p % 2 == 0 {
                            2.0 / (p as f64 + 1.0)
                        } else {
                            0.0
                        }
                    };
                    let q = integrate(&rule, i, j, deg - i.min(deg));
                    let e = ex(i) * ex(j) * ex(deg - i.min(deg));
                    assert!((q - e).abs() < 1e-14, "n {n}: {i} {j}: {q} vs {e}");
                }
            }
        }
    }
}
