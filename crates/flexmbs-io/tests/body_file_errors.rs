//! Reduced-body file: bad, foreign, damaged and inconsistent files give located errors, never a
//! panic.

use crate::body_file_support;

use body_file_support::{sample_body, sample_geometric, sample_rotary, temp_dir};
use flexmbs_io::body_file::{
    decode_body_file, read_body, read_body_file, write_body, write_body_file, BodyFile,
    BodyFileError,
};
use hdf5_pure::{AttrValue, File, FileBuilder};
use std::path::{Path, PathBuf};

fn written(tag: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let path = dir.join("arm.fmb.h5");
    write_body(&path, &sample_body(20, 3, 2)).unwrap();
    (dir, path)
}

/// A valid body file with the optional geometric stiffness (3 modes, six patterns).
fn written_kg(tag: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let path = dir.join("arm.fmb.h5");
    write_body_file(&path, &sample_body(20, 3, 2), Some(&sample_geometric(3, 4))).unwrap();
    (dir, path)
}

/// A valid body file with geometric stiffness and node rotary inertias (20 nodes).
fn written_rot(tag: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let path = dir.join("arm.fmb.h5");
    BodyFile {
        body: sample_body(20, 3, 2),
        geometric: Some(sample_geometric(3, 4)),
        rotary_inertia: Some(sample_rotary(20, 5)),
        stress: None,
        inertia_gram: None,
    }
    .write(&path)
    .unwrap();
    (dir, path)
}

/// Applies an in-place edit (hdf5-pure's `open_rw`) to a valid body file.
fn edit(path: &Path, f: impl FnOnce(&File)) {
    let file = File::open_rw(path).unwrap();
    f(&file);
    file.commit().unwrap();
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let err = read_body(Path::new("/nonexistent/dir/x.fmb.h5")).unwrap_err();
    assert!(matches!(err, BodyFileError::Io { .. }));
    assert!(
        err.to_string().starts_with("/nonexistent/dir/x.fmb.h5: "),
        "{err}"
    );
}

#[test]
fn text_file_is_rejected_as_not_hdf5() {
    let dir = temp_dir("err-text");
    let path = dir.join("nodes.txt");
    std::fs::write(&path, "1, 0.0, 0.0, 0.0\n2, 1.0, 0.0, 0.0\n").unwrap();
    let err = read_body(&path).unwrap_err();
    assert!(matches!(err, BodyFileError::Hdf5 { .. }), "{err:?}");
    assert!(err.to_string().contains("nodes.txt"), "{err}");
}

#[test]
fn foreign_hdf5_file_is_not_a_body_file() {
    let dir = temp_dir("err-foreign");
    let path = dir.join("other.h5");
    let mut fb = FileBuilder::new();
    fb.create_dataset("temperature").with_f64_data(&[1.0, 2.0]);
    fb.write(&path).unwrap();
    let err = read_body(&path).unwrap_err();
    assert!(matches!(err, BodyFileError::NotABodyFile { .. }), "{err:?}");
    let mut fb = FileBuilder::new();
    fb.set_attr("format", AttrValue::VarLenString("netcdf".into()));
    fb.write(&path).unwrap();
    let err = read_body(&path).unwrap_err();
    assert!(err.to_string().contains("format = 'netcdf'"), "{err}");
}

#[test]
fn future_format_version_is_refused() {
    let (_d, path) = written("err-version");
    edit(&path, |f| {
        f.root()
            .set_attr("format_version", AttrValue::I64(3))
            .unwrap()
    });
    match read_body(&path) {
        Err(BodyFileError::UnsupportedVersion {
            found: 3,
            supported: 2,
            ..
        }) => {}
        other => panic!("expected UnsupportedVersion, got {other:?}"),
    }
}

#[test]
fn missing_dataset_is_named() {
    let (_d, path) = written("err-missing");
    edit(&path, |f| f.root().delete("modes/translation").unwrap());
    match read_body(&path) {
        Err(BodyFileError::MissingDataset { dataset, .. }) => {
            assert_eq!(dataset, "modes/translation")
        }
        other => panic!("expected MissingDataset, got {other:?}"),
    }
}

#[test]
fn wrong_shape_is_located() {
    let (_d, path) = written("err-shape");
    edit(&path, |f| {
        let root = f.root();
        root.delete("reduced/stiffness").unwrap();
        root.create_dataset("reduced/stiffness", |b| {
            b.with_f64_data(&[0.0; 12]).with_shape(&[3, 4]);
        })
        .unwrap();
    });
    match read_body(&path) {
        Err(e @ BodyFileError::WrongShape { .. }) => {
            let s = e.to_string();
            assert!(
                s.contains("'reduced/stiffness' has shape [3, 4], expected [N_f, N_f] = [3, 3]"),
                "{s}"
            );
        }
        other => panic!("expected WrongShape, got {other:?}"),
    }
}

#[test]
fn index_out_of_range_is_located() {
    let (_d, path) = written("err-index");
    edit(&path, |f| {
        let root = f.root();
        root.delete("nodes/fixed").unwrap();
        root.create_dataset("nodes/fixed", |b| {
            b.with_u64_data(&[20]);
        })
        .unwrap();
    });
    let err = read_body(&path).unwrap_err();
    assert!(matches!(err, BodyFileError::Invalid { .. }), "{err:?}");
    assert!(
        err.to_string()
            .contains("'nodes/fixed': index 20 out of range (N = 20)"),
        "{err}"
    );
}

#[test]
fn bad_attribute_is_located() {
    let (_d, path) = written("err-attr");
    edit(&path, |f| {
        f.root()
            .set_attr("units", AttrValue::VarLenString("furlong".into()))
            .unwrap()
    });
    let err = read_body(&path).unwrap_err();
    assert!(err.to_string().contains("attribute '/@units'"), "{err}");
}

/// Every truncation of a valid file (at 1/97 steps and around the start) is an error; none makes
/// the HDF5 decoder panic (the panic guard in `decode_body` reports "panicked" if one did).
#[test]
fn truncated_files_are_errors_not_panics() {
    truncations_are_errors(written("err-trunc").1);
    truncations_are_errors(written_kg("err-trunc-kg").1);
}

fn truncations_are_errors(path: PathBuf) {
    let bytes = std::fs::read(&path).unwrap();
    let mut cuts: Vec<usize> = (0..97).map(|k| k * bytes.len() / 97).collect();
    cuts.extend(0..64);
    cuts.push(bytes.len() - 1);
    let mut guarded = 0;
    for &cut in &cuts {
        match decode_body_file(&path, bytes[..cut].to_vec()) {
            Ok(_) => panic!("truncation to {cut} of {} bytes was accepted", bytes.len()),
            Err(e) => guarded += usize::from(e.to_string().contains("panicked")),
        }
    }
    assert_eq!(
        guarded, 0,
        "{guarded} truncations made the HDF5 decoder panic"
    );
}

/// Corrupting single bytes anywhere gives an error or, where the byte is unused, the unchanged
/// body: metadata carries HDF5 checksums and every data array a Fletcher-32 checksum, so no
/// corruption is silently accepted. The decoder never panics.
#[test]
fn corrupted_bytes_never_panic() {
    corruptions_are_detected(written("err-flip").1, false);
    corruptions_are_detected(written_kg("err-flip-kg").1, true);
    corruptions_are_detected(written_rot("err-flip-rot").1, true);
}

/// `b` with the variable-length strings of `like` (body name, provenance, mode label names):
/// HDF5 keeps them in the global heap, which carries no checksum (a known limit of the layout).
fn with_strings_of(mut b: BodyFile, like: &BodyFile) -> BodyFile {
    b.body.name = like.body.name.clone();
    b.body.provenance = like.body.provenance.clone();
    for (l, o) in b.body.labels.iter_mut().zip(&like.body.labels) {
        l.dominant = o.dominant.clone();
    }
    b
}

/// Flips single bytes of the file at `path`. With `strings_unchecked`, a corruption that
/// changes only the body's variable-length strings (global heap, not checksummed) is tolerated
/// and counted; any other silent change (floats, indices, the geometric stiffness and its
/// pattern names, which parse strictly) fails.
fn corruptions_are_detected(path: PathBuf, strings_unchecked: bool) {
    let original = read_body_file(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let (mut errors, mut accepted, mut guarded, mut silent) = (0, 0, 0, Vec::new());
    let mut strings = 0;
    for k in 0..400 {
        let pos = (k * 7919) % bytes.len();
        let mut b = bytes.clone();
        b[pos] ^= 0x5a;
        match decode_body_file(&path, b) {
            Ok(b) => {
                accepted += 1;
                if b != original {
                    let b = with_strings_of(b, &original);
                    if strings_unchecked && b == original {
                        strings += 1;
                    } else {
                        silent.push(pos);
                    }
                }
            }
            Err(e) => {
                errors += 1;
                guarded += usize::from(e.to_string().contains("panicked"));
            }
        }
    }
    eprintln!(
        "400 corrupted copies of {} bytes: {errors} errors ({guarded} caught panics), {accepted} accepted, of which {strings} changed only strings and {} changed the body (at {silent:?})",
        bytes.len(),
        silent.len()
    );
    assert_eq!(errors + accepted, 400);
    assert!(errors > 0);
    assert!(
        silent.is_empty(),
        "silently accepted corruption at byte offsets {silent:?}"
    );
}

/// Replaces the dataset `name` of the file at `path` by `f64` data of the given shape.
fn replace_f64(path: &Path, name: &str, data: Vec<f64>, shape: Vec<u64>) {
    edit(path, |f| {
        let root = f.root();
        root.delete(name).unwrap();
        root.create_dataset(name, |b| {
            b.with_f64_data(&data).with_shape(&shape);
        })
        .unwrap();
    });
}

/// The stored K_G data of `written_kg` (six 3 x 3 matrices, row-major).
fn kg_data() -> Vec<f64> {
    let g = sample_geometric(3, 4);
    g.matrices
        .iter()
        .flat_map(|m| (0..3).flat_map(move |r| (0..3).map(move |c| m[(r, c)])))
        .collect()
}

/// Malformed geometric stiffness in a body file: every case is an error naming the dataset
/// (`read_body` checks the group too), never a panic and never silently ignored.
#[test]
fn malformed_geometric_stiffness_is_located() {
    // not symmetric: K_xy[0][2] changed by 1e-6 relative
    let (_d, path) = written_kg("err-kg-sym");
    let mut d = kg_data();
    d[9 + 2] += 1e-6 * d[9..18].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    replace_f64(&path, "geometric/stiffness", d, vec![6, 3, 3]);
    let err = read_body(&path).unwrap_err();
    assert!(matches!(err, BodyFileError::Invalid { .. }), "{err:?}");
    let s = err.to_string();
    assert!(
        s.contains("'geometric/stiffness'")
            && s.contains("matrix 1 (centrifugal_xy) is not symmetric"),
        "{s}"
    );

    // NaN entry
    let (_d, path) = written_kg("err-kg-nan");
    let mut d = kg_data();
    d[5 * 9 + 4] = f64::NAN;
    replace_f64(&path, "geometric/stiffness", d, vec![6, 3, 3]);
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'geometric/stiffness'")
            && s.contains("matrix 5 (centrifugal_zz) has the non-finite entry NaN at (1, 1)"),
        "{s}"
    );

    // shape not [P, N_f, N_f]
    let (_d, path) = written_kg("err-kg-shape");
    replace_f64(&path, "geometric/stiffness", vec![0.0; 36], vec![6, 3, 2]);
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'geometric/stiffness' has shape [6, 3, 2], expected [P, N_f, N_f] = [6, 3, 3]"),
        "{s}"
    );
    replace_f64(&path, "geometric/stiffness", vec![0.0; 54], vec![54]);
    assert!(matches!(
        read_body_file(&path),
        Err(BodyFileError::WrongShape { .. })
    ));

    // float32 matrices are refused (lossy)
    let (_d, path) = written_kg("err-kg-f32");
    edit(&path, |f| {
        let root = f.root();
        root.delete("geometric/stiffness").unwrap();
        root.create_dataset("geometric/stiffness", |b| {
            b.with_f32_data(&[0.0f32; 54]).with_shape(&[6, 3, 3]);
        })
        .unwrap();
    });
    assert!(matches!(
        read_body_file(&path),
        Err(BodyFileError::WrongType { ref dataset, .. }) if dataset == "geometric/stiffness"
    ));

    // unknown pattern name
    let (_d, path) = written_kg("err-kg-name");
    edit(&path, |f| {
        let root = f.root();
        root.delete("geometric/load_pattern").unwrap();
        root.create_dataset("geometric/load_pattern", |b| {
            b.with_vlen_strings(&[
                "centrifugal_xx",
                "centrifugal_xy",
                "centrifugal_xz",
                "centrifugal_yy",
                "coriolis_yz",
                "centrifugal_zz",
            ]);
        })
        .unwrap();
    });
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'geometric/load_pattern'")
            && s.contains("entry 4: unknown load pattern 'coriolis_yz'"),
        "{s}"
    );

    // a pattern twice
    let (_d, path) = written_kg("err-kg-dup");
    edit(&path, |f| {
        let root = f.root();
        root.delete("geometric/load_pattern").unwrap();
        root.create_dataset("geometric/load_pattern", |b| {
            b.with_vlen_strings(&[
                "centrifugal_xx",
                "centrifugal_xy",
                "centrifugal_xz",
                "centrifugal_yy",
                "centrifugal_xy",
                "centrifugal_zz",
            ]);
        })
        .unwrap();
    });
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'geometric/load_pattern'")
            && s.contains("entry 4: load pattern 'centrifugal_xy' appears twice"),
        "{s}"
    );

    // one dataset of the pair missing
    for (gone, other) in [
        ("geometric/stiffness", "geometric/load_pattern"),
        ("geometric/load_pattern", "geometric/stiffness"),
    ] {
        let (_d, path) = written_kg("err-kg-half");
        edit(&path, |f| f.root().delete(gone).unwrap());
        match read_body_file(&path) {
            Err(BodyFileError::MissingDataset { dataset, .. }) => assert_eq!(dataset, gone),
            r => panic!("{other} without {gone}: expected MissingDataset, got {r:?}"),
        }
    }

    // more patterns than matrices
    let (_d, path) = written_kg("err-kg-count");
    replace_f64(
        &path,
        "geometric/stiffness",
        kg_data()[..45].to_vec(),
        vec![5, 3, 3],
    );
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(s.contains("expected [P, N_f, N_f] = [6, 3, 3]"), "{s}");
}

/// Every single-byte corruption of the stored K_G values (located in the file by their bytes) is
/// detected by the Fletcher-32 checksum of `geometric/stiffness`: never a silently different K_G.
#[test]
fn corrupted_geometric_stiffness_data_is_detected() {
    let (_d, path) = written_kg("err-kg-flip");
    let bytes = std::fs::read(&path).unwrap();
    let data: Vec<u8> = kg_data().iter().flat_map(|x| x.to_le_bytes()).collect();
    let start = bytes
        .windows(data.len())
        .position(|w| w == data.as_slice())
        .expect("K_G data not stored contiguously");
    for pos in start..start + data.len() {
        let mut b = bytes.clone();
        b[pos] ^= 0x5a;
        match decode_body_file(&path, b) {
            Err(e) => assert!(
                e.to_string().contains("geometric/stiffness"),
                "byte {pos}: {e}"
            ),
            Ok(_) => panic!("corruption of K_G byte {} accepted", pos - start),
        }
    }
}

/// The stored node inertias of `written_rot` (20 nodes, row-major `[N, 3, 3]`).
fn rot_data() -> Vec<f64> {
    sample_rotary(20, 5)
        .iter()
        .flat_map(|m| (0..3).flat_map(move |a| (0..3).map(move |b| m[(a, b)])))
        .collect()
}

/// Malformed node rotary inertias: every case is an error naming `nodes/rotary_inertia` (and
/// the node), also through `read_body`; never a panic, never silently ignored.
#[test]
fn malformed_rotary_inertia_is_located() {
    const DS: &str = "nodes/rotary_inertia";
    let (_d, path) = written_rot("err-rot-ok");
    assert!(read_body_file(&path).unwrap().rotary_inertia.is_some());

    // not symmetric: node 6, entry (0, 2) changed by 1e-9 relative
    let mut d = rot_data();
    let scale = d[54..63].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    d[54 + 2] += 1e-9 * scale;
    replace_f64(&path, DS, d, vec![20, 3, 3]);
    let err = read_body(&path).unwrap_err();
    assert!(matches!(err, BodyFileError::Invalid { .. }), "{err:?}");
    let s = err.to_string();
    assert!(
        s.contains("'nodes/rotary_inertia'") && s.contains("node 6: not symmetric"),
        "{s}"
    );

    // NaN entry at node 11
    let mut d = rot_data();
    d[11 * 9 + 4] = f64::NAN;
    replace_f64(&path, DS, d, vec![20, 3, 3]);
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(s.contains("'nodes/rotary_inertia'") && s.contains("node 11: non-finite entry NaN"));

    // indefinite: node 2 with a negative diagonal entry
    let mut d = rot_data();
    d[2 * 9 + 8] = -1.0;
    replace_f64(&path, DS, d, vec![20, 3, 3]);
    let s = read_body_file(&path).unwrap_err().to_string();
    assert!(
        s.contains("'nodes/rotary_inertia'") && s.contains("node 2: not positive semi-definite"),
        "{s}"
    );

    // shapes other than [N, 3, 3]
    for shape in [vec![19, 3, 3], vec![20, 9], vec![20, 3, 3, 1], vec![180]] {
        let len: u64 = shape.iter().product();
        replace_f64(&path, DS, vec![0.0; len as usize], shape.clone());
        match read_body_file(&path) {
            Err(BodyFileError::WrongShape {
                dataset,
                expected,
                found,
                ..
            }) => {
                assert_eq!(dataset, DS);
                assert_eq!(expected, "[N, 3, 3] = [20, 3, 3]");
                assert_eq!(found, shape);
            }
            r => panic!("shape {shape:?}: expected WrongShape, got {r:?}"),
        }
    }

    // float32 refused (lossy)
    edit(&path, |f| {
        let root = f.root();
        root.delete(DS).unwrap();
        root.create_dataset(DS, |b| {
            b.with_f32_data(&[0.0f32; 180]).with_shape(&[20, 3, 3]);
        })
        .unwrap();
    });
    assert!(matches!(
        read_body_file(&path),
        Err(BodyFileError::WrongType { ref dataset, .. }) if dataset == DS
    ));

    // removed: the file reads as one without rotary inertias (optional dataset)
    edit(&path, |f| f.root().delete(DS).unwrap());
    assert_eq!(read_body_file(&path).unwrap().rotary_inertia, None);
}

/// Every single-byte corruption of the stored node inertias (located in the file by their
/// bytes) is detected by the Fletcher-32 checksum of `nodes/rotary_inertia`.
#[test]
fn corrupted_rotary_inertia_data_is_detected() {
    let (_d, path) = written_rot("err-rot-flip");
    let bytes = std::fs::read(&path).unwrap();
    let data: Vec<u8> = rot_data().iter().flat_map(|x| x.to_le_bytes()).collect();
    let start = bytes
        .windows(data.len())
        .position(|w| w == data.as_slice())
        .expect("rotary inertia data not stored contiguously");
    for pos in start..start + data.len() {
        let mut b = bytes.clone();
        b[pos] ^= 0x5a;
        match decode_body_file(&path, b) {
            Err(e) => assert!(
                e.to_string().contains("nodes/rotary_inertia"),
                "byte {pos}: {e}"
            ),
            Ok(_) => panic!("corruption of rotary inertia byte {} accepted", pos - start),
        }
    }
}
