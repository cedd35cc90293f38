//! Property test: construction from random (often invalid) input never panics; it returns a
//! typed error or an object whose evaluation and search also never panic.
use crate::common;
use common::Rng;
use flexmbs_nurbs::*;
use nalgebra::Vector3;

fn weird(rng: &mut Rng) -> f64 {
    match rng.below(12) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1.0,
        3 => 0.0,
        4 => 1e300,
        _ => rng.range(-2.0, 2.0),
    }
}

fn maybe_weird(rng: &mut Rng) -> f64 {
    if rng.below(20) == 0 {
        weird(rng)
    } else {
        rng.range(-2.0, 2.0)
    }
}

fn random_knots(rng: &mut Rng, len: usize) -> Vec<f64> {
    let mut k: Vec<f64> = (0..len).map(|_| (rng.below(6) as f64) * 0.25).collect();
    if rng.below(3) > 0 {
        k.sort_by(|a, b| a.partial_cmp(b).unwrap());
    }
    if rng.below(10) == 0 && len > 0 {
        let i = rng.below(len);
        k[i] = weird(rng);
    }
    k
}

/// Mostly valid clamped knots for `n` control points of degree `p`, sometimes perturbed.
fn clamped_knots(rng: &mut Rng, p: usize, n: usize) -> Vec<f64> {
    if rng.below(2) == 0 || n < p + 1 {
        return random_knots(rng, n + p + 1);
    }
    let mut k = vec![0.0; p + 1];
    k.extend((1..n - p).map(|i| i as f64 / (n - p) as f64));
    k.extend(vec![1.0; p + 1]);
    if rng.below(5) == 0 {
        let i = rng.below(k.len());
        k[i] = weird(rng);
    }
    k
}

fn point(rng: &mut Rng) -> Vector3<f64> {
    Vector3::new(maybe_weird(rng), maybe_weird(rng), maybe_weird(rng))
}

fn exercise_curve(c: &NurbsCurve, rng: &mut Rng) {
    let mut s = c.scratch();
    for _ in 0..5 {
        let u = if rng.below(4) == 0 {
            weird(rng)
        } else {
            rng.range(-0.5, 1.5)
        };
        let _ = c.derivatives(u, &mut s);
        let _ = c.derivatives_left(u, &mut s);
    }
    if let Ok(mut search) = CurveSearch::new(
        c,
        SearchGrid::EqualSpacing(1 + rng.below(6)),
        SearchSettings::default(),
    ) {
        for _ in 0..3 {
            let _ = search.search(c, &mut s, &point(rng));
        }
    }
}

fn exercise_surface(surf: &NurbsSurface, rng: &mut Rng) {
    let mut s = surf.scratch();
    for _ in 0..5 {
        let _ = surf.derivatives(maybe_weird(rng), maybe_weird(rng), &mut s);
    }
    let grids = [
        SearchGrid::EqualSpacing(rng.below(5)),
        SearchGrid::EqualSpacing(1 + rng.below(5)),
    ];
    if let Ok(mut search) = SurfaceSearch::new(surf, grids, SearchSettings::default()) {
        for _ in 0..3 {
            let _ = search.search(surf, &mut s, &point(rng));
        }
    }
}

#[test]
fn curve_construction_never_panics() {
    let mut rng = Rng::new(1234);
    let (mut ok, mut err) = (0, 0);
    for _ in 0..4000 {
        let degree = rng.below(6);
        let n = rng.below(9);
        let knots = if rng.below(4) == 0 {
            let len = (n + degree + 1 + rng.below(3)).saturating_sub(1);
            random_knots(&mut rng, len)
        } else {
            clamped_knots(&mut rng, degree, n)
        };
        let pts: Vec<_> = (0..n).map(|_| point(&mut rng)).collect();
        let w: Vec<f64> = (0..n + usize::from(rng.below(10) == 0))
            .map(|_| {
                if rng.below(15) == 0 {
                    weird(&mut rng)
                } else {
                    rng.range(0.1, 2.0)
                }
            })
            .collect();
        let r = if rng.below(2) == 0 {
            NurbsCurve::new(degree, knots, &pts, &w)
        } else {
            NurbsCurve::new_periodic(degree, knots, &pts, &w)
        };
        match r {
            Ok(c) => {
                ok += 1;
                exercise_curve(&c, &mut rng);
            }
            Err(_) => err += 1,
        }
    }
    assert!(ok > 100 && err > 100, "{ok} valid, {err} rejected");
}

#[test]
fn interpolation_construction_never_panics() {
    let mut rng = Rng::new(99);
    let (mut ok, mut err) = (0, 0);
    for _ in 0..3000 {
        let degree = rng.below(6);
        let closed = rng.below(2) == 0;
        let k = rng.below(10);
        let mut pts: Vec<_> = (0..k).map(|_| point(&mut rng)).collect();
        if k > 1 && rng.below(8) == 0 {
            pts[1] = pts[0];
        }
        let method = if rng.below(2) == 0 {
            ParamMethod::ChordLength
        } else {
            ParamMethod::Centripetal
        };
        match CurveInterpolator::from_points(&pts, method, degree, closed) {
            Ok(ip) => {
                ok += 1;
                let c = ip.interpolate(&pts);
                if let Ok(c) = c {
                    exercise_curve(&c, &mut rng);
                }
            }
            Err(_) => err += 1,
        }
        let params: Vec<f64> = (0..k)
            .map(|_| maybe_weird(&mut rng).abs().min(0.99))
            .collect();
        let _ = CurveInterpolator::new(&params, degree, closed);
        let (ne, nx) = (rng.below(7), rng.below(7));
        let grid: Vec<_> = (0..ne * nx + usize::from(rng.below(10) == 0))
            .map(|_| point(&mut rng))
            .collect();
        let degrees = [rng.below(5), rng.below(5)];
        let closed2 = [rng.below(2) == 0, rng.below(2) == 0];
        if let Ok(ip) = SurfaceInterpolator::from_grid(&grid, ne, nx, method, degrees, closed2) {
            if let Ok(s) = ip.interpolate(&grid) {
                exercise_surface(&s, &mut rng);
            }
        }
    }
    assert!(ok > 50 && err > 50, "{ok} valid, {err} rejected");
}

#[test]
fn surface_construction_never_panics() {
    let mut rng = Rng::new(4321);
    let mut ok = 0;
    for _ in 0..3000 {
        let (p, q) = (rng.below(5), rng.below(5));
        let (ne, nx) = (rng.below(7), rng.below(7));
        let ke = KnotVector::new(p, clamped_knots(&mut rng, p, ne), ne);
        let kx = if rng.below(2) == 0 {
            KnotVector::new(q, clamped_knots(&mut rng, q, nx), nx)
        } else {
            KnotVector::periodic(q, random_knots(&mut rng, nx + q + 1), nx)
        };
        let n = ne * nx + usize::from(rng.below(10) == 0);
        let pts: Vec<_> = (0..n).map(|_| point(&mut rng)).collect();
        let w: Vec<f64> = (0..n)
            .map(|_| {
                if rng.below(30) == 0 {
                    weird(&mut rng)
                } else {
                    1.0
                }
            })
            .collect();
        if let (Ok(ke), Ok(kx)) = (ke, kx) {
            if let Ok(s) = NurbsSurface::new(ke, kx, &pts, &w) {
                ok += 1;
                exercise_surface(&s, &mut rng);
            }
        }
    }
    assert!(ok > 20, "{ok} valid");
}
