//! Neutral contours of FFR bodies (seed 000 §3.2.2): the deformed NURBS contour passes through the
//! deformed nodes (checked against the element's own node-frame kinematics), a contour point moves
//! as a material point (`v = J_T u`, `J_T` equals finite differences of the contour point's
//! position along `q ⊕ dv`), the contact frame is orthonormal, a point above the contour is found
//! by the search as its normal projection, and bad node lists are refused with the reason.

use crate::plate;

use faer::Mat;
use flexmbs_core::ffr::contour::{
    ContourError, ContourSettings, FfrCurveContour, FfrSurfaceContour,
};
use flexmbs_core::ffr::{FfrElement, FfrEval};
use flexmbs_core::rotation::rotation_vector_matrix;
use flexmbs_core::{Element, FrameKinematics, LocalFrame};
use flexmbs_nurbs::{SearchGrid, SearchSettings, SurfaceSearch};
use nalgebra::Vector3;
use plate::{rnd, NF, NX, NY};

/// The shared test plate as an element.
fn plate(seed: &mut u64) -> FfrElement {
    FfrElement::new(plate::plate(seed))
}

fn state(seed: &mut u64, e: &FfrElement) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut u) = (vec![0.0; e.nq()], vec![0.0; e.nu()]);
    e.reference_coordinates(&mut q, &mut u);
    e.set_pose(
        &mut q,
        &Vector3::new(0.3, -0.2, 0.5),
        &rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7)),
    );
    let nq = q.len();
    for x in &mut q[nq - NF..] {
        *x = 0.3 * rnd(seed);
    }
    for x in u.iter_mut() {
        *x = rnd(seed);
    }
    (q, u)
}

fn grid() -> Vec<usize> {
    (0..NX * NY).collect() // row i = node column along x (eta), j along y (xi)
}

/// The body state of `e` at `(q, u)` (rotation state, q_f, q_f_dot).
fn evaluated(e: &FfrElement, q: &[f64], u: &[f64]) -> flexmbs_core::ElementScratch {
    e.evaluated(q, u).unwrap()
}

#[test]
fn surface_contour_interpolates_deformed_nodes_and_moves_as_material_points() {
    let mut seed = 5;
    let e = plate(&mut seed);
    let c = FfrSurfaceContour::new(e.body(), &grid(), NX, NY, ContourSettings::default()).unwrap();
    let mut st = c.state().unwrap();
    let (q, u) = state(&mut seed, &e);
    let mut ev = evaluated(&e, &q, &u);
    let s = ev.get::<FfrEval>().state.clone();
    c.update(&s, &mut st).unwrap();
    let (r, rd) = (
        Vector3::new(q[0], q[1], q[2]),
        Vector3::new(u[0], u[1], u[2]),
    );
    // through the deformed nodes, with the nodes' velocities
    let (pe, px) = (
        c.interpolator().eta().params().to_vec(),
        c.interpolator().xi().params().to_vec(),
    );
    for (i, eta) in pe.iter().enumerate() {
        for (j, xi) in px.iter().enumerate() {
            let p = c.point(&r, &rd, &s, &mut st, *eta, *xi).unwrap();
            let mut frame = LocalFrame::at(Vector3::zeros());
            frame.mesh_node = Some(i * NY + j);
            let mut k = FrameKinematics::new(e.nu());
            e.frame_kinematics(&q, &u, &mut ev, &frame, &mut k);
            assert!((p.position - k.position).norm() < 1e-12, "node ({i}, {j})");
            assert!(
                (p.velocity - k.velocity).norm() < 1e-12,
                "node ({i}, {j}) velocity"
            );
        }
    }
    // between the nodes: v = J_T u, J_T = d r / d(q ⊕ dv), orthonormal contact frame
    let nu = e.nu();
    for (eta, xi) in [(0.13, 0.41), (0.77, 0.9), (0.5, 0.05)] {
        let p = c.point(&r, &rd, &s, &mut st, eta, xi).unwrap();
        let mut jt = Mat::<f64>::zeros(3, nu);
        c.jacobian_translation(&s, &mut st, eta, xi, jt.as_mut())
            .unwrap();
        let v = Vector3::from_fn(|i, _| (0..nu).map(|j| jt[(i, j)] * u[j]).sum::<f64>());
        assert!((v - p.velocity).norm() < 1e-12 * p.velocity.norm().max(1.0));
        let (n, t1, t2) = (p.normal, p.tangents[0], p.tangents[1]);
        assert!((n.norm() - 1.0).abs() < 1e-14 && (t1.norm() - 1.0).abs() < 1e-14);
        assert!(n.dot(&t1).abs() < 1e-14 && n.dot(&t2).abs() < 1e-14);
        assert!((t1.cross(&t2) - n).norm() < 1e-14);
        let (mut dv, mut qp, eps) = (vec![0.0; nu], q.clone(), 1e-6);
        let mut st2 = c.state().unwrap();
        for jcol in 0..nu {
            let mut pos = [Vector3::zeros(); 2];
            for (m, sign) in [1.0, -1.0].into_iter().enumerate() {
                dv[jcol] = sign * eps;
                e.integrate_position(&q, &dv, &mut qp);
                let ev2 = evaluated(&e, &qp, &u);
                let s2 = &ev2.get::<FfrEval>().state;
                c.update(s2, &mut st2).unwrap();
                let r2 = Vector3::new(qp[0], qp[1], qp[2]);
                pos[m] = c.point(&r2, &rd, s2, &mut st2, eta, xi).unwrap().position;
            }
            dv[jcol] = 0.0;
            let fd = (pos[0] - pos[1]) / (2.0 * eps);
            let an = Vector3::new(jt[(0, jcol)], jt[(1, jcol)], jt[(2, jcol)]);
            assert!(
                (fd - an).norm() < 1e-7 * an.norm().max(1.0),
                "column {jcol}: {fd} vs {an}"
            );
        }
    }
}

#[test]
fn search_finds_the_normal_projection_on_the_deformed_contour() {
    let mut seed = 11;
    let e = plate(&mut seed);
    let c = FfrSurfaceContour::new(e.body(), &grid(), NX, NY, ContourSettings::default()).unwrap();
    let mut st = c.state().unwrap();
    let (q, u) = state(&mut seed, &e);
    let ev = evaluated(&e, &q, &u);
    let s = ev.get::<FfrEval>().state.clone();
    c.update(&s, &mut st).unwrap();
    let (r, rd) = (
        Vector3::new(q[0], q[1], q[2]),
        Vector3::new(u[0], u[1], u[2]),
    );
    let grids = [
        SearchGrid::EqualSpacing(NX - 1),
        SearchGrid::EqualSpacing(NY - 1),
    ];
    let mut search = SurfaceSearch::new(&st.surface, grids, SearchSettings::default()).unwrap();
    let mut sc = st.surface.scratch();
    // a point 2 cm off the contour point (0.4, 0.6) along its normal
    let target = c.point(&r, &rd, &s, &mut st, 0.4, 0.6).unwrap();
    let p = target.position + 0.02 * target.normal;
    let local = s.a.transpose() * (p - r);
    let hit = search
        .search(&st.surface, &mut sc, &local)
        .expect("a normal projection");
    let found = c.point(&r, &rd, &s, &mut st, hit.eta, hit.xi).unwrap();
    assert!(
        (hit.eta - 0.4).abs() < 1e-9 && (hit.xi - 0.6).abs() < 1e-9,
        "{} {}",
        hit.eta,
        hit.xi
    );
    assert!(((p - found.position).norm() - 0.02).abs() < 1e-12);
    assert!((p - found.position).normalize().cross(&found.normal).norm() < 1e-9);
}

#[test]
fn curve_contour_through_a_node_row_and_its_jacobian() {
    let mut seed = 3;
    let e = plate(&mut seed);
    let row: Vec<usize> = (0..NX).map(|i| i * NY + 1).collect();
    let c = FfrCurveContour::new(e.body(), &row, ContourSettings::default()).unwrap();
    let mut st = c.state().unwrap();
    let (q, u) = state(&mut seed, &e);
    let mut ev = evaluated(&e, &q, &u);
    let s = ev.get::<FfrEval>().state.clone();
    c.update(&s, &mut st).unwrap();
    let (r, rd) = (
        Vector3::new(q[0], q[1], q[2]),
        Vector3::new(u[0], u[1], u[2]),
    );
    for (i, eta) in c.interpolator().params().to_vec().iter().enumerate() {
        let p = c.point(&r, &rd, &s, &mut st, *eta).unwrap();
        let mut frame = LocalFrame::at(Vector3::zeros());
        frame.mesh_node = Some(row[i]);
        let mut k = FrameKinematics::new(e.nu());
        e.frame_kinematics(&q, &u, &mut ev, &frame, &mut k);
        assert!((p.position - k.position).norm() < 1e-12);
        assert!((p.tangents[0].norm() - 1.0).abs() < 1e-14);
    }
    let mut jt = Mat::<f64>::zeros(3, e.nu());
    c.jacobian_translation(&s, &mut st, 0.37, jt.as_mut())
        .unwrap();
    let p = c.point(&r, &rd, &s, &mut st, 0.37).unwrap();
    let v = Vector3::from_fn(|i, _| (0..e.nu()).map(|j| jt[(i, j)] * u[j]).sum::<f64>());
    assert!((v - p.velocity).norm() < 1e-12 * p.velocity.norm().max(1.0));
}

#[test]
fn bad_node_lists_are_refused() {
    let mut seed = 1;
    let e = plate(&mut seed);
    let b = e.body();
    let mut g = grid();
    g[5] = 4;
    assert_eq!(
        FfrSurfaceContour::new(b, &g, NX, NY, ContourSettings::default()).unwrap_err(),
        ContourError::DuplicateNode { node: 4 }
    );
    g[5] = 999;
    assert!(matches!(
        FfrSurfaceContour::new(b, &g, NX, NY, ContourSettings::default()),
        Err(ContourError::UnknownNode { node: 999, .. })
    ));
    assert!(matches!(
        FfrSurfaceContour::new(b, &grid(), NX, NY + 1, ContourSettings::default()),
        Err(ContourError::Shape { .. })
    ));
    // three nodes cannot carry a cubic curve
    assert!(matches!(
        FfrCurveContour::new(b, &[0, 4, 8], ContourSettings::default()),
        Err(ContourError::Nurbs(_))
    ));
}
