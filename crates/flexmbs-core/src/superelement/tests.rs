//! Unit tests of the superelement: frame recovery, mass, tangent = finite differences.

use super::*;
use crate::element::{finite_difference_tangents, Element, TangentScratch};
use faer::Mat;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Rotation3, Vector3};

/// The tube of `benchmarks.md` (seed 001), segment of length `l`.
pub(super) fn tube_segment(
    l: f64,
    internal_modes: usize,
    frame: FrameLocation,
) -> SuperelementData {
    beam_segment(&BeamSegmentSpec {
        length: l,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 4,
        internal_modes,
        frame,
    })
    .unwrap()
}

/// A deformed state: interface `k` displaced and rotated by 0.1-1 rad.
fn deformed_state(se: &Superelement, l: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
    se.reference_coordinates(&mut q, &mut u);
    let base = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.7, 0.5));
    se.set_pose(&mut q, &Vector3::new(0.2, -0.1, 0.4), base.matrix());
    let rots = [Vector3::new(0.1, 0.25, -0.4), Vector3::new(-0.3, 0.5, 0.6)];
    let offs = [
        Vector3::new(0.01, -0.02, 0.015) * l,
        Vector3::new(-0.03, 0.05, 0.02) * l,
    ];
    for k in 0..2 {
        let o = se.q_offset[k];
        let p = crate::NodeKind::Pose;
        let r = p.rotation(&q[o..o + 7]) * Rotation3::from_scaled_axis(rots[k]).matrix();
        let x = Vector3::new(q[o], q[o + 1], q[o + 2]) + offs[k];
        p.set_pose(&mut q[o..o + 7], &x, &r);
    }
    for i in 0..se.data.internal_modes {
        q[se.q_eta + i] = 1e-3 * (i as f64 + 1.0);
    }
    (q, u)
}

fn check_tangent(se: &Superelement, gravity: Vector3<f64>) -> f64 {
    let (q, u) = deformed_state(se, 0.3);
    let mut s = se.evaluated(&q, &u).unwrap();
    let n = se.nu();
    let (mut a, mut a_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let (mut f, mut f_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let mut fd = TangentScratch::new(se);
    se.force_tangents(
        0.0,
        &q,
        &u,
        &gravity,
        &mut s,
        a.as_mut(),
        a_u.as_mut(),
        &mut fd,
    );
    finite_difference_tangents(se, 0.0, &q, &u, &gravity, f.as_mut(), f_u.as_mut(), &mut fd);
    let (mut err, mut scale) = (0.0_f64, 0.0_f64);
    for i in 0..n {
        for j in 0..n {
            err = err.max((a[(i, j)] - f[(i, j)]).abs());
            scale = scale.max(f[(i, j)].abs());
        }
    }
    err / scale
}

#[test]
fn frame_recovery_satisfies_the_frame_condition_at_a_deformed_state() {
    for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
        let se = Superelement::new(tube_segment(0.3, 2, frame)).unwrap();
        let (q, u) = deformed_state(&se, 0.3);
        let mut s = se.evaluated(&q, &u).unwrap();
        let e = s.get_mut::<SuperelementEval>();
        let c = &se.data.phi_cb * &e.q_loc;
        assert!(c.amax() < 1e-14, "{c}");
        assert!(e.iterations <= 6, "{} iterations", e.iterations);
    }
}

#[test]
fn rigid_placement_has_no_deformation_and_the_mass_of_the_tube() {
    let se = Superelement::new(tube_segment(0.3, 2, FrameLocation::CentreOfMass)).unwrap();
    let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
    se.reference_coordinates(&mut q, &mut u);
    let r = Rotation3::from_scaled_axis(Vector3::new(0.4, 1.1, -0.3));
    se.set_pose(&mut q, &Vector3::new(1.0, 2.0, 3.0), r.matrix());
    let mut s = se.evaluated(&q, &u).unwrap();
    let e = s.get_mut::<SuperelementEval>();
    assert!(e.q_loc.amax() < 1e-14);
    assert!((e.x_j - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-14);
    // m = rho A L
    let a = std::f64::consts::PI * (0.01f64.powi(2) - 0.009f64.powi(2));
    assert!((se.mass() - 2700.0 * a * 0.3).abs() < 1e-12 * se.mass());
}

#[test]
fn tangent_equals_finite_difference_jacobian() {
    let g = Vector3::new(0.0, -9.81, 3.0);
    for matrices in [TransformMatrices::Exact, TransformMatrices::Approximated] {
        for modes in [0, 2] {
            for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
                let se = Superelement::new(tube_segment(0.3, modes, frame))
                    .unwrap()
                    .with_matrices(matrices);
                let rel = check_tangent(&se, g);
                println!("{matrices:?} modes {modes} {frame:?}: {rel:e}");
                assert!(rel < 1e-6, "{matrices:?} modes {modes} {frame:?}: {rel:e}");
            }
        }
    }
}
