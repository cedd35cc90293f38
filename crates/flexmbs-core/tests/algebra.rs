//! The two algebra backends against each other and the block-Cholesky mass solver against a
//! dense LU: same matrices, same solutions; same generalized-alpha trajectories and static
//! equilibria.
use crate::chain;
use crate::common;
use chain::{chain, Link};
use flexmbs_core::algebra::{BlockMass, LinearSolver, SaddleKind, SystemMatrix};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, Statics, StaticsSettings};
use flexmbs_core::linsolve::DenseLu;
use flexmbs_core::system;
use flexmbs_core::*;
use std::f64::consts::PI;

/// Spring and follower force on the chain.
const FOLLOWER: Option<LoadCoordinates> = Some(LoadCoordinates::Frame);

/// Largest `|a_i - b_i|` relative to `max(1e-300, max |b|)`.
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// A flexible 4-link chain with a spring and a follower force after 30 dense steps (deformed,
/// moving, multipliers set).
fn moving_chain() -> (Model, State) {
    let (model, mut s) = chain(4, Link::Flexible, FOLLOWER);
    let mut ws = Workspace::with_linear_solver(&model, LinearSolver::Dense);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    for _ in 0..30 {
        ga.step(&model, &mut s, &mut ws, 2e-3).unwrap();
    }
    (model, s)
}

/// Builds `kind` with `choice` at state `s`, factors it and solves for a fixed right-hand side.
fn solve_with(model: &Model, s: &State, kind: SaddleKind, choice: LinearSolver) -> Vec<f64> {
    let mut ws = Workspace::with_linear_solver(model, choice);
    let sys = &mut ws.sys;
    system::evaluate(model, &s.q, &s.u, sys).unwrap();
    system::assemble_constraints(
        model,
        s.t,
        &sys.frames,
        &mut sys.g,
        sys.g_jac.as_mut(),
        &mut sys.g_t,
        &mut sys.g_bias,
    );
    let mut m = SystemMatrix::new(model, choice);
    assert_eq!(m.is_sparse(), choice == LinearSolver::Sparse);
    m.build(kind, model, &s.q, &s.u, &s.lambda, sys);
    assert!(m.factor(), "{kind:?} {choice:?} singular");
    let mut x: Vec<f64> = (0..m.dim())
        .map(|i| (0.37 * i as f64).sin() + 0.1)
        .collect();
    m.solve_in_place(&mut x);
    x
}

/// Same matrix, two factorizations: the sparse LU solution equals the dense LU solution to
/// 1e-12 relative for the iteration matrix (element blocks, a spring and a
/// follower force coupling bodies; each body carries at most one load, so the finite-difference
/// load columns are the same numbers in both backends) and the least-squares matrix, and to
/// 1e-10 for the augmented mass (`cond_1(M)` of these links is 2e5, see
/// `block_cholesky_mass_solves_equal_dense_lu`; measured 1.2e-12). The static
/// tangent's constraint-force columns are central differences (step 1e-6) of `G^T lambda`,
/// summed joint by joint in the sparse backend and row by row in the dense one: the round-off of
/// those sums (1e-16 relative) divided by the step gives 1e-10, hence 1e-8 there.
#[test]
fn sparse_and_dense_backends_solve_the_same_systems() {
    let (model, s) = moving_chain();
    let cases = [
        (SaddleKind::AugmentedMass, 1e-10),
        (
            SaddleKind::Iteration {
                t: s.t,
                c_u: 2e-3 * 0.6,
                c_q: 4e-6 * 0.3,
            },
            1e-12,
        ),
        (SaddleKind::LeastSquares, 1e-12),
        (SaddleKind::StaticTangent { t: s.t, mu: 1.0 }, 1e-8),
    ];
    let mut errors = Vec::new();
    for (kind, tol) in cases {
        let xd = solve_with(&model, &s, kind, LinearSolver::Dense);
        let xs = solve_with(&model, &s, kind, LinearSolver::Sparse);
        let e = rel_diff(&xs, &xd);
        println!("{kind:?}: sparse vs dense {e:e}");
        errors.push((kind, e, tol));
    }
    for (kind, e, tol) in errors {
        assert!(e < tol, "{kind:?}: {e:e}");
    }
}

/// Generalized-alpha with the sparse backend follows the dense trajectory to 1e-10 (relative to
/// the largest coordinate) on every step: the flexible chain with loads (full and modified
/// Newton), a rigid chain, and the physical pendulum of `tests/pendulum.rs` (Cardan and
/// quaternion).
#[test]
fn sparse_trajectories_equal_dense_ones() {
    let (flex, flex0) = chain(4, Link::Flexible, FOLLOWER);
    let (rigid, rigid0) = chain(6, Link::Rigid, FOLLOWER);
    let cases: Vec<(&str, &Model, State, bool, f64, usize)> = vec![
        (
            "flexible chain, full Newton",
            &flex,
            flex0.clone(),
            false,
            1e-3,
            200,
        ),
        (
            "flexible chain, modified Newton",
            &flex,
            flex0,
            true,
            1e-3,
            200,
        ),
        ("rigid chain", &rigid, rigid0, false, 1e-3, 300),
    ];
    let pend = [
        common::Pendulum::new(RotationParam::Cardan),
        common::Pendulum::new(RotationParam::Quaternion),
    ];
    let mut all = cases;
    for p in &pend {
        all.push(("pendulum", &p.model, p.state(0.5), false, 1e-3, 500));
    }
    for (name, model, s0, modified, h, steps) in all {
        let d = common::genalpha_trajectory(model, &s0, LinearSolver::Dense, modified, h, steps);
        let sp = common::genalpha_trajectory(model, &s0, LinearSolver::Sparse, modified, h, steps);
        let worst = d
            .iter()
            .zip(&sp)
            .map(|(a, b)| rel_diff(b, a))
            .fold(0.0, f64::max);
        println!("{name}: worst step difference {worst:e}");
        assert!(worst < 1e-10, "{name}: {worst:e}");
    }
}

/// Statics (geometric stiffness of the joints, spring and force tangents) reaches the same
/// equilibrium of a hanging rigid chain with both backends, to 1e-9 relative (a conservative
/// load set: a follower force makes the equilibrium path depend on the load increments).
#[test]
fn sparse_statics_equals_dense_statics() {
    let (model, mut s0) = chain(3, Link::Rigid, Some(LoadCoordinates::Global));
    // assembled, hanging down at angles -90 + 20, -90 + 40, -90 + 60 degrees from x (the
    // horizontal chain has no static stiffness against rotation)
    let mut hinge = nalgebra::Vector3::zeros();
    for i in 0..3 {
        let angle = -0.5 * PI + 0.35 * (i + 1) as f64;
        let r = nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), angle);
        let axis = r * nalgebra::Vector3::x() * chain::LINK_LENGTH;
        let b = model.body_id(&format!("link{i}")).unwrap();
        model.set_body_pose(&mut s0, b, hinge + 0.5 * axis, *r.matrix());
        hinge += axis;
    }
    let statics = Statics::new(StaticsSettings {
        load_steps: 4,
        ..Default::default()
    });
    let mut q = Vec::new();
    for choice in [LinearSolver::Dense, LinearSolver::Sparse] {
        let mut s = s0.clone();
        let mut ws = Workspace::with_linear_solver(&model, choice);
        let st = statics.solve(&model, &mut s, &mut ws).unwrap();
        println!("{choice:?}: {st:?}");
        assert!(st.iterations >= 4, "a non-trivial solve");
        q.push(s.q);
    }
    let e = rel_diff(&q[1], &q[0]);
    println!("equilibrium sparse vs dense {e:e}");
    assert!(e < 1e-9, "{e:e}");
}

/// Block-Cholesky `M^-1 B` (three right-hand sides) equals a dense LU of the assembled `M` at a
/// deformed state to `4 cond_1(M) eps` (both are backward stable); constant rigid-body blocks factor once, FFR blocks
/// (mass depends on the modal coordinates) are refactored when `q` changes.
#[test]
fn block_cholesky_mass_solves_equal_dense_lu() {
    let (model, s) = moving_chain();
    let nu = model.nu;
    let mut bm = BlockMass::new(&model);
    let mut ws = Workspace::new(&model);
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    bm.update(&model, &s.q, &mut ws.sys.eval).unwrap();
    let mut m = faer::Mat::zeros(nu, nu);
    system::assemble_mass(&model, &s.q, &mut ws.sys.eval, m.as_mut(), &mut []);
    let mut lu = DenseLu::new(nu);
    lu.a.copy_from(&m);
    assert!(lu.factor());
    // condition number cond_1(M) = |M|_1 |M^-1|_1 (M^-1 column by column from the LU)
    let norm1 = |a: &faer::Mat<f64>| {
        (0..a.ncols())
            .map(|j| a.col_as_slice(j).iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let inv = faer::Mat::from_fn(nu, nu, |_, _| 0.0);
    let mut inv = inv;
    for j in 0..nu {
        let mut e = vec![0.0; nu];
        e[j] = 1.0;
        lu.solve_in_place(&mut e);
        inv.col_as_slice_mut(j).copy_from_slice(&e);
    }
    let cond = norm1(&m) * norm1(&inv);
    let tol = 4.0 * cond * f64::EPSILON;
    println!("cond_1(M) = {cond:e}, tolerance {tol:e}");
    let k = 3;
    let b: Vec<f64> = (0..nu * k).map(|i| (0.7 * i as f64).cos()).collect();
    let mut x = b.clone();
    bm.solve_in_place(&mut x, k);
    for c in 0..k {
        let mut y = b[c * nu..(c + 1) * nu].to_vec();
        lu.solve_in_place(&mut y);
        let e = rel_diff(&x[c * nu..(c + 1) * nu], &y);
        println!("column {c}: block Cholesky vs LU {e:e}");
        assert!(e < tol, "column {c}: {e:e}");
    }
    // FFR links: moving the modal coordinates changes every block
    let before = bm.refactorizations();
    let mut q2 = s.q.clone();
    for b in 0..model.bodies.len() {
        // first modal coordinate (after position + quaternion)
        model.body_q_mut(flexmbs_core::BodyId(b), &mut q2)[7] += 1e-3;
    }
    system::evaluate(&model, &q2, &s.u, &mut ws.sys).unwrap();
    bm.update(&model, &q2, &mut ws.sys.eval).unwrap();
    assert_eq!(bm.refactorizations() - before, model.bodies.len());
    // rigid quaternion links: constant mass, factored once
    let (rigid, r0) = chain(5, Link::Rigid, None);
    let mut bm = BlockMass::new(&rigid);
    let mut ws = Workspace::new(&rigid);
    system::evaluate(&rigid, &r0.q, &r0.u, &mut ws.sys).unwrap();
    bm.update(&rigid, &r0.q, &mut ws.sys.eval).unwrap();
    let mut q = r0.q.clone();
    q[0] += 0.3;
    system::evaluate(&rigid, &q, &r0.u, &mut ws.sys).unwrap();
    bm.update(&rigid, &q, &mut ws.sys.eval).unwrap();
    assert_eq!(bm.refactorizations(), rigid.bodies.len());
}

/// The automatic choice: dense for small models, sparse for a long chain.
#[test]
fn automatic_choice_by_size() {
    let (small, _) = chain(2, Link::Flexible, None);
    assert!(!SystemMatrix::new(&small, LinearSolver::Auto).is_sparse());
    let (long, _) = chain(40, Link::Flexible, None);
    assert!(SystemMatrix::new(&long, LinearSolver::Auto).is_sparse());
    assert!(!SystemMatrix::new(&long, LinearSolver::Dense).is_sparse());
}
