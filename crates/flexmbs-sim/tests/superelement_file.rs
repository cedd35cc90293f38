//! Superelement beams in model files (`type = "superelement_beam"`): the model a file builds is
//! the chain the validation cases build in Rust (`flexmbs-validate` `cantilever_static`,
//! `cantilever_transient`: nodes, bodies, fixed joint), so statics and generalized-alpha give the
//! same numbers; the static cantilever meets the elastica; rigid bodies joint to interface
//! points; bad input is refused with key paths.

use crate::common;

use flexmbs_core::integrator::{self, GenAlpha, GenAlphaStepper, Statics, StaticsStepper, Stepper};
use flexmbs_core::superelement::{
    beam_segment, BeamSegmentSpec, FictitiousForces, FrameLocation, Superelement, TransformMatrices,
};
use flexmbs_core::{
    FrameId, Joint, Load, LoadCoordinates, Model, ModelSpec, NodeKind, State, TimeFunction,
    Workspace,
};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::compile::SolverConfig;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, CompiledModel};
use nalgebra::{Matrix3, Vector3};
use std::ops::ControlFlow;
use std::path::Path;

const E: f64 = 70e9;

/// The static cantilever of `validation/cantilever_static`: 10 equal superelements of the tube,
/// clamped at the start, 1000 N down at the tip.
const CANTILEVER: &str = r#"
[model]
name = "se_cantilever"

[solver]
type = "statics"
load_steps = 20

[[body]]
name = "beam"
type = "superelement_beam"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
length = "1 m"
segments = 10
fixed = ["i0"]

[[load]]
type = "force"
frame = "beam.i10"
vector = [0, "-1 kN", 0]

[output]
signals = ["beam.i10.position", "beam.s9.deformation", "beam.s9.frame_iterations"]
animation = false
"#;

fn file() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/superelement.toml")
}

fn compiled(text: &str) -> CompiledModel {
    compile_model(text, &file()).unwrap_or_else(|e| panic!("{e}"))
}

/// Options of a Rust-built chain.
#[derive(Clone, Copy)]
struct ChainOptions {
    n: usize,
    internal_modes: usize,
    frame: FrameLocation,
    matrices: TransformMatrices,
    fictitious: FictitiousForces,
}

const VALIDATION_CHAIN: ChainOptions = ChainOptions {
    n: 10,
    internal_modes: 0,
    frame: FrameLocation::CentreOfMass,
    matrices: TransformMatrices::Exact,
    fictitious: FictitiousForces::Neglected,
};

/// The Rust-built chain of the validation cases: `n` equal tube superelements on shared pose
/// nodes (internal-mode nodes between their interface nodes), a ground frame and a fixed joint
/// at node 0, a force `force(t)` down at the tip.
fn rust_chain(o: ChainOptions, force: f64, time: TimeFunction) -> (Model, FrameId) {
    let n = o.n;
    let mut spec = ModelSpec::new();
    let mut nodes = vec![spec.add_node("n0", NodeKind::Pose)];
    let mut bodies = Vec::new();
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: 1.0 / n as f64,
            material: Material {
                e: E,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: o.internal_modes,
            frame: o.frame,
        })
        .unwrap();
        let se = Superelement::new(data)
            .unwrap()
            .with_matrices(o.matrices)
            .with_fictitious_forces(o.fictitious);
        let mut on = vec![nodes[i]];
        if o.internal_modes > 0 {
            on.push(spec.add_node(&format!("eta{i}"), NodeKind::Vector(o.internal_modes)));
        }
        nodes.push(spec.add_node(&format!("n{}", i + 1), NodeKind::Pose));
        on.push(nodes[i + 1]);
        bodies.push(spec.add_body_on(&format!("b{i}"), se, &on));
    }
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), Matrix3::identity());
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -force, 0.0),
        time,
        coordinates: LoadCoordinates::Global,
    });
    let l = 1.0 / n as f64;
    let mut x = 0.0;
    for b in &bodies {
        let origin = match o.frame {
            FrameLocation::CentreOfMass => x + 0.5 * l,
            FrameLocation::FirstInterface => x,
        };
        spec.set_initial_pose(*b, Vector3::new(origin, 0.0, 0.0), Matrix3::identity());
        x += l;
    }
    (spec.compile().unwrap(), tip)
}

/// Statics (the runner's stepper and driver) on `model` from its initial state: the tip
/// position after every load increment.
fn statics_path(cm: &CompiledModel, model: &Model, tip: FrameId) -> Vec<Vector3<f64>> {
    let SolverConfig::Statics { settings } = cm.solver else {
        panic!("not statics")
    };
    let mut s = model.initial_state();
    let mut ws = Workspace::with_linear_solver(model, cm.linear_solver);
    let solver = Statics::new(settings);
    let mut stepper = StaticsStepper::new(solver);
    stepper.initialize(model, &mut s, &mut ws).unwrap();
    let mut path = Vec::new();
    integrator::drive(
        &mut stepper,
        model,
        &mut s,
        &mut ws,
        solver.control(),
        1.0,
        |st, _| {
            path.push(model.frame_kinematics(st, tip).unwrap().position);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    path
}

/// Generalized-alpha (the runner's stepper and driver) on `model`: the tip position at every
/// step, the initial state first.
fn dynamic_path(cm: &CompiledModel, model: &Model, tip: FrameId) -> Vec<Vector3<f64>> {
    let SolverConfig::GenAlpha {
        settings, h, t_end, ..
    } = cm.solver
    else {
        panic!("not generalized-alpha")
    };
    let mut s: State = model.initial_state();
    let mut ws = Workspace::with_linear_solver(model, cm.linear_solver);
    let ga = GenAlpha::new(settings).unwrap().with_step_energy(false);
    let mut stepper = GenAlphaStepper::new(ga, None);
    stepper.initialize(model, &mut s, &mut ws).unwrap();
    let control = stepper.control(h);
    let mut path = vec![model.frame_kinematics(&s, tip).unwrap().position];
    integrator::drive(
        &mut stepper,
        model,
        &mut s,
        &mut ws,
        control,
        t_end,
        |st, _| {
            path.push(model.frame_kinematics(st, tip).unwrap().position);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    path
}

fn max_rel_diff(a: &[Vector3<f64>], b: &[Vector3<f64>], scale: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).amax() / scale)
        .fold(0.0, f64::max)
}

/// The file's cantilever is the validation case's chain: the static path equals the Rust-built
/// one to 1e-10 relative (in fact bitwise), the runner writes the same tip, and the tip at 1000 N
/// is within 0.5 % of the inextensible elastica (`flexmbs_validate::elastica`, no code shared
/// with the superelement).
#[test]
fn static_cantilever_equals_rust_chain_and_elastica() {
    let cm = compiled(CANTILEVER);
    let tip = cm.model.frame_id("beam.i10").unwrap();
    let from_file = statics_path(&cm, &cm.model, tip);
    let (rust, rust_tip) = rust_chain(VALIDATION_CHAIN, 1000.0, TimeFunction::Constant(1.0));
    let reference = statics_path(&cm, &rust, rust_tip);
    let last = *reference.last().unwrap();
    let scale = (last - Vector3::x()).amax();
    let diff = max_rel_diff(&from_file, &reference, scale);
    eprintln!("static: file vs Rust chain {diff:e} relative");
    assert!(diff <= 1e-10, "file vs Rust chain: {diff:e} relative");
    let ei = E * BeamSection::tube(0.01, 0.001).iz;
    let (u, v) = flexmbs_validate::elastica::elastica_elliptic(1000.0, 1.0, ei);
    let (u_se, v_se) = (1.0 - last.x, -last.y);
    assert!(((u_se - u) / u).abs() < 5e-3, "u {u_se} vs elastica {u}");
    assert!(((v_se - v) / v).abs() < 5e-3, "v {v_se} vs elastica {v}");
    eprintln!("tip u {u_se} (elastica {u}), v {v_se} (elastica {v})");
    // the runner: one row per load increment, the same tip, the signals of the superelement
    let out = common::work_dir("se", "static");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let y = r.series("beam.i10.position.y").unwrap().to_vec();
    assert_eq!(y.len(), reference.len());
    for (a, b) in y.iter().zip(&reference) {
        assert!((a - b.y).abs() <= 1e-10 * scale, "runner {a} vs {}", b.y);
    }
    // the last superelement's tip interface: its local deflection is a fraction of the tip's
    let w = r.series("beam.s9.deformation.u1_y").unwrap();
    let w_last = *w.last().unwrap();
    assert!(
        w_last < 0.0 && w_last.abs() < 0.1 * v,
        "local deflection {w_last}"
    );
    let it = r.series("beam.s9.frame_iterations.value").unwrap();
    assert!(it.iter().all(|&k| (1.0..=30.0).contains(&k)), "{it:?}");
    let _ = std::fs::remove_dir_all(&out);
}

/// The cantilever with a 2 ms tip pulse of 100 N under generalized-alpha until `t_end`.
fn vibration_text(t_end: &str) -> String {
    CANTILEVER
        .replace(
            "type = \"statics\"\nload_steps = 20",
            &format!("type = \"generalized-alpha\"\nh = \"0.1 ms\"\nt_end = \"{t_end}\""),
        )
        .replace(
            "vector = [0, \"-1 kN\", 0]",
            "vector = [0, \"-100 N\", 0]\ntime = { type = \"pulse\", value = 1, t0 = 0, t1 = \"2 ms\" }",
        )
}

/// The tip histories of the file's model and the Rust-built chain `o` (the runner's
/// generalized-alpha stepper), with the peak deflection; asserts they agree to 1e-12 of it.
fn file_vs_rust_vibration(text: &str, o: ChainOptions) -> (CompiledModel, Vec<Vector3<f64>>, f64) {
    let cm = compiled(text);
    let tip = cm
        .model
        .frame_id("beam.i10")
        .unwrap_or_else(|| cm.model.frame_id("beam.i3").unwrap());
    let from_file = dynamic_path(&cm, &cm.model, tip);
    let pulse = TimeFunction::Pulse {
        value: 1.0,
        t0: 0.0,
        t1: 2e-3,
    };
    let (rust, rust_tip) = rust_chain(o, 100.0, pulse);
    let reference = dynamic_path(&cm, &rust, rust_tip);
    let peak = reference.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
    assert!(peak > 1e-3, "peak deflection {peak}");
    let diff = max_rel_diff(&from_file, &reference, peak);
    eprintln!("dynamic: file vs Rust chain {diff:e} of the peak {peak}");
    assert!(diff <= 1e-12, "file vs Rust chain: {diff:e} of the peak");
    (cm, reference, peak)
}

/// The free vibration (first bending period about 52 ms) after a 2 ms tip pulse of a clamped
/// chain of 10 superelements: the file's model under the runner's generalized-alpha equals the
/// Rust-built chain bitwise (to 1e-12 of the peak deflection asserted), and the runner writes
/// the same history.
#[test]
fn free_vibration_equals_rust_chain() {
    let (cm, reference, peak) = file_vs_rust_vibration(&vibration_text("60 ms"), VALIDATION_CHAIN);
    // it vibrates: the tip crosses its rest position after the pulse
    let after: Vec<f64> = reference.iter().skip(25).map(|p| p.y).collect();
    assert!(after.iter().any(|&y| y > 0.0) && after.iter().any(|&y| y < 0.0));
    let out = common::work_dir("se", "dynamic");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let y = r.series("beam.i10.position.y").unwrap().to_vec();
    assert_eq!(y.len(), reference.len());
    for (a, b) in y.iter().zip(&reference) {
        assert!((a - b.y).abs() <= 1e-12 * peak, "runner {a} vs {}", b.y);
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The other options map to the engine's: 3 superelements with 2 internal modes each (node
/// order `n0, eta0, n1, ...`), floating frames at the first interfaces, approximated matrices,
/// fictitious forces from `M_CB`: the same history (15 ms) as the Rust-built chain to 1e-12.
#[test]
fn superelement_options_equal_rust_chain() {
    let text = vibration_text("15 ms")
        .replace(
            "segments = 10",
            "segments = 3\ninternal_modes = 2\nframe = \"interface\"\nmatrices = \"approximated\"\nfictitious_forces = \"from_mcb\"",
        )
        .replace("beam.i10", "beam.i3")
        .replace("beam.s9", "beam.s2");
    let options = ChainOptions {
        n: 3,
        internal_modes: 2,
        frame: FrameLocation::FirstInterface,
        matrices: TransformMatrices::Approximated,
        fictitious: FictitiousForces::FromMcb,
    };
    let (cm, _, _) = file_vs_rust_vibration(&text, options);
    // 3 pose nodes and 3 mode nodes: 4 x 7 + 3 x 2 position coordinates
    assert_eq!(cm.model.nq, 4 * 7 + 3 * 2);
    // coordinate names from the nodes (`Model::q_owner`/`u_owner`): every coordinate named once
    let (q, u, _) = flexmbs_sim::signals::coordinate_names(&cm.model, &cm.bodies);
    let ends = |v: &[String], s: &str| v.iter().filter(|n| n.ends_with(s)).count();
    assert_eq!(
        (ends(&q, ".x"), ends(&q, ".p3"), ends(&q, ".2")),
        (4, 4, 3),
        "{q:?}"
    );
    assert_eq!((ends(&u, ".w_z"), ends(&u, ".d2")), (4, 3), "{u:?}");
    for v in [&q, &u] {
        let set: std::collections::HashSet<_> = v.iter().collect();
        assert_eq!(set.len(), v.len(), "{v:?}");
    }
}

/// The tip of a static model-file run (runner), at every load increment.
fn static_tip(text: &str, name: &str, tip: &str) -> Vec<f64> {
    let cm = compiled(text);
    let out = common::work_dir("se", name);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let y = r.series(&format!("{tip}.position.y")).unwrap().to_vec();
    let _ = std::fs::remove_dir_all(&out);
    y
}

/// Two components joined by naming the same interface (the second starts at `beam.i4`, its
/// position taken from there) are the single 10-superelement cantilever: the same nodes and
/// bodies, initial positions equal up to the round-off of summing lengths, so the tip path
/// agrees to 1e-10 relative.
#[test]
fn components_joined_at_a_named_interface_are_one_chain() {
    let one = static_tip(CANTILEVER, "one", "beam.i10");
    let two_text = CANTILEVER
        .replace(
            "length = \"1 m\"\nsegments = 10",
            "length = \"0.4 m\"\nsegments = 4",
        )
        .replace(
            "[[load]]",
            r#"[[body]]
name = "outer"
type = "superelement_beam"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
lengths = ["100 mm", "100 mm", 0.1, 0.1, 0.1, 0.1]
interfaces = ["beam.i4", "o1", "o2", "o3", "o4", "o5", "end"]

[[load]]"#,
        )
        .replace("frame = \"beam.i10\"", "frame = \"end\"")
        .replace(
            "\"beam.i10.position\", \"beam.s9.deformation\"",
            "\"end.position\", \"outer.s5.deformation\"",
        )
        .replace("beam.s9.frame_iterations", "outer.s5.frame_iterations");
    let two = static_tip(&two_text, "two", "end");
    assert_eq!(one.len(), two.len());
    let scale = one.last().unwrap().abs();
    for (a, b) in one.iter().zip(&two) {
        assert!((a - b).abs() <= 1e-10 * scale, "{a} vs {b}");
    }
}

/// A rigid body welded (fixed joint, through a `[[frame]]` on interface `i5`) to the tip of a
/// clamped 5-superelement beam under gravity loads it like its weight as a tip force: the same
/// static tip to 1e-9 relative (the mass's centre at the interface point, so no moment).
#[test]
fn rigid_body_jointed_to_an_interface_point() {
    let beam = r#"
[model]
name = "se_tip_mass"
gravity = [0, "-9.81 m/s^2", 0]

[solver]
type = "statics"
load_steps = 10

[[body]]
name = "beam"
type = "superelement_beam"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
length = "1 m"
segments = 5
fixed = ["i0"]
"#;
    let with_mass = format!(
        "{beam}{}",
        r#"
[[body]]
name = "mass"
type = "rigid"
mass = 20.0
inertia = [0.1, 0.1, 0.1]
position = [1, 0, 0]

[[frame]]
name = "tip"
body = "beam"
interface = "i5"

[[joint]]
name = "weld"
type = "fixed"
a = "tip"
b = "mass"

[output]
signals = ["beam.i5.position", "weld.force"]
animation = false
"#
    );
    let with_force = format!(
        "{beam}{}",
        r#"
[[load]]
type = "force"
frame = "beam.i5"
vector = [0, -196.2, 0]

[output]
signals = ["beam.i5.position"]
animation = false
"#
    );
    let a = static_tip(&with_mass, "mass", "beam.i5");
    let b = static_tip(&with_force, "force", "beam.i5");
    assert_eq!(a.len(), b.len());
    let scale = b.last().unwrap().abs();
    assert!(scale > 0.05, "tip deflection {scale}");
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-9 * scale, "{x} vs {y}");
    }
}

/// Bad input is refused by `check` (the compiler) at its key path.
#[test]
fn bad_superelement_input_names_the_key_path() {
    let second = r#"[[body]]
name = "outer"
type = "superelement_beam"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
INTERFACE

[[load]]"#;
    let cases: Vec<(String, &str, &str)> = vec![
        (CANTILEVER.replace("segments = 10", "segments = 0"), "body[0].segments", "at least 1"),
        (
            CANTILEVER.replace("length = \"1 m\"\nsegments = 10", "lengths = []"),
            "body[0].lengths",
            "at least 1",
        ),
        (
            CANTILEVER.replace("length = \"1 m\"\nsegments = 10", "lengths = [0.5, \"-1 m\"]"),
            "body[0].lengths[1]",
            "must be > 0",
        ),
        (
            CANTILEVER.replace("length = \"1 m\"", "length = \"1 m\"\nlengths = [1.0]"),
            "body[0]`",
            "not both",
        ),
        (CANTILEVER.replace("wall = 0.001", "wall = 0.02"), "body[0].section", "positive"),
        (
            CANTILEVER.replace("e = 70e9", "e = -70e9"),
            "body[0].material",
            "e > 0",
        ),
        (
            CANTILEVER.replace("segments = 10", "segments = 10\ninternal_modes = 20"),
            "body[0].internal_modes",
            "interior DOFs",
        ),
        (CANTILEVER.replace("[\"i0\"]", "[\"root\"]"), "body[0].fixed[0]", "unknown interface `root`"),
        (
            CANTILEVER.replace("segments = 10", "segments = 10\nmass = 2.0"),
            "body[0].mass",
            "not used by a superelement_beam body",
        ),
        (
            CANTILEVER.replace("segments = 10", "segments = 10\nload_stiffening = true"),
            "body[0].load_stiffening",
            "not used by a superelement_beam body",
        ),
        (
            CANTILEVER.replace("frame = \"beam.i10\"", "frame = \"beam.i11\""),
            "load[0].frame",
            "unknown frame `beam.i11`",
        ),
        (
            CANTILEVER.replace("[[load]]", &second.replace("INTERFACE", "length = 1.0\nsegments = 2\ninterfaces = [\"beam.i10\", \"a\", \"b\"]\nposition = [1.5, 0, 0]")),
            "body[1].interfaces[0]",
            "must coincide at t = 0",
        ),
        (
            CANTILEVER.replace("[[load]]", &second.replace("INTERFACE", "length = 1.0\nsegments = 2\ninterfaces = [\"a\", \"beam.i10\", \"b\"]")),
            "body[1].interfaces[1]",
            "interior point of this body",
        ),
        (
            CANTILEVER.replace("[[load]]", &second.replace("INTERFACE", "length = 1.0\nsegments = 2\ninterfaces = [\"a\", \"b\"]")),
            "body[1].interfaces",
            "one per interface point (3)",
        ),
        (
            CANTILEVER.replace("[[load]]", "[[frame]]\nname = \"f\"\nbody = \"beam\"\ninterface = \"i12\"\n\n[[load]]"),
            "frame[0].interface",
            "unknown interface `i12`",
        ),
        (
            CANTILEVER.replace("[[load]]", "[[frame]]\nname = \"g\"\nbody = \"ground\"\n\n[[joint]]\nname = \"pin\"\ntype = \"spherical\"\na = \"g\"\nb = \"beam.s3\"\n\n[[load]]"),
            "joint[0].b",
            "floating frame of superelement `beam.s3`",
        ),
        (
            CANTILEVER.replace(
                "[[load]]",
                "[[frame]]\nname = \"f\"\nbody = \"beam.s2\"\nnearest = [0, 0, 0]\n\n[[load]]",
            ),
            "frame[0]",
            "frames on its points use `body = \"beam\"`",
        ),
        (
            CANTILEVER.replace("beam.s9.deformation", "beam.i3.deformation"),
            "output.signals[1]",
            "not a node frame",
        ),
    ];
    for (text, path, fragment) in cases {
        let err = compile_model(&text, &file()).expect_err(path).to_string();
        assert!(err.contains(&format!("at `{path}")), "{path}: {err}");
        assert!(err.contains(fragment), "{path}: {err}");
        assert!(err.contains("superelement.toml:"), "{err}");
    }
}

/// The cantilever along global z (`direction = [0, 0, 1]`) under the same load deflects like
/// the one along x: the model is invariant under the rotation (1e-9 relative).
#[test]
fn beam_direction_rotates_the_chain() {
    let along_x = static_tip(CANTILEVER, "x", "beam.i10");
    let along_z = static_tip(
        &CANTILEVER.replace("segments = 10", "segments = 10\ndirection = [0, 0, 1]"),
        "z",
        "beam.i10",
    );
    let scale = along_x.last().unwrap().abs();
    for (a, b) in along_x.iter().zip(&along_z) {
        assert!((a - b).abs() <= 1e-9 * scale, "{a} vs {b}");
    }
}

/// A component continuing a chain at a right angle (an L frame): the shared node keeps the axes
/// of the first component and the second one's first interface is rotated accordingly, so the
/// initial state is undeformed (no elastic energy), and it sags under gravity.
#[test]
fn chain_continued_at_an_angle_starts_undeformed() {
    let text = CANTILEVER
        .replace(
            "[[load]]",
            r#"[[body]]
name = "leg"
type = "superelement_beam"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
direction = [0, 1, 0]
length = 0.5
segments = 2
interfaces = ["beam.i10", "knee", "foot"]

[[load]]"#,
        )
        .replace("\"-1 kN\"", "0")
        .replace("beam.i10.position", "foot.position");
    let cm = compiled(&text);
    let mut eval: Vec<_> = cm
        .model
        .bodies
        .iter()
        .map(|b| b.element.new_scratch())
        .collect();
    let s = cm.initial.clone();
    flexmbs_core::system::evaluate_elements(&cm.model, &s.q, &s.u, &mut eval).unwrap();
    let frames = cm.model.frame_buffers();
    let e = flexmbs_core::system::energy(&cm.model, &s.q, &s.u, &mut eval, &frames);
    assert!(e.elastic.abs() < 1e-20, "elastic energy {:e}", e.elastic);
    let foot = cm.model.frame_id("foot").unwrap();
    let p0 = cm.model.frame_kinematics(&s, foot).unwrap().position;
    assert!((p0 - Vector3::new(1.0, 0.5, 0.0)).amax() < 1e-15, "{p0}");
    // under gravity the beam sags and its end rotates: the leg standing on it tilts away from the
    // clamp
    let loaded = compiled(&text.replace(
        "name = \"se_cantilever\"",
        "name = \"l\"\ngravity = [0, -9.81, 0]",
    ));
    let path = statics_path(&loaded, &loaded.model, foot);
    let d = path.last().unwrap() - p0;
    assert!(d.y < -1e-3 && d.x > 1e-4, "foot displacement {d}");
}
