//! Reduced-body files are checked for physical consistency when written and read (symmetry and
//! definiteness of the reduced matrices, rigid null space, stored frequencies, node masses), and
//! their text fields are covered by a checksum (format version 2; version 1 still read).

use crate::body_file_support;

use body_file_support::{sample_body, temp_dir};
use faer::Mat;
use flexmbs_fe::eigen::dense_generalized;
use flexmbs_fe::modes::frequencies_hz;
use flexmbs_fe::reduction::{ReducedBody, ReductionKind};
use flexmbs_io::body_file::{read_body, text_sha256, write_body, BodyFileError};
use hdf5_pure::{AttrValue, File};
use std::path::{Path, PathBuf};

/// The error of writing `body`, which must be refused without creating the file.
fn refused(tag: &str, body: &ReducedBody) -> String {
    let path = temp_dir(tag).join("bad.fmb.h5");
    let err = write_body(&path, body).expect_err("an inconsistent body must be refused");
    assert!(matches!(err, BodyFileError::Invalid { .. }), "{err:?}");
    assert!(!path.exists(), "nothing may be written");
    err.to_string()
}

/// Recomputes the stored frequencies from the reduced pair (after an edit of K or M).
fn refresh_frequencies(b: &mut ReducedBody) {
    let (w2, _) = dense_generalized(b.k_red.as_ref(), b.m_red.as_ref()).unwrap();
    b.frequencies_hz = frequencies_hz(&w2);
}

fn written(tag: &str) -> PathBuf {
    let path = temp_dir(tag).join("arm.fmb.h5");
    write_body(&path, &sample_body(20, 3, 2)).unwrap();
    path
}

fn replace_f64(path: &Path, name: &str, data: &[f64], shape: &[u64]) {
    let file = File::open_rw(path).unwrap();
    let root = file.root();
    root.delete(name).unwrap();
    root.create_dataset(name, |b| {
        b.with_f64_data(data).with_shape(shape);
    })
    .unwrap();
    file.commit().unwrap();
}

#[test]
fn consistent_body_round_trips_with_version_2_and_its_digest() {
    let path = written("cons-ok");
    let body = sample_body(20, 3, 2);
    assert_eq!(read_body(&path).unwrap(), body);
    let file = File::open(&path).unwrap();
    let attrs = file.root().attrs().unwrap();
    assert_eq!(attrs["format_version"], AttrValue::I64(2));
    let digest = attrs["text_sha256"].as_str().unwrap().to_string();
    assert_eq!(digest, text_sha256(&body, None));
    assert_eq!(digest.len(), 64);
}

#[test]
fn unsymmetric_stiffness_is_refused() {
    let mut b = sample_body(20, 3, 2);
    b.k_red[(0, 1)] *= 1.0 + 1e-6;
    b.k_red[(0, 1)] += 1e-3;
    let msg = refused("cons-sym", &b);
    assert!(
        msg.contains("'reduced/stiffness'") && msg.contains("not symmetric"),
        "{msg}"
    );
}

#[test]
fn negative_reduced_mass_is_refused() {
    let mut b = sample_body(20, 3, 2);
    b.m_red[(1, 1)] = -b.m_red[(1, 1)];
    let msg = refused("cons-mneg", &b);
    assert!(
        msg.contains("'reduced/mass'") && msg.contains("not positive definite"),
        "{msg}"
    );
}

#[test]
fn indefinite_stiffness_is_refused() {
    let mut b = sample_body(20, 3, 2);
    b.k_red[(2, 2)] = -1e7;
    let msg = refused("cons-kneg", &b);
    assert!(
        msg.contains("'reduced/stiffness'") && msg.contains("indefinite"),
        "{msg}"
    );
}

#[test]
fn frequencies_that_do_not_belong_to_the_matrices_are_refused() {
    let mut b = sample_body(20, 3, 2);
    b.frequencies_hz[1] *= 1.0 + 1e-4;
    let msg = refused("cons-freq", &b);
    assert!(
        msg.contains("'modes/frequency_hz'") && msg.contains("do not belong"),
        "{msg}"
    );
    // Round-off is accepted: a relative 1e-9 change in frequency.
    let mut b = sample_body(20, 3, 2);
    b.frequencies_hz[1] *= 1.0 + 1e-9;
    write_body(&temp_dir("cons-freq-ok").join("a.fmb.h5"), &b).unwrap();
}

/// A rigid-body mode in an FFR basis (modal, free-free) is refused; a Craig-Bampton basis may
/// span the rigid motion (up to six modes).
#[test]
fn rigid_null_space_is_checked_by_reduction_kind() {
    let mut b = sample_body(20, 3, 2);
    for j in 0..3 {
        b.k_red[(0, j)] = 0.0;
        b.k_red[(j, 0)] = 0.0;
    }
    refresh_frequencies(&mut b);
    write_body(&temp_dir("cons-null-cb").join("a.fmb.h5"), &b).unwrap();
    for kind in [ReductionKind::Modal, ReductionKind::FreeFree] {
        b.kind = kind;
        let msg = refused("cons-null", &b);
        assert!(
            msg.contains("1 zero-energy modes") && msg.contains("rigid-body"),
            "{msg}"
        );
    }
}

#[test]
fn scaled_node_masses_are_refused() {
    // With rotational mode shapes the lumped translational projection is a lower bound.
    let mut b = sample_body(20, 3, 2);
    for m in b.node_masses.as_mut().unwrap() {
        *m *= 10.0;
    }
    let msg = refused("cons-m10", &b);
    assert!(
        msg.contains("'nodes/mass'") && msg.contains("ratio 9.99"),
        "{msg}"
    );
    // Without rotations it is exact: too small is refused as well.
    let mut b = solid_body();
    write_body(&temp_dir("cons-solid").join("a.fmb.h5"), &b).unwrap();
    for m in b.node_masses.as_mut().unwrap() {
        *m *= 0.5;
    }
    let msg = refused("cons-m05", &b);
    assert!(
        msg.contains("ratio 0.5") && msg.contains("expected 1"),
        "{msg}"
    );
}

/// The sample body without rotations, its reduced mass the exact lumped projection.
fn solid_body() -> ReducedBody {
    let mut b = sample_body(20, 3, 2);
    b.modes_r = None;
    let m = b.node_masses.clone().unwrap();
    let nf = b.num_modes();
    b.m_red = Mat::from_fn(nf, nf, |i, j| {
        (0..3 * m.len())
            .map(|r| m[r / 3] * b.modes_t[(r, i)] * b.modes_t[(r, j)])
            .sum()
    });
    refresh_frequencies(&mut b);
    b
}

#[test]
fn non_finite_mode_shape_is_refused() {
    let mut b = sample_body(20, 3, 2);
    b.modes_t[(7, 2)] = f64::NAN;
    let msg = refused("cons-nan", &b);
    assert!(
        msg.contains("'modes/translation'") && msg.contains("[7, 2] is NaN"),
        "{msg}"
    );
}

/// The reader applies the same checks to a file edited after writing.
#[test]
fn edited_node_masses_are_refused_on_reading() {
    let path = written("cons-read-m");
    let mut m = sample_body(20, 3, 2).node_masses.unwrap();
    for x in &mut m {
        *x *= 10.0;
    }
    replace_f64(&path, "nodes/mass", &m, &[20]);
    let msg = read_body(&path).unwrap_err().to_string();
    assert!(
        msg.contains("arm.fmb.h5") && msg.contains("'nodes/mass'"),
        "{msg}"
    );
}

#[test]
fn edited_text_fields_are_refused_by_their_checksum() {
    let path = written("cons-text");
    let file = File::open_rw(&path).unwrap();
    file.root()
        .set_attr("name", AttrValue::VarLenString("crank arn".into()))
        .unwrap();
    file.commit().unwrap();
    let msg = read_body(&path).unwrap_err().to_string();
    assert!(
        msg.contains("'/@text_sha256'") && msg.contains("altered"),
        "{msg}"
    );

    let path = written("cons-label");
    let file = File::open_rw(&path).unwrap();
    let root = file.root();
    root.delete("modes/label_dominant").unwrap();
    root.create_dataset("modes/label_dominant", |b| {
        b.with_vlen_strings(&["ux", "uy", "rz"]);
    })
    .unwrap();
    file.commit().unwrap();
    let msg = read_body(&path).unwrap_err().to_string();
    assert!(msg.contains("'/@text_sha256'"), "{msg}");
}

/// Version 1 files (no text checksum) are still read.
#[test]
fn version_1_file_is_read_without_a_text_checksum() {
    let path = written("cons-v1");
    let file = File::open_rw(&path).unwrap();
    let root = file.root();
    root.set_attr("format_version", AttrValue::I64(1)).unwrap();
    root.set_attr("name", AttrValue::VarLenString("renamed".into()))
        .unwrap();
    file.commit().unwrap();
    assert_eq!(read_body(&path).unwrap().name, "renamed");
}
