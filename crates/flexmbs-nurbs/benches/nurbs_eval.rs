//! Micro-benchmark (`cargo bench -p flexmbs-nurbs --bench nurbs_eval`): surface evaluation,
//! re-interpolation of a 50 x 5 node grid, and the contact search. Prints the best of 5 runs.
//! `NURBS_BENCH_EVALS=n` (default 1e6) scales all counts (n evaluations, n/100 re-interpolations
//! and warm searches, n/1000 full searches), e.g. for a run under callgrind; every phase is its
//! own `#[inline(never)]` function (`--toggle-collect` targets, `phase_*`).
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

#[inline(never)]
fn phase_derivatives(surf: &NurbsSurface, params: &[(f64, f64)], s: &mut SurfaceScratch) {
    for &(u, v) in params {
        black_box(surf.derivatives(black_box(u), v, s));
    }
}

#[inline(never)]
fn phase_points(surf: &NurbsSurface, params: &[(f64, f64)], s: &mut SurfaceScratch) {
    for &(u, v) in params {
        black_box(surf.point(black_box(u), v, s));
    }
}

#[inline(never)]
fn phase_reinterpolation(
    ip: &SurfaceInterpolator,
    grids: [&[Vector3<f64>]; 2],
    reps: usize,
    surf: &mut NurbsSurface,
) {
    for r in 0..reps {
        ip.update_surface(black_box(grids[r % 2]), surf).unwrap();
    }
}

#[inline(never)]
fn phase_warm_search(
    search: &mut SurfaceSearch,
    surf: &NurbsSurface,
    path: &[Vector3<f64>],
    s: &mut SurfaceScratch,
) {
    search.reset();
    for x in path {
        black_box(search.search(surf, s, x));
    }
}

#[inline(never)]
fn phase_full_search(
    search: &mut SurfaceSearch,
    surf: &NurbsSurface,
    path: &[Vector3<f64>],
    s: &mut SurfaceScratch,
) {
    for x in path {
        black_box(search.full_search(surf, s, x));
    }
}

fn main() {
    let n: usize = std::env::var("NURBS_BENCH_EVALS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
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
    let params: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            (
                (i as f64 * 0.618_033_988_7) % 1.0,
                (i as f64 * 0.414_213_562_3) % 1.0,
            )
        })
        .collect();
    let derivs = best_of_5(|| phase_derivatives(&surf, &params, &mut s)) / n as f64;
    let points = best_of_5(|| phase_points(&surf, &params, &mut s)) / n as f64;
    let reps = (n / 100).max(1);
    let reinterp =
        best_of_5(|| phase_reinterpolation(&ip, [&g1, &g0], reps, &mut surf)) / reps as f64;
    ip.update_surface(&g1, &mut surf).unwrap();
    let grids = [SearchGrid::EqualSpacing(49), SearchGrid::EqualSpacing(4)];
    let mut search = SurfaceSearch::new(&surf, grids, SearchSettings::default()).unwrap();
    let m = (n / 100).max(1);
    let path: Vec<Vector3<f64>> = (0..m)
        .map(|i| Vector3::new(0.05 + 0.9 * i as f64 / m as f64, 0.1, 0.05))
        .collect();
    let warm = best_of_5(|| phase_warm_search(&mut search, &surf, &path, &mut s)) / m as f64;
    let sparse: Vec<Vector3<f64>> = path.iter().step_by(10).copied().collect();
    let full =
        best_of_5(|| phase_full_search(&mut search, &surf, &sparse, &mut s)) / sparse.len() as f64;
    println!("bicubic 50 x 5 surface (open x open), one thread, best of 5:");
    println!(
        "  set-up (parameters, knots, two LU factorizations): {:.1} us",
        setup * 1e6
    );
    println!(
        "  {n} evaluations of S, S_u, S_v, S_uu, S_uv, S_vv: {:.0} ns each",
        derivs * 1e9
    );
    println!("  {n} evaluations of S only: {:.0} ns each", points * 1e9);
    println!(
        "  re-interpolation of the 50 x 5 grid (update_surface): {:.2} us",
        reinterp * 1e6
    );
    println!(
        "  contact search, warm start (point sliding along the beam): {:.2} us",
        warm * 1e6
    );
    println!(
        "  contact search, full (coarse grid 49 x 4 + Newton): {:.1} us",
        full * 1e6
    );
}
