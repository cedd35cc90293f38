//! The results file and the animation read by the reference readers: h5py (libhdf5) and VTK's own
//! XML reader. Skipped with a printed reason when python3, h5py, numpy or vtk are missing (CI:
//! `.ci/run` installs them with pip).

use crate::body_file_support;
use crate::results_support;

use body_file_support::{python_has, run_python, temp_dir};
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::Cell;
use flexmbs_io::results::{AnimationBody, AnimationWriter, ResultsWriter, RunStatus};
use results_support::{layout, rows};
use std::time::Duration;

/// h5py opens a finished file and a file of a killed run (writer dropped after a flush): shapes,
/// attributes, status, column names and exact values as documented in docs/formats/results.md.
#[test]
fn h5py_reads_results_files() {
    if !python_has(&["h5py", "numpy"], "h5py_reads_results_files") {
        return;
    }
    let dir = temp_dir("results-h5py");
    let l = layout(5, 4, 2, true);
    let data = rows(&l, 30, 17);

    let done = dir.join("done.h5");
    let mut w = ResultsWriter::create(&done, l.clone(), &[("solver", "HHT-α")]).unwrap();
    for r in &data {
        w.push(&r.view()).unwrap();
    }
    w.finish(&RunStatus::Failed {
        t: 0.0295,
        message: "step size below 1e-12".into(),
    })
    .unwrap();

    let killed = dir.join("killed.h5");
    let mut w = ResultsWriter::create(&killed, l.clone(), &[]).unwrap();
    w.set_flush_interval(Duration::from_secs(3600));
    for r in &data[..12] {
        w.push(&r.view()).unwrap();
    }
    w.flush().unwrap();
    w.push(&data[12].view()).unwrap();
    drop(w);

    let empty = dir.join("empty.h5");
    ResultsWriter::create(&empty, layout(0, 0, 0, false), &[])
        .unwrap()
        .finish(&RunStatus::Interrupted { t: 0.0 })
        .unwrap();

    let code = r#"
import sys, h5py, numpy as np
bits = lambda x: int(np.float64(x).view(np.uint64))
with h5py.File(sys.argv[1], 'r') as f:
    a = f.attrs
    assert a['format'] == 'flexmbs-results' and int(a['format_version']) == 2, dict(a)
    assert a['model'] == 'slider crank µ' and a['solver'] == 'HHT-α'
    assert a['status'] == 'failed' and a['status_message'] == 'step size below 1e-12'
    assert float(a['status_time']) == 0.0295
    # version 2: a matrix is a 1-d dataset of rows, read by NumPy as an (n, k) float64 array
    shapes = {k: f[k][()].shape for k in ['time', 'q', 'u', 'lambda', 'energy', 'drift', 'step']}
    assert shapes == {'time': (30,), 'q': (30, 5), 'u': (30, 4), 'lambda': (30, 2),
                      'energy': (30, 4), 'drift': (30, 2), 'step': (30, 3)}, shapes
    assert all(f[k][()].dtype == np.float64 for k in shapes)
    assert f['q'].shape == (30,) and f['q'].maxshape == (None,)
    assert list(f['energy'].attrs['columns']) == ['kinetic', 'gravity', 'elastic', 'springs']
    assert list(f['step'].attrs['columns']) == ['h', 'iterations', 'residual']
    s = lambda d: [x.decode() if isinstance(x, bytes) else x for x in f[d][()]]
    assert s('coordinates') == ['rod.q0', 'rod.q1', 'rod.q2', 'rod.q3', 'rod.q4'], s('coordinates')
    assert s('multipliers') == ['pin.row0', 'pin.row1']
    assert list(f['signals'].attrs['names']) == ['tip.position', 'crank.angle']
    tip = f['signals/tip.position']
    assert tip[()].shape == (30, 3) and tip.attrs['unit'] == 'm'
    assert list(tip.attrs['components']) == ['x', 'y', 'z']
    assert f['signals/crank.angle'][()].shape == (30, 1)
    assert f['q'].fletcher32 and f['q'].chunks is not None
    print(bits(f['time'][29]), bits(f['q'][7][3]), bits(f['lambda'][()][29, 1]),
          bits(f['energy'][3][2]), bits(tip[()][11, 2]), bits(f['signals/crank.angle'][5][0]))
with h5py.File(sys.argv[2], 'r') as f:
    assert f.attrs['status'] == 'running', f.attrs['status']
    assert f['time'].shape == (12,) and f['q'][()].shape == (12, 5)
    assert f['signals/tip.position'][()].shape == (12, 3)
    print(bits(f['u'][()][11, 3]))
with h5py.File(sys.argv[3], 'r') as f:
    assert f.attrs['status'] == 'interrupted' and float(f.attrs['status_time']) == 0.0
    assert f['time'].shape == (0,) and f['q'].shape == (0, 0) and f['energy'][()].shape == (0, 4)
    assert len(f['coordinates']) == 0 and len(f['signals']) == 0
print('ok')
"#;
    let out = run_python(
        code,
        &[
            done.to_str().unwrap(),
            killed.to_str().unwrap(),
            empty.to_str().unwrap(),
        ],
    );
    let v: Vec<u64> = out
        .split_whitespace()
        .filter_map(|s| s.parse().ok())
        .collect();
    let expected = [
        data[29].t.to_bits(),
        data[7].q[3].to_bits(),
        data[29].lambda[1].to_bits(),
        data[3].energy[2].to_bits(),
        data[11].signals[2].to_bits(),
        data[5].signals[3].to_bits(),
        data[11].u[3].to_bits(),
    ];
    assert_eq!(v, expected);
    assert!(out.trim_end().ends_with("ok"));
}

/// VTK's XML reader opens every frame listed in the .pvd (parsed with Python's xml module; VTK's
/// Python package has no .pvd reader): point and cell counts, cell types, `displacement` equal to
/// current minus reference positions, `body` per cell, frame times.
#[test]
fn vtk_reads_animation_frames() {
    if !python_has(&["vtk"], "vtk_reads_animation_frames") {
        return;
    }
    let dir = temp_dir("results-vtk");
    let bodies = vec![
        AnimationBody {
            name: "block".into(),
            reference_points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 1.0],
            ],
            cells: vec![Cell {
                kind: ElementKind::Hex8,
                nodes: (0..8).collect(),
            }],
        },
        AnimationBody {
            name: "rod".into(),
            reference_points: vec![[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]],
            cells: vec![
                Cell {
                    kind: ElementKind::Beam2,
                    nodes: vec![0, 1],
                },
                Cell {
                    kind: ElementKind::Beam2,
                    nodes: vec![1, 2],
                },
            ],
        },
    ];
    let mut w = AnimationWriter::create(&dir, "anim", bodies.clone()).unwrap();
    for k in 0..4 {
        // Block lifted by 0.1 k in z, rod bent: point j moved by 0.01 k j in y.
        let block: Vec<[f64; 3]> = bodies[0]
            .reference_points
            .iter()
            .map(|p| [p[0], p[1], p[2] + 0.1 * k as f64])
            .collect();
        let rod: Vec<[f64; 3]> = bodies[1]
            .reference_points
            .iter()
            .enumerate()
            .map(|(j, p)| [p[0], p[1] + 0.01 * (k * j) as f64, p[2]])
            .collect();
        w.write_frame(0.25 * k as f64, &[&block, &rod]).unwrap();
    }
    w.flush().unwrap();
    let code = r#"
import sys, os, vtk, xml.etree.ElementTree as ET
pvd = sys.argv[1]
root = ET.parse(pvd).getroot()
assert root.get('type') == 'Collection'
sets = root.find('Collection').findall('DataSet')
assert [float(d.get('timestep')) for d in sets] == [0.0, 0.25, 0.5, 0.75], [d.get('timestep') for d in sets]
for k, d in enumerate(sets):
    f = d.get('file')
    assert not os.path.isabs(f), f
    r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(os.path.join(os.path.dirname(pvd), f)); r.Update()
    g = r.GetOutput()
    assert g.GetNumberOfPoints() == 11 and g.GetNumberOfCells() == 3, (g.GetNumberOfPoints(), g.GetNumberOfCells())
    assert [g.GetCellType(c) for c in range(3)] == [12, 3, 3]
    disp = g.GetPointData().GetArray('displacement')
    assert disp is not None and disp.GetNumberOfComponents() == 3 and disp.GetNumberOfTuples() == 11
    body = g.GetCellData().GetArray('body')
    assert [body.GetValue(c) for c in range(3)] == [0.0, 1.0, 1.0]
    assert abs(g.GetFieldData().GetArray('TimeValue').GetValue(0) - 0.25 * k) < 1e-15
    for i in range(8):
        dx, dy, dz = disp.GetTuple3(i)
        assert dx == 0.0 and dy == 0.0 and abs(dz - 0.1 * k) < 1e-15, (i, disp.GetTuple3(i))
        assert abs(g.GetPoint(i)[2] - (i >= 4) - 0.1 * k) < 1e-15
    for j in range(3):
        assert disp.GetTuple3(8 + j) == (0.0, 0.01 * k * j, 0.0), (j, disp.GetTuple3(8 + j))
print('ok', len(sets))
"#;
    let out = run_python(code, &[w.pvd_path().to_str().unwrap()]);
    assert_eq!(out.trim(), "ok 4");
}

/// A results file written from scratch by h5py (libhdf5: contiguous datasets, its own attribute
/// and string encodings) following docs/formats/results.md is read correctly, as long as it keeps
/// the documented types; a float32 `q` and an impossible row count are refused with located errors.
#[test]
fn reads_results_written_by_h5py() {
    if !python_has(&["h5py", "numpy"], "reads_results_written_by_h5py") {
        return;
    }
    let dir = temp_dir("results-from-h5py");
    let path = dir.join("py.h5");
    let code = r#"
import sys, h5py, numpy as np
S = h5py.string_dtype()
with h5py.File(sys.argv[1], 'w') as f:
    f.attrs.update(format='flexmbs-results', format_version=1, model='pendulum', status='interrupted',
                   status_time=0.25, status_message='', author='h5py')
    f['time'] = [0.0, 0.1, 0.2]
    f['q'] = np.arange(6, dtype=float).reshape(3, 2) / 8
    f['u'] = np.zeros((3, 1))
    f['lambda'] = np.zeros((3, 0))
    f['energy'] = np.ones((3, 4)); f['drift'] = np.zeros((3, 2)); f['step'] = np.full((3, 3), 0.1)
    f['coordinates'] = np.array(['phi', 'psi'], dtype=S)
    f['velocities'] = np.array(['dphi'], dtype=S)
    f['multipliers'] = np.array([], dtype=S)
    g = f.create_group('signals'); g.attrs['names'] = np.array(['bob.position'], dtype=S)
    d = g.create_dataset('bob.position', data=np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]))
    d.attrs['unit'] = 'm'; d.attrs['components'] = np.array(['x', 'y'], dtype=S)
with h5py.File(sys.argv[2], 'w') as f2, h5py.File(sys.argv[1], 'r') as f:
    for k in f: f.copy(k, f2)
    f2.attrs.update(f.attrs)
    del f2['q']; f2['q'] = np.zeros((3, 2), dtype=np.float32)
with h5py.File(sys.argv[3], 'w') as f3, h5py.File(sys.argv[1], 'r') as f:
    for k in f: f.copy(k, f3)
    f3.attrs.update(f.attrs)
    del f3['time']; f3.create_dataset('time', shape=(10**12,), dtype='f8', chunks=(1024,))
"#;
    let bad = dir.join("f32.h5");
    let huge = dir.join("huge.h5");
    run_python(
        code,
        &[
            path.to_str().unwrap(),
            bad.to_str().unwrap(),
            huge.to_str().unwrap(),
        ],
    );
    let r = flexmbs_io::results::read_results(&path).unwrap();
    assert_eq!(r.status, RunStatus::Interrupted { t: 0.25 });
    assert_eq!(r.layout.model, "pendulum");
    assert_eq!(r.layout.coordinates, ["phi", "psi"]);
    assert!(r.layout.multipliers.is_empty());
    assert_eq!(r.time, [0.0, 0.1, 0.2]);
    assert_eq!(r.series("q/psi").unwrap(), [0.125, 0.375, 0.625]);
    assert_eq!(r.series("bob.position.y").unwrap(), [2.0, 4.0, 6.0]);
    assert_eq!(r.series("energy/total").unwrap(), [4.0; 3]);
    assert_eq!(r.attribute("author"), Some("h5py"));
    let err = flexmbs_io::results::read_results(&bad)
        .unwrap_err()
        .to_string();
    assert!(err.contains("'q'") && err.contains("f64"), "{err}");
    // A shape of 10^12 rows (legal HDF5, chunks never written) is refused before any allocation.
    let err = flexmbs_io::results::read_results(&huge)
        .unwrap_err()
        .to_string();
    assert!(err.contains("'time'") && err.contains("file size"), "{err}");
}
