//! Contact signals `<contact>.force`, `.point_a`, `.point_b`, `.normal` and `.coordinates`: a
//! ball resting on a regularized floor carries its weight, a set-valued bouncing ball's forces
//! are its impulses over the step, and a point mass pressed into a flexible beam's NURBS face
//! reports contour coordinates inside the face's parameter range and a contact point on the face
//! below the mass.

use crate::common;

use crate::common::CONTACT_BEAM as BEAM;
use flexmbs_core::contact::NeutralSurface;
use flexmbs_io::results::{read_results, Results};
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::Path;

fn run(dir: &Path, tag: &str, text: &str, files: &[(&str, &str)]) -> Results {
    for (name, body) in files {
        std::fs::write(dir.join(name), body).unwrap();
    }
    let file = dir.join(format!("{tag}.toml"));
    std::fs::write(&file, text).unwrap();
    let cm = compile_model(text, &file).unwrap();
    let out = dir.join(tag);
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    read_results(&out.join("results.h5")).unwrap()
}

fn series(r: &Results, name: &str) -> Vec<f64> {
    r.series(name)
        .unwrap_or_else(|e| panic!("{name}: {e} ({:?})", r.series_names()))
}

fn vector(r: &Results, name: &str) -> Vec<[f64; 3]> {
    let [x, y, z] = ["x", "y", "z"].map(|c| series(r, &format!("{name}.{c}")));
    (0..x.len()).map(|i| [x[i], y[i], z[i]]).collect()
}

/// A 1 kg ball (radius 0.1 m) placed at rest at its static penetration `m g / k` on a
/// regularized floor (generalized-alpha): at every row the normal force is `m g` to 1e-9
/// relative, no friction force, the normal is the floor's z axis, the floor's contact point lies
/// in the floor plane under the centre and the ball's is its lowest point, with the contours given
/// in either order in the file (`point_a` and `point_b` follow the file).
#[test]
fn resting_ball_carries_its_weight() {
    let dir = common::work_dir("contact_signals", "rest");
    let (m, g, k, r) = (1.0, 9.81, 1e6, 0.1);
    let z0 = r - m * g / k;
    for (tag, a, b, floor_is_a) in [
        ("sphere_first", "sphere", "plane", false),
        ("plane_first", "plane", "sphere", true),
    ] {
        let contour = |kind: &str| {
            if kind == "sphere" {
                r#"{ type = "sphere", frame = "ball", radius = "0.1 m" }"#
            } else {
                r#"{ type = "plane", frame = "floor" }"#
            }
        };
        let text = format!(
            r#"
[model]
name = "rest"
gravity = [0, 0, "-9.81 m/s^2"]
[solver]
type = "generalized-alpha"
t_end = "0.05 s"
h = "1 ms"
[[body]]
name = "ball"
type = "rigid"
mass = "1 kg"
inertia = [4e-3, 4e-3, 4e-3]
position = ["0.3 m", "-0.2 m", "{z0} m"]
[[frame]]
name = "floor"
body = "ground"
[[contact]]
name = "touch"
a = {}
b = {}
normal = "regularized"
stiffness = "1e6 N/m"
damping = "200 N*s/m"
friction = "regularized"
mu = 0.3
slip_velocity = "0.01 m/s"
[output]
signals = ["ball.position", "touch.force", "touch.impulse", "touch.point_a", "touch.point_b", "touch.normal", "touch.gap"]
animation = false
"#,
            contour(a),
            contour(b)
        );
        let res = run(&dir, tag, &text, &[]);
        let (fn_, ft1, ft2) = (
            series(&res, "touch.force.n"),
            series(&res, "touch.force.t1"),
            series(&res, "touch.force.t2"),
        );
        let centre = vector(&res, "ball.position");
        let (pa, pb) = (vector(&res, "touch.point_a"), vector(&res, "touch.point_b"));
        let normal = vector(&res, "touch.normal");
        let gap = series(&res, "touch.gap.n");
        let (floor, ball) = if floor_is_a { (&pa, &pb) } else { (&pb, &pa) };
        assert!(fn_.len() > 10, "{tag}: {} rows", fn_.len());
        let mut worst = 0.0f64;
        for i in 0..fn_.len() {
            worst = worst.max((fn_[i] - m * g).abs() / (m * g));
            assert!(
                ft1[i].abs() < 1e-9 && ft2[i].abs() < 1e-9,
                "{tag} row {i}: friction"
            );
            assert_eq!(normal[i], [0.0, 0.0, 1.0], "{tag} row {i}: normal");
            let c = centre[i];
            assert!(
                floor[i][2] == 0.0
                    && (floor[i][0] - c[0]).abs() < 1e-12
                    && (floor[i][1] - c[1]).abs() < 1e-12,
                "{tag} row {i}: floor point {:?}, centre {c:?}",
                floor[i]
            );
            let low = [c[0], c[1], c[2] - r];
            for d in 0..3 {
                assert!(
                    (ball[i][d] - low[d]).abs() < 1e-12,
                    "{tag} row {i}: ball point"
                );
            }
            // the gap runs from the floor point to the ball point along the normal
            assert!(
                (ball[i][2] - floor[i][2] - gap[i]).abs() < 1e-12,
                "{tag} row {i}: gap"
            );
        }
        eprintln!("{tag}: max |F_N - m g| / m g = {worst:e}");
        assert!(worst < 1e-9, "{tag}: {worst:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A ball dropped with a sideways velocity on a floor with Newton's impact law (restitution 0.5)
/// and Coulomb friction, Moreau steps of 1 ms recorded every step: in every row `force * h` (with
/// the row's step `step/h`) equals the impulse to round-off in all three components; there are
/// impacts (an impulse above the weight's impulse) and the ball comes to rest on the floor with
/// `F_N = m g`.
#[test]
fn set_valued_force_is_impulse_over_step() {
    let dir = common::work_dir("contact_signals", "moreau");
    let text = r#"
[model]
name = "bounce"
gravity = [0, 0, "-9.81 m/s^2"]
[solver]
type = "moreau"
t_end = "1.2 s"
h = "1 ms"
[[body]]
name = "ball"
type = "rigid"
mass = "2 kg"
inertia = [8e-3, 8e-3, 8e-3]
position = [0, 0, "0.2 m"]
velocity = ["0.5 m/s", "0.2 m/s", 0]
[[frame]]
name = "floor"
body = "ground"
[[contact]]
name = "floor_contact"
a = { type = "sphere", frame = "ball", radius = "0.1 m" }
b = { type = "plane", frame = "floor" }
normal = "unilateral"
restitution = 0.5
friction = "coulomb"
mu = 0.3
[output]
every = 1
signals = ["floor_contact.force", "floor_contact.impulse", "floor_contact.normal"]
animation = false
"#;
    let res = run(&dir, "bounce", text, &[]);
    let h = series(&res, "step/h");
    let (mut impacts, mut friction) = (0, 0);
    let weight = 2.0 * 9.81;
    for c in ["n", "t1", "t2"] {
        let f = series(&res, &format!("floor_contact.force.{c}"));
        let p = series(&res, &format!("floor_contact.impulse.{c}"));
        assert!(f.len() > 1000, "{} rows", f.len());
        for i in 1..f.len() {
            let d = (f[i] * h[i] - p[i]).abs();
            assert!(
                d <= 1e-14 * p[i].abs().max(1e-300),
                "{c} row {i}: F h {} impulse {}",
                f[i] * h[i],
                p[i]
            );
            if c == "n" && f[i] > 10.0 * weight {
                impacts += 1;
            }
            if c != "n" && f[i] != 0.0 {
                friction += 1;
            }
        }
        if c == "n" {
            let last = f[f.len() - 1];
            assert!(
                (last - weight).abs() < 1e-6 * weight,
                "resting F_N {last}, m g {weight}"
            );
        }
    }
    eprintln!("impact rows {impacts}, friction rows {friction}");
    assert!(impacts >= 2, "impacts {impacts}");
    assert!(friction > 0, "no friction force");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A point mass dropped on the top face (a NURBS surface contour) of the flexible beam with a
/// regularized law (generalized-alpha: the contact geometry is the row's state). While the mass
/// presses into the face: the coordinates lie in the face's parameter ranges, `point_b` is the
/// mass's position, and `point_a` is the mass's position minus `gap * normal` to 1e-9 m (the
/// contact point on the deformed face is the normal projection of the mass); without a contact
/// point they are NaN. The `coordinates` signal of a rigid contact is refused.
#[test]
fn point_on_flexible_face_reports_contour_coordinates() {
    let dir = common::work_dir("contact_signals", "flexible");
    let text = r#"
[model]
name = "press"
[solver]
type = "generalized-alpha"
t_end = "0.03 s"
h = "1e-4 s"
rho_inf = 0.8
[[body]]
name = "beam"
type = "ffr"
source = "beam.toml"
inertia = "consistent"
[[body]]
name = "mass"
type = "rigid"
mass = "0.2 kg"
inertia = [1e-6, 1e-6, 1e-6]
position = ["150 mm", "40.5 mm", "17 mm"]
velocity = ["0.3 m/s", "-0.2 m/s", 0]
[[frame]]
name = "wall"
body = "ground"
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[contact]]
name = "press"
a = { type = "surface", body = "beam", face = "ymax" }
b = { type = "point", frame = "mass" }
normal = "regularized"
stiffness = "1e4 N/m"
damping = "2 N*s/m"
[output]
every = 1
signals = ["mass.position", "press.gap", "press.force", "press.point_a", "press.point_b", "press.normal", "press.coordinates"]
animation = false
"#;
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    let file = dir.join("press.toml");
    let cm = compile_model(text, &file).unwrap();
    let surf = cm.model.contacts[0]
        .contour_a
        .as_any()
        .downcast_ref::<NeutralSurface>()
        .expect("the surface is contour a");
    let interp = surf.contour().interpolator();
    let range = |p: &[f64]| (p[0], p[p.len() - 1]);
    let (eta_range, xi_range) = (range(interp.eta().params()), range(interp.xi().params()));
    let coords = cm.signals.iter().find(|s| s.name == "press.coordinates");
    assert_eq!(coords.map(|s| s.unit.as_str()), Some("1"));
    let res = run(&dir, "press", text, &[]);
    let pos = vector(&res, "mass.position");
    let (pa, pb) = (vector(&res, "press.point_a"), vector(&res, "press.point_b"));
    let normal = vector(&res, "press.normal");
    let gap = series(&res, "press.gap.n");
    let force = series(&res, "press.force.n");
    let (eta, xi) = (
        series(&res, "press.coordinates.eta"),
        series(&res, "press.coordinates.xi"),
    );
    let (mut pressed, mut worst) = (0, 0.0f64);
    for i in 0..gap.len() {
        if !gap[i].is_finite() {
            assert!(eta[i].is_nan() && pa[i][0].is_nan() && normal[i][0].is_nan());
            continue;
        }
        assert!(
            (eta_range.0..=eta_range.1).contains(&eta[i])
                && (xi_range.0..=xi_range.1).contains(&xi[i]),
            "row {i}: (eta, xi) = ({}, {}) outside {eta_range:?} x {xi_range:?}",
            eta[i],
            xi[i]
        );
        assert!((normal[i].iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        for d in 0..3 {
            assert_eq!(pb[i][d], pos[i][d], "row {i}: point_b is the mass");
            let expected = pos[i][d] - gap[i] * normal[i][d];
            worst = worst.max((pa[i][d] - expected).abs());
        }
        if force[i] > 0.0 {
            pressed += 1;
            assert!(
                gap[i] < 0.0,
                "row {i}: force {} at gap {}",
                force[i],
                gap[i]
            );
        }
    }
    eprintln!("rows pressed {pressed}, max |point_a - (r - g n)| = {worst:e} m");
    assert!(pressed > 20, "pressed rows {pressed}");
    assert!(worst < 1e-9, "{worst:e}");
    // a rigid pair has no contour coordinates
    let rigid = text.replace(
        r#"a = { type = "surface", body = "beam", face = "ymax" }"#,
        r#"a = { type = "plane", frame = "wall" }"#,
    );
    let e = compile_model(&rigid, &file).unwrap_err().to_string();
    assert!(e.contains("has no flexible contour"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
