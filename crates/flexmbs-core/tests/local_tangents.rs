//! Load and constraint-force tangents restricted to the owners of each load's / joint's frames
//! (`system::add_load_tangents`, `system::subtract_constraint_force_tangent`) against an
//! independent global central-difference tangent written here: every coordinate of every body
//! perturbed through `system::integrate_positions`, every frame re-evaluated, all loads /
//! all joints assembled.

use faer::Mat;
use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam as FfrRot};
use flexmbs_core::system::{
    add_load_forces, add_load_tangents, assemble_constraints, evaluate, integrate_positions,
    subtract_constraint_force_tangent,
};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, Model, ModelSpec, RigidBody, RotationParam, TimeFunction,
    Workspace,
};
use nalgebra::{Matrix3, Vector3};

/// An FFR box (8 nodes, 3 modes with rotational mode rows, Cardan), a quaternion rigid body and a
/// Cardan rigid body that carries nothing but its own spring to ground; loads: a follower force at
/// an FFR node, a torque on the rigid body, spring-dampers FFR node - rigid body and ground -
/// third body; joints: revolute FFR node - rigid body, spherical ground - FFR origin.
fn model() -> Model {
    let mut x = Vec::new();
    for s in [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ] {
        x.push([0.3 * s[0], 0.1 * s[1], 0.05 * s[2]]);
    }
    let m = [1.5, 1.2, 1.0, 0.8, 1.1, 1.3, 0.9, 1.4];
    let modes_t = Mat::from_fn(24, 3, |r, c| {
        let p = x[r / 3];
        match (c, r % 3) {
            (0, 1) => 10.0 * p[0] * p[2],
            (1, 2) => 3.0 * p[0] * p[1] + p[0],
            (2, 0) => p[1] - 2.0 * p[2],
            _ => 0.1 * (r as f64 * 0.37 + c as f64).sin(),
        }
    });
    let modes_r = Mat::from_fn(24, 3, |r, c| 0.5 * ((r * 3 + c) as f64 * 0.71).cos());
    let k = Mat::from_fn(3, 3, |i, j| {
        if i == j {
            [400.0, 900.0, 1600.0][i]
        } else {
            0.0
        }
    });
    let inv = FfrInvariants::from_lumped(&x, &m, modes_t.as_ref()).unwrap();
    let body = FfrBody::new(
        inv,
        FfrRot::Cardan,
        &x,
        modes_t.as_ref(),
        Some(modes_r.as_ref()),
        k.as_ref(),
    )
    .unwrap();
    let mut spec = ModelSpec::new();
    let f = spec.add_body("flex", FfrElement::new(body));
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.2, 0.3, 0.4));
    let r = spec.add_body(
        "rigid",
        RigidBody::new(2.0, inertia).with_rotation(RotationParam::Quaternion),
    );
    let c = spec.add_body("third", RigidBody::new(1.0, inertia));
    let node6 = spec.add_node_frame("n6", f, 6, Vector3::from(x[6]));
    let node2 = spec.add_node_frame("n2", f, 2, Vector3::from(x[2]));
    let origin = spec.add_frame("o", f, Vector3::zeros(), Matrix3::identity());
    let rf = spec.add_frame("r", r, Vector3::new(0.1, -0.2, 0.05), Matrix3::identity());
    let cf = spec.add_frame("c", c, Vector3::new(0.0, 0.3, 0.0), Matrix3::identity());
    let g = spec.add_ground_frame("g", Vector3::new(0.5, 0.1, 0.0), Matrix3::identity());
    spec.add_load(Load::Force {
        frame: node6,
        vector: Vector3::new(3.0, -2.0, 1.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Frame,
    });
    spec.add_load(Load::Torque {
        frame: rf,
        vector: Vector3::new(0.5, 1.0, -2.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Frame,
    });
    spec.add_load(Load::SpringDamper {
        frame_a: node2,
        frame_b: rf,
        stiffness: 300.0,
        damping: 4.0,
        free_length: 0.2,
    });
    spec.add_load(Load::SpringDamper {
        frame_a: g,
        frame_b: cf,
        stiffness: 50.0,
        damping: 2.0,
        free_length: 0.1,
    });
    spec.add_joint(Joint::revolute("rev", node6, rf));
    spec.add_joint(Joint::spherical("sph", g, origin));
    spec.compile().unwrap()
}

/// A general state: `q = q_ref ⊕ dv` with a pseudo-random `dv`, pseudo-random `u`.
fn general_state(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let s = model.initial_state();
    let dv: Vec<f64> = (0..model.nu)
        .map(|i| 0.3 * ((i as f64 * 1.7 + 0.4).sin()))
        .collect();
    let mut q = s.q.clone();
    integrate_positions(model, &s.q, &dv, &mut q);
    let u = (0..model.nu)
        .map(|i| 2.0 * ((i as f64 * 0.9 + 1.1).cos()))
        .collect();
    (q, u)
}

/// A global force vector `h(q, u)` (length nu) written into the last argument.
type GlobalForce<'a> = dyn FnMut(&[f64], &[f64], &mut [f64]) + 'a;

/// Column-by-column central differences of `f(q, u)` (length nu) over all coordinates:
/// position columns along `q ⊕ dv` with step 1e-6, velocity columns with 1e-6 max(1, |u_j|).
fn global_fd(model: &Model, q: &[f64], u: &[f64], f: &mut GlobalForce<'_>) -> (Mat<f64>, Mat<f64>) {
    let nu = model.nu;
    let (mut dq, mut du) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
    let (mut hp, mut hm) = (vec![0.0; nu], vec![0.0; nu]);
    let mut qp = q.to_vec();
    for j in 0..nu {
        let eps = 1e-6;
        let mut dv = vec![0.0; nu];
        dv[j] = eps;
        integrate_positions(model, q, &dv, &mut qp);
        f(&qp, u, &mut hp);
        dv[j] = -eps;
        integrate_positions(model, q, &dv, &mut qp);
        f(&qp, u, &mut hm);
        for i in 0..nu {
            dq[(i, j)] = (hp[i] - hm[i]) / (2.0 * eps);
        }
        let eps = 1e-6 * u[j].abs().max(1.0);
        let mut up = u.to_vec();
        up[j] = u[j] + eps;
        f(q, &up, &mut hp);
        up[j] = u[j] - eps;
        f(q, &up, &mut hm);
        for i in 0..nu {
            du[(i, j)] = (hp[i] - hm[i]) / (2.0 * eps);
        }
    }
    (dq, du)
}

fn assert_close(what: &str, a: &Mat<f64>, b: &Mat<f64>, rel: f64) {
    let scale = b.norm_max().max(1.0);
    let diff = (a - b).norm_max();
    assert!(
        diff <= rel * scale,
        "{what}: max difference {diff:e} > {rel:e} * {scale:e}"
    );
}

#[test]
fn load_tangent_equals_global_finite_differences() {
    let model = model();
    let (q, u) = general_state(&model);
    let mut ws = Workspace::new(&model);
    let mut sys = Workspace::new(&model).sys;
    let (ref_q, ref_u) = global_fd(&model, &q, &u, &mut |q, u, h| {
        evaluate(&model, q, u, &mut sys).unwrap();
        h.fill(0.0);
        add_load_forces(&model, 0.3, 1.0, &sys.frames, h);
    });
    evaluate(&model, &q, &u, &mut ws.sys).unwrap();
    let before: Vec<_> = ws.sys.frames.iter().map(|k| k.position).collect();
    ws.sys.dh_dq.fill(0.0);
    ws.sys.dh_du.fill(0.0);
    add_load_tangents(&model, 0.3, &q, &u, 1.0, &mut ws.sys);
    // the same differences, summed per load instead of over all loads: round-off only
    // (|h| ~ 1e2, eps 1e-6: ~1e-8 absolute), far below the O(eps^2) truncation error
    assert_close("dh/dq of the loads", &ws.sys.dh_dq, &ref_q, 1e-8);
    assert_close("dh/du of the loads", &ws.sys.dh_du, &ref_u, 1e-8);
    assert!(
        ref_q.norm_max() > 10.0 && ref_u.norm_max() > 1.0,
        "non-trivial"
    );
    // the frames are left at (q, u), bitwise
    for (k, p) in ws.sys.frames.iter().zip(&before) {
        assert_eq!(k.position, *p);
    }
}

#[test]
fn constraint_force_tangent_equals_global_finite_differences() {
    let model = model();
    let (q, u) = general_state(&model);
    let lambda: Vec<f64> = (0..model.nc)
        .map(|k| 5.0 * (k as f64 + 0.5).sin())
        .collect();
    let mut ws = Workspace::new(&model);
    let mut sys = Workspace::new(&model).sys;
    let (ref_q, _) = global_fd(&model, &q, &u, &mut |q, u, h| {
        evaluate(&model, q, u, &mut sys).unwrap();
        assemble_constraints(
            &model,
            0.3,
            &sys.frames,
            &mut sys.g,
            sys.g_jac.as_mut(),
            &mut sys.g_t,
            &mut sys.g_bias,
        );
        for (i, hi) in h.iter_mut().enumerate() {
            *hi = -(0..model.nc)
                .map(|k| sys.g_jac[(k, i)] * lambda[k])
                .sum::<f64>();
        }
    });
    evaluate(&model, &q, &u, &mut ws.sys).unwrap();
    ws.sys.dh_dq.fill(0.0);
    subtract_constraint_force_tangent(&model, 0.3, &q, &u, &lambda, &mut ws.sys);
    assert_close("d(G^T lambda)/dq", &ws.sys.dh_dq, &ref_q, 1e-8);
    assert!(ref_q.norm_max() > 1.0, "non-trivial");
}

/// A load on one body leaves the tangent columns and rows of an unrelated body exactly zero.
#[test]
fn load_tangent_touches_only_the_owners() {
    let model = model();
    let (q, u) = general_state(&model);
    let mut ws = Workspace::new(&model);
    evaluate(&model, &q, &u, &mut ws.sys).unwrap();
    ws.sys.dh_dq.fill(0.0);
    ws.sys.dh_du.fill(0.0);
    add_load_tangents(&model, 0.0, &q, &u, 1.0, &mut ws.sys);
    // body 0 (flex) and 1 (rigid) are coupled by the spring; body 2 only to ground
    let third = model
        .body_dofs(flexmbs_core::BodyId(2))
        .u
        .as_range()
        .unwrap();
    let coupled = 0..third.start;
    for i in coupled.clone() {
        for j in third.clone() {
            assert_eq!(ws.sys.dh_dq[(i, j)], 0.0);
            assert_eq!(ws.sys.dh_dq[(j, i)], 0.0);
            assert_eq!(ws.sys.dh_du[(i, j)], 0.0);
        }
    }
}
