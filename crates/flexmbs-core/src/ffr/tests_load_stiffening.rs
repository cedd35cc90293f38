//! Unit tests of [`LoadStiffening`]: grouping of the FE patterns, force/tangent/power against the
//! assembled matrix, and rejected inputs.

use super::{FfrError, LoadStiffening};
use faer::Mat;
use flexmbs_fe::geometric::InertialLoad;
use flexmbs_fe::geometric_loads::{LoadGeometricStiffness, NodeLoad, UnitLoad};
use nalgebra::{DMatrix, DVector};

fn pattern_matrix(k: usize, nf: usize) -> Mat<f64> {
    Mat::from_fn(nf, nf, |i, j| ((3 * i + 5 * j + 7 * k) % 11) as f64 - 5.0)
}

fn fe(patterns: Vec<UnitLoad>, relief: bool, nf: usize) -> LoadGeometricStiffness {
    LoadGeometricStiffness {
        matrices: (0..patterns.len()).map(|k| pattern_matrix(k, nf)).collect(),
        patterns,
        inertia_relief: relief,
    }
}

/// Patterns are grouped by node (force x, y, z, moment x, y, z; missing ones zero), the
/// accelerations of a supported body follow; `add_force`, `add_tangent` and `power` agree with
/// `-K_load(c) q_f` from the assembled `matrix` to 1e-13 relative.
#[test]
fn patterns_group_by_node_and_force_matches_matrix() {
    let nf = 3;
    let mut pats = vec![
        UnitLoad::Node(NodeLoad::Moment { node: 4, axis: 1 }),
        UnitLoad::Node(NodeLoad::Force { node: 9, axis: 0 }),
        UnitLoad::Node(NodeLoad::Force { node: 4, axis: 2 }),
    ];
    for d in 0..3 {
        pats.push(UnitLoad::Inertial(InertialLoad::Translation(d)));
        pats.push(UnitLoad::Inertial(InertialLoad::AngularAcceleration(d)));
    }
    let g = fe(pats, false, nf);
    let ls = LoadStiffening::from_fe(&g, nf).unwrap();
    assert_eq!(ls.interfaces.len(), 2);
    assert_eq!((ls.interfaces[0].node, ls.interfaces[1].node), (4, 9));
    assert_eq!(ls.num_coefficients(), 18);
    let same =
        |a: &DMatrix<f64>, k: usize| a == &DMatrix::from_fn(nf, nf, |i, j| g.matrices[k][(i, j)]);
    assert!(same(&ls.interfaces[0].matrices[4], 0));
    assert!(same(&ls.interfaces[1].matrices[0], 1));
    assert!(same(&ls.interfaces[0].matrices[2], 2));
    assert!(ls.interfaces[0].matrices[0].iter().all(|x| *x == 0.0));
    let acc = ls.acceleration.as_ref().unwrap();
    assert!(same(&acc[0], 3) && same(&acc[3], 4) && same(&acc[2], 7));
    let c: Vec<f64> = (0..18).map(|k| (k as f64 * 0.37).sin()).collect();
    let qf = DVector::from_vec(vec![0.3, -0.2, 0.5]);
    let qfd = [1.5, 0.25, -0.75];
    let k = ls.matrix(&c);
    let expect = -(&k * &qf);
    let mut out = vec![0.0; 6 + nf];
    ls.add_force(&c, &qf, &mut out);
    let scale = expect.amax();
    for i in 0..nf {
        assert!((out[6 + i] - expect[i]).abs() <= 1e-13 * scale);
    }
    let p: f64 = (0..nf).map(|i| qfd[i] * expect[i]).sum();
    assert!((ls.power(&c, &qf, &qfd) - p).abs() <= 1e-13 * scale);
    let mut t = faer::Mat::<f64>::zeros(6 + nf, 6 + nf);
    ls.add_tangent(&c, nf, t.as_mut());
    for i in 0..nf {
        for j in 0..nf {
            assert!((t[(6 + i, 6 + j)] + k[(i, j)]).abs() <= 1e-13 * k.amax());
        }
    }
}

/// Centrifugal patterns, acceleration patterns of a relieved (free-free) body, an incomplete set
/// of acceleration patterns and wrong matrix sizes are typed errors.
#[test]
fn bad_patterns_are_rejected() {
    let nf = 2;
    let cen = fe(
        vec![UnitLoad::Inertial(InertialLoad::Centrifugal(0, 0))],
        false,
        nf,
    );
    assert!(matches!(
        LoadStiffening::from_fe(&cen, nf),
        Err(FfrError::UnsupportedLoadPattern { .. })
    ));
    let relieved = fe(
        vec![UnitLoad::Inertial(InertialLoad::Translation(0))],
        true,
        nf,
    );
    assert!(matches!(
        LoadStiffening::from_fe(&relieved, nf),
        Err(FfrError::UnsupportedLoadPattern { .. })
    ));
    let partial = fe(
        vec![UnitLoad::Inertial(InertialLoad::Translation(0))],
        false,
        nf,
    );
    assert!(matches!(
        LoadStiffening::from_fe(&partial, nf),
        Err(FfrError::DimensionMismatch { found: 1, .. })
    ));
    let node = fe(
        vec![UnitLoad::Node(NodeLoad::Force { node: 0, axis: 0 })],
        true,
        nf,
    );
    assert!(matches!(
        LoadStiffening::from_fe(&node, 3),
        Err(FfrError::DimensionMismatch { expected: 3, .. })
    ));
}
