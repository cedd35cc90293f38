//! Micro-benchmark (`cargo bench -p flexmbs-nurbs --bench nurbs_eval`): surface evaluation,
//! re-interpolation of a 50 x 5 node grid, and the contact search. Prints the best of 5 runs.
use flexmbs_nurbs::*;
use nalgebra::Vector3;
use std::hint::black_box;
use std::time::Instant;

/// Best wall time of 5 runs of `f`, in seconds.
fn best_of_5(mut f: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// All partials at every parameter pair (own function: callgrind `--toggle-collect` target).
#[inline(never)]
fn evaluate_derivatives(surf: &NurbsSurface, params: &[(f64, f64)], s: &mut SurfaceScratch) {
    for &(u, v) in params {
        black_box(surf.derivatives(black_box(u), v, s));
    }
}

/// Top surface of a beam, 50 x 5 nodes, slightly bent by `amp`.
fn beam_grid(amp: f64) -> Vec<Vector3<f64>> {
    let (ne, nx) = (50, 5);
    let mut g = Vec::with_capacity(ne * nx);
    for i in 0..ne {
        for j in 0..nx {
            let x = i as f64 / (ne - 1) as f64;
            g.push(Vector3::new(
                x,
                0.05 * j as f64,
                0.02 + amp * x * x * (3.0 - x),
            ));
        }
    }
    g
}

fn main() {
    let (g0, g1) = (beam_grid(0.0), beam_grid(0.01));
    let t = Instant::now();
    let ip = SurfaceInterpolator::from_grid(
        &g0,
        50,
        5,
        ParamMethod::ChordLength,
        [3, 3],
        [false, false],
    )
    .unwrap();
    let setup = t.elapsed().as_secs_f64();
    let mut surf = ip.interpolate(&g0).unwrap();
    let mut s = surf.scratch();
    // NURBS_BENCH_EVALS: fewer evaluations for a run under callgrind
    let n: usize = std::env::var("NURBS_BENCH_EVALS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let params: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            (
                (i as f64 * 0.618_033_988_7) % 1.0,
                (i as f64 * 0.414_213_562_3) % 1.0,
            )
        })
        .collect();
    let derivs = best_of_5(|| evaluate_derivatives(&surf, &params, &mut s));
    let points = best_of_5(|| {
        for &(u, v) in &params {
            black_box(surf.point(black_box(u), v, &mut s));
        }
    });
    let reps = 10_000;
    let reinterp = best_of_5(|| {
        for r in 0..reps {
            ip.update_surface(black_box(if r % 2 == 0 { &g1 } else { &g0 }), &mut surf)
                .unwrap();
        }
    }) / reps as f64;
    ip.update_surface(&g1, &mut surf).unwrap();
    println!("bicubic 50 x 5 surface, {n} evaluations (open x open), one thread:");
    println!(
        "  set-up (parameters, knots, two LU factorizations): {:.1} us",
        setup * 1e6
    );
    println!(
        "  evaluations of S, S_u, S_v, S_uu, S_uv, S_vv: {:.3} s ({:.0} ns each)",
        derivs,
        derivs * 1e9 / n as f64
    );
    println!(
        "  evaluations of S only: {:.3} s ({:.0} ns each)",
        points,
        points * 1e9 / n as f64
    );
    println!(
        "  re-interpolation of the 50 x 5 grid (update_surface): {:.2} us",
        reinterp * 1e6
    );
    bench_search(&surf);
}

/// Warm-started search of a point sliding along the beam, and full searches.
fn bench_search(surf: &NurbsSurface) {
    let mut s = surf.scratch();
    let mut search = SurfaceSearch::new(
        surf,
        [SearchGrid::EqualSpacing(49), SearchGrid::EqualSpacing(4)],
        SearchSettings::default(),
    )
    .unwrap();
    let m = 10_000;
    let path: Vec<Vector3<f64>> = (0..m)
        .map(|i| Vector3::new(0.05 + 0.9 * i as f64 / m as f64, 0.1, 0.05))
        .collect();
    let warm = best_of_5(|| {
        search.reset();
        for x in &path {
            black_box(search.search(surf, &mut s, x));
        }
    }) / m as f64;
    let full = best_of_5(|| {
        for x in path.iter().step_by(10) {
            black_box(search.full_search(surf, &mut s, x));
        }
    }) / (m / 10) as f64;
    println!(
        "  contact search, warm start (point sliding along the beam): {:.2} us",
        warm * 1e6
    );
    println!(
        "  contact search, full (coarse grid 49 x 4 + Newton): {:.1} us",
        full * 1e6
    );
}
