//! Contacts in the ParaView animation, read back from the written files: a point mass pressed
//! into the top face (a neutral NURBS surface through its 11 x 3 corner nodes) of a clamped flexible beam under a penalty law
//! (generalized-alpha). The `.pvd` lists the bodies, contact points and contours as parts 0, 1
//! and 2 of each time; in the last frame every node of the face lies on the written contour
//! (the deformed FE node positions from the results' coordinates through the mesh-node
//! kinematics, an independent path), and the contact points, gap and normal force are where
//! and what the result signals say; VTK's own reader loads the parts (quads, vertices and
//! fields; skipped without python3 and its vtk module).

use crate::common;

use crate::common::CONTACT_BEAM as BEAM;
use flexmbs_core::LocalFrame;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use nalgebra::Vector3;
use std::path::Path;

const MODEL: &str = r#"
[model]
name = "pressed_beam"
[solver]
type = "generalized-alpha"
t_end = "2 ms"
h = "0.1 ms"
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
position = ["170 mm", "39.5 mm", "17 mm"]
velocity = ["0.1 m/s", "-0.1 m/s", 0]
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
stiffness = "2e4 N/m"
damping = "2 N*s/m"
[output]
dt = "0.5 ms"
signals = ["mass.position", "press.gap", "press.impulse"]
"#;

/// The values of the ASCII `DataArray` named `name` in a `.vtu` text.
fn data_array(vtu: &str, name: &str) -> Vec<f64> {
    let key = format!("Name=\"{name}\"");
    let start = vtu.find(&key).unwrap_or_else(|| panic!("no array {name}"));
    let body = &vtu[start..];
    let open = body.find('>').unwrap() + 1;
    let close = body.find("</DataArray>").unwrap();
    body[open..close]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

/// The last frame file of part `part` in `frames`.
fn last_frame(frames: &Path, part: &str) -> String {
    let prefix = format!("pressed_beam_{part}_");
    let mut files: Vec<_> = std::fs::read_dir(frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.starts_with(&prefix))
        .collect();
    files.sort();
    std::fs::read_to_string(frames.join(files.last().unwrap())).unwrap()
}

fn triples(v: &[f64]) -> Vec<Vector3<f64>> {
    v.chunks(3)
        .map(|c| Vector3::new(c[0], c[1], c[2]))
        .collect()
}

#[test]
fn contact_points_and_deformed_contours_are_drawn() {
    let dir = common::work_dir("contact-animation", "pressed");
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    let file = dir.join("model.toml");
    std::fs::write(&file, MODEL).unwrap();
    let cm = compile_model(MODEL, &file).unwrap();
    let out = dir.join("out");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let pvd = std::fs::read_to_string(out.join("pressed_beam.pvd")).unwrap();
    for part in 0..3 {
        let n = pvd.matches(&format!("part=\"{part}\"")).count();
        assert_eq!(n, 5, "part {part}: {n} frames in\n{pvd}");
    }
    let frames = out.join("pressed_beam_frames");
    let contours = last_frame(&frames, "contours");
    let points = last_frame(&frames, "contact_points");

    // the final state and signals
    let r = read_results(&out.join("results.h5")).unwrap();
    let last = r.rows() - 1;
    let row = r.row(last).unwrap();
    let signal = |name: &str| *r.series(name).unwrap().last().unwrap();
    let m = &cm.model;
    let beam = &cm.bodies[0];
    let (q, u) = m.body_coordinates(beam.id, row.q, row.u);
    let mut eval = beam_scratch(m, beam.id);
    let body = &m.bodies[beam.id.0];
    body.element.update(&q, &u, &mut eval).unwrap();

    // every node of the contour's grid on the top face (reference y = 0.04; the hex20 face's
    // corner nodes, 11 x 3; the midside nodes are not interpolation nodes) lies on the written
    // contour
    let mut written = triples(&data_array(&contours, "Points"));
    // the point contour (drawn last, as a vertex) at the mass centre
    let vertex = written.pop().unwrap();
    let mut k = flexmbs_core::FrameKinematics::for_body(m, beam.id);
    let (mut nodes, mut worst, mut moved) = (0, 0.0_f64, 0.0_f64);
    for (n, p) in beam.geometry.points.iter().enumerate() {
        let on_grid = |x: f64| ((x / 0.02).round() * 0.02 - x).abs() < 1e-12;
        let on_line = on_grid(p[0]) && on_grid(p[2]);
        if (p[1] - 0.04).abs() > 1e-12 || !on_line {
            continue;
        }
        let mut lf = LocalFrame::at(Vector3::from(*p));
        lf.mesh_node = Some(n);
        body.element
            .frame_kinematics(&q, &u, &mut eval, &lf, &mut k);
        let d = written
            .iter()
            .map(|w| (w - k.position).norm())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
        moved = moved.max((k.position - Vector3::from(*p)).norm());
        nodes += 1;
    }
    println!(
        "{nodes} face nodes: farthest from the contour {worst:.2e} m (moved up to {moved:.2e} m)"
    );
    assert_eq!(nodes, 11 * 3, "grid nodes of the hex20 top face");
    assert!(moved > 1e-5, "the beam deforms: {moved:e}");
    assert!(worst < 1e-10, "face node off the contour by {worst:e}");

    // contact points: the mass centre (point b) and its projection, gap and force as signalled
    let pts = triples(&data_array(&points, "Points"));
    let (gap, force) = (
        data_array(&points, "gap"),
        data_array(&points, "normal_force"),
    );
    let normal = triples(&data_array(&points, "normal"));
    assert_eq!(pts.len(), 2);
    let mass = Vector3::new(
        signal("mass.position.x"),
        signal("mass.position.y"),
        signal("mass.position.z"),
    );
    let g = signal("press.gap.n");
    assert!(g < 0.0, "pressed in: gap {g}");
    assert!((pts[1] - mass).norm() < 1e-12, "{:?} vs {mass:?}", pts[1]);
    assert!((vertex - mass).norm() < 1e-12, "{vertex:?} vs {mass:?}");
    assert!((pts[0] - (mass - g * normal[0])).norm() < 1e-12);
    assert!((gap[0] - g).abs() < 1e-15 && (gap[1] - g).abs() < 1e-15);
    let f = signal("press.impulse.n") / signal("step/h");
    assert!(
        f > 0.0 && (force[0] - f).abs() < 1e-12 * f,
        "{force:?} vs {f}"
    );
    vtk_reads_the_parts(&frames, written.len() + 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// VTK's own reader (`vtkXMLUnstructuredGridReader`, PyPI `vtk`) loads the last contour and
/// contact-point files: the contour as quads (cell type 9) and the point contour as a vertex
/// (type 1) with as many points as written, the contact points as two vertices (type 1) with the point fields. Skipped with a printed reason
/// when python3 or its vtk module is missing (a failure with `FLEXMBS_REQUIRE_TOOLS=1`, as in CI).
fn vtk_reads_the_parts(frames: &Path, contour_points: usize) {
    let last = |part: &str| {
        let prefix = format!("pressed_beam_{part}_");
        let mut files: Vec<_> = std::fs::read_dir(frames)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|f| {
                f.file_name()
                    .unwrap()
                    .to_string_lossy()
                    .starts_with(&prefix)
            })
            .collect();
        files.sort();
        files.pop().unwrap()
    };
    let script = format!(
        r#"
import vtk
out = []
for f in [{:?}, {:?}]:
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(f)
    r.Update()
    g = r.GetOutput()
    types = sorted(set(g.GetCellType(i) for i in range(g.GetNumberOfCells())))
    names = [g.GetPointData().GetArrayName(i) for i in range(g.GetPointData().GetNumberOfArrays())]
    out.append("%d %s %s" % (g.GetNumberOfPoints(), types, names))
print("|".join(out))
"#,
        last("contours").to_string_lossy(),
        last("contact_points").to_string_lossy()
    );
    if !flexmbs_io::test_tools::python_or_skip("contact_animation VTK reader check", &["vtk"]) {
        return;
    }
    let run = std::process::Command::new("python3")
        .arg("-c")
        .arg(&script)
        .output()
        .expect("python3 runs");
    assert!(
        run.status.success(),
        "VTK reader failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = String::from_utf8_lossy(&run.stdout).trim().to_string();
    println!("VTK reader: {out}");
    let (contours, points) = out.split_once('|').unwrap();
    assert_eq!(contours, format!("{contour_points} [1, 9] []"));
    assert_eq!(points, "2 [1] ['gap', 'normal_force', 'normal', 'contact']");
}

/// A fresh evaluation scratch of body `b`.
fn beam_scratch(m: &flexmbs_core::Model, b: flexmbs_core::BodyId) -> flexmbs_core::ElementScratch {
    m.bodies[b.0].element.new_scratch()
}
