//! Contact search (seed 000 §3.3) on analytic contours with known closest points, and on NURBS
//! contours against brute-force dense sampling.
use crate::common;
use common::Rng;
use flexmbs_nurbs::*;
use nalgebra::Vector3;
use std::f64::consts::{PI, TAU};

/// Plane patch `o + eta a + xi b`, `eta in [0, 2]`, `xi in [0, 1]`, `a` and `b` orthogonal.
struct Plane {
    o: Vector3<f64>,
    a: Vector3<f64>,
    b: Vector3<f64>,
}
impl ParametricSurface for Plane {
    type Scratch = ();
    fn ranges(&self) -> [ParamRange; 2] {
        [
            ParamRange {
                lo: 0.0,
                hi: 2.0,
                closed: false,
            },
            ParamRange {
                lo: 0.0,
                hi: 1.0,
                closed: false,
            },
        ]
    }
    fn surface_derivatives(&self, eta: f64, xi: f64, _: &mut ()) -> SurfaceDerivs {
        SurfaceDerivs {
            s: self.o + self.a * eta + self.b * xi,
            s_u: self.a,
            s_v: self.b,
            ..Default::default()
        }
    }
}

/// Sphere cap of radius `r` as a graph `(eta, xi, sqrt(r^2 - eta^2 - xi^2))` over `[-h, h]^2`.
struct SphereCap {
    r: f64,
    h: f64,
}
impl ParametricSurface for SphereCap {
    type Scratch = ();
    fn ranges(&self) -> [ParamRange; 2] {
        [ParamRange {
            lo: -self.h,
            hi: self.h,
            closed: false,
        }; 2]
    }
    fn surface_derivatives(&self, e: f64, x: f64, _: &mut ()) -> SurfaceDerivs {
        let z = (self.r * self.r - e * e - x * x).sqrt();
        let z3 = z * z * z;
        SurfaceDerivs {
            s: Vector3::new(e, x, z),
            s_u: Vector3::new(1.0, 0.0, -e / z),
            s_v: Vector3::new(0.0, 1.0, -x / z),
            s_uu: Vector3::new(0.0, 0.0, -1.0 / z - e * e / z3),
            s_uv: Vector3::new(0.0, 0.0, -e * x / z3),
            s_vv: Vector3::new(0.0, 0.0, -1.0 / z - x * x / z3),
        }
    }
}

/// Sphere band, closed in the longitude `eta in [0, 2 pi)`, latitude `xi in [-0.8, 0.8]`.
struct SphereBand;
impl ParametricSurface for SphereBand {
    type Scratch = ();
    fn ranges(&self) -> [ParamRange; 2] {
        [
            ParamRange {
                lo: 0.0,
                hi: TAU,
                closed: true,
            },
            ParamRange {
                lo: -0.8,
                hi: 0.8,
                closed: false,
            },
        ]
    }
    fn surface_derivatives(&self, e: f64, x: f64, _: &mut ()) -> SurfaceDerivs {
        let (se, ce, sx, cx) = (e.sin(), e.cos(), x.sin(), x.cos());
        SurfaceDerivs {
            s: Vector3::new(cx * ce, cx * se, sx),
            s_u: Vector3::new(-cx * se, cx * ce, 0.0),
            s_v: Vector3::new(-sx * ce, -sx * se, cx),
            s_uu: Vector3::new(-cx * ce, -cx * se, 0.0),
            s_uv: Vector3::new(sx * se, -sx * ce, 0.0),
            s_vv: Vector3::new(-cx * ce, -cx * se, -sx),
        }
    }
}

/// Saddle `(eta, xi, k (eta^2 - xi^2))` over `[-1, 1]^2`.
struct Saddle {
    k: f64,
}
impl ParametricSurface for Saddle {
    type Scratch = ();
    fn ranges(&self) -> [ParamRange; 2] {
        [ParamRange {
            lo: -1.0,
            hi: 1.0,
            closed: false,
        }; 2]
    }
    fn surface_derivatives(&self, e: f64, x: f64, _: &mut ()) -> SurfaceDerivs {
        let k = self.k;
        SurfaceDerivs {
            s: Vector3::new(e, x, k * (e * e - x * x)),
            s_u: Vector3::new(1.0, 0.0, 2.0 * k * e),
            s_v: Vector3::new(0.0, 1.0, -2.0 * k * x),
            s_uu: Vector3::new(0.0, 0.0, 2.0 * k),
            s_uv: Vector3::zeros(),
            s_vv: Vector3::new(0.0, 0.0, -2.0 * k),
        }
    }
}

fn grid(n: usize) -> [SearchGrid; 2] {
    [SearchGrid::EqualSpacing(n), SearchGrid::EqualSpacing(n)]
}

#[test]
fn plane_projection_inside_and_no_contact_outside() {
    let plane = Plane {
        o: Vector3::new(1.0, 2.0, 3.0),
        a: Vector3::new(0.6, 0.8, 0.0),
        b: Vector3::new(0.0, 0.0, 2.0),
    };
    let n = plane.a.cross(&plane.b).normalize();
    let mut s = SurfaceSearch::new(&plane, grid(4), SearchSettings::default()).unwrap();
    let mut rng = Rng::new(1);
    for _ in 0..200 {
        let (e, x, h) = (
            rng.range(-0.5, 2.5),
            rng.range(-0.5, 1.5),
            rng.range(-1.0, 1.0),
        );
        let p = plane.o + plane.a * e + plane.b * x + n * h;
        s.reset();
        let r = s.search(&plane, &mut (), &p);
        let inside = (0.0..=2.0).contains(&e) && (0.0..=1.0).contains(&x);
        // 1e-9 margin: exactly-on-the-edge feet may go either way
        if e > 1e-9 && e < 2.0 - 1e-9 && x > 1e-9 && x < 1.0 - 1e-9 {
            let r = r.expect("projection inside the patch");
            assert!(
                (r.eta - e).abs() < 1e-12 && (r.xi - x).abs() < 1e-12,
                "({e},{x}) -> ({},{})",
                r.eta,
                r.xi
            );
            assert!((r.signed_distance - h).abs() < 1e-12 && (r.distance - h.abs()).abs() < 1e-12);
        } else if !inside {
            assert!(r.is_none(), "({e},{x}) is outside the patch, got {r:?}");
        }
    }
    // exactly above an edge: either no contact or the foot on the edge, never another point
    let p = plane.o + plane.a * 2.0 + plane.b * 0.5 + n;
    if let Some(r) = s.search(&plane, &mut (), &p) {
        assert!((r.eta - 2.0).abs() < 1e-12 && (r.xi - 0.5).abs() < 1e-12);
    }
}

#[test]
fn sphere_cap_radial_projection_from_outside_and_inside() {
    let cap = SphereCap { r: 2.0, h: 1.0 };
    let mut s = SurfaceSearch::new(&cap, grid(5), SearchSettings::default()).unwrap();
    let mut rng = Rng::new(2);
    let (mut found, mut outside) = (0, 0);
    for _ in 0..300 {
        let x = Vector3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(0.3, 4.0),
        );
        let foot = x * (cap.r / x.norm());
        s.reset();
        let r = s.search(&cap, &mut (), &x);
        let margin = foot.x.abs().max(foot.y.abs());
        if margin < cap.h - 1e-6 {
            let r = r.expect("foot on the cap");
            assert!(
                (r.derivs.s - foot).norm() < 1e-12,
                "{x:?}: {:?} vs {foot:?}",
                r.derivs.s
            );
            assert!((r.distance - (x.norm() - cap.r).abs()).abs() < 1e-12);
            found += 1;
        } else if margin > cap.h + 1e-6 {
            assert!(
                r.is_none(),
                "{x:?}: foot {foot:?} outside the cap, got {r:?}"
            );
            outside += 1;
        }
    }
    assert!(found > 50 && outside > 50, "{found} {outside}");
}

/// Point (0, 0, h) above a saddle z = k (eta^2 - xi^2): for h > 1/(2k) two closest points
/// eta = +-sqrt((2kh - 1) / (2k^2)), xi = 0 at distance^2 = h/k - 1/(4k^2) (the origin is a
/// saddle point of the distance and is rejected); for h < 1/(2k) the origin.
#[test]
fn saddle_several_candidates_and_known_closest_points() {
    let k = 1.0;
    let saddle = Saddle { k };
    let mut s = SurfaceSearch::new(&saddle, grid(6), SearchSettings::default()).unwrap();
    for h in [0.8, 1.0, 1.2] {
        s.reset();
        let r = s
            .search(&saddle, &mut (), &Vector3::new(0.0, 0.0, h))
            .unwrap();
        let e = ((2.0 * k * h - 1.0) / (2.0 * k * k)).sqrt();
        assert!(
            (r.eta.abs() - e).abs() < 1e-10 && r.xi.abs() < 1e-12,
            "h={h}: ({}, {})",
            r.eta,
            r.xi
        );
        assert!((r.distance.powi(2) - (h / k - 0.25 / (k * k))).abs() < 1e-12);
        // the other candidate is found from a warm start on its side
        let mut s2 = s.clone();
        s2.reset();
        let shifted = s2
            .search(
                &saddle,
                &mut (),
                &Vector3::new(-0.01 * r.eta.signum(), 0.0, h),
            )
            .unwrap();
        assert!(
            shifted.eta * r.eta < 0.0,
            "the shifted point picks the closer candidate"
        );
    }
    s.reset();
    let r = s
        .search(&saddle, &mut (), &Vector3::new(0.0, 0.0, 0.2))
        .unwrap();
    assert!(r.eta.abs() < 1e-12 && r.xi.abs() < 1e-12 && (r.distance - 0.2).abs() < 1e-12);
    // without the minimum filter the saddle point of the distance may be chosen: minima matter
    let mut raw = SurfaceSearch::new(
        &saddle,
        grid(6),
        SearchSettings {
            minima_only: false,
            ..Default::default()
        },
    )
    .unwrap();
    let r = raw
        .search(&saddle, &mut (), &Vector3::new(0.0, 0.0, 1.0))
        .unwrap();
    assert!(r.distance <= 0.75f64.sqrt() + 1e-12);
}

/// Closed direction: points around the seam of a sphere band project radially, with the warm
/// start carried across the seam several times.
#[test]
fn sphere_band_closed_direction_and_seam() {
    let band = SphereBand;
    let mut s = SurfaceSearch::new(
        &band,
        [SearchGrid::EqualSpacing(8), SearchGrid::EqualSpacing(4)],
        SearchSettings::default(),
    )
    .unwrap();
    let (steps, mut fallbacks, mut warm_hits) = (2000, 0, 0);
    for i in 0..=steps {
        let t = i as f64 / steps as f64;
        let (lon, lat) = (3.0 * TAU * t - 0.3, 1.1 * (5.0 * PI * t).sin());
        let rad = 1.5 + 0.4 * (7.0 * t).cos();
        let x = Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * rad;
        let (warm, full_before) = (s.last().is_some(), s.full_search_count());
        let r = s.search(&band, &mut (), &x);
        fallbacks += usize::from(warm && s.full_search_count() > full_before);
        warm_hits += usize::from(warm && s.full_search_count() == full_before);
        if lat.abs() < 0.8 - 1e-6 {
            let r = r.unwrap_or_else(|| panic!("step {i}: lat {lat}"));
            assert!((r.derivs.s - x / rad).norm() < 1e-12, "step {i}");
            assert!((0.0..TAU).contains(&r.eta));
            assert!(
                (r.signed_distance - (rad - 1.0)).abs() < 1e-12,
                "outward normal (3.27)"
            );
        } else if lat.abs() > 0.8 + 1e-6 {
            assert!(r.is_none(), "step {i}: lat {lat} beyond the band edge");
        }
    }
    // the warm start fails only where the point leaves the band (10 crossings of the edges)
    assert!(
        fallbacks <= 12 && warm_hits > steps / 2,
        "warm start: {fallbacks} failures, {warm_hits} hits"
    );
}

/// Warm start while the point slides over the whole cap in a meander (analytic reference).
#[test]
fn warm_start_sliding_over_sphere_cap() {
    let cap = SphereCap { r: 2.0, h: 1.0 };
    let mut s = SurfaceSearch::new(&cap, grid(4), SearchSettings::default()).unwrap();
    let rows = 12;
    let per_row = 200;
    let mut contacts = 0;
    for row in 0..rows {
        let y = -1.2 + 2.4 * row as f64 / (rows - 1) as f64;
        for i in 0..=per_row {
            let t = i as f64 / per_row as f64;
            let xx = if row % 2 == 0 {
                -1.3 + 2.6 * t
            } else {
                1.3 - 2.6 * t
            };
            let x = Vector3::new(xx, y, 2.3);
            let foot = x * (cap.r / x.norm());
            let r = s.search(&cap, &mut (), &x);
            let m = foot.x.abs().max(foot.y.abs());
            if m < cap.h - 1e-6 {
                assert!((r.unwrap().derivs.s - foot).norm() < 1e-12);
                contacts += 1;
            } else if m > cap.h + 1e-6 {
                assert!(r.is_none());
            }
        }
    }
    assert!(contacts > rows * per_row / 3);
    assert!(
        s.full_search_count() < rows * per_row / 4,
        "{} full searches",
        s.full_search_count()
    );
}

/// Dense brute-force closest sample (grid, then two local refinements): the reference for NURBS.
fn brute_force(surf: &NurbsSurface, sc: &mut SurfaceScratch, x: &Vector3<f64>) -> (f64, f64, f64) {
    let [re, rx] = surf.ranges();
    let (mut be, mut bx, mut bd) = (0.0, 0.0, f64::INFINITY);
    let (mut e0, mut e1, mut x0, mut x1) = (re.lo, re.hi, rx.lo, rx.hi);
    for n in [160usize, 40, 40] {
        for i in 0..=n {
            for j in 0..=n {
                let (e, xi) = (
                    e0 + (e1 - e0) * i as f64 / n as f64,
                    x0 + (x1 - x0) * j as f64 / n as f64,
                );
                let d = (x - surf.point(e, xi, sc)).norm();
                if d < bd {
                    (be, bx, bd) = (e, xi, d);
                }
            }
        }
        let (he, hx) = (2.0 * (e1 - e0) / n as f64, 2.0 * (x1 - x0) / n as f64);
        (e0, e1, x0, x1) = (
            (be - he).max(re.lo),
            (be + he).min(re.hi),
            (bx - hx).max(rx.lo),
            (bx + hx).min(rx.hi),
        );
    }
    (be, bx, bd)
}

/// A point slides over a whole interpolated (wavy) NURBS contour; every warm-started result
/// equals the brute-force closest point (inside points; near the edges the brute force may find
/// an edge point that is no normal projection, there the search must report no contact).
#[test]
fn warm_start_sliding_over_nurbs_surface_matches_brute_force() {
    let (ne, nx) = (12, 8);
    let mut g = Vec::new();
    for i in 0..ne {
        for j in 0..nx {
            let (e, x) = (2.0 * i as f64 / (ne - 1) as f64, j as f64 / (nx - 1) as f64);
            g.push(Vector3::new(e, x, 0.15 * (2.5 * e).sin() * (3.0 * x).cos()));
        }
    }
    let surf = SurfaceInterpolator::from_grid(
        &g,
        ne,
        nx,
        ParamMethod::ChordLength,
        [3, 3],
        [false, false],
    )
    .unwrap()
    .interpolate(&g)
    .unwrap();
    let mut sc = surf.scratch();
    let mut bsc = surf.scratch();
    let mut s = SurfaceSearch::new(
        &surf,
        [SearchGrid::EqualSpacing(11), SearchGrid::EqualSpacing(7)],
        SearchSettings::default(),
    )
    .unwrap();
    let (mut checked, steps, mut fallbacks, mut warm_hits) = (0, 240, 0, 0);
    for i in 0..=steps {
        let t = i as f64 / steps as f64;
        let x = Vector3::new(
            -0.1 + 2.2 * t,
            0.5 + 0.45 * (3.0 * TAU * t).sin(),
            0.25 + 0.1 * (TAU * t).cos(),
        );
        let (warm, full_before) = (s.last().is_some(), s.full_search_count());
        let r = s.search(&surf, &mut sc, &x);
        fallbacks += usize::from(warm && s.full_search_count() > full_before);
        warm_hits += usize::from(warm && s.full_search_count() == full_before);
        let (be, bx, bd) = brute_force(&surf, &mut bsc, &x);
        let [re, rx] = surf.ranges();
        let interior =
            be > re.lo + 1e-3 && be < re.hi - 1e-3 && bx > rx.lo + 1e-3 && bx < rx.hi - 1e-3;
        match r {
            Some(r) => {
                assert!(
                    r.distance <= bd + 1e-12,
                    "step {i}: search {} > brute force {bd}",
                    r.distance
                );
                if interior {
                    assert!((r.distance - bd).abs() < 1e-7, "step {i}");
                    assert!(
                        (r.eta - be).abs() < 1e-3 && (r.xi - bx).abs() < 1e-3,
                        "step {i}"
                    );
                    checked += 1;
                }
            }
            None => assert!(
                !interior,
                "step {i}: brute force has an interior minimum ({be}, {bx})"
            ),
        }
    }
    assert!(checked > steps / 2, "{checked}");
    // the point leaves the contour once at each end
    assert!(
        fallbacks <= 2 && warm_hits > steps / 2,
        "warm start: {fallbacks} failures, {warm_hits} hits"
    );
}

/// Grid given by nodes (seed `setNodes`) gives the same answer as equal spacing.
#[test]
fn grid_by_nodes() {
    let cap = SphereCap { r: 2.0, h: 1.0 };
    let nodes = SearchGrid::Nodes(vec![-1.0, -0.7, -0.1, 0.3, 0.9, 1.0]);
    let mut s =
        SurfaceSearch::new(&cap, [nodes.clone(), nodes], SearchSettings::default()).unwrap();
    let x = Vector3::new(0.4, -0.3, 3.0);
    let r = s.search(&cap, &mut (), &x).unwrap();
    assert!((r.derivs.s - x * (2.0 / x.norm())).norm() < 1e-12);
    let bad = SurfaceSearch::new(
        &cap,
        [
            SearchGrid::Nodes(vec![0.0, -0.5]),
            SearchGrid::EqualSpacing(3),
        ],
        SearchSettings::default(),
    );
    assert!(matches!(bad, Err(NurbsError::InvalidGrid { .. })));
    let bad = SurfaceSearch::new(
        &cap,
        [SearchGrid::EqualSpacing(0), SearchGrid::EqualSpacing(3)],
        SearchSettings::default(),
    );
    assert!(matches!(bad, Err(NurbsError::InvalidGrid { .. })));
}

/// Parabola `(t, t^2, 0)`, `t in [-1, 1]` (open).
struct Parabola;
impl ParametricCurve for Parabola {
    type Scratch = ();
    fn range(&self) -> ParamRange {
        ParamRange {
            lo: -1.0,
            hi: 1.0,
            closed: false,
        }
    }
    fn curve_derivatives(&self, t: f64, _: &mut ()) -> CurveDerivs {
        CurveDerivs {
            c: Vector3::new(t, t * t, 0.0),
            d1: Vector3::new(1.0, 2.0 * t, 0.0),
            d2: Vector3::new(0.0, 2.0, 0.0),
        }
    }
}

/// 1D contour: the point (0, h) has two closest points t = +-sqrt(h - 1/2) on the parabola;
/// (3, 0.5) projects beyond the end t = 1 (no contact).
#[test]
fn curve_search_on_parabola() {
    let mut s = CurveSearch::new(
        &Parabola,
        SearchGrid::EqualSpacing(8),
        SearchSettings::default(),
    )
    .unwrap();
    let r = s
        .search(&Parabola, &mut (), &Vector3::new(0.0, 0.75, 0.0))
        .unwrap();
    assert!(
        (r.eta.abs() - 0.5).abs() < 1e-12 && (r.distance - (0.25f64 + 0.25).sqrt()).abs() < 1e-12
    );
    s.reset();
    assert!(s
        .search(&Parabola, &mut (), &Vector3::new(3.0, 0.5, 0.0))
        .is_none());
    s.reset();
    let r = s
        .search(&Parabola, &mut (), &Vector3::new(0.0, 0.2, 0.0))
        .unwrap();
    assert!(r.eta.abs() < 1e-12 && (r.distance - 0.2).abs() < 1e-12);
}

/// Closed NURBS curve (periodic interpolation of an ellipse-like loop): a point going round it
/// three times, warm-started, against brute-force sampling.
#[test]
fn curve_search_on_closed_nurbs_matches_brute_force() {
    let pts: Vec<Vector3<f64>> = (0..20)
        .map(|i| {
            let t = TAU * i as f64 / 20.0;
            Vector3::new(2.0 * t.cos(), t.sin(), 0.1 * (3.0 * t).sin())
        })
        .collect();
    let c = CurveInterpolator::from_points(&pts, ParamMethod::Centripetal, 3, true)
        .unwrap()
        .interpolate(&pts)
        .unwrap();
    let mut sc = c.scratch();
    let mut s =
        CurveSearch::new(&c, SearchGrid::EqualSpacing(10), SearchSettings::default()).unwrap();
    for i in 0..=300 {
        let t = 3.0 * TAU * i as f64 / 300.0;
        let x = Vector3::new(2.4 * t.cos(), 1.3 * t.sin(), 0.2);
        let r = s.search(&c, &mut sc, &x).unwrap();
        let n = 20000;
        let (bu, bd) = (0..n)
            .map(|j| j as f64 / n as f64)
            .map(|u| (u, (x - c.point(u, &mut sc)).norm()))
            .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        assert!(
            r.distance <= bd + 1e-12 && bd - r.distance < 1e-6,
            "step {i}: {} vs {bd}",
            r.distance
        );
        let du = (r.eta - bu).abs();
        assert!(du.min(1.0 - du) < 1e-3, "step {i}: eta {} vs {bu}", r.eta);
    }
    assert!(s.full_search_count() < 10);
}

/// Torus with major radius 2 and tube radius 0.5, closed in both directions.
struct Torus;
impl ParametricSurface for Torus {
    type Scratch = ();
    fn ranges(&self) -> [ParamRange; 2] {
        [ParamRange {
            lo: 0.0,
            hi: TAU,
            closed: true,
        }; 2]
    }
    fn surface_derivatives(&self, a: f64, b: f64, _: &mut ()) -> SurfaceDerivs {
        let (sa, ca, sb, cb) = (a.sin(), a.cos(), b.sin(), b.cos());
        let rr = 2.0 + 0.5 * cb;
        SurfaceDerivs {
            s: Vector3::new(rr * ca, rr * sa, 0.5 * sb),
            s_u: Vector3::new(-rr * sa, rr * ca, 0.0),
            s_v: Vector3::new(-0.5 * sb * ca, -0.5 * sb * sa, 0.5 * cb),
            s_uu: Vector3::new(-rr * ca, -rr * sa, 0.0),
            s_uv: Vector3::new(0.5 * sb * sa, -0.5 * sb * ca, 0.0),
            s_vv: Vector3::new(-0.5 * cb * ca, -0.5 * cb * sa, -0.5 * sb),
        }
    }
}

/// Closed in both directions: the closest point of x on a torus lies on the tube circle's
/// radius through x: c = 2 x_xy / |x_xy|, closest = c + 0.5 (x - c) / |x - c|. A point circles
/// the torus through the hole and around the tube (seams of both directions crossed).
#[test]
fn torus_closed_in_both_directions() {
    let mut s = SurfaceSearch::new(&Torus, grid(6), SearchSettings::default()).unwrap();
    let steps = 3000;
    for i in 0..=steps {
        let t = i as f64 / steps as f64;
        let (a, b) = (2.0 * TAU * t + 0.1, 7.0 * TAU * t);
        let rho = 0.2 + 0.6 * (3.0 * TAU * t).sin().abs();
        let x = Vector3::new(
            (2.0 + rho * b.cos()) * a.cos(),
            (2.0 + rho * b.cos()) * a.sin(),
            rho * b.sin(),
        );
        let c = Vector3::new(x.x, x.y, 0.0).normalize() * 2.0;
        let closest = c + (x - c).normalize() * 0.5;
        let r = s
            .search(&Torus, &mut (), &x)
            .unwrap_or_else(|| panic!("step {i}"));
        assert!(
            (r.derivs.s - closest).norm() < 1e-12,
            "step {i}: {:?} vs {closest:?}",
            r.derivs.s
        );
        assert!((r.distance - (rho - 0.5).abs()).abs() < 1e-12);
    }
    assert!(
        s.full_search_count() < steps / 20,
        "{} full searches",
        s.full_search_count()
    );
}

/// Open NURBS curve (interpolated arc): points whose projection falls beyond either end get no
/// contact; inside, the result equals brute-force sampling.
#[test]
fn curve_search_on_open_nurbs_edges() {
    let pts: Vec<Vector3<f64>> = (0..9)
        .map(|i| {
            let t = 0.4 * i as f64;
            Vector3::new(t.cos(), t.sin(), 0.05 * t)
        })
        .collect();
    let c = CurveInterpolator::from_points(&pts, ParamMethod::ChordLength, 3, false)
        .unwrap()
        .interpolate(&pts)
        .unwrap();
    let mut sc = c.scratch();
    let mut s =
        CurveSearch::new(&c, SearchGrid::EqualSpacing(8), SearchSettings::default()).unwrap();
    let (d0, d1) = (c.derivatives(0.0, &mut sc), c.derivatives(1.0, &mut sc));
    // beyond the start and the end, along the end tangents (and a bit off them)
    for (end, sign) in [(d0, -1.0), (d1, 1.0)] {
        let x = end.c + end.d1.normalize() * (0.3 * sign) + Vector3::new(0.0, 0.0, 0.05);
        s.reset();
        assert!(s.search(&c, &mut sc, &x).is_none(), "beyond an end: {x:?}");
    }
    for k in 0..40 {
        let t = 0.1 + 2.9 * k as f64 / 39.0;
        let x = Vector3::new(1.3 * t.cos(), 1.3 * t.sin(), 0.05 * t + 0.1);
        let r = s.search(&c, &mut sc, &x).unwrap();
        let n = 20000;
        let bd = (0..=n)
            .map(|j| (x - c.point(j as f64 / n as f64, &mut sc)).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            r.distance <= bd + 1e-12 && bd - r.distance < 1e-6,
            "{k}: {} vs {bd}",
            r.distance
        );
    }
}
