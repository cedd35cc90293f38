//! The analytic tangent of a point force on an FFR body (`Element::force_load_tangent`) equals
//! central finite differences of `J_T^T f` along `q ⊕ dv` at deformed states: dead and follower
//! forces, at a beam-node frame (rotational modes, an oriented frame) and at a point fixed in the
//! floating frame, with Cardan angles and quaternions.

use faer::Mat;
use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam};
use flexmbs_core::rotation::rotation_vector_matrix;
use flexmbs_core::{Element, FrameKinematics, LocalFrame};
use nalgebra::{DVector, Vector3};

fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

const NODES: usize = 5;
const NF: usize = 4;

/// A lumped body with random translational and (optionally) rotational modes.
fn element(seed: &mut u64, rot: RotationParam, rotational_modes: bool) -> FfrElement {
    let u0: Vec<[f64; 3]> = (0..NODES)
        .map(|i| [0.25 * i as f64, 0.1 * rnd(seed), 0.05 * rnd(seed)])
        .collect();
    let masses: Vec<f64> = (0..NODES).map(|_| 1.0 + 0.5 * rnd(seed)).collect();
    let modes_t = Mat::from_fn(3 * NODES, NF, |_, _| 0.3 * rnd(seed));
    let modes_r = Mat::from_fn(3 * NODES, NF, |_, _| rnd(seed));
    let k = Mat::from_fn(NF, NF, |i, j| if i == j { 100.0 } else { 0.0 });
    let inv = FfrInvariants::from_lumped(&u0, &masses, modes_t.as_ref()).unwrap();
    let modes_r = rotational_modes.then_some(modes_r.as_ref());
    let body = FfrBody::new(inv, rot, &u0, modes_t.as_ref(), modes_r, k.as_ref()).unwrap();
    FfrElement::new(body)
}

/// A general pose, deformation `q_f` of size ~0.5 (elastic node rotations ~0.5 rad), random `u`.
fn state(seed: &mut u64, e: &FfrElement) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut u) = (vec![0.0; e.nq()], vec![0.0; e.nu()]);
    e.reference_coordinates(&mut q, &mut u);
    let pose = rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7));
    e.set_pose(&mut q, &Vector3::new(0.3, -0.2, 0.5), &pose);
    let qf = DVector::from_fn(NF, |_, _| 0.5 * rnd(seed));
    let nq = q.len();
    q[nq - NF..].copy_from_slice(qf.as_slice());
    for x in u.iter_mut() {
        *x = 2.0 * rnd(seed);
    }
    (q, u)
}

/// `J_T^T f` of the force at `frame` at `(q, u)`: `f` global, or turned by the frame (follower).
fn generalized_force(
    e: &FfrElement,
    q: &[f64],
    u: &[f64],
    frame: &LocalFrame,
    force: &Vector3<f64>,
    follower: bool,
) -> Vec<f64> {
    let mut s = e.evaluated(q, u).unwrap();
    let mut k = FrameKinematics::new(e.nu());
    e.frame_kinematics(q, u, &mut s, frame, &mut k);
    let f = if follower { k.rotation * force } else { *force };
    (0..e.nu())
        .map(|j| (0..3).map(|i| k.jac_t[(i, j)] * f[i]).sum())
        .collect()
}

#[test]
fn force_load_tangent_equals_finite_differences() {
    let mut seed = 17;
    let force = Vector3::new(3.0, -2.0, 1.5);
    let mut node_frame = LocalFrame::at(Vector3::zeros());
    node_frame.mesh_node = Some(3);
    node_frame.rotation = rotation_vector_matrix(&Vector3::new(0.2, 0.1, -0.3));
    let mut point_frame = LocalFrame::at(Vector3::new(0.2, -0.1, 0.3));
    point_frame.rotation = rotation_vector_matrix(&Vector3::new(-0.5, 0.3, 0.1));
    let mut worst: f64 = 0.0;
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        for rotational_modes in [true, false] {
            let e = element(&mut seed, rot, rotational_modes);
            let (q, u) = state(&mut seed, &e);
            let nu = e.nu();
            for frame in [&node_frame, &point_frame] {
                for follower in [false, true] {
                    let mut s = e.evaluated(&q, &u).unwrap();
                    let mut an = Mat::<f64>::zeros(nu, nu);
                    assert!(e.force_load_tangent(
                        &q,
                        &u,
                        &mut s,
                        frame,
                        &force,
                        follower,
                        an.as_mut()
                    ));
                    let mut fd = Mat::<f64>::zeros(nu, nu);
                    let (mut dv, mut qp) = (vec![0.0; nu], q.clone());
                    let eps = 1e-6;
                    for j in 0..nu {
                        let mut h = [vec![], vec![]];
                        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
                            dv[j] = sign * eps;
                            e.integrate_position(&q, &dv, &mut qp);
                            h[k] = generalized_force(&e, &qp, &u, frame, &force, follower);
                        }
                        dv[j] = 0.0;
                        for i in 0..nu {
                            fd[(i, j)] = (h[0][i] - h[1][i]) / (2.0 * eps);
                        }
                    }
                    let scale = fd.norm_max();
                    let diff = (&an - &fd).norm_max();
                    let case = format!(
                        "{rot:?} rot. modes {rotational_modes} node {:?} follower {follower}",
                        frame.mesh_node
                    );
                    assert!(scale > 0.1, "{case}: trivial tangent");
                    assert!(
                        diff <= 1e-7 * scale,
                        "{case}: difference {diff:e}, scale {scale:e}\n{an:?}\n{fd:?}"
                    );
                    worst = worst.max(diff / scale);
                }
            }
        }
    }
    eprintln!("worst relative difference {worst:e}");
}
