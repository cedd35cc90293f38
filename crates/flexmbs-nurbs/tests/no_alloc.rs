//! Evaluation, re-interpolation and (warm and full) contact search allocate nothing once the
//! scratch exists (the counting global allocator of the test binary counts on the measuring
//! thread only).
use crate::counting_alloc::allocations_in as counted;
use flexmbs_nurbs::*;
use nalgebra::Vector3;

fn grid(ne: usize, nx: usize, amp: f64) -> Vec<Vector3<f64>> {
    let mut g = Vec::new();
    for i in 0..ne {
        for j in 0..nx {
            let (t, z) = (std::f64::consts::TAU * i as f64 / ne as f64, 0.3 * j as f64);
            g.push(Vector3::new(t.cos(), t.sin(), z + amp * (2.0 * t).sin()));
        }
    }
    g
}

#[test]
fn evaluation_reinterpolation_and_search_do_not_allocate() {
    let (ne, nx) = (16, 5);
    let g0 = grid(ne, nx, 0.0);
    let g1 = grid(ne, nx, 0.01);
    let sip = SurfaceInterpolator::from_grid(
        &g0,
        ne,
        nx,
        ParamMethod::ChordLength,
        [3, 3],
        [true, false],
    )
    .unwrap();
    let mut surf = sip.interpolate(&g0).unwrap();
    let mut ss = surf.scratch();
    let mut search = SurfaceSearch::new(
        &surf,
        [SearchGrid::EqualSpacing(8), SearchGrid::EqualSpacing(4)],
        SearchSettings::default(),
    )
    .unwrap();
    let mut ctrl = vec![Vector3::zeros(); sip.n_ctrl()];
    let line: Vec<Vector3<f64>> = (0..ne).map(|i| g0[i * nx]).collect();
    let cip = CurveInterpolator::from_points(&line, ParamMethod::Centripetal, 3, true).unwrap();
    let mut curve = cip.interpolate(&line).unwrap();
    let mut cs = curve.scratch();
    let mut csearch = CurveSearch::new(
        &curve,
        SearchGrid::EqualSpacing(8),
        SearchSettings::default(),
    )
    .unwrap();
    let mut cctrl = vec![Vector3::zeros(); cip.n_ctrl()];
    let mut acc = 0.0;
    let mut fs = sip.scratch();
    let mut cfs = cip.scratch();
    let n = counted(|| {
        for step in 0..50 {
            let x = Vector3::new(
                1.5 * (0.1 * step as f64).cos(),
                1.5 * (0.1 * step as f64).sin(),
                0.6,
            );
            let g = if step % 2 == 0 { &g1 } else { &g0 };
            sip.update_surface(g, &mut surf).unwrap();
            sip.control_points_into(g, &mut ctrl).unwrap();
            let d = surf.derivatives(0.3, 0.4, &mut ss);
            acc += d.s_uv.norm() + surf.point(0.1, 0.9, &mut ss).x;
            if step == 10 {
                search.reset();
                csearch.reset();
            }
            acc += search
                .search(&surf, &mut ss, &x)
                .map_or(0.0, |p| p.distance);
            acc += search
                .full_search(&surf, &mut ss, &(x * 0.5))
                .map_or(0.0, |p| p.distance);
            let cline: Vec<Vector3<f64>> = Vec::new(); // empty Vec does not allocate
            assert!(cip.control_points_into(&cline, &mut cctrl).is_err()); // error path, no allocation
            cip.control_points_into(&line, &mut cctrl).unwrap();
            cip.update_curve(&line, &mut curve).unwrap();
            acc += curve.derivatives(0.7, &mut cs).d2.norm();
            acc += sip.field_derivatives(&ctrl, 0.2, 0.3, &mut fs).unwrap()[4].norm();
            acc += cip.field_derivatives(&cctrl, 0.2, &mut cfs).unwrap()[2].norm();
            acc += csearch
                .search(&curve, &mut cs, &x)
                .map_or(0.0, |p| p.distance);
        }
    });
    assert!(acc.is_finite());
    assert!(search.full_search_count() >= 50 && csearch.full_search_count() >= 1);
    assert_eq!(
        n, 0,
        "allocations in evaluation / re-interpolation / search"
    );
}
