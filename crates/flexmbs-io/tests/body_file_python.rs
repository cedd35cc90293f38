//! Interoperability of the reduced-body file with the reference HDF5 library: h5py (libhdf5)
//! reads what we write, and we read what h5py writes. Skipped with a printed reason when python3,
//! h5py or numpy are missing (CI: `pip install h5py numpy`). `h5dump` (Debian `hdf5-tools`) is
//! checked when installed.

use crate::body_file_support;

use body_file_support::{python_has, run_python, sample_body, sample_geometric, temp_dir};
use flexmbs_fe::geometric::InertialLoad;
use flexmbs_fe::reduction::ReductionKind;
use flexmbs_fe::UnitSystem;
use flexmbs_io::body_file::{
    read_body, read_body_file, write_body, write_body_file, BodyFile, BodyFileError,
};
use std::process::Command;

/// h5py opens the file, sees the documented layout, shapes, attributes and exact values.
#[test]
fn h5py_reads_written_file() {
    if !python_has(&["h5py", "numpy"], "h5py_reads_written_file") {
        return;
    }
    let dir = temp_dir("py-read");
    let body = sample_body(30, 5, 11);
    let path = dir.join("arm.fmb.h5");
    write_body(&path, &body).unwrap();
    let code = r#"
import sys, h5py, numpy as np
f = h5py.File(sys.argv[1], 'r')
a = f.attrs
assert a['format'] == 'flexmbs.reduced_body', a['format']
assert int(a['format_version']) == 2
assert a['units'] == 'SI(mm)' and a['name'] == 'crank arm' and a['reduction'] == 'craig_bampton'
assert f['provenance'].attrs['notes'].endswith('(µm mesh)')
t = f['modes/translation']
assert t.dtype == np.float64 and t.shape == (90, 5), (t.dtype, t.shape)
assert f['modes/rotation'].shape == (90, 5)
assert f['nodes/position'].shape == (30, 3) and f['nodes/id'].dtype == np.uint64
assert f['reduced/stiffness'].shape == (5, 5) and f['reduced/mass'].shape == (5, 5)
assert f['modes/effective_mass_fraction'].shape == (5, 3)
dom = [s.decode() if isinstance(s, bytes) else s for s in f['modes/label_dominant'][()]]
assert dom == ['ux', 'uy', 'uz', 'rx', 'ry'], dom
names = list(f['cells/kind'].attrs['names'])
kinds = [names[k] for k in f['cells/kind'][()]]
assert kinds == ['Hex8', 'Hex8I', 'Hex20', 'Hex20R', 'Tet10', 'Beam2'], kinds
off = f['cells/offsets'][()]
assert list(off) == [0, 8, 16, 36, 56, 66, 68], off
# Node 7, y translation (row 3*7+1) of mode 3 (column 2): exact bits.
bits = lambda x: int(np.float64(x).view(np.uint64))
print(bits(t[3*7+1, 2]), bits(f['nodes/position'][4, 1]), bits(f['reduced/stiffness'][1, 0]),
      int(f['nodes/id'][29]), f['nodes/fixed'][()].tolist(), f['nodes/interface'][()].tolist())
"#;
    let out = run_python(code, &[path.to_str().unwrap()]);
    let v: Vec<&str> = out.split_whitespace().collect();
    assert_eq!(
        v[0].parse::<u64>().unwrap(),
        body.modes_t[(3 * 7 + 1, 2)].to_bits()
    );
    assert_eq!(v[1].parse::<u64>().unwrap(), body.nodes[4][1].to_bits());
    assert_eq!(v[2].parse::<u64>().unwrap(), body.k_red[(1, 0)].to_bits());
    assert_eq!(v[3].parse::<u64>().unwrap(), body.node_ids[29]);
    assert_eq!(out.split_once('[').unwrap().1.trim(), "2] [0, 3, 29]");
}

/// A body of 70 000 nodes (index vectors longer than 65 535 entries, which once gave chunk
/// dimensions libhdf5 refused to open): h5py reads every dataset, the node ids to the last.
#[test]
fn h5py_reads_every_dataset_of_a_large_body() {
    if !python_has(
        &["h5py", "numpy"],
        "h5py_reads_every_dataset_of_a_large_body",
    ) {
        return;
    }
    let dir = temp_dir("py-large");
    let mut body = sample_body(70_000, 1, 5);
    for (i, id) in body.node_ids.iter_mut().enumerate() {
        *id = 10 * i as u64 + 1;
    }
    let path = dir.join("large.fmb.h5");
    write_body(&path, &body).unwrap();
    let code = r#"
import sys, h5py
f = h5py.File(sys.argv[1], 'r')
names = []
f.visit(names.append)
for n in names:
    o = f[n]
    if isinstance(o, h5py.Dataset):
        o[()]
print(len(names), int(f['nodes/id'][-1]), f['nodes/id'].shape[0])
"#;
    let out = run_python(code, &[path.to_str().unwrap()]);
    let v: Vec<&str> = out.split_whitespace().collect();
    assert!(v[0].parse::<usize>().unwrap() > 10, "{out}");
    assert_eq!(v[1], "699991", "{out}");
    assert_eq!(v[2], "70000", "{out}");
}

/// libhdf5 rewrites every object of our file (h5py `copy`, which goes through H5Ocopy and writes
/// its own object headers and heaps); our reader gets back exactly the same body.
#[test]
fn file_rewritten_by_h5py_reads_back_identically() {
    if !python_has(
        &["h5py", "numpy"],
        "file_rewritten_by_h5py_reads_back_identically",
    ) {
        return;
    }
    let dir = temp_dir("py-copy");
    let body = sample_body(50, 6, 21);
    let src = dir.join("src.fmb.h5");
    let dst = dir.join("dst.fmb.h5");
    write_body(&src, &body).unwrap();
    let code = r#"
import sys, h5py
with h5py.File(sys.argv[1], 'r') as a, h5py.File(sys.argv[2], 'w') as b:
    for k in a:
        a.copy(k, b)
    for k, v in a.attrs.items():
        b.attrs[k] = v
"#;
    run_python(code, &[src.to_str().unwrap(), dst.to_str().unwrap()]);
    assert_ne!(std::fs::read(&src).unwrap(), std::fs::read(&dst).unwrap());
    assert_eq!(read_body(&dst).unwrap(), body);
}

/// A body written from scratch by a Python user with plain NumPy types (int64 indices, Python
/// str attributes) following docs/formats/reduced-body.md is read correctly.
#[test]
fn reads_file_written_from_scratch_by_h5py() {
    if !python_has(
        &["h5py", "numpy"],
        "reads_file_written_from_scratch_by_h5py",
    ) {
        return;
    }
    let dir = temp_dir("py-write");
    let path = dir.join("py.fmb.h5");
    let code = r#"
import sys, h5py, numpy as np
n, nf = 4, 2
with h5py.File(sys.argv[1], 'w') as f:
    f.attrs.update(format='flexmbs.reduced_body', format_version=1, name='plate', units='SI',
                   reduction='modal', internal_modes=0)
    p = f.create_group('provenance'); p.attrs.update(source='python', program='h5py', notes='')
    f['nodes/position'] = np.arange(12, dtype=float).reshape(n, 3) / 10
    f['nodes/id'] = np.array([10, 20, 30, 40])            # int64
    f['nodes/interface'] = np.zeros(0, dtype=np.int64)
    f['nodes/fixed'] = np.array([0])
    f['modes/translation'] = np.arange(3*n*nf, dtype=float).reshape(3*n, nf)
    f['modes/frequency_hz'] = [12.5, 40.0]
    f['modes/label_index'] = [1, 2]
    f['modes/label_frequency_hz'] = [12.5, 40.0]
    f['modes/label_dominant'] = ['uz', 'rx']
    f['modes/effective_mass_fraction'] = np.array([[0.0, 0.0, 0.6], [0.1, 0.0, 0.0]])
    f['reduced/stiffness'] = np.diag((2*np.pi*np.array([12.5, 40.0]))**2)
    f['reduced/mass'] = np.eye(2)
    f['cells/kind'] = np.array([0], dtype=np.uint8)
    f['cells/kind'].attrs['names'] = ['Hex8']
    f['cells/offsets'] = [0, 8]
    f['cells/connectivity'] = [0, 1, 2, 3, 0, 1, 2, 3]
"#;
    run_python(code, &[path.to_str().unwrap()]);
    let b = read_body(&path).unwrap();
    assert_eq!(b.name, "plate");
    assert_eq!(b.units, UnitSystem::Si);
    assert_eq!(b.kind, ReductionKind::Modal);
    assert_eq!(b.node_ids, vec![10, 20, 30, 40]);
    assert_eq!(b.nodes[3], [0.9, 1.0, 1.1]);
    assert_eq!(b.fixed_nodes, vec![0]);
    assert!(b.interface_nodes.is_empty() && b.node_masses.is_none() && b.modes_r.is_none());
    assert_eq!((b.modes_t.nrows(), b.modes_t.ncols()), (12, 2));
    assert_eq!(b.modes_t[(5, 1)], 11.0); // row-major arange: row 5, col 1 = 5*2+1
    let w = 2.0 * std::f64::consts::PI * 40.0;
    assert_eq!(b.k_red[(1, 1)], w * w);
    assert_eq!(b.k_red[(0, 1)], 0.0);
    assert_eq!(b.labels[1].dominant, "rx");
    assert_eq!(b.labels[0].effective_mass_fraction, [0.0, 0.0, 0.6]);
    assert_eq!(b.cells.len(), 1);
    assert_eq!(b.cells[0].nodes, vec![0, 1, 2, 3, 0, 1, 2, 3]);

    // The same file with a float32 mode matrix is refused with a located type error.
    let code32 = r#"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], 'a') as f:
    t = f['modes/translation'][()]
    del f['modes/translation']
    f['modes/translation'] = t.astype(np.float32)
"#;
    run_python(code32, &[path.to_str().unwrap()]);
    match read_body(&path) {
        Err(BodyFileError::WrongType {
            dataset, expected, ..
        }) => {
            assert_eq!(dataset, "modes/translation");
            assert_eq!(expected, "f64");
        }
        other => panic!("expected WrongType, got {other:?}"),
    }
}

/// The reference command-line tools list and dump the file without complaint.
#[test]
fn h5dump_and_h5ls_read_written_file() {
    let dir = temp_dir("h5dump");
    let body = sample_body(20, 2, 5);
    let path = dir.join("arm.fmb.h5");
    write_body(&path, &body).unwrap();
    let out = match Command::new("h5dump").arg(&path).output() {
        Ok(o) => o,
        Err(e) => {
            flexmbs_io::test_tools::skip_for_missing_tool(
                "h5dump_and_h5ls_read_written_file",
                &format!("h5dump not runnable ({e}); apt-get install hdf5-tools"),
            );
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "h5dump failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "h5dump warnings: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needle in [
        "DATASET \"translation\"",
        "DATASPACE  SIMPLE { ( 60, 2 ) / ( 60, 2 ) }",
        "\"flexmbs.reduced_body\"",
        "H5T_STD_U64LE",
    ] {
        assert!(text.contains(needle), "h5dump output lacks {needle:?}");
    }
    let ls = Command::new("h5ls").arg("-r").arg(&path).output().unwrap();
    assert!(ls.status.success());
    let ls = String::from_utf8_lossy(&ls.stdout);
    let line = ls
        .lines()
        .find(|l| l.starts_with("/modes/translation "))
        .unwrap_or("");
    assert!(line.ends_with("Dataset {60, 2}"), "{ls}");
}

/// The optional `geometric` group: h5py reads our K_G (shape, pattern names, exact bits) and we
/// read K_G that h5py writes into a body file (numpy `(P, N_f, N_f)` array, Python strings),
/// bit for bit.
#[test]
fn geometric_stiffness_interoperates_with_h5py() {
    if !python_has(
        &["h5py", "numpy"],
        "geometric_stiffness_interoperates_with_h5py",
    ) {
        return;
    }
    let dir = temp_dir("py-kg");
    let body = sample_body(20, 4, 3);
    let g = sample_geometric(4, 8);
    let path = dir.join("arm.fmb.h5");
    write_body_file(&path, &body, Some(&g)).unwrap();
    let code = r#"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], 'a') as f:
    k = f['geometric/stiffness']
    assert k.dtype == np.float64 and k.shape == (6, 4, 4), (k.dtype, k.shape)
    names = f['geometric/load_pattern'].asstr()[()].tolist()
    assert names == ['centrifugal_xx', 'centrifugal_xy', 'centrifugal_xz', 'centrifugal_yy',
                     'centrifugal_yz', 'centrifugal_zz'], names
    kv = k[()]
    assert np.array_equal(kv, np.transpose(kv, (0, 2, 1)))
    print(int(np.float64(kv[4, 1, 3]).view(np.uint64)))
    # replace by two patterns written the numpy way
    del f['geometric']
    g = f.create_group('geometric')
    g['load_pattern'] = ['centrifugal_yy', 'centrifugal_zz']
    a = np.arange(16.0).reshape(4, 4) / 3.0
    g['stiffness'] = np.stack([a + a.T, -(a + a.T)])
    # the text fields changed: recompute their checksum as the format documents it
    import hashlib
    h = hashlib.sha256()
    p = f['provenance'].attrs
    fields = [f.attrs['name'], f.attrs['units'], f.attrs['reduction'], p['source'], p['program'],
              p['notes']] + f['modes/label_dominant'].asstr()[()].tolist() \
             + ['centrifugal_yy', 'centrifugal_zz']
    for s in fields:
        h.update(s.encode('utf-8') + b'\0')
    f.attrs['text_sha256'] = h.hexdigest()
"#;
    let out = run_python(code, &[path.to_str().unwrap()]);
    assert_eq!(
        out.trim().parse::<u64>().unwrap(),
        g.matrices[4][(1, 3)].to_bits()
    );
    let back = read_body_file(&path).unwrap();
    assert_eq!(back.body, body);
    let kg = back.geometric.unwrap();
    assert_eq!(
        kg.load_patterns,
        vec![
            InertialLoad::Centrifugal(1, 1),
            InertialLoad::Centrifugal(2, 2)
        ]
    );
    let a = |i: usize, j: usize| (4 * i + j) as f64 / 3.0;
    for i in 0..4 {
        for j in 0..4 {
            assert_eq!(
                kg.matrices[0][(i, j)].to_bits(),
                (a(i, j) + a(j, i)).to_bits()
            );
            assert_eq!(
                kg.matrices[1][(i, j)].to_bits(),
                (-(a(i, j) + a(j, i))).to_bits()
            );
        }
    }
}

/// The optional `nodes/rotary_inertia`: h5py reads ours (shape `(N, 3, 3)`, row-major per node,
/// exact bits) and we read node inertias h5py writes (a numpy stack of `diag(1, 2, 3) k / 7`),
/// bit for bit; a non-symmetric one written by h5py is refused with the dataset and node named.
#[test]
fn rotary_inertia_interoperates_with_h5py() {
    if !python_has(&["h5py", "numpy"], "rotary_inertia_interoperates_with_h5py") {
        return;
    }
    let dir = temp_dir("py-rot");
    let body = sample_body(20, 3, 5);
    let r = body_file_support::sample_rotary(20, 6);
    let path = dir.join("beam.fmb.h5");
    BodyFile {
        body: body.clone(),
        geometric: None,
        rotary_inertia: Some(r.clone()),
        stress: None,
        inertia_gram: None,
    }
    .write(&path)
    .unwrap();
    let code = r#"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], 'a') as f:
    d = f['nodes/rotary_inertia']
    assert d.dtype == np.float64 and d.shape == (20, 3, 3), (d.dtype, d.shape)
    v = d[()]
    assert np.array_equal(v, np.transpose(v, (0, 2, 1)))
    print(int(np.float64(v[7, 0, 2]).view(np.uint64)))
    del f['nodes/rotary_inertia']
    k = np.arange(20.0).reshape(20, 1, 1)
    f['nodes/rotary_inertia'] = np.diag([1.0, 2.0, 3.0])[None, :, :] * k / 7.0
    if sys.argv[2] == 'asym':
        d = f['nodes/rotary_inertia']
        d[3, 0, 1] = 1.0
"#;
    let out = run_python(code, &[path.to_str().unwrap(), "sym"]);
    assert_eq!(out.trim().parse::<u64>().unwrap(), r[7][(0, 2)].to_bits());
    let back = read_body_file(&path).unwrap();
    assert_eq!(back.body, body);
    let stored = back.rotary_inertia.unwrap();
    for (k, m) in stored.iter().enumerate() {
        for a in 0..3 {
            for b in 0..3 {
                let e = if a == b {
                    (a + 1) as f64 * k as f64 / 7.0
                } else {
                    0.0
                };
                assert_eq!(m[(a, b)].to_bits(), e.to_bits(), "node {k} ({a}, {b})");
            }
        }
    }
    run_python(code, &[path.to_str().unwrap(), "asym"]);
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'nodes/rotary_inertia'") && s.contains("node 3: not symmetric"),
        "{s}"
    );
}
