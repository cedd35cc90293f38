//! The flexmbs models of `slider_crank_3d` (seed 001 §5.1): rigid crank driven at a prescribed
//! 150 rad/s (revolute joint to ground), the connecting rod joined to the crank pin by a
//! **spherical** joint and to the slider by a **universal** joint (slider-fixed pin vertical, the
//! rod's pin along its local y), the slider on a frictionless **prismatic** guide along the global
//! x axis. The rod as a chain of superelements, as one FFR body (optionally with geometric
//! stiffening under its end loads), or rigid (kinematics check). The crank geometry is a
//! [`Crank`]: the spatial case (axis along x, offset horizontally by d) or the planar one of
//! `slider_crank_2d` (axis along z through the origin).

use crate::slider_crank_3d_reference::{local_y, Crank};
use anyhow::{Context, Result};
use flexmbs_core::ffr::{FfrBody, FfrElement, LoadStiffening, RotationParam};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{
    BodyId, FrameId, Joint, Model, ModelSpec, NodeKind, PrescribedMotion, RigidBody, State,
    TimeFunction, Workspace,
};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::InertialLoad;
use flexmbs_fe::geometric_loads::{load_geometric_stiffness, NodeLoad, UnitLoad};
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Crank length (m).
pub const CRANK: f64 = 0.15;
/// Rod length (m).
pub const ROD: f64 = 0.3;
/// Crank angular velocity (rad/s).
pub const OMEGA: f64 = 150.0;
/// Rod diameter (m).
pub const DIAMETER: f64 = 0.006;
/// FE beam elements of the FFR rod.
const FFR_ELEMENTS: usize = 20;

/// The rod's material (E = 200 GPa, nu = 0.3, rho = 7870 kg/m³).
pub fn material() -> Material {
    Material {
        e: 200e9,
        nu: 0.3,
        rho: 7870.0,
    }
}

/// Rod mass (kg).
pub fn rod_mass() -> f64 {
    material().rho * PI * DIAMETER * DIAMETER / 4.0 * ROD
}

/// The spatial crank (seed 001 Fig. 5.4, **assumed** geometry): rotation axis along global x
/// through `(0, d, 0)` (offset horizontally by `d` from the slider's guide line, the x axis),
/// the crank vertical (pointing up, +z) at angle 0, turning towards -y.
pub fn spatial_crank(d: f64) -> Crank {
    Crank {
        centre: Vector3::new(0.0, d, 0.0),
        e1: Vector3::z(),
        e2: -Vector3::y(),
        radius: CRANK,
        omega: OMEGA,
    }
}

/// The planar crank of `slider_crank_2d`: axis along z through the origin, along +x at angle 0.
pub fn planar_crank() -> Crank {
    Crank {
        centre: Vector3::zeros(),
        e1: Vector3::x(),
        e2: Vector3::y(),
        radius: CRANK,
        omega: OMEGA,
    }
}

/// How the connecting rod is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rod {
    /// A chain of `n` (even) equal superelements (2 FE beam elements each, floating frame at the
    /// centre of mass, exact matrices, static modes only).
    Superelements(usize),
    /// One FFR body with `modes` free-free modes of 20 beam elements (lumped mass), with
    /// geometric stiffening under its end loads if `stiffened` (as `slider_crank_2d`).
    Ffr {
        /// Free-free modes.
        modes: usize,
        /// Load stiffening on.
        stiffened: bool,
    },
    /// A rigid rod (slender, uniform).
    Rigid,
}

/// Samples of a run, one per step from `t = 0`.
#[derive(Debug, Clone, Default)]
pub struct Run {
    /// Crank angle (rad).
    pub theta: Vec<f64>,
    /// Rod midpoint deflection along the rod's local y ([`local_y`] of the pin-slider chord).
    pub w_y: Vec<f64>,
    /// Along local z = chord x local y.
    pub w_z: Vec<f64>,
    /// Slider position along the guide (m).
    pub slider_x: Vec<f64>,
    /// Largest position-constraint violation over the run.
    pub g_max: f64,
}

/// The rigid-mechanism pose of the rod at angle 0: end A (pin), unit axis, rotation (columns:
/// axis, local y, local z) and the velocity of A and the angular velocity (spin about the axis
/// from the universal joint: the rod's pin stays horizontal).
struct RodStart {
    a: Vector3<f64>,
    t: Vector3<f64>,
    rot: Matrix3<f64>,
    va: Vector3<f64>,
    omega: Vector3<f64>,
}

fn rod_start(crank: &Crank) -> RodStart {
    let (a, va) = crank.pin(0.0);
    let (xs, vs) = crank.rigid_slider(ROD, 0.0);
    let t = (Vector3::new(xs, 0.0, 0.0) - a) / ROD;
    let y = local_y(&t);
    let rot = Matrix3::from_columns(&[t, y, t.cross(&y)]);
    let perp = t.cross(&(Vector3::new(vs, 0.0, 0.0) - va)) / ROD;
    // d/dt (z . y_rod) = 0: (omega x y) . z = omega . (y x z) = 0
    let w = y.cross(&Vector3::z());
    let spin = -perp.dot(&w) / t.dot(&w);
    RodStart {
        a,
        t,
        rot,
        va,
        omega: perp + t * spin,
    }
}

/// Orientation of the rod's universal-joint frame relative to its end (node or body) axes: the
/// frame's x = the rod's local y (the rod's pin).
fn universal_frame_rotation() -> Matrix3<f64> {
    Matrix3::from_columns(&[Vector3::y(), Vector3::z(), Vector3::x()])
}

/// The model with the rod as `rod` at crank angle 0 with the rigid-mechanism velocities, and
/// the frames at the rod's end A, end B, midpoint, and the slider.
pub fn build(crank: &Crank, rod: Rod) -> Result<(Model, State, [FrameId; 4])> {
    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let axes = Matrix3::from_columns(&[crank.e1, crank.e2, crank.e1.cross(&crank.e2)]);
    let crank_body = spec.add_body(
        "crank",
        RigidBody::new(0.1, Matrix3::from_diagonal(&Vector3::new(1e-5, 2e-4, 2e-4)))
            .with_rotation(RotationParam::Quaternion),
    );
    let slider = spec.add_body(
        "slider",
        RigidBody::new(0.5 * rod_mass(), i3 * 1e-6).with_rotation(RotationParam::Quaternion),
    );
    let g0 = spec.add_ground_frame("pivot", crank.centre, axes);
    let gs = spec.add_ground_frame("guide", Vector3::zeros(), i3);
    let c0 = spec.add_frame(
        "crank pivot",
        crank_body,
        Vector3::new(-CRANK / 2.0, 0.0, 0.0),
        i3,
    );
    let c1 = spec.add_frame(
        "crank pin",
        crank_body,
        Vector3::new(CRANK / 2.0, 0.0, 0.0),
        i3,
    );
    let s0 = spec.add_frame("slider", slider, Vector3::zeros(), i3);
    let start = rod_start(crank);
    let uv = universal_frame_rotation();
    let (rod_bodies, frames) = match rod {
        Rod::Superelements(n) => add_superelement_rod(&mut spec, n, uv)?,
        Rod::Ffr { modes, stiffened } => add_ffr_rod(&mut spec, modes, stiffened, uv)?,
        Rod::Rigid => {
            let m = rod_mass();
            let j = m * ROD * ROD / 12.0;
            let b = spec.add_body(
                "rod",
                RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(1e-3 * j, j, j)))
                    .with_rotation(RotationParam::Quaternion),
            );
            let h = ROD / 2.0;
            let f = [
                spec.add_frame("rod A", b, Vector3::new(-h, 0.0, 0.0), i3),
                spec.add_frame("rod B", b, Vector3::new(h, 0.0, 0.0), uv),
                spec.add_frame("rod mid", b, Vector3::zeros(), i3),
            ];
            (vec![(b, h)], f)
        }
    };
    let [ra, rb, rm] = frames;
    spec.add_joint(Joint::revolute("crank drive", g0, c0).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(crank.omega),
        },
    ));
    spec.add_joint(Joint::spherical("crank-rod", c1, ra));
    // universal: e_z(slider) . e_x(rod frame) = 0 (the locked ry row)
    spec.add_joint(Joint::new(
        "rod-slider",
        s0,
        rb,
        [true, true, true, false, true, false],
    ));
    spec.add_joint(Joint::prismatic("slider guide", gs, s0));
    let model = spec.compile()?;
    let mut s = model.initial_state();
    let (xs, vs) = crank.rigid_slider(ROD, 0.0);
    model.set_body_pose(
        &mut s,
        crank_body,
        crank.centre + axes * Vector3::new(CRANK / 2.0, 0.0, 0.0),
        axes,
    );
    model.set_body_velocity(
        &mut s,
        crank_body,
        crank.e2 * (crank.omega * CRANK / 2.0),
        axes.column(2) * crank.omega,
    );
    model.set_body_pose(&mut s, slider, Vector3::new(xs, 0.0, 0.0), i3);
    model.set_body_velocity(&mut s, slider, Vector3::new(vs, 0.0, 0.0), Vector3::zeros());
    for (b, x) in rod_bodies {
        let r = start.t * x;
        model.set_body_pose(&mut s, b, start.a + r, start.rot);
        model.set_body_velocity(&mut s, b, start.va + start.omega.cross(&r), start.omega);
    }
    Ok((model, s, [ra, rb, rm, s0]))
}

type RodParts = (Vec<(BodyId, f64)>, [FrameId; 3]);

/// `n` superelements on shared pose nodes; bodies with the distance of their reference origin
/// (centre) from end A.
fn add_superelement_rod(spec: &mut ModelSpec, n: usize, uv: Matrix3<f64>) -> Result<RodParts> {
    anyhow::ensure!(
        n >= 2 && n.is_multiple_of(2),
        "the midpoint must be an interface node: an even number of bodies (got {n})"
    );
    let l = ROD / n as f64;
    let nodes: Vec<_> = (0..=n)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let mut bodies = Vec::new();
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: l,
            material: material(),
            section: BeamSection::circle(DIAMETER),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: 0,
            frame: FrameLocation::CentreOfMass,
        })?;
        let b = spec.add_body_on(
            &format!("rod{i}"),
            Superelement::new(data)?,
            &nodes[i..i + 2],
        );
        bodies.push((b, (i as f64 + 0.5) * l));
    }
    let i3 = Matrix3::identity();
    let frames = [
        spec.add_node_owned_frame("rod A", nodes[0], Vector3::zeros(), i3),
        spec.add_node_owned_frame("rod B", nodes[n], Vector3::zeros(), uv),
        spec.add_node_owned_frame("rod mid", nodes[n / 2], Vector3::zeros(), i3),
    ];
    Ok((bodies, frames))
}

/// One FFR body (20 Euler-Bernoulli elements along x from end A, lumped mass, `modes` free-free
/// modes, unit quaternion), stiffened as in `slider_crank_2d` if asked.
fn add_ffr_rod(
    spec: &mut ModelSpec,
    modes: usize,
    stiffened: bool,
    uv: Matrix3<f64>,
) -> Result<RodParts> {
    let mesh = beam_line(
        [0.0; 3],
        [ROD, 0.0, 0.0],
        FFR_ELEMENTS,
        BeamSection::circle(DIAMETER),
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        material(),
        UnitSystem::Si,
    )?;
    let sys = FeSystem::assemble(
        &mesh,
        &BoundaryConditions::default(),
        MassKind::Lumped,
        &mut |_, _| {},
    )?;
    let modal = modal_analysis(&sys, modes, &EigenOptions::default(), &mut |_| {})?;
    let body = reduce_modal(&mesh, &sys, &modal, modes, "rod", Provenance::default())?;
    let mut ffr = FfrBody::from_reduced(&body, RotationParam::Quaternion)?;
    if stiffened {
        let mut patterns = Vec::new();
        for node in [0, FFR_ELEMENTS] {
            for axis in 0..3 {
                patterns.push(UnitLoad::Node(NodeLoad::Force { node, axis }));
                patterns.push(UnitLoad::Node(NodeLoad::Moment { node, axis }));
            }
        }
        patterns.extend(
            InertialLoad::centrifugal()
                .into_iter()
                .map(UnitLoad::Inertial),
        );
        let g = load_geometric_stiffness(&mesh, &sys, &body, MassKind::Lumped, &patterns)?;
        ffr = ffr
            .with_load_stiffening(LoadStiffening::from_fe(&g.without_centrifugal(), modes)?)?
            .with_geometric_stiffening(&g.centrifugal())?;
    }
    let b = spec.add_body("rod", FfrElement::new(ffr));
    let node = |i: usize| Vector3::from(body.nodes[i]);
    let frames = [
        spec.add_node_frame("rod A", b, 0, node(0)),
        spec.add_oriented_node_frame("rod B", b, FFR_ELEMENTS, node(FFR_ELEMENTS), uv),
        spec.add_node_frame("rod mid", b, FFR_ELEMENTS / 2, node(FFR_ELEMENTS / 2)),
    ];
    Ok((vec![(b, 0.0)], frames))
}

/// Simulates `revolutions` crank revolutions of `rod` on `crank` with generalized-alpha
/// (`rho_inf = 0.8`, full Newton, step `h`), sampling every step.
pub fn simulate(crank: &Crank, rod: Rod, h: f64, revolutions: f64) -> Result<Run> {
    let (model, mut s, [a, b, m, sl]) = build(crank, rod)?;
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.8,
        ..GenAlphaSettings::default()
    })?;
    ga.initialize(&model, &mut s, &mut ws)?;
    let mut run = Run::default();
    let mut failed = false;
    let mut sample = |st: &State, run: &mut Run| {
        let k = [a, b, m, sl].map(|f| model.frame_kinematics(st, f));
        let [Some(a), Some(b), Some(m), Some(sl)] = k else {
            failed = true;
            return;
        };
        let chord = (b.position - a.position).normalize();
        let y = local_y(&chord);
        let d = m.position - a.position;
        run.theta.push(crank.omega * st.t);
        run.w_y.push(d.dot(&y));
        run.w_z.push(d.dot(&chord.cross(&y)));
        run.slider_x.push(sl.position[0]);
    };
    sample(&s, &mut run);
    ga.integrate(
        &model,
        &mut s,
        &mut ws,
        h,
        revolutions * 2.0 * PI / crank.omega,
        |st, stats| {
            run.g_max = run.g_max.max(stats.g_max);
            sample(st, &mut run);
        },
    )
    .with_context(|| format!("time integration of the 3D slider-crank, rod {rod:?}"))?;
    anyhow::ensure!(!failed, "frame kinematics failed");
    Ok(run)
}
