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
