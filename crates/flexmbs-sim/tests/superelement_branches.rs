//! Superelement beams that branch and close (a component starting at any existing interface
//! point, or ending at one): a T of three beams meeting at one shared point equals the same T
//! built from separate interface points welded by `fixed` joints (statics and generalized-alpha);
//! a closed square frame of four beams pulled at opposite corners stretches as small-deflection
//! frame theory predicts.

use flexmbs_core::integrator::{self, GenAlpha, GenAlphaStepper, Statics, StaticsStepper, Stepper};
use flexmbs_core::{Model, State, Workspace};
use flexmbs_sim::compile::SolverConfig;
use flexmbs_sim::{compile_model, CompiledModel};
use nalgebra::Vector3;
use std::ops::ControlFlow;
use std::path::Path;

const TUBE: &str = r#"material = { e = 70e9, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }"#;

fn compiled(text: &str) -> CompiledModel {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/superelement.toml");
    compile_model(text, &file).unwrap_or_else(|e| panic!("{e}"))
}

/// Statics (the runner's stepper and driver): the position of frame `tip` at the end.
fn static_position(cm: &CompiledModel, tip: &str) -> Vector3<f64> {
    let SolverConfig::Statics { settings } = cm.solver else {
        panic!("not statics")
    };
    let model = &cm.model;
    let tip = model.frame_id(tip).unwrap();
    let mut s = cm.initial.clone();
    let mut ws = Workspace::with_linear_solver(model, cm.linear_solver);
    let solver = Statics::new(settings);
    let mut stepper = StaticsStepper::new(solver);
    stepper.initialize(model, &mut s, &mut ws).unwrap();
    integrator::drive(
        &mut stepper,
        model,
        &mut s,
        &mut ws,
        solver.control(),
        1.0,
        |_, _| ControlFlow::Continue(()),
    )
    .unwrap();
    model.frame_kinematics(&s, tip).unwrap().position
}

/// Generalized-alpha (the runner's stepper and driver): the position of frame `tip` at every
/// step, the initial state first.
fn dynamic_path(cm: &CompiledModel, tip: &str) -> Vec<Vector3<f64>> {
    let SolverConfig::GenAlpha {
        settings, h, t_end, ..
    } = cm.solver
    else {
        panic!("not generalized-alpha")
    };
    let model: &Model = &cm.model;
    let tip = model.frame_id(tip).unwrap();
    let mut s: State = cm.initial.clone();
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

/// A T: `left` (clamped at x = 0) and `right` (clamped at x = 1 m) meet `stem` (up along y,
/// 0.4 m) at `p` = (0.5, 0, 0); a force at the stem's tip. `shared`: `right` and `stem` start at
/// `left`'s end interface (the stem's superelement nodes scattered); otherwise each has its own
/// first interface point, welded to `left`'s end by a `fixed` joint (the stem's through a frame
/// turned to its axes).
fn t_frame(shared: bool, solver: &str) -> String {
    let (right_start, stem_start) = if shared { ("p", "p") } else { ("r0", "s0") };
    let mut text = format!(
        r#"[model]
name = "t_frame"

[solver]
{solver}

[[body]]
name = "left"
type = "superelement_beam"
{TUBE}
length = 0.5
segments = 2
interfaces = ["root", "l1", "p"]
fixed = ["root"]

[[body]]
name = "stem"
type = "superelement_beam"
{TUBE}
position = [0.5, 0, 0]
orientation = {{ axis = [0, 0, 1], angle = "90 deg" }}
length = 0.4
segments = 2
interfaces = ["{stem_start}", "s1", "tip"]

[[body]]
name = "right"
type = "superelement_beam"
{TUBE}
position = [0.5, 0, 0]
length = 0.5
segments = 2
interfaces = ["{right_start}", "r1", "end"]
fixed = ["end"]

[[load]]
type = "force"
frame = "tip"
vector = ["3 N", 0, "2 N"]
LOAD_TIME
"#
    );
    if !shared {
        text.push_str(
            r#"
[[frame]]
name = "p_stem"
body = "left"
interface = "p"
orientation = { axis = [0, 0, 1], angle = "90 deg" }

[[joint]]
name = "weld_right"
type = "fixed"
a = "p"
b = "r0"

[[joint]]
name = "weld_stem"
type = "fixed"
a = "p_stem"
b = "s0"
"#,
        );
    }
    text
}

/// The shared-point T has no joints and scattered superelements; the welded one has 12 joint
/// rows more. Statics under the tip force, `right` free or clamped too, with the dense and the
/// sparse linear solver: the same tip position to 1e-8 of its displacement. (Clamped at both
/// ends, the dense solver once refused the regular tangent as singular: its pivot test was
/// relative to the largest entry of the matrix, not of the pivot's column.)
#[test]
fn t_frame_with_shared_point_equals_welded_t_frame_statics() {
    for (solver, clamps) in [("dense", 1), ("dense", 2), ("sparse", 2)] {
        let statics = format!("type = \"statics\"\nload_steps = 2\nlinear_solver = \"{solver}\"");
        let text = |shared| {
            let t = t_frame(shared, &statics).replace("LOAD_TIME", "");
            if clamps == 1 {
                t.replace("fixed = [\"end\"]", "")
            } else {
                t
            }
        };
        let (a, b) = (compiled(&text(true)), compiled(&text(false)));
        let nc = 6 * clamps;
        assert_eq!(
            (a.model.nc, b.model.nc),
            (nc, nc + 12),
            "clamps (and welds)"
        );
        assert!(a.model.bodies.iter().any(|b| b.is_scattered()));
        let x0 = Vector3::new(0.5, 0.4, 0.0);
        let (pa, pb) = (static_position(&a, "tip"), static_position(&b, "tip"));
        let d = (pb - x0).norm();
        println!(
            "{solver}, {clamps} clamps: tip displacement {d:e} m, shared vs welded {:e}",
            (pa - pb).norm()
        );
        assert!(d > 1e-4, "the tip moves: {d}");
        assert!((pa - pb).norm() <= 1e-8 * d, "{pa} vs {pb}");
    }
}

/// A 2 ms force pulse on the stem tip, 20 ms of generalized-alpha: the same tip history to
/// 1e-8 of the peak displacement.
#[test]
fn t_frame_with_shared_point_equals_welded_t_frame_dynamics() {
    let ga = "type = \"generalized-alpha\"\nh = \"0.1 ms\"\nt_end = \"20 ms\"";
    let pulse = "time = { type = \"pulse\", value = 1, t0 = 0, t1 = \"2 ms\" }";
    let (a, b) = (
        compiled(&t_frame(true, ga).replace("LOAD_TIME", pulse)),
        compiled(&t_frame(false, ga).replace("LOAD_TIME", pulse)),
    );
    let (pa, pb) = (dynamic_path(&a, "tip"), dynamic_path(&b, "tip"));
    assert_eq!(pa.len(), pb.len());
    let peak = pb.iter().map(|p| (p - pb[0]).norm()).fold(0.0, f64::max);
    let diff = pa
        .iter()
        .zip(&pb)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    println!("peak {peak:e} m, shared vs welded {:e} of it", diff / peak);
    assert!(peak > 1e-5, "the tip moves: {peak}");
    assert!(diff <= 1e-8 * peak, "{:e} of the peak", diff / peak);
}

/// A closed square frame (side `L` = 0.5 m, four components of two superelements each, the
/// last one ending at the first corner: a loop), clamped at corner `c0` and pulled at the
/// opposite corner `c2` along the diagonal by `P`. By symmetry the clamp carries no moment, so
/// this is the free square under opposed diagonal loads: bending moment `M = P (s - L/2) /
/// (2 sqrt 2)` along each side and axial force `P / (2 sqrt 2)`, so by Castigliano the corners
/// separate by `δ = P L³ / (24 E I) + P L / (2 E A)`. Checked to 1e-4 (the load is small: the
/// geometric nonlinearity `N L² / (E I)` is about 1e-4; measured 1.1e-5). The frame starts stress-free (corners,
/// the closing one included, undeformed at t = 0).
#[test]
fn closed_square_frame_stretches_as_frame_theory_predicts() {
    let (l, p) = (0.5, 0.2);
    let side = |name: &str, from: &str, to: &str, at: [f64; 2], dir: [f64; 2], fixed: bool| {
        format!(
            r#"
[[body]]
name = "{name}"
type = "superelement_beam"
{TUBE}
position = [{}, {}, 0]
direction = [{}, {}, 0]
length = {l}
segments = 2
interfaces = ["{from}", "{name}_m", "{to}"]
{}"#,
            at[0],
            at[1],
            dir[0],
            dir[1],
            if fixed { "fixed = [\"i0\"]" } else { "" }
        )
    };
    let text = format!(
        r#"[model]
name = "square"

[solver]
type = "statics"
load_steps = 1
{}{}{}{}
[[load]]
type = "force"
frame = "c2"
vector = [{f}, {f}, 0]
"#,
        side("a", "c0", "c1", [0.0, 0.0], [1.0, 0.0], true),
        side("b", "c1", "c2", [l, 0.0], [0.0, 1.0], false),
        side("c", "c2", "c3", [l, l], [-1.0, 0.0], false),
        side("d", "c3", "c0", [0.0, l], [0.0, -1.0], false),
        f = p / 2f64.sqrt()
    );
    let cm = compiled(&text);
    assert_eq!(cm.model.nc, 6, "only the clamp");
    let scattered: Vec<_> = cm
        .model
        .bodies
        .iter()
        .filter(|b| b.is_scattered())
        .map(|b| b.name.clone())
        .collect();
    assert_eq!(
        scattered,
        vec!["d.s1".to_string()],
        "the closing superelement"
    );
    // stress-free start
    let s = cm.initial.clone();
    let mut eval: Vec<_> = cm
        .model
        .bodies
        .iter()
        .map(|b| b.element.new_scratch())
        .collect();
    flexmbs_core::system::evaluate_elements(&cm.model, &s.q, &s.u, &mut eval).unwrap();
    let e =
        flexmbs_core::system::energy(&cm.model, &s.q, &s.u, &mut eval, &cm.model.frame_buffers());
    assert!(
        e.elastic.abs() < 1e-20,
        "elastic energy at t = 0: {:e}",
        e.elastic
    );
    let x = static_position(&cm, "c2");
    let delta = (x - Vector3::new(l, l, 0.0)).dot(&Vector3::new(1.0, 1.0, 0.0).normalize());
    let (ro, ri, e_mod) = (0.01f64, 0.009f64, 70e9);
    let i = std::f64::consts::PI / 4.0 * (ro.powi(4) - ri.powi(4));
    let a = std::f64::consts::PI * (ro * ro - ri * ri);
    let expected = p * l.powi(3) / (24.0 * e_mod * i) + p * l / (2.0 * e_mod * a);
    let rel = (delta - expected).abs() / expected;
    println!("square: delta {delta:e} m, frame theory {expected:e} m, relative {rel:e}");
    assert!(rel < 1e-4, "{delta:e} vs {expected:e}");
    let sideways = (x - Vector3::new(l, l, 0.0)).cross(&Vector3::new(1.0, 1.0, 0.0));
    assert!(
        sideways.norm() < 1e-3 * expected,
        "moves along the diagonal: {sideways}"
    );
}
