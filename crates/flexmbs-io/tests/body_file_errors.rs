//! Reduced-body file: bad, foreign, damaged and inconsistent files give located errors, never a
//! panic.

mod body_file_support;

use body_file_support::{sample_body, temp_dir};
use flexmbs_io::body_file::{decode_body, read_body, write_body, BodyFileError};
use hdf5_pure::{AttrValue, File, FileBuilder};
use std::path::{Path, PathBuf};

fn written(tag: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(tag);
    let path = dir.join("arm.fmb.h5");
    write_body(&path, &sample_body(20, 3, 2)).unwrap();
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
            .set_attr("format_version", AttrValue::I64(2))
            .unwrap()
    });
    match read_body(&path) {
        Err(BodyFileError::UnsupportedVersion {
            found: 2,
            supported: 1,
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
    let (_d, path) = written("err-trunc");
    let bytes = std::fs::read(&path).unwrap();
    let mut cuts: Vec<usize> = (0..97).map(|k| k * bytes.len() / 97).collect();
    cuts.extend(0..64);
    cuts.push(bytes.len() - 1);
    let mut guarded = 0;
    for &cut in &cuts {
        match decode_body(&path, bytes[..cut].to_vec()) {
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
    let (_d, path) = written("err-flip");
    let original = read_body(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let (mut errors, mut accepted, mut guarded, mut silent) = (0, 0, 0, Vec::new());
    for k in 0..400 {
        let pos = (k * 7919) % bytes.len();
        let mut b = bytes.clone();
        b[pos] ^= 0x5a;
        match decode_body(&path, b) {
            Ok(b) => {
                accepted += 1;
                if b != original {
                    silent.push(pos);
                }
            }
            Err(e) => {
                errors += 1;
                guarded += usize::from(e.to_string().contains("panicked"));
            }
        }
    }
    eprintln!(
        "400 corrupted copies of {} bytes: {errors} errors ({guarded} caught panics), {accepted} accepted, of which {} changed the body (at {silent:?})",
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
