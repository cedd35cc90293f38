//! Superelement dynamics: small free vibration of one clamped superelement (the tube of
//! `benchmarks.md`, 1 m, floating frame at the centre of mass, two internal Craig-Bampton modes)
//! started in its first mode, against the eigenfrequency of the linear Craig-Bampton model with
//! the first interface fixed (`det(K_ff − ω² M_ff) = 0` on the free coordinates of `K_CB`,
//! `M_CB`: no superelement kinematics involved).

use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{Joint, ModelSpec, NodeKind, Workspace};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{DMatrix, Matrix3, Rotation3, Vector3};

#[test]
fn clamped_superelement_vibrates_at_the_craig_bampton_frequency() {
    let modes = 2;
    let data = beam_segment(&BeamSegmentSpec {
        length: 1.0,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 8,
        internal_modes: modes,
        frame: FrameLocation::CentreOfMass,
    })
    .unwrap();
    // reference: lowest mode of the free coordinates (interface 1 and the internal modes)
    let free: Vec<usize> = (6..12 + modes).collect();
    let pick =
        |a: &DMatrix<f64>| DMatrix::from_fn(free.len(), free.len(), |i, j| a[(free[i], free[j])]);
    let (k, m) = (pick(&data.k_cb), pick(&data.m_cb));
    let l_inv = m.clone().cholesky().unwrap().l().try_inverse().unwrap();
    let eig = (&l_inv * &k * l_inv.transpose()).symmetric_eigen();
    let i_min = (0..free.len())
        .min_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]))
        .unwrap();
    let omega = eig.eigenvalues[i_min].sqrt();
    let shape = l_inv.transpose() * eig.eigenvectors.column(i_min);
    let period = 2.0 * std::f64::consts::PI / omega;
    println!(
        "reference: f = {:.6} Hz",
        omega / (2.0 * std::f64::consts::PI)
    );

    let mut spec = ModelSpec::new();
    let n0 = spec.add_node("n0", NodeKind::Pose);
    let eta = spec.add_node("eta", NodeKind::Vector(modes));
    let n1 = spec.add_node("n1", NodeKind::Pose);
    let body = spec.add_body_on("beam", Superelement::new(data).unwrap(), &[n0, eta, n1]);
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", n0, Vector3::zeros(), Matrix3::identity());
    let tip = spec.add_node_owned_frame("tip", n1, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        body,
        Vector3::new(0.5, 0.0, 0.0),
        Matrix3::identity(),
    );
    // start in the mode, tip amplitude 1e-2 m (geometric nonlinearity ~1e-4 in the frequency;
    // at 1e-4 m the elastic forces, ~K_CB eps |x| ~ 1e-9 N of round-off from the absolute
    // coordinates, sit above the Newton tolerance of the generalized-alpha residual)
    let scale = 1e-2 / shape.rows(0, 3).norm();
    let q = model.body_q_mut(body, &mut s.q);
    // node order n0 (7), eta (modes), n1 (7)
    let o = 7 + modes;
    for i in 0..3 {
        q[o + i] += scale * shape[i];
    }
    let r = Rotation3::from_scaled_axis(Vector3::new(shape[3], shape[4], shape[5]) * scale);
    let x_tip = Vector3::new(q[o], q[o + 1], q[o + 2]);
    NodeKind::Pose.set_pose(&mut q[o..o + 7], &x_tip, r.matrix());
    for i in 0..modes {
        q[7 + i] = scale * shape[6 + i];
    }
    let dir = Vector3::new(shape[0], shape[1], shape[2]).normalize();
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..Default::default()
    })
    .unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let h = period / 400.0;
    let mut crossings = Vec::new();
    let (mut t_last, mut y_last) = (0.0, 1.0);
    ga.integrate(&model, &mut s, &mut ws, h, 3.2 * period, |st, _| {
        let k = model.frame_kinematics(st, tip).unwrap();
        let y = (k.position - Vector3::new(1.0, 0.0, 0.0)).dot(&dir);
        if y_last > 0.0 && y <= 0.0 {
            crossings.push(t_last + (st.t - t_last) * y_last / (y_last - y));
        }
        (t_last, y_last) = (st.t, y);
    })
    .unwrap();
    let measured = (crossings[2] - crossings[0]) / 2.0;
    println!(
        "period {measured:.8} s, reference {period:.8} s, rel {:e}",
        measured / period - 1.0
    );
    assert!((measured / period - 1.0).abs() < 1e-3);
}

/// A free superelement (0.5 m tube, two internal modes) tumbling at 20-30 rad/s while it
/// vibrates, 0.02 s, generalized-alpha with `rho_inf = 1`. Neglecting the fictitious forces, the
/// energy `T + V` drifts by 1.1e-3 (h = 1e-4) and 2.1e-4 (h = 1e-5, 2e-5 likewise: the limit of
/// a non-conservative model). With [`FictitiousForces::FromMcb`] the model is conservative (power
/// identity and rigid-body limit in the unit tests) but stiff (gyroscopic coupling of the small
/// rotary inertia of the interface rotations): 0.13 at h = 1e-4, 5.9e-3 at 2e-5, 2.0e-3 at 1e-5,
/// (1.1e-3 at 5e-6 over 0.05 s), falling with the step.
#[test]
fn fictitious_forces_from_mcb_conserve_energy() {
    use flexmbs_core::superelement::FictitiousForces;
    use flexmbs_core::Element;
    let modes = 2;
    let data = beam_segment(&BeamSegmentSpec {
        length: 0.5,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 4,
        internal_modes: modes,
        frame: FrameLocation::CentreOfMass,
    })
    .unwrap();
    let mut drift = Vec::new();
    for (fictitious, h) in [
        (FictitiousForces::Neglected, 1e-4),
        (FictitiousForces::Neglected, 1e-5),
        (FictitiousForces::FromMcb, 2e-5),
        (FictitiousForces::FromMcb, 1e-5),
    ] {
        let se = Superelement::new(data.clone())
            .unwrap()
            .with_fictitious_forces(fictitious);
        let mut spec = ModelSpec::new();
        let body = spec.add_body("beam", se.clone());
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(&mut s, body, Vector3::zeros(), Matrix3::identity());
        {
            let q = model.body_q_mut(body, &mut s.q);
            q[1] += 2e-3; // first interface displaced across the beam
            q[7] = 1e-3; // internal mode amplitudes
            q[8] = -5e-4;
        }
        model.set_body_velocity(
            &mut s,
            body,
            Vector3::zeros(),
            Vector3::new(5.0, 30.0, 20.0),
        );
        let energy = |q: &[f64], u: &[f64]| {
            let mut e = se.evaluated(q, u).unwrap();
            se.kinetic_energy(q, u, &mut e) + se.elastic_energy(q)
        };
        let e0 = energy(model.body_q(body, &s.q), model.body_u(body, &s.u));
        let mut ws = Workspace::new(&model);
        let ga = GenAlpha::new(GenAlphaSettings {
            rho_inf: 1.0,
            ..Default::default()
        })
        .unwrap();
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        let mut worst: f64 = 0.0;
        ga.integrate(&model, &mut s, &mut ws, h, 0.02, |st, _| {
            let e = energy(model.body_q(body, &st.q), model.body_u(body, &st.u));
            worst = worst.max((e - e0).abs() / e0);
        })
        .unwrap();
        println!("{fictitious:?} h {h:e}: E0 {e0:.6} J, max |E - E0| / E0 = {worst:.3e}");
        drift.push(worst);
    }
    // neglected: the drift tends to a limit as h -> 0 (the model is not conservative)
    assert!(drift[1] < 5e-4 && drift[1] > 1e-4, "neglected: {drift:?}");
    // from M_CB: conservative, the drift is the integrator's and falls with h
    assert!(
        drift[3] < 0.5 * drift[2] && drift[3] < 3e-3,
        "from M_CB: {drift:?}"
    );
}

/// The same clamped tube (lumped FE mass, two internal modes) as one superelement and as one FFR
/// body with the same FE model and modes (the superelement's free Craig-Bampton coordinates as
/// FFR modes: tip static modes and internal modes, node masses and rotary inertias of the lumped
/// FE mass), both started in the first mode with a tip amplitude of 1e-2 m: the tip deflections
/// agree to 1e-3 of the amplitude over three periods.
#[test]
fn clamped_superelement_matches_the_ffr_body_of_the_same_modes() {
    use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam};
    use flexmbs_core::superelement::beam_segment_basis;
    use flexmbs_fe::element::MassKind;
    let (modes, ne, l) = (2, 8, 1.0);
    let (data, v, m_fe) = beam_segment_basis(
        &BeamSegmentSpec {
            length: l,
            material: Material {
                e: 70e9,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: ne,
            internal_modes: modes,
            frame: FrameLocation::CentreOfMass,
        },
        MassKind::Lumped,
    )
    .unwrap();
    // the lowest mode of the free coordinates (tip interface and internal modes)
    let free: Vec<usize> = (6..12 + modes).collect();
    let nf = free.len();
    let pick = |a: &DMatrix<f64>| DMatrix::from_fn(nf, nf, |i, j| a[(free[i], free[j])]);
    let (k, m) = (pick(&data.k_cb), pick(&data.m_cb));
    let l_inv = m.clone().cholesky().unwrap().l().try_inverse().unwrap();
    let eig = (&l_inv * &k * l_inv.transpose()).symmetric_eigen();
    let i_min = (0..nf)
        .min_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]))
        .unwrap();
    let period = 2.0 * std::f64::consts::PI / eig.eigenvalues[i_min].sqrt();
    let shape = l_inv.transpose() * eig.eigenvectors.column(i_min);
    let scale = 1e-2 / shape.rows(0, 3).norm();
    let dir = Vector3::new(shape[0], shape[1], shape[2]).normalize();
    let h = period / 400.0;
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..Default::default()
    })
    .unwrap();

    // superelement
    let y_se = {
        let mut spec = ModelSpec::new();
        let n0 = spec.add_node("n0", NodeKind::Pose);
        let eta = spec.add_node("eta", NodeKind::Vector(modes));
        let n1 = spec.add_node("n1", NodeKind::Pose);
        let body = spec.add_body_on("beam", Superelement::new(data).unwrap(), &[n0, eta, n1]);
        let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
        let root = spec.add_node_owned_frame("root", n0, Vector3::zeros(), Matrix3::identity());
        let tip = spec.add_node_owned_frame("tip", n1, Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::fixed("clamp", ground, root));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(
            &mut s,
            body,
            Vector3::new(0.5 * l, 0.0, 0.0),
            Matrix3::identity(),
        );
        let q = model.body_q_mut(body, &mut s.q);
        let o = 7 + modes;
        let x_tip = Vector3::new(q[o], q[o + 1], q[o + 2]) + scale * shape.fixed_rows::<3>(0);
        let r = Rotation3::from_scaled_axis(shape.fixed_rows::<3>(3) * scale);
        NodeKind::Pose.set_pose(&mut q[o..o + 7], &x_tip, r.matrix());
        for i in 0..modes {
            q[7 + i] = scale * shape[6 + i];
        }
        let mut ws = Workspace::new(&model);
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        let mut y = vec![];
        ga.integrate(&model, &mut s, &mut ws, h, 3.0 * period, |st, _| {
            let k = model.frame_kinematics(st, tip).unwrap();
            y.push((k.position - Vector3::new(l, 0.0, 0.0)).dot(&dir));
        })
        .unwrap();
        y
    };

    // FFR body: frame at the clamp, modes = the free columns of the Craig-Bampton basis
    let y_ffr = {
        let nodes: Vec<[f64; 3]> = (0..=ne)
            .map(|i| [l * i as f64 / ne as f64, 0.0, 0.0])
            .collect();
        let modes_t =
            faer::Mat::from_fn(3 * (ne + 1), nf, |r, c| v[(6 * (r / 3) + r % 3, free[c])]);
        let modes_r = faer::Mat::from_fn(3 * (ne + 1), nf, |r, c| {
            v[(6 * (r / 3) + 3 + r % 3, free[c])]
        });
        let k_ff = faer::Mat::from_fn(nf, nf, |i, j| k[(i, j)]);
        let masses: Vec<f64> = (0..=ne).map(|i| m_fe[(6 * i, 6 * i)]).collect();
        let rotary: Vec<Matrix3<f64>> = (0..=ne)
            .map(|i| Matrix3::from_fn(|a, b| m_fe[(6 * i + 3 + a, 6 * i + 3 + b)]))
            .collect();
        let inv = FfrInvariants::from_lumped(&nodes, &masses, modes_t.as_ref()).unwrap();
        let mut body = FfrBody::new(
            inv,
            RotationParam::Quaternion,
            &nodes,
            modes_t.as_ref(),
            Some(modes_r.as_ref()),
            k_ff.as_ref(),
        )
        .unwrap();
        body.set_rotary_inertia(&rotary).unwrap();
        let mut spec = ModelSpec::new();
        let b = spec.add_body("beam", FfrElement::new(body));
        let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
        let root = spec.add_frame("root", b, Vector3::zeros(), Matrix3::identity());
        let tip = spec.add_node_frame("tip", b, ne, Vector3::new(l, 0.0, 0.0));
        spec.add_joint(Joint::fixed("clamp", ground, root));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        let q = model.body_q_mut(b, &mut s.q);
        for i in 0..nf {
            q[7 + i] = scale * shape[i];
        }
        let mut ws = Workspace::new(&model);
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        let mut y = vec![];
        ga.integrate(&model, &mut s, &mut ws, h, 3.0 * period, |st, _| {
            let k = model.frame_kinematics(st, tip).unwrap();
            y.push((k.position - Vector3::new(l, 0.0, 0.0)).dot(&dir));
        })
        .unwrap();
        y
    };
    assert_eq!(y_se.len(), y_ffr.len());
    let dev = y_se
        .iter()
        .zip(&y_ffr)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let amp = y_ffr.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    println!(
        "max |y_se - y_ffr| = {dev:e} m, amplitude {amp:e} m, rel {:e}",
        dev / amp
    );
    assert!(dev < 1e-3 * amp, "{dev:e} vs amplitude {amp:e}");
}
