//! Global interpolation of curves and surfaces, open and closed (seed 000 (3.18)-(3.23)).
use crate::common;
use common::Rng;
use flexmbs_nurbs::params::curve_parameters;
use flexmbs_nurbs::*;
use nalgebra::Vector3;
use std::f64::consts::TAU;

/// A wavy open polyline (distinct, unevenly spaced points).
fn wavy(k: usize, rng: &mut Rng) -> Vec<Vector3<f64>> {
    let mut x = 0.0;
    (0..k)
        .map(|i| {
            x += rng.range(0.3, 1.5);
            Vector3::new(x, (0.7 * x).sin() + 0.1 * i as f64, 0.3 * (1.3 * x).cos())
        })
        .collect()
}

/// A closed, non-circular loop (unevenly spaced angles).
fn loop_points(k: usize, rng: &mut Rng) -> Vec<Vector3<f64>> {
    (0..k)
        .map(|i| {
            let t = TAU * (i as f64 + rng.range(-0.3, 0.3)) / k as f64;
            let r = 1.0 + 0.3 * (3.0 * t).cos();
            Vector3::new(r * t.cos(), 0.7 * r * t.sin(), 0.2 * (2.0 * t).sin())
        })
        .collect()
}

fn close(a: &Vector3<f64>, b: &Vector3<f64>, tol: f64) -> bool {
    (a - b).norm() <= tol * (1.0 + a.norm())
}

#[test]
fn open_and_closed_curves_pass_through_the_points() {
    let mut rng = Rng::new(5);
    for degree in 1..=5 {
        for method in [ParamMethod::ChordLength, ParamMethod::Centripetal] {
            for closed in [false, true] {
                let k = degree + 1 + rng.below(25);
                let pts = if closed {
                    loop_points(k.max(4), &mut rng)
                } else {
                    wavy(k, &mut rng)
                };
                let ip = CurveInterpolator::from_points(&pts, method, degree, closed).unwrap();
                let c = ip.interpolate(&pts).unwrap();
                assert_eq!(c.is_periodic(), closed);
                let mut s = c.scratch();
                for (q, &u) in pts.iter().zip(ip.params()) {
                    let p = c.point(u, &mut s);
                    assert!(
                        close(&p, q, 1e-12),
                        "p={degree} closed={closed}: |C(u)-Q| = {:e}",
                        (p - q).norm()
                    );
                }
            }
        }
    }
}

/// (3.19)-(3.21): chord-length parameters are the normalized cumulative chord lengths.
#[test]
fn chord_length_and_centripetal_parameters() {
    let pts: Vec<Vector3<f64>> = [0.0, 1.0, 3.0, 7.0]
        .iter()
        .map(|&x| Vector3::new(x, 0.0, 0.0))
        .collect();
    let u = curve_parameters(&pts, ParamMethod::ChordLength, false).unwrap();
    assert_eq!(u, vec![0.0, 1.0 / 7.0, 3.0 / 7.0, 1.0]);
    let u = curve_parameters(&pts, ParamMethod::Centripetal, false).unwrap();
    let d = 1.0 + 2f64.sqrt() + 2.0;
    let expect = [0.0, 1.0 / d, (1.0 + 2f64.sqrt()) / d, 1.0];
    assert!(u.iter().zip(expect).all(|(a, b)| (a - b).abs() < 1e-15));
    let u = curve_parameters(&pts, ParamMethod::ChordLength, true).unwrap();
    assert_eq!(u, vec![0.0, 1.0 / 14.0, 3.0 / 14.0, 7.0 / 14.0]);
}

/// An open interpolant of degree p reproduces a polynomial curve of degree p exactly (the
/// spline space contains the polynomials): reference independent of the interpolation code.
#[test]
fn open_interpolation_reproduces_polynomials() {
    let mut rng = Rng::new(9);
    for degree in 1..=5 {
        let k = degree + 1 + rng.below(15);
        let mut params: Vec<f64> = (0..k).map(|_| rng.uniform()).collect();
        params.sort_by(|a, b| a.partial_cmp(b).unwrap());
        params.dedup();
        if params.len() < degree + 1 {
            continue;
        }
        let poly = |u: f64| {
            Vector3::new(
                u.powi(degree as i32),
                1.0 - 2.0 * u,
                (0..=degree).map(|j| u.powi(j as i32)).sum(),
            )
        };
        let dpoly = |u: f64| {
            Vector3::new(
                degree as f64 * u.powi(degree as i32 - 1),
                -2.0,
                (1..=degree).map(|j| j as f64 * u.powi(j as i32 - 1)).sum(),
            )
        };
        let ip = CurveInterpolator::new(&params, degree, false).unwrap();
        let pts: Vec<_> = params.iter().map(|&u| poly(u)).collect();
        let c = ip.interpolate(&pts).unwrap();
        let mut s = c.scratch();
        let (lo, hi) = c.domain();
        for i in 0..=100 {
            let u = lo + (hi - lo) * i as f64 / 100.0;
            let d = c.derivatives(u, &mut s);
            assert!(
                (d.c - poly(u)).norm() < 1e-9,
                "degree {degree}: {:e}",
                (d.c - poly(u)).norm()
            );
            assert!(
                (d.d1 - dpoly(u)).norm() < 1e-7 * (1.0 + dpoly(u).norm()),
                "degree {degree} C'"
            );
        }
    }
}

/// Closed interpolants are C^2 across the seam (cubic, quartic, quintic) and at interior knots:
/// one-sided limits from the left equal the values from the right.
#[test]
fn closed_curves_are_c2_across_the_seam() {
    let mut rng = Rng::new(21);
    for degree in 3..=5 {
        let pts = loop_points(12, &mut rng);
        let ip =
            CurveInterpolator::from_points(&pts, ParamMethod::Centripetal, degree, true).unwrap();
        let c = ip.interpolate(&pts).unwrap();
        let mut s = c.scratch();
        let (lo, hi) = c.domain();
        let knots = c.knot_vector().knots().to_vec();
        for &u in knots.iter().filter(|&&u| u >= lo && u < hi) {
            let right = c.derivatives(u, &mut s);
            let left = c.derivatives_left(u, &mut s);
            let scale = 1.0 + right.d2.norm();
            assert!(close(&left.c, &right.c, 1e-13), "C0 at {u}");
            assert!((left.d1 - right.d1).norm() < 1e-11 * scale, "C1 at {u}");
            assert!(
                (left.d2 - right.d2).norm() < 1e-10 * scale,
                "C2 at {u}: {:e}",
                (left.d2 - right.d2).norm()
            );
        }
        // the seam: the end of the period continues into its start
        let end = c.derivatives_left(hi, &mut s);
        let start = c.derivatives(lo, &mut s);
        assert!((end.d2 - start.d2).norm() < 1e-10 * (1.0 + start.d2.norm()));
        // and it is a genuine seam: the left evaluation at lo uses the last span of the period
        assert!((c.derivatives(hi - 1e-9, &mut s).c - start.c).norm() < 1e-7);
    }
}

/// A closed cubic through k points of a circle converges to the circle at O(h^4).
#[test]
fn closed_cubic_converges_to_circle_fourth_order() {
    let mut errs = Vec::new();
    for k in [8usize, 16, 32] {
        let pts: Vec<_> = (0..k)
            .map(|i| {
                let t = TAU * i as f64 / k as f64;
                Vector3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let c = CurveInterpolator::from_points(&pts, ParamMethod::ChordLength, 3, true)
            .unwrap()
            .interpolate(&pts)
            .unwrap();
        let mut s = c.scratch();
        let err = (0..1000)
            .map(|i| (c.point(i as f64 / 1000.0, &mut s).norm() - 1.0).abs())
            .fold(0.0, f64::max);
        errs.push(err);
    }
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 3.7, "radial error {errs:?}, order {order}");
    }
    assert!(errs[2] < 1e-5, "{errs:?}");
}

/// The map points -> control points is linear (mode shapes can be interpolated once), and
/// re-interpolation in place equals a fresh interpolation.
#[test]
fn reinterpolation_is_linear_and_matches_fresh_interpolation() {
    let mut rng = Rng::new(33);
    for closed in [false, true] {
        let pts = if closed {
            loop_points(15, &mut rng)
        } else {
            wavy(15, &mut rng)
        };
        let ip = CurveInterpolator::from_points(&pts, ParamMethod::ChordLength, 3, closed).unwrap();
        let mut curve = ip.interpolate(&pts).unwrap();
        let shape: Vec<Vector3<f64>> = (0..15)
            .map(|_| Vector3::new(rng.uniform(), rng.uniform(), rng.uniform()))
            .collect();
        let deformed: Vec<_> = pts.iter().zip(&shape).map(|(p, s)| p + s * 0.05).collect();
        let n = ip.n_ctrl();
        let (mut c0, mut cs, mut cd) = (
            vec![Vector3::zeros(); n],
            vec![Vector3::zeros(); n],
            vec![Vector3::zeros(); n],
        );
        ip.control_points_into(&pts, &mut c0).unwrap();
        ip.control_points_into(&shape, &mut cs).unwrap();
        ip.control_points_into(&deformed, &mut cd).unwrap();
        for i in 0..n {
            assert!((cd[i] - (c0[i] + cs[i] * 0.05)).norm() < 1e-13 * (1.0 + cd[i].norm()));
        }
        ip.update_curve(&deformed, &mut curve).unwrap();
        let fresh = ip.interpolate(&deformed).unwrap();
        for (a, b) in curve
            .control_points_w()
            .iter()
            .zip(fresh.control_points_w())
        {
            assert!((a - b).norm() < 1e-14 * (1.0 + a.norm()));
        }
    }
}

/// A grid on a deformed cylinder patch: `eta` around (closed or open), `xi` along the axis.
fn cylinder_grid(ne: usize, nx: usize, closed_eta: bool, rng: &mut Rng) -> Vec<Vector3<f64>> {
    let span = if closed_eta {
        TAU / ne as f64
    } else {
        2.0 / (ne - 1) as f64
    };
    let mut g = Vec::new();
    for i in 0..ne {
        for j in 0..nx {
            let t = span * i as f64 + 0.02 * rng.range(-1.0, 1.0);
            let z = 0.4 * j as f64 + 0.05 * (i as f64).sin();
            let r = 1.0 + 0.1 * (t * 2.0).cos() + 0.05 * z * z;
            g.push(Vector3::new(r * t.cos(), r * t.sin(), z));
        }
    }
    g
}

/// Seam continuity of a surface along its closed direction, at several lines across it: the
/// one-sided limits from the end of the period equal the values at its start up to order two.
fn assert_c2_across_seam(surf: &NurbsSurface, closed: [bool; 2], s: &mut SurfaceScratch) {
    for line in 0..5 {
        let t = 0.1 + 0.2 * line as f64;
        let (a, b) = if closed[0] {
            let (lo, hi) = surf.eta_knots().domain();
            (
                surf.derivatives(lo, t, s),
                surf.derivatives_left(hi, t, [true, false], s),
            )
        } else if closed[1] {
            let (lo, hi) = surf.xi_knots().domain();
            (
                surf.derivatives(t, lo, s),
                surf.derivatives_left(t, hi, [false, true], s),
            )
        } else {
            continue;
        };
        let sc = 1.0 + a.s_uu.norm() + a.s_vv.norm() + a.s_uv.norm();
        assert!((a.s - b.s).norm() < 1e-13 * sc);
        assert!((a.s_u - b.s_u).norm() + (a.s_v - b.s_v).norm() < 1e-11 * sc);
        assert!(
            (a.s_uu - b.s_uu).norm() + (a.s_uv - b.s_uv).norm() + (a.s_vv - b.s_vv).norm()
                < 1e-10 * sc,
            "{closed:?}"
        );
    }
}

#[test]
fn surfaces_pass_through_the_grid_and_closed_directions_are_c2() {
    let mut rng = Rng::new(44);
    for (closed, degrees) in [
        ([false, false], [3, 3]),
        ([true, false], [3, 3]),
        ([true, false], [3, 2]),
        ([false, true], [2, 3]),
    ] {
        let (ne, nx) = (11, 7);
        let grid = if closed[1] {
            // closed along xi: transpose the cylinder so the loop runs along j
            let g = cylinder_grid(nx, ne, true, &mut rng);
            (0..ne)
                .flat_map(|i| (0..nx).map(move |j| (i, j)))
                .map(|(i, j)| g[j * ne + i])
                .collect()
        } else {
            cylinder_grid(ne, nx, closed[0], &mut rng)
        };
        let ip = SurfaceInterpolator::from_grid(
            &grid,
            ne,
            nx,
            ParamMethod::ChordLength,
            degrees,
            closed,
        )
        .unwrap();
        let surf = ip.interpolate(&grid).unwrap();
        let mut s = surf.scratch();
        for i in 0..ne {
            for j in 0..nx {
                let (u, v) = (ip.eta().params()[i], ip.xi().params()[j]);
                let p = surf.point(u, v, &mut s);
                assert!(
                    close(&p, &grid[i * nx + j], 1e-12),
                    "{closed:?} ({i},{j}): {:e}",
                    (p - grid[i * nx + j]).norm()
                );
            }
        }
        assert_c2_across_seam(&surf, closed, &mut s);
        // in-place update equals a fresh interpolation
        let moved: Vec<_> = grid
            .iter()
            .map(|p| p + Vector3::new(0.01 * p.z, 0.0, 0.02 * p.x))
            .collect();
        let mut upd = surf.clone();
        ip.update_surface(&moved, &mut upd).unwrap();
        let fresh = ip.interpolate(&moved).unwrap();
        for (a, b) in upd.control_points_w().iter().zip(fresh.control_points_w()) {
            assert!((a - b).norm() < 1e-14 * (1.0 + a.norm()));
        }
    }
}

/// Surface derivatives of an interpolated (non-rational) surface equal central differences.
#[test]
fn interpolated_surface_derivatives_equal_finite_differences() {
    let mut rng = Rng::new(8);
    let grid = cylinder_grid(9, 6, true, &mut rng);
    let surf = SurfaceInterpolator::from_grid(
        &grid,
        9,
        6,
        ParamMethod::Centripetal,
        [3, 3],
        [true, false],
    )
    .unwrap()
    .interpolate(&grid)
    .unwrap();
    let mut s = surf.scratch();
    let h = 1e-6;
    let knots: Vec<f64> = surf
        .eta_knots()
        .knots()
        .iter()
        .chain(surf.xi_knots().knots())
        .copied()
        .collect();
    for _ in 0..300 {
        let (u, v) = (rng.uniform(), rng.range(0.01, 0.99));
        if knots
            .iter()
            .any(|k| (u - k).abs() < 1e-4 || (v - k).abs() < 1e-4)
        {
            continue;
        }
        let d = surf.derivatives(u, v, &mut s);
        let (up, um) = (
            surf.derivatives(u + h, v, &mut s),
            surf.derivatives(u - h, v, &mut s),
        );
        let (vp, vm) = (
            surf.derivatives(u, v + h, &mut s),
            surf.derivatives(u, v - h, &mut s),
        );
        let n = 1.0 + d.s_uu.norm() + d.s_vv.norm() + d.s_uv.norm();
        assert!((d.s_u - (up.s - um.s) / (2.0 * h)).norm() < 1e-7 * n);
        assert!((d.s_v - (vp.s - vm.s) / (2.0 * h)).norm() < 1e-7 * n);
        assert!((d.s_uu - (up.s_u - um.s_u) / (2.0 * h)).norm() < 1e-6 * n);
        assert!((d.s_vv - (vp.s_v - vm.s_v) / (2.0 * h)).norm() < 1e-6 * n);
        assert!((d.s_uv - (vp.s_u - vm.s_u) / (2.0 * h)).norm() < 1e-6 * n);
    }
}

/// A torus grid (closed in both directions): the surface passes through the points, is C^2
/// across both seams, and approximates the torus to O(h^4) (checked against the exact radius of
/// the tube at points between the nodes).
#[test]
fn torus_closed_in_both_directions() {
    let (big, small) = (2.0, 0.5);
    let torus = |a: f64, b: f64| {
        let rr = big + small * b.cos();
        Vector3::new(rr * a.cos(), rr * a.sin(), small * b.sin())
    };
    let mut errs = Vec::new();
    for (ne, nx) in [(16, 8), (32, 16)] {
        let grid: Vec<_> = (0..ne)
            .flat_map(|i| (0..nx).map(move |j| (i, j)))
            .map(|(i, j)| torus(TAU * i as f64 / ne as f64, TAU * j as f64 / nx as f64))
            .collect();
        let ip = SurfaceInterpolator::from_grid(
            &grid,
            ne,
            nx,
            ParamMethod::ChordLength,
            [3, 3],
            [true, true],
        )
        .unwrap();
        let surf = ip.interpolate(&grid).unwrap();
        let mut s = surf.scratch();
        for i in 0..ne {
            for j in 0..nx {
                let p = surf.point(ip.eta().params()[i], ip.xi().params()[j], &mut s);
                assert!(close(&p, &grid[i * nx + j], 1e-12));
            }
        }
        assert_c2_across_seam(&surf, [true, false], &mut s);
        assert_c2_across_seam(&surf, [false, true], &mut s);
        let mut err: f64 = 0.0;
        for k in 0..2000 {
            let (u, v) = ((k as f64 * 0.618_034) % 1.0, (k as f64 * 0.414_214) % 1.0);
            let p = surf.point(u, v, &mut s);
            let centre = Vector3::new(p.x, p.y, 0.0).normalize() * big;
            err = err.max(((p - centre).norm() - small).abs());
        }
        errs.push(err);
    }
    let order = (errs[0] / errs[1]).log2();
    assert!(
        order > 3.5 && errs[1] < 1e-4,
        "tube radius errors {errs:?}, order {order}"
    );
}

/// The data weights reproduce the interpolated curve and surface (`Σ w_i Q_i = C(u)` to 1e-12
/// for data they were not built from), sum to 1, and are the unit vector at a data parameter
/// (open and closed).
#[test]
fn data_weights_reproduce_the_interpolants() {
    let mut rng = Rng::new(71);
    for closed in [false, true] {
        let pts = if closed {
            loop_points(9, &mut rng)
        } else {
            wavy(9, &mut rng)
        };
        let ip = CurveInterpolator::from_points(&pts, ParamMethod::ChordLength, 3, closed).unwrap();
        let curve = ip.interpolate(&pts).unwrap();
        let mut s = curve.scratch();
        for u in [0.0, 0.137, 0.5, 0.731, 0.999] {
            let w = ip.data_weights(u).unwrap();
            let c: Vector3<f64> = w.iter().zip(&pts).map(|(wi, p)| *wi * p).sum();
            assert!(
                close(&c, &curve.point(u, &mut s), 1e-12),
                "closed {closed}, u {u}"
            );
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
        let u3 = ip.params()[3];
        let w = ip.data_weights(u3).unwrap();
        for (i, wi) in w.iter().enumerate() {
            assert!(
                (wi - f64::from(u8::from(i == 3))).abs() < 1e-12,
                "{i}: {wi}"
            );
        }
    }
    let (ne, nx) = (11, 7);
    let grid = cylinder_grid(ne, nx, false, &mut rng);
    let ip = SurfaceInterpolator::from_grid(
        &grid,
        ne,
        nx,
        ParamMethod::ChordLength,
        [3, 3],
        [false, false],
    )
    .unwrap();
    let surf = ip.interpolate(&grid).unwrap();
    let mut s = surf.scratch();
    for (eta, xi) in [(0.2, 0.3), (0.55, 0.91), (0.0, 1.0)] {
        let w = ip.data_weights(eta, xi).unwrap();
        let p: Vector3<f64> = w.iter().zip(&grid).map(|(wi, q)| *wi * q).sum();
        assert!(
            close(&p, &surf.point(eta, xi, &mut s), 1e-12),
            "({eta}, {xi})"
        );
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
}
