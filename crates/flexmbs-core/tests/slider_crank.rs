//! Rigid slider-crank with prescribed crank rotation: slider position vs the analytic
//! x(phi) = r cos phi + sqrt(l^2 - r^2 sin^2 phi).
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

#[test]
fn slider_position_matches_analytic_solution() {
    let (r, l, w) = (0.1, 0.3, 2.0 * PI);
    let id = Matrix3::identity();
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let crank = spec.add_body("crank", RigidBody::new(1.0, id * 1e-3));
    let rod = spec.add_body(
        "rod",
        RigidBody::new(0.5, Matrix3::from_diagonal(&Vector3::new(1e-4, 4e-3, 4e-3))),
    );
    let slider = spec.add_body("slider", RigidBody::new(2.0, id * 1e-3));
    let origin = spec.add_ground_frame("origin", Vector3::zeros(), id);
    let crank_o = spec.add_frame("crank_o", crank, Vector3::new(-r / 2.0, 0.0, 0.0), id);
    let crank_tip = spec.add_frame("crank_tip", crank, Vector3::new(r / 2.0, 0.0, 0.0), id);
    let rod_a = spec.add_frame("rod_a", rod, Vector3::new(-l / 2.0, 0.0, 0.0), id);
    let rod_b = spec.add_frame("rod_b", rod, Vector3::new(l / 2.0, 0.0, 0.0), id);
    let slider_c = spec.add_frame("slider_c", slider, Vector3::zeros(), id);
    let drive = PrescribedMotion::RevoluteRate {
        initial_angle: 0.0,
        rate: TimeFunction::Constant(w),
    };
    spec.add_joint(Joint::revolute("crank_bearing", origin, crank_o).with_prescribed(drive));
    spec.add_joint(Joint::revolute("crank_rod", crank_tip, rod_a));
    spec.add_joint(Joint::prismatic("guide", origin, slider_c));
    // planar point coincidence (x, y only): a spatial revolute here would be redundant
    spec.add_joint(Joint::new(
        "rod_slider",
        slider_c,
        rod_b,
        [true, true, false, false, false, false],
    ));
    let model = spec.compile().unwrap();
    assert_eq!((model.nu, model.nc), (18, 18));
    let mut s = model.initial_state();
    let z = Vector3::z();
    model.set_body_pose(&mut s, crank, Vector3::new(r / 2.0, 0.0, 0.0), id);
    model.set_body_pose(&mut s, rod, Vector3::new(r + l / 2.0, 0.0, 0.0), id);
    model.set_body_pose(&mut s, slider, Vector3::new(r + l, 0.0, 0.0), id);
    model.set_body_velocity(&mut s, crank, Vector3::new(0.0, w * r / 2.0, 0.0), z * w);
    model.set_body_velocity(
        &mut s,
        rod,
        Vector3::new(0.0, w * r / 2.0, 0.0),
        z * (-w * r / l),
    );
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let h = 1e-3;
    let (mut max_err, mut g_max, mut gd_max): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut checks = 0;
    ga.integrate(&model, &mut s, &mut ws, h, 1.0, |s, st| {
        g_max = g_max.max(st.g_max);
        gd_max = gd_max.max(st.g_dot_max);
        let k = (s.t / h).round() as usize;
        if k.is_multiple_of(125) {
            let phi = w * s.t;
            let x = r * phi.cos() + (l * l - r * r * phi.sin().powi(2)).sqrt();
            max_err = max_err.max((model.body_q(slider, &s.q)[0] - x).abs());
            checks += 1;
        }
    })
    .unwrap();
    println!(
        "checks {checks}, max |x - x_exact| {max_err:e}, max |g| {g_max:e}, max |g_dot| {gd_max:e}"
    );
    assert_eq!(checks, 8);
    assert!(max_err < 1e-8);
    assert!(g_max < 1e-10);
    // The step monitor reuses the converged Newton evaluation (frames, constraints): its drift
    // and energies are bitwise those of a fresh `monitor` at the committed state; without
    // per-step energies the drift is unchanged and the energy field is zero.
    for on in [true, false] {
        let ga = ga.with_step_energy(on);
        for _ in 0..5 {
            let st = ga.step(&model, &mut s, &mut ws, h).unwrap();
            let (e, g, gd) = flexmbs_core::integrator::monitor(&model, &s, &mut ws);
            assert_eq!(st.g_max.to_bits(), g.to_bits());
            assert_eq!(st.g_dot_max.to_bits(), gd.to_bits());
            assert!(gd > 0.0 && e.kinetic > 0.0, "{gd} {e:?}");
            let expected = if on { e } else { system::Energy::default() };
            assert_eq!(st.energy, expected);
        }
    }
}
