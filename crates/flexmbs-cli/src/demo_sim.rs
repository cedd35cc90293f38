//! The dynamic part of the main job: the reduced cantilever as an FFR body, clamped through a fixed
//! joint at its reference frame, under a tip force step; results as CSV, a plot and a ParaView
//! animation of the deformed mesh.

use anyhow::{Context, Result};
use flexmbs_core::ffr::{reduced_body_to_si, FfrBody, FfrElement, RotationParam};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{
    FrameKinematics, Joint, Load, LoadCoordinates, LocalFrame, ModelSpec, TimeFunction, Workspace,
};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::fmt::Write;
use std::path::Path;

/// Simulates 0.2 s of the cantilever under a 20 N tip force step in -z; writes `tip.csv`,
/// `tip.png` and `animation/cantilever.pvd`.
pub fn run(out: &Path, reduced: &ReducedBody, quiet: bool) -> Result<()> {
    let body = reduced_body_to_si(reduced);
    let tip = nearest(&body, [1.0, 0.01, 0.01]);
    let ffr = FfrBody::from_reduced(&body, RotationParam::Cardan)?;
    let element = FfrElement::new(ffr);
    let mut spec = ModelSpec::new();
    let b = spec.add_body("cantilever", element);
    let origin = spec.add_frame("origin", b, Vector3::zeros(), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    let tip_frame = spec.add_node_frame("tip", b, tip, Vector3::from(body.nodes[tip]));
    spec.add_joint(Joint::fixed("clamp", ground, origin));
    spec.add_load(Load::Force {
        frame: tip_frame,
        vector: Vector3::new(0.0, 0.0, -20.0),
        time: TimeFunction::Step {
            t0: 0.0,
            before: 0.0,
            after: 1.0,
        },
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile()?;
    let mut state = model.initial_state();
    let mut ws = Workspace::new(&model);
    let integrator = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.9,
        ..GenAlphaSettings::default()
    })?;
    integrator.initialize(&model, &mut state, &mut ws)?;
    let (h, t_end, every) = (2e-4, 0.2, 10usize);
    let nu = model.bodies[b.0].element.nu();
    let mut samples: Vec<(f64, Vec<f64>)> = vec![(0.0, model.body_q(b, &state.q).to_vec())];
    let mut step = 0usize;
    integrator
        .integrate(&model, &mut state, &mut ws, h, t_end, |s, _| {
            step += 1;
            if step.is_multiple_of(every) {
                samples.push((s.t, model.body_q(b, &s.q).to_vec()));
            }
        })
        .context("time integration of the cantilever")?;
    // tip displacement and animation from the node kinematics of the element
    let element = &model.bodies[b.0].element;
    let zero_u = vec![0.0; nu];
    let mut fk = FrameKinematics::new(nu);
    let mut csv = String::from("t,tip_ux,tip_uy,tip_uz\n");
    let mut tip_z = Vec::new();
    let anim = out.join("animation");
    std::fs::create_dir_all(anim.join("frames"))?;
    let mut pvd = Vec::new();
    for (i, (t, q)) in samples.iter().enumerate() {
        let mut points = Vec::with_capacity(body.nodes.len());
        let mut disp = Vec::with_capacity(3 * body.nodes.len());
        let mut eval = element.new_scratch();
        element
            .update_kinematics(q, &zero_u, &mut eval)
            .map_err(|e| anyhow::anyhow!("demo body cannot be evaluated at t = {t}: {e}"))?;
        for (n, x0) in body.nodes.iter().enumerate() {
            let frame = LocalFrame {
                position: Vector3::from(*x0),
                rotation: Matrix3::identity(),
                mesh_node: Some(n),
            };
            element.frame_kinematics(q, &zero_u, &mut eval, &frame, &mut fk);
            points.push([fk.position[0], fk.position[1], fk.position[2]]);
            disp.extend((0..3).map(|d| fk.position[d] - x0[d]));
        }
        let d = [
            points[tip][0] - body.nodes[tip][0],
            points[tip][1] - body.nodes[tip][1],
            points[tip][2] - body.nodes[tip][2],
        ];
        let _ = writeln!(csv, "{t:.6e},{:.9e},{:.9e},{:.9e}", d[0], d[1], d[2]);
        tip_z.push((t * 1e3, d[2] * 1e3));
        let name = format!("frames/step_{i:05}.vtu");
        flexmbs_io::vtk::write_vtu(
            &anim.join(&name),
            &points,
            &body.cells,
            &[("displacement", 3, &disp)],
            &[],
        )?;
        pvd.push((*t, name));
    }
    let entries: Vec<(f64, &str)> = pvd.iter().map(|(t, n)| (*t, n.as_str())).collect();
    flexmbs_io::vtk::write_pvd(&anim.join("cantilever.pvd"), &entries)?;
    std::fs::write(out.join("tip.csv"), csv)?;
    // static reference: P L^3 / (3 E I) = 20 / 8400 N/m (Guyan check in the tests)
    let w_static = -20.0 / (3.0 * 210e9 * 0.02f64.powi(4) / 12.0);
    LinePlot {
        title: "Cantilever FFR body: tip deflection under a 20 N step force".into(),
        x_label: "t [ms]".into(),
        y_label: "tip u_z [mm]".into(),
        series: vec![
            Series {
                name: "flexmbs (FFR, 12 modes, generalized-alpha)".into(),
                points: tip_z,
                style: Style::Line,
            },
            Series {
                name: "static deflection PL^3/3EI".into(),
                points: vec![(0.0, w_static * 1e3), (t_end * 1e3, w_static * 1e3)],
                style: Style::Line,
            },
        ],
        log_x: false,
        log_y: false,
    }
    .write(&out.join("tip.png"))?;
    if !quiet {
        eprintln!(
            "simulated {} steps; {} animation frames",
            step,
            samples.len()
        );
    }
    Ok(())
}

fn nearest(body: &ReducedBody, x: [f64; 3]) -> usize {
    let d = |p: &[f64; 3]| (0..3).map(|k| (p[k] - x[k]).powi(2)).sum::<f64>();
    (0..body.nodes.len())
        .min_by(|&a, &b| d(&body.nodes[a]).total_cmp(&d(&body.nodes[b])))
        .unwrap_or(0)
}
