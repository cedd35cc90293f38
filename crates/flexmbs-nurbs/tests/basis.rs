//! Basis functions, rational curves and surfaces against The NURBS Book and analytic geometry.
use crate::common;
use common::Rng;
use flexmbs_nurbs::*;
use nalgebra::Vector3;
use std::f64::consts::FRAC_1_SQRT_2;

fn basis_at(kv: &KnotVector, u: f64, s: &mut BasisScratch) -> (usize, Vec<[f64; 3]>) {
    let span = kv.basis_derivatives(u, 2, false, s);
    let p = kv.degree();
    (
        span,
        (0..=p)
            .map(|j| [s.der(0, j), s.der(1, j), s.der(2, j)])
            .collect(),
    )
}

/// NURBS Book Ex2.3 / Ex2.4: U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2: span 4,
/// N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8; N' = -1/2, 0, 1/2; N'' = 1, -2, 1
/// (N_{2,2} = (3-u)^2/2, N_{3,2} = -11/2 + 5u - u^2, N_{4,2} = (u-2)^2/2 on [2, 3)).
#[test]
fn nurbs_book_example_2_3_basis_values_and_derivatives() {
    let kv = KnotVector::new(2, vec![0., 0., 0., 1., 2., 3., 4., 4., 5., 5., 5.], 8).unwrap();
    let mut s = BasisScratch::new(2);
    let (span, n) = basis_at(&kv, 2.5, &mut s);
    assert_eq!(span, 4);
    let expect = [[0.125, -0.5, 1.0], [0.75, 0.0, -2.0], [0.125, 0.5, 1.0]];
    for j in 0..3 {
        for k in 0..3 {
            assert!(
                (n[j][k] - expect[j][k]).abs() < 1e-15,
                "N^({k})_{} = {}",
                span - 2 + j,
                n[j][k]
            );
        }
    }
}

fn random_knots(rng: &mut Rng, p: usize, n_ctrl: usize) -> Vec<f64> {
    let mut interior: Vec<f64> = (0..n_ctrl - p - 1).map(|_| rng.range(0.0, 1.0)).collect();
    interior.sort_by(|a, b| a.partial_cmp(b).unwrap());
    interior.dedup();
    if interior.len() < n_ctrl - p - 1 {
        return random_knots(rng, p, n_ctrl);
    }
    let mut k = vec![0.0; p + 1];
    k.extend(interior);
    k.extend(vec![1.0; p + 1]);
    k
}

/// Partition of unity: sum_i N_{i,p} = 1 and the derivative sums vanish, for random clamped
/// knot vectors of degree 1..6 and random parameters.
#[test]
fn partition_of_unity_random_knots() {
    let mut rng = Rng::new(7);
    for trial in 0..200 {
        let p = 1 + trial % 6;
        let n_ctrl = p + 1 + rng.below(8);
        let kv = KnotVector::new(p, random_knots(&mut rng, p, n_ctrl), n_ctrl).unwrap();
        let mut s = BasisScratch::new(p);
        for _ in 0..20 {
            let (_, n) = basis_at(&kv, rng.uniform(), &mut s);
            let sums: Vec<f64> = (0..3).map(|k| n.iter().map(|v| v[k]).sum()).collect();
            let scale: f64 = n.iter().map(|v| v[2].abs()).sum::<f64>() + 1.0;
            assert!((sums[0] - 1.0).abs() < 1e-14, "sum N = {}", sums[0]);
            assert!(sums[1].abs() < 1e-12 * scale, "sum N' = {}", sums[1]);
            assert!(sums[2].abs() < 1e-11 * scale, "sum N'' = {}", sums[2]);
            assert!(n.iter().all(|v| v[0] >= 0.0));
        }
    }
}

/// Basis derivatives equal central finite differences of the lower order (inside a span).
#[test]
fn basis_derivatives_equal_finite_differences() {
    let mut rng = Rng::new(11);
    let h = 1e-6;
    for trial in 0..60 {
        let p = 1 + trial % 5;
        // interior knots 0.2 apart at least, jittered: FD error ~ h^2 N''' stays small
        let mut k = vec![0.0; p + 1];
        k.extend((1..5).map(|i| 0.2 * i as f64 + rng.range(-0.05, 0.05)));
        k.extend(vec![1.0; p + 1]);
        let kv = KnotVector::new(p, k, p + 5).unwrap();
        let mut s = BasisScratch::new(p);
        for _ in 0..10 {
            let u = rng.range(0.01, 0.99);
            let (span, n) = basis_at(&kv, u, &mut s);
            let k = kv.knots();
            if (u - k[span]).abs() < 2.0 * h || (k[span + 1] - u).abs() < 2.0 * h {
                continue;
            }
            let (_, np) = basis_at(&kv, u + h, &mut s);
            let (_, nm) = basis_at(&kv, u - h, &mut s);
            for j in 0..=p {
                let scale = 1.0 + n[j][1].abs() + n[j][2].abs();
                assert!((n[j][1] - (np[j][0] - nm[j][0]) / (2.0 * h)).abs() < 1e-7 * scale);
                if p >= 2 {
                    assert!((n[j][2] - (np[j][1] - nm[j][1]) / (2.0 * h)).abs() < 1e-6 * scale);
                }
            }
        }
    }
}

/// The unit circle as a rational quadratic (NURBS Book Ex7.1: nine control points, weights
/// 1, 1/sqrt2, ..., knots {0,0,0,1/4,1/4,1/2,1/2,3/4,3/4,1,1,1}).
pub fn unit_circle() -> NurbsCurve {
    let pts: Vec<Vector3<f64>> = [
        (1., 0.),
        (1., 1.),
        (0., 1.),
        (-1., 1.),
        (-1., 0.),
        (-1., -1.),
        (0., -1.),
        (1., -1.),
        (1., 0.),
    ]
    .iter()
    .map(|&(x, y)| Vector3::new(x, y, 0.0))
    .collect();
    let w: Vec<f64> = (0..9)
        .map(|i| if i % 2 == 0 { 1.0 } else { FRAC_1_SQRT_2 })
        .collect();
    let knots = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
    NurbsCurve::new(2, knots, &pts, &w).unwrap()
}

/// Every circle point at radius 1 to 1e-14; the curvature |C' x C''| / |C'|^3 is 1 (checks the
/// rational second derivative against geometry, not against the code).
#[test]
fn rational_quadratic_circle_radius_and_curvature() {
    let c = unit_circle();
    let mut s = c.scratch();
    for i in 0..=2000 {
        let u = i as f64 / 2000.0;
        let d = c.derivatives(u, &mut s);
        assert!(
            (d.c.norm() - 1.0).abs() < 1e-14,
            "radius at {u}: {}",
            d.c.norm()
        );
        assert!(
            d.c.dot(&d.d1).abs() < 1e-13 * d.d1.norm(),
            "tangent not orthogonal to radius"
        );
        let kappa = d.d1.cross(&d.d2).norm() / d.d1.norm().powi(3);
        assert!((kappa - 1.0).abs() < 1e-12, "curvature {kappa} at {u}");
    }
}

/// Rational curve derivatives equal central finite differences (circle, off the knots).
#[test]
fn rational_curve_derivatives_equal_finite_differences() {
    let c = unit_circle();
    let mut s = c.scratch();
    let h = 1e-6;
    for i in 0..97 {
        let u = 0.005 + 0.99 * i as f64 / 96.0;
        if [0.25, 0.5, 0.75].iter().any(|k: &f64| (u - k).abs() < 1e-3) {
            continue; // C^0 in the parameter at the double knots
        }
        let d = c.derivatives(u, &mut s);
        let (p, m) = (c.derivatives(u + h, &mut s), c.derivatives(u - h, &mut s));
        assert!((d.d1 - (p.c - m.c) / (2.0 * h)).norm() < 1e-7 * d.d1.norm());
        assert!((d.d2 - (p.d1 - m.d1) / (2.0 * h)).norm() < 1e-6 * d.d2.norm());
    }
}

/// The unit sphere as a rational biquadratic surface of revolution (NURBS Book §8.5: the
/// semicircle of 5 points, weights 1, 1/sqrt2, 1, 1/sqrt2, 1, revolved by the 9-point circle).
pub fn unit_sphere() -> NurbsSurface {
    let circle = unit_circle();
    let half = [
        (0., -1., 1.0),
        (1., -1., FRAC_1_SQRT_2),
        (1., 0., 1.0),
        (1., 1., FRAC_1_SQRT_2),
        (0., 1., 1.0),
    ];
    let (mut pts, mut w) = (Vec::new(), Vec::new());
    for &(r, z, wm) in &half {
        for c in circle.control_points_w() {
            let (cx, cy, wc) = (c.x / c.w, c.y / c.w, c.w);
            pts.push(Vector3::new(r * cx, r * cy, z));
            w.push(wm * wc);
        }
    }
    let eta = KnotVector::new(2, vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.], 5).unwrap();
    let xi = circle.knot_vector().clone();
    NurbsSurface::new(eta, xi, &pts, &w).unwrap()
}

#[test]
fn rational_sphere_points_on_radius_and_derivatives_equal_finite_differences() {
    let s = unit_sphere();
    let mut sc = s.scratch();
    let h = 1e-6;
    let mut rng = Rng::new(3);
    for _ in 0..400 {
        let (u, v) = (rng.range(0.02, 0.98), rng.range(0.0, 1.0));
        let d = s.derivatives(u, v, &mut sc);
        assert!((d.s.norm() - 1.0).abs() < 1e-14, "radius {}", d.s.norm());
        if [0.5].iter().any(|k: &f64| (u - k).abs() < 2.0 * h)
            || [0.25, 0.5, 0.75]
                .iter()
                .any(|k: &f64| (v - k).abs() < 2.0 * h)
        {
            continue;
        }
        let (up, um) = (
            s.derivatives(u + h, v, &mut sc),
            s.derivatives(u - h, v, &mut sc),
        );
        let (vp, vm) = (
            s.derivatives(u, v + h, &mut sc),
            s.derivatives(u, v - h, &mut sc),
        );
        let n = 1.0 + d.s_uu.norm() + d.s_vv.norm() + d.s_uv.norm();
        assert!((d.s_u - (up.s - um.s) / (2.0 * h)).norm() < 1e-7 * n);
        assert!((d.s_v - (vp.s - vm.s) / (2.0 * h)).norm() < 1e-7 * n);
        assert!((d.s_uu - (up.s_u - um.s_u) / (2.0 * h)).norm() < 1e-6 * n);
        assert!((d.s_vv - (vp.s_v - vm.s_v) / (2.0 * h)).norm() < 1e-6 * n);
        assert!((d.s_uv - (vp.s_u - vm.s_u) / (2.0 * h)).norm() < 1e-6 * n);
        assert!((d.s_uv - (up.s_v - um.s_v) / (2.0 * h)).norm() < 1e-6 * n);
        // the normal (3.27) of a sphere is radial
        assert!(d.normal().cross(&d.s).norm() < 1e-12);
    }
}

#[test]
fn bad_curve_input_gives_typed_errors() {
    let pts = vec![Vector3::zeros(); 4];
    let w = vec![1.0; 4];
    let e = NurbsCurve::new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 0.9], &pts, &w).unwrap_err();
    assert!(
        matches!(e, NurbsError::KnotsNotNondecreasing { index: 7, .. }),
        "{e}"
    );
    let e = NurbsCurve::new(3, vec![0., 0., 0., 0., 1., 1., 1.], &pts, &w).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::KnotCountMismatch {
                got: 7,
                expected: 8,
                ..
            }
        ),
        "{e}"
    );
    let e = NurbsCurve::new(3, vec![0.; 7], &pts[..3], &w[..3]).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::TooFewPoints {
                got: 3,
                needed: 4,
                ..
            }
        ),
        "{e}"
    );
    let e = NurbsCurve::new(
        3,
        vec![0., 0., 0., 0., 1., 1., 1., 1.],
        &pts,
        &[1., 0., 1., 1.],
    )
    .unwrap_err();
    assert!(
        matches!(e, NurbsError::NonPositiveWeight { index: 1, .. }),
        "{e}"
    );
    let e = NurbsCurve::new(3, vec![0., 0., 0., 0., 1., 1., 1., 1.], &pts, &w[..3]).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::SizeMismatch {
                what: "weights",
                ..
            }
        ),
        "{e}"
    );
    let e = NurbsCurve::new(3, vec![0., 0., 0., 0., f64::NAN, 1., 1., 1.], &pts, &w).unwrap_err();
    assert!(
        matches!(e, NurbsError::NonFiniteKnot { index: 4, .. }),
        "{e}"
    );
    let e = NurbsCurve::new(3, vec![0.; 8], &pts, &w).unwrap_err();
    assert!(matches!(e, NurbsError::EmptyDomain { .. }), "{e}");
    let e = NurbsCurve::new(0, vec![0., 0.5, 1., 1., 1.], &pts, &w).unwrap_err();
    assert!(matches!(e, NurbsError::ZeroDegree { .. }), "{e}");
    let pts8 = vec![Vector3::zeros(); 8];
    let knots = vec![0., 0., 0., 0., 0.5, 0.5, 0.5, 0.5, 1., 1., 1., 1.];
    let e = NurbsCurve::new(3, knots, &pts8, &[1.; 8]).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::KnotMultiplicity {
                multiplicity: 4,
                allowed: 3,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn bad_interpolation_input_gives_typed_errors() {
    let pts = [Vector3::<f64>::zeros(); 4];
    let e =
        CurveInterpolator::from_points(&pts[..3], ParamMethod::ChordLength, 3, false).unwrap_err();
    assert!(
        matches!(e, NurbsError::CoincidentPoints { index: 0, next: 1 }),
        "{e}"
    );
    let e = CurveInterpolator::new(&[0.0, 0.5, 0.4, 1.0], 3, false).unwrap_err();
    assert!(
        matches!(e, NurbsError::ParametersNotIncreasing { index: 2 }),
        "{e}"
    );
    let e = CurveInterpolator::new(&[0.0, 0.5, 1.0], 3, false).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::TooFewPoints {
                got: 3,
                needed: 4,
                ..
            }
        ),
        "{e}"
    );
    let e = CurveInterpolator::new(&[0.0, 0.3, 0.6, 1.0], 3, true).unwrap_err();
    assert!(
        matches!(e, NurbsError::ParametersNotIncreasing { .. }),
        "{e}"
    );
    let ip = CurveInterpolator::new(&[0.0, 0.3, 0.6, 1.0], 3, false).unwrap();
    let mut ctrl = vec![0.0; 3];
    let e = ip.control_points_into(&[0.0; 4], &mut ctrl).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::SizeMismatch {
                expected: 4,
                got: 3,
                ..
            }
        ),
        "{e}"
    );
}

/// One-sided evaluation really picks the span on the left: at the double knots of the circle
/// the parametric second derivative jumps (the curve is only C^1 in its parameter there).
#[test]
fn left_limits_differ_where_the_curve_is_not_c2() {
    let c = unit_circle();
    let mut s = c.scratch();
    let (l, r) = (
        c.derivatives_left(0.25, &mut s),
        c.derivatives(0.25, &mut s),
    );
    assert!((l.c - r.c).norm() < 1e-15);
    assert!(
        (l.d2 - r.d2).norm() > 1.0,
        "left {:?} right {:?}",
        l.d2,
        r.d2
    );
    let (lm, rm) = (
        c.derivatives(0.25 - 1e-9, &mut s),
        c.derivatives(0.25 + 1e-9, &mut s),
    );
    assert!(
        (l.d2 - lm.d2).norm() < 1e-6 * l.d2.norm() && (r.d2 - rm.d2).norm() < 1e-6 * r.d2.norm()
    );
}
