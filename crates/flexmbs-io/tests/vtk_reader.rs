//! VTU/PVD output checked with VTK's own reader (`vtkXMLUnstructuredGridReader`, PyPI `vtk`).
//! Skipped with a printed reason when python3 or the vtk module is missing (CI: `pip install vtk`).

use crate::body_file_support;

use body_file_support::{python_has, run_python, sample_body, temp_dir};
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::Cell;
use flexmbs_io::vtk::{write_mode_shapes_with, write_vtu_with, ModeShapeOptions, VtuEncoding};

fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        (a[0] + b[0]) / 2.0,
        (a[1] + b[1]) / 2.0,
        (a[2] + b[2]) / 2.0,
    ]
}

/// One element of each kind on the box [0,2]x[0,3]x[0,1], nodes in Abaqus order: mid-edge nodes
/// are built from the Abaqus edge tables (C3D20: 9:(1,2) 10:(2,3) 11:(3,4) 12:(4,1) 13:(5,6)
/// 14:(6,7) 15:(7,8) 16:(8,5) 17:(1,5) 18:(2,6) 19:(3,7) 20:(4,8); C3D10: 5:(1,2) 6:(2,3) 7:(3,1)
/// 8:(1,4) 9:(2,4) 10:(3,4)), independent of VTK's tables.
fn reference_elements() -> (Vec<[f64; 3]>, Vec<Cell>) {
    let c = [
        [0., 0., 0.],
        [2., 0., 0.],
        [2., 3., 0.],
        [0., 3., 0.],
        [0., 0., 1.],
        [2., 0., 1.],
        [2., 3., 1.],
        [0., 3., 1.],
    ];
    let mut pts = Vec::new();
    let mut cells = Vec::new();
    let mut add = |kind, p: Vec<[f64; 3]>| {
        let base = pts.len();
        cells.push(Cell {
            kind,
            nodes: (base..base + p.len()).collect(),
        });
        pts.extend(p);
    };
    add(ElementKind::Hex8, c.to_vec());
    let edges20 = [
        (1, 2),
        (2, 3),
        (3, 4),
        (4, 1),
        (5, 6),
        (6, 7),
        (7, 8),
        (8, 5),
        (1, 5),
        (2, 6),
        (3, 7),
        (4, 8),
    ];
    let mut h20 = c.to_vec();
    h20.extend(edges20.iter().map(|&(a, b)| mid(c[a - 1], c[b - 1])));
    add(ElementKind::Hex20R, h20);
    let t = [[0., 0., 0.], [2., 0., 0.], [0., 3., 0.], [0., 0., 1.]];
    let edges10 = [(1, 2), (2, 3), (3, 1), (1, 4), (2, 4), (3, 4)];
    let mut t10 = t.to_vec();
    t10.extend(edges10.iter().map(|&(a, b)| mid(t[a - 1], t[b - 1])));
    add(ElementKind::Tet10, t10);
    add(ElementKind::Beam2, vec![[0., 0., 0.], [0., 0., 5.]]);
    (pts, cells)
}

/// VTK recognises each cell and our node order is VTK's: at the position of node i, VTK's own
/// interpolation weights (from its Newton inversion, converged to ~1e-3 in parametric space) are
/// the unit vector e_i within 1e-2 with the largest weight at i, and the cell sizes are the exact
/// volumes (hexes 6, tet 1, line 5; relative 1e-9), which a permuted mid-edge node would distort.
#[test]
fn vtk_reads_cells_in_matching_node_order() {
    if !python_has(&["vtk"], "vtk_reads_cells_in_matching_node_order") {
        return;
    }
    let dir = temp_dir("vtk-order");
    let (pts, cells) = reference_elements();
    let code = r#"
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput()
assert g.GetNumberOfPoints() == 40 and g.GetNumberOfCells() == 4, (g.GetNumberOfPoints(), g.GetNumberOfCells())
assert [g.GetCellType(i) for i in range(4)] == [12, 25, 24, 3]
for c in range(4):
    cell = g.GetCell(c)
    n = cell.GetNumberOfPoints()
    for i in range(n):
        x = cell.GetPoints().GetPoint(i)
        closest = [0.0] * 3; sub = vtk.reference(0); pc = [0.0] * 3; d2 = vtk.reference(0.0); w = [0.0] * n
        st = cell.EvaluatePosition(x, closest, sub, pc, d2, w)
        assert st == 1, (c, i, st)
        err = max(abs(w[j] - (1.0 if j == i else 0.0)) for j in range(n))
        assert err < 1e-2 and max(range(n), key=lambda j: w[j]) == i, (c, i, w)
s = vtk.vtkCellSizeFilter(); s.SetInputData(g); s.Update()
o = s.GetOutput().GetCellData()
sizes = [o.GetArray('Volume').GetValue(0), o.GetArray('Volume').GetValue(1), o.GetArray('Volume').GetValue(2), o.GetArray('Length').GetValue(3)]
for got, want in zip(sizes, [6.0, 6.0, 1.0, 5.0]):
    assert abs(got - want) < 1e-9 * want, sizes
print('ok')
"#;
    for enc in [VtuEncoding::Base64, VtuEncoding::Ascii] {
        let path = dir.join(format!("ref_{enc:?}.vtu"));
        write_vtu_with(&path, &pts, &cells, &[], &[], &[], enc).unwrap();
        assert_eq!(run_python(code, &[path.to_str().unwrap()]).trim(), "ok");
    }
}

/// Point, cell and field data arrive with their names, component counts and exact values.
#[test]
fn vtk_reads_fields_exactly() {
    if !python_has(&["vtk"], "vtk_reads_fields_exactly") {
        return;
    }
    let dir = temp_dir("vtk-fields");
    let (pts, cells) = reference_elements();
    let temp: Vec<f64> = (0..pts.len()).map(|i| 0.1 * i as f64 - 1.0).collect();
    let disp: Vec<f64> = (0..3 * pts.len())
        .map(|i| (i as f64).sin() * 1e-3)
        .collect();
    let cid: Vec<f64> = vec![10.0, 20.0, 30.0, 40.0];
    let freq = [1.5, 2.5, 1e6];
    let code = r#"
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput()
pd, cd, fd = g.GetPointData(), g.GetCellData(), g.GetFieldData()
t, d, c, f = pd.GetArray('temperature'), pd.GetArray('displacement'), cd.GetArray('cell id'), fd.GetArray('frequency_hz')
assert t.GetNumberOfComponents() == 1 and d.GetNumberOfComponents() == 3 and d.GetNumberOfTuples() == 40
print(repr(t.GetRange()), repr(d.GetRange(1)), repr(d.GetComponent(7, 2)), repr(c.GetRange()), [f.GetValue(i) for i in range(f.GetNumberOfTuples())])
"#;
    let want_d = disp
        .iter()
        .skip(1)
        .step_by(3)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    for enc in [VtuEncoding::Base64, VtuEncoding::Ascii] {
        let path = dir.join(format!("fields_{enc:?}.vtu"));
        write_vtu_with(
            &path,
            &pts,
            &cells,
            &[("temperature", 1, &temp), ("displacement", 3, &disp)],
            &[("cell id", 1, &cid)],
            &[("frequency_hz", 1, &freq)],
            enc,
        )
        .unwrap();
        let out = run_python(code, &[path.to_str().unwrap()]);
        // Python's repr is the shortest round-trip text, as Rust's Display: exact comparison.
        let want = format!(
            "({:?}, {:?}) ({:?}, {:?}) {:?} ({:?}, {:?}) [{:?}, {:?}, {:?}]",
            temp[0],
            temp[39],
            want_d.0,
            want_d.1,
            disp[3 * 7 + 2],
            10.0,
            40.0,
            freq[0],
            freq[1],
            freq[2]
        );
        assert_eq!(out.trim(), want, "{enc:?}");
    }
}

/// Mode shape export: `modes.vtu` holds every mode scaled to the requested peak (1e-12), the
/// animation frames of the first two modes are the undeformed mesh plus sin(2 pi j / F) times the
/// mode (1e-12), and the PVD lists them with time k - 1 + j / F.
#[test]
fn mode_shapes_read_by_vtk() {
    if !python_has(&["vtk"], "mode_shapes_read_by_vtk") {
        return;
    }
    let dir = temp_dir("vtk-modes");
    let body = sample_body(24, 3, 17);
    let files = write_mode_shapes_with(
        &dir,
        &body,
        &ModeShapeOptions {
            scale: 0.25,
            frames_per_mode: 8,
            animated_modes: 2,
        },
    )
    .unwrap();
    assert_eq!(files.len(), 1 + 2 * 8 + 1); // modes.vtu, 2 animated modes x 8 frames, pvd
    let code = r#"
import sys, os, math, vtk, xml.etree.ElementTree as ET
d = sys.argv[1]
def load(p):
    r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(p); r.Update(); return r.GetOutput()
g = load(os.path.join(d, 'modes.vtu'))
assert g.GetNumberOfPoints() == 24 and g.GetNumberOfCells() == 6
pd = g.GetPointData()
for k in (1, 2, 3):
    a = pd.GetArray('mode_%02d' % k)
    assert a.GetNumberOfComponents() == 3
    assert abs(a.GetMaxNorm() - 0.25) < 1e-12, a.GetMaxNorm()
assert pd.GetArray('node_id').GetValue(23) == 1000 + 7 * 23
f = g.GetFieldData().GetArray('frequency_hz')
print(' '.join(repr(f.GetValue(i)) for i in range(3)))
entries = ET.parse(os.path.join(d, 'modes_animation.pvd')).getroot().find('Collection').findall('DataSet')
assert len(entries) == 16
e = entries[8 + 2]  # mode 2, frame 2: phase sin(2 pi 2/8) = 1/sqrt(2)
assert abs(float(e.get('timestep')) - 1.25) < 1e-15
h = load(os.path.join(d, e.get('file')))
u = h.GetPointData().GetArray('displacement')
m = pd.GetArray('mode_02')
s = math.sin(2 * math.pi * 2 / 8)
err = 0.0
for i in range(24):
    x0, x = g.GetPoint(i), h.GetPoint(i)
    for c in range(3):
        err = max(err, abs(u.GetComponent(i, c) - s * m.GetComponent(i, c)), abs(x[c] - x0[c] - u.GetComponent(i, c)))
assert err < 1e-12, err
print('ok')
"#;
    let out = run_python(code, &[dir.to_str().unwrap()]);
    let want: Vec<String> = body
        .frequencies_hz
        .iter()
        .map(|f| format!("{f:?}"))
        .collect();
    assert_eq!(out.lines().next().unwrap(), want.join(" "));
    assert_eq!(out.lines().nth(1), Some("ok"));
}
