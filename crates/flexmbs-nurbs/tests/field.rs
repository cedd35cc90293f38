//! Interpolated fields (positions, mode shapes, scalars) evaluated with the interpolator's basis.
use crate::common;
use common::Rng;
use flexmbs_nurbs::*;
use nalgebra::Vector3;

/// A scalar bicubic polynomial is reproduced exactly by open bicubic interpolation (the spline
/// space contains it): value and all partials up to order two against the analytic ones.
#[test]
fn scalar_polynomial_field_is_reproduced_with_its_partials() {
    let mut rng = Rng::new(17);
    let pe: Vec<f64> = (0..9)
        .map(|i| (i as f64 + 0.3 * rng.uniform()) / 8.3)
        .collect();
    let px: Vec<f64> = (0..6)
        .map(|j| (j as f64 + 0.3 * rng.uniform()) / 5.3)
        .collect();
    let f = |u: f64, v: f64| u.powi(3) - 2.0 * u * v * v + v + 0.5 * u * u * v.powi(3);
    let partials = |u: f64, v: f64| {
        [
            f(u, v),
            3.0 * u * u - 2.0 * v * v + u * v.powi(3),
            -4.0 * u * v + 1.0 + 1.5 * u * u * v * v,
            6.0 * u + v.powi(3),
            -4.0 * v + 3.0 * u * v * v,
            -4.0 * u + 3.0 * u * u * v,
        ]
    };
    let ip = SurfaceInterpolator::new(&pe, &px, [3, 3], [false, false]).unwrap();
    let values: Vec<f64> = pe
        .iter()
        .flat_map(|&u| px.iter().map(move |&v| f(u, v)))
        .collect();
    let mut net = vec![0.0; ip.n_ctrl()];
    ip.control_points_into(&values, &mut net).unwrap();
    let mut s = ip.scratch();
    for _ in 0..200 {
        let (u, v) = (rng.range(pe[0], pe[8]), rng.range(px[0], px[5]));
        let got = ip.field_derivatives(&net, u, v, &mut s).unwrap();
        let want = partials(u, v);
        for k in 0..6 {
            assert!(
                (got[k] - want[k]).abs() < 1e-10,
                "partial {k} at ({u},{v}): {} vs {}",
                got[k],
                want[k]
            );
        }
    }
    let e = ip
        .field_derivatives(&net[1..], 0.5, 0.5, &mut s)
        .unwrap_err();
    assert!(matches!(
        e,
        NurbsError::SizeMismatch {
            what: "control net",
            ..
        }
    ));
}

/// The contour of a deformed body: positions X0 + Phi q of the nodes. Its derivatives equal the
/// fields of the undeformed net plus the mode shape's net times q (nets interpolated once), and
/// the derivatives of the surface interpolated through the deformed nodes.
#[test]
fn mode_shape_nets_superpose_to_the_deformed_contour() {
    let (ne, nx) = (10, 4);
    let mut x0 = Vec::new();
    let mut phi = Vec::new();
    for i in 0..ne {
        for j in 0..nx {
            let (a, b) = (i as f64 / (ne - 1) as f64, j as f64 / (nx - 1) as f64);
            x0.push(Vector3::new(2.0 * a, 0.3 * b, 0.05 * (3.0 * a).sin()));
            phi.push(Vector3::new(0.0, 0.1 * a * b, a * a * (3.0 - 2.0 * a)));
        }
    }
    let ip = SurfaceInterpolator::from_grid(
        &x0,
        ne,
        nx,
        ParamMethod::ChordLength,
        [3, 3],
        [false, false],
    )
    .unwrap();
    let (mut n0, mut nphi) = (
        vec![Vector3::zeros(); ip.n_ctrl()],
        vec![Vector3::zeros(); ip.n_ctrl()],
    );
    ip.control_points_into(&x0, &mut n0).unwrap();
    ip.control_points_into(&phi, &mut nphi).unwrap();
    let q = 0.37;
    let deformed: Vec<_> = x0.iter().zip(&phi).map(|(x, p)| x + p * q).collect();
    let surf = ip.interpolate(&deformed).unwrap();
    let (mut s, mut ss) = (ip.scratch(), surf.scratch());
    let mut rng = Rng::new(2);
    for _ in 0..100 {
        let (u, v) = (rng.uniform(), rng.uniform());
        let a = ip.field_derivatives(&n0, u, v, &mut s).unwrap();
        let b = ip.field_derivatives(&nphi, u, v, &mut s).unwrap();
        let d = surf.derivatives(u, v, &mut ss);
        let want = [d.s, d.s_u, d.s_v, d.s_uu, d.s_uv, d.s_vv];
        for k in 0..6 {
            assert!(
                (a[k] + b[k] * q - want[k]).norm() < 1e-12 * (1.0 + want[k].norm()),
                "partial {k}"
            );
        }
    }
}

/// Curves: a closed interpolant's field equals the curve, and an open one reproduces a cubic.
#[test]
fn curve_fields() {
    let pts: Vec<Vector3<f64>> = (0..12)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 12.0;
            Vector3::new(t.cos(), 0.5 * t.sin(), 0.1 * t.cos() * t.sin())
        })
        .collect();
    let ip = CurveInterpolator::from_points(&pts, ParamMethod::Centripetal, 3, true).unwrap();
    let c = ip.interpolate(&pts).unwrap();
    let mut net = vec![Vector3::zeros(); ip.n_ctrl()];
    ip.control_points_into(&pts, &mut net).unwrap();
    let (mut s, mut cs) = (ip.scratch(), c.scratch());
    for i in 0..50 {
        let u = i as f64 / 50.0;
        let f = ip.field_derivatives(&net, u, &mut s).unwrap();
        let d = c.derivatives(u, &mut cs);
        assert!((f[0] - d.c).norm() + (f[1] - d.d1).norm() + (f[2] - d.d2).norm() < 1e-12);
    }
    let params = [0.0, 0.1, 0.35, 0.5, 0.8, 1.0];
    let ip = CurveInterpolator::new(&params, 3, false).unwrap();
    let vals: Vec<f64> = params.iter().map(|u| 2.0 * u * u * u - u + 0.5).collect();
    let mut net = vec![0.0; 6];
    ip.control_points_into(&vals, &mut net).unwrap();
    let mut s = ip.scratch();
    let f = ip.field_derivatives(&net, 0.6, &mut s).unwrap();
    assert!((f[0] - (2.0 * 0.216 - 0.6 + 0.5)).abs() < 1e-13);
    assert!((f[1] - (6.0 * 0.36 - 1.0)).abs() < 1e-12);
    assert!((f[2] - 12.0 * 0.6).abs() < 1e-11);
    let other = CurveInterpolator::new(&params, 2, false).unwrap();
    let e = other.field_derivatives(&net, 0.5, &mut s).unwrap_err();
    assert!(
        matches!(
            e,
            NurbsError::SizeMismatch {
                what: "scratch degree",
                ..
            }
        ),
        "{e}"
    );
}
