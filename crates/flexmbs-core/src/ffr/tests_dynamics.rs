//! End-to-end checks: free-flight conservation with RK4, generalized forces, rotation Jacobians,
//! damping, SI conversion, errors and absence of run-time allocation.

use super::body::faer_view_mut;
use super::tests::{body_of, jt, random_data, random_state, rnd};
use super::*;
use nalgebra::{DMatrix, DVector, Vector3};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Counts allocations of the current thread (for the allocation-free checks).
struct CountingAllocator;
thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}
#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

/// Energy T + 1/2 q_f^T k q_f, linear and angular momentum sum_j m_j r_j × r_dot_j (about the
/// global origin) of the state.
fn invariants_of_motion(
    b: &FfrBody,
    masses: &[f64],
    q: &[f64],
    u: &[f64],
    s: &mut FfrScratch,
) -> (f64, Vector3<f64>, Vector3<f64>) {
    b.update(q, u, s).unwrap();
    let mut e = b.kinetic_energy(s, u);
    e += 0.5 * s.qf.dot(&(&b.k_ff * &s.qf));
    let mut p = Vector3::zeros();
    let mut l = Vector3::zeros();
    for (j, m) in masses.iter().enumerate() {
        let k = b.node_kinematics(j, q, u, s).unwrap();
        p += *m * k.v;
        l += *m * k.r.cross(&k.v);
    }
    (e, p, l)
}

/// A free, undamped, spinning FFR body (6 nodes, 2 modes) integrated with explicit RK4
/// (1000 steps of 1e-3 s) conserves energy, linear and angular momentum to 1e-8 relative, for
/// Cardan and quaternion coordinates: validates M, Q_v and K end to end.
#[test]
fn free_flight_rk4_conserves_energy_and_momentum() {
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let mut seed = 77;
        let d = random_data(&mut seed, 6, 2, 0.3);
        let b = body_of(&d, rot, false);
        let mut q = match rot {
            RotationParam::Cardan => vec![0.1, -0.2, 0.3, 0.2, 0.3, -0.1],
            RotationParam::Quaternion => vec![0.1, -0.2, 0.3, 0.9, 0.1, 0.3, -0.2],
        };
        q.extend([0.05, -0.03]);
        b.normalize(&mut q).unwrap();
        let mut u = vec![0.3, -0.1, 0.2, 1.5, -2.0, 1.0, 0.2, -0.1];
        let mut s = FfrScratch::new(b.nf());
        let (nq, nu) = (b.nq(), b.nu());
        let g = Vector3::zeros();
        let (e0, p0, l0) = invariants_of_motion(&b, &d.masses, &q, &u, &mut s);
        let dt = 1e-3;
        let rhs = |q: &[f64], u: &[f64], s: &mut FfrScratch, dq: &mut [f64], du: &mut [f64]| {
            b.coordinate_rates(q, u, dq);
            b.accelerations(q, u, &g, s, du).unwrap();
        };
        let (mut kq, mut ku) = (vec![vec![0.0; nq]; 4], vec![vec![0.0; nu]; 4]);
        let (mut qt, mut ut) = (vec![0.0; nq], vec![0.0; nu]);
        for _ in 0..1000 {
            for stage in 0..4 {
                let c = [0.0, 0.5, 0.5, 1.0][stage];
                for i in 0..nq {
                    qt[i] = q[i]
                        + if stage > 0 {
                            c * dt * kq[stage - 1][i]
                        } else {
                            0.0
                        };
                }
                for i in 0..nu {
                    ut[i] = u[i]
                        + if stage > 0 {
                            c * dt * ku[stage - 1][i]
                        } else {
                            0.0
                        };
                }
                let (a, bq) = kq.split_at_mut(stage);
                let _ = a;
                let (a2, bu) = ku.split_at_mut(stage);
                let _ = a2;
                rhs(&qt, &ut, &mut s, &mut bq[0], &mut bu[0]);
            }
            for i in 0..nq {
                q[i] += dt / 6.0 * (kq[0][i] + 2.0 * kq[1][i] + 2.0 * kq[2][i] + kq[3][i]);
            }
            for i in 0..nu {
                u[i] += dt / 6.0 * (ku[0][i] + 2.0 * ku[1][i] + 2.0 * ku[2][i] + ku[3][i]);
            }
        }
        let (e1, p1, l1) = invariants_of_motion(&b, &d.masses, &q, &u, &mut s);
        let (de, dp, dl) = (
            (e1 - e0).abs() / e0,
            (p1 - p0).norm() / p0.norm(),
            (l1 - l0).norm() / l0.norm(),
        );
        eprintln!("{rot:?}: rel. drift energy {de:e}, momentum {dp:e}, angular momentum {dl:e}");
        assert!(de < 1e-8 && dp < 1e-8 && dl < 1e-8);
        // the motion is not trivial: the modes moved
        assert!((q[nq - 2] - 0.05).abs() > 1e-3);
    }
}

/// Gravity force = sum_j m_j J_j^T g, node force = J_T^T F (2.76), node torque = J_R^T τ (1e-12).
#[test]
fn generalized_forces_equal_jacobian_transposes() {
    let mut seed = 3;
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let d = random_data(&mut seed, 5, 3, 0.3);
        let b = body_of(&d, rot, true);
        let (q, u) = random_state(&mut seed, &b, 0.5);
        let mut s = FfrScratch::new(b.nf());
        b.update(&q, &u, &mut s).unwrap();
        let g = Vector3::new(0.3, -9.81, 1.2);
        let mut got = vec![0.0; b.nu()];
        b.add_gravity_force(&s, &g, &mut got);
        let mut brute = DVector::zeros(b.nu());
        for j in 0..b.num_nodes() {
            brute += d.masses[j] * jt(&b, j, &q, &u).transpose() * g;
        }
        assert!((DVector::from_column_slice(&got) - &brute).norm() < 1e-12 * brute.norm());
        let f = Vector3::new(1.0, -2.0, 0.5);
        let mut got = vec![0.0; b.nu()];
        b.add_node_force(2, &f, &s, &mut got).unwrap();
        let exp = jt(&b, 2, &q, &u).transpose() * f;
        assert!((DVector::from_column_slice(&got) - &exp).norm() < 1e-12 * exp.norm());
        let mut jr = DMatrix::zeros(3, b.nu());
        b.node_jacobian_rotation(4, &s, faer_view_mut(&mut jr))
            .unwrap();
        let mut got = vec![0.0; b.nu()];
        b.add_node_torque(4, &f, &s, &mut got).unwrap();
        let exp = jr.transpose() * f;
        assert!((DVector::from_column_slice(&got) - &exp).norm() < 1e-12 * exp.norm());
    }
}

/// Mass matrix, Q_v, node Jacobians and node kinematics allocate nothing after the scratch exists.
#[test]
fn runtime_calls_do_not_allocate() {
    let mut seed = 12;
    let d = random_data(&mut seed, 6, 4, 0.3);
    let probe = allocations();
    let v = std::hint::black_box(vec![1.0f64; 16]);
    assert!(
        allocations() > probe && v.len() == 16,
        "the allocation counter works"
    );
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let b = body_of(&d, rot, true);
        let (q, u) = random_state(&mut seed, &b, 0.3);
        let mut s = FfrScratch::new(b.nf());
        let mut m = DMatrix::zeros(b.nu(), b.nu());
        let mut v = vec![0.0; b.nu()];
        let mut j3 = DMatrix::zeros(3, b.nu());
        let before = allocations();
        b.update(&q, &u, &mut s).unwrap();
        b.mass_matrix(&s, faer_view_mut(&mut m));
        b.quadratic_velocity(&s, &mut v);
        b.add_internal_forces(&s, &mut v);
        b.add_gravity_force(&s, &Vector3::new(0.0, 0.0, -9.81), &mut v);
        b.node_jacobian_translation(1, &s, faer_view_mut(&mut j3))
            .unwrap();
        b.node_jacobian_rotation(1, &s, faer_view_mut(&mut j3))
            .unwrap();
        b.node_kinematics(2, &q, &u, &s).unwrap();
        b.add_node_force(2, &Vector3::x(), &s, &mut v).unwrap();
        b.accelerations(&q, &u, &Vector3::zeros(), &mut s, &mut v)
            .unwrap();
        assert_eq!(allocations() - before, 0);
    }
}

/// Modal damping d_ii = 2 zeta_i omega_i for mass-normalised modes; Rayleigh alpha m + beta k;
/// non-diagonal matrices are rejected.
#[test]
fn damping_matrices() {
    let mut seed = 2;
    let d = random_data(&mut seed, 6, 2, 0.3);
    let mut b = body_of(&d, RotationParam::Quaternion, false);
    // make the modes mass-normalised and diagonal: replace m_ff/k_ff by diagonal values
    b.invariants.m_ff = DMatrix::identity(2, 2);
    b.k_ff = DMatrix::from_diagonal(&DVector::from_vec(vec![100.0, 400.0]));
    b.set_modal_damping(&[0.01, 0.02]).unwrap();
    assert!((b.d_ff[(0, 0)] - 2.0 * 0.01 * 10.0).abs() < 1e-15);
    assert!((b.d_ff[(1, 1)] - 2.0 * 0.02 * 20.0).abs() < 1e-15);
    assert_eq!(b.d_ff[(0, 1)], 0.0);
    b.set_rayleigh_damping(0.5, 0.001);
    assert!((b.d_ff[(1, 1)] - (0.5 + 0.4)).abs() < 1e-15);
    b.k_ff[(0, 1)] = 1.0;
    assert!(matches!(
        b.set_modal_damping(&[0.01, 0.02]),
        Err(FfrError::NotDiagonal { row: 0, col: 1, .. })
    ));
    assert!(matches!(
        b.set_modal_damping(&[0.01]),
        Err(FfrError::DimensionMismatch { .. })
    ));
}

/// Bad input gives typed errors: Cardan singularity, wrong lengths, node out of range, negative
/// mass, missing lumped masses.
#[test]
fn errors_are_reported() {
    let mut seed = 4;
    let d = random_data(&mut seed, 4, 1, 0.3);
    let b = body_of(&d, RotationParam::Cardan, false);
    let mut s = FfrScratch::new(1);
    let u = vec![0.0; 7];
    let q = vec![0.0, 0.0, 0.0, 0.1, std::f64::consts::FRAC_PI_2, 0.0, 0.0];
    assert!(matches!(
        b.update(&q, &u, &mut s),
        Err(FfrError::Rotation(_))
    ));
    assert!(matches!(
        b.update(&q[..5], &u, &mut s),
        Err(FfrError::DimensionMismatch { what: "q", .. })
    ));
    let q = vec![0.0; 7];
    b.update(&q, &u, &mut s).unwrap();
    assert!(matches!(
        b.node_kinematics(9, &q, &u, &s),
        Err(FfrError::NodeOutOfRange { node: 9, nodes: 4 })
    ));
    let mut m = d.masses.clone();
    m[1] = -1.0;
    assert!(matches!(
        FfrInvariants::from_lumped(&d.u0, &m, d.modes_t.as_ref()),
        Err(FfrError::InvalidMass { node: 1, .. })
    ));
    let rb = reduced(&d, flexmbs_fe::UnitSystem::Si, false);
    assert!(matches!(
        FfrBody::from_reduced(&rb, RotationParam::Cardan),
        Err(FfrError::MissingNodeMasses { .. })
    ));
}

fn reduced(
    d: &super::tests::Data,
    units: flexmbs_fe::UnitSystem,
    masses: bool,
) -> flexmbs_fe::reduction::ReducedBody {
    let nf = d.modes_t.ncols();
    let mut diag = faer::Mat::zeros(3 * d.u0.len(), 3 * d.u0.len());
    for i in 0..3 * d.u0.len() {
        diag[(i, i)] = d.masses[i / 3];
    }
    let m_red = d.modes_t.transpose() * &diag * &d.modes_t;
    flexmbs_fe::reduction::ReducedBody {
        name: "test".into(),
        units,
        nodes: d.u0.clone(),
        node_ids: (1..=d.u0.len() as u64).collect(),
        node_masses: masses.then(|| d.masses.clone()),
        modes_t: d.modes_t.clone(),
        modes_r: Some(d.modes_r.clone()),
        k_red: d.k.clone(),
        m_red,
        frequencies_hz: vec![1.0; nf],
        labels: vec![],
        interface_nodes: vec![],
        fixed_nodes: vec![],
        kind: flexmbs_fe::reduction::ReductionKind::Modal,
        cells: vec![],
        provenance: Default::default(),
    }
}

/// SI(mm) -> SI: positions x1e-3, masses x1e3, m_red equals Φ_si^T diag(m_si) Φ_si, the
/// generalized eigenvalues of (k_red, m_red) are unchanged, and the physical rigid-body mass
/// matrix at q_f = 0 scales as kg and kg m^2 (1e-12).
#[test]
fn reduced_body_si_conversion() {
    let mut seed = 6;
    let d = random_data(&mut seed, 5, 2, 0.3);
    let mm = reduced(&d, flexmbs_fe::UnitSystem::SiMm, true);
    let si = reduced_body_to_si(&mm);
    assert_eq!(si.units, flexmbs_fe::UnitSystem::Si);
    assert!((si.nodes[2][1] - 1e-3 * mm.nodes[2][1]).abs() < 1e-18);
    let m_si = si.node_masses.clone().unwrap();
    assert!((m_si[3] - 1e3 * d.masses[3]).abs() < 1e-12);
    let inv = FfrInvariants::from_lumped(&si.nodes, &m_si, si.modes_t.as_ref()).unwrap();
    for i in 0..2 {
        for j in 0..2 {
            assert!((inv.m_ff[(i, j)] - si.m_red[(i, j)]).abs() < 1e-12 * si.m_red[(0, 0)].abs());
        }
        // diagonal k (d.k) and m_red: Rayleigh quotients k_ii / m_ii are unit independent
        let ratio_mm = mm.k_red[(i, i)] / mm.m_red[(i, i)];
        let ratio_si = si.k_red[(i, i)] / si.m_red[(i, i)];
        assert!((ratio_mm - ratio_si).abs() < 1e-12 * ratio_mm);
    }
    let b_mm = FfrBody::from_reduced(&mm, RotationParam::Quaternion).unwrap();
    let b_si = FfrBody::from_reduced(&si, RotationParam::Quaternion).unwrap();
    assert!((b_si.invariants.i1 - 1e3 * b_mm.invariants.i1).abs() < 1e-12 * b_si.invariants.i1);
    let j_ratio = b_si.invariants.i_kl[(0, 0)] / b_mm.invariants.i_kl[(0, 0)];
    assert!((j_ratio - 1e3 * 1e-6).abs() < 1e-15);
    // rotational modes: Φ_r q gives the same rotation for q_si = q L / c
    let c = flexmbs_fe::UnitSystem::SiMm.mode_to_si();
    let q_mm = 0.37;
    let q_si = q_mm * 1e-3 / c;
    let rot_mm = mm.modes_r.as_ref().unwrap()[(4, 1)] * q_mm;
    let rot_si = si.modes_r.as_ref().unwrap()[(4, 1)] * q_si;
    assert!((rot_mm - rot_si).abs() < 1e-14);
    let _ = rnd;
}
