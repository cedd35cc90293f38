//! Reduced-body file: write -> read round trips are bit-identical; timing for a large body.

use crate::body_file_support;

use body_file_support::{sample_body, sample_geometric, temp_dir};
use faer::Mat;
use flexmbs_fe::geometric::InertialLoad;
use flexmbs_fe::reduction::{ReducedBody, ReductionKind};
use flexmbs_io::body_file::{
    read_body, read_body_file, write_body, write_body_file, BodyFile, BodyFileError,
};
use std::time::Instant;

fn mat_bits(m: &Mat<f64>) -> Vec<u64> {
    (0..m.ncols())
        .flat_map(|c| (0..m.nrows()).map(move |r| (r, c)))
        .map(|(r, c)| m[(r, c)].to_bits())
        .collect()
}

/// Bitwise equality of every float (distinguishes -0.0 from 0.0 and compares NaN payloads).
fn assert_bits_equal(a: &ReducedBody, b: &ReducedBody) {
    let nb = |x: &ReducedBody| {
        x.nodes
            .iter()
            .flatten()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(nb(a), nb(b));
    assert_eq!(mat_bits(&a.modes_t), mat_bits(&b.modes_t));
    assert_eq!(
        a.modes_r.as_ref().map(mat_bits),
        b.modes_r.as_ref().map(mat_bits)
    );
    assert_eq!(mat_bits(&a.k_red), mat_bits(&b.k_red));
    assert_eq!(mat_bits(&a.m_red), mat_bits(&b.m_red));
    let fb = |x: &ReducedBody| {
        x.frequencies_hz
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(fb(a), fb(b));
    let lb = |x: &ReducedBody| {
        x.labels
            .iter()
            .flat_map(|l| {
                [
                    l.frequency_hz,
                    l.effective_mass_fraction[0],
                    l.effective_mass_fraction[1],
                    l.effective_mass_fraction[2],
                ]
            })
            .map(f64::to_bits)
            .collect::<Vec<_>>()
    };
    assert_eq!(lb(a), lb(b));
}

#[test]
fn full_body_round_trip_is_bit_identical() {
    let dir = temp_dir("rt-full");
    let mut body = sample_body(40, 7, 42);
    // Awkward values: signed zero, subnormal, extremes.
    // (Where the physical checks of the reader allow them: positions and mass fractions.)
    body.modes_t[(0, 0)] = -0.0;
    body.modes_t[(1, 0)] = f64::MIN_POSITIVE / 8.0;
    body.nodes[0][0] = f64::MAX;
    body.nodes[0][1] = -f64::MAX;
    body.labels[0].effective_mass_fraction[2] = f64::MIN_POSITIVE / 8.0;
    let path = dir.join("arm.fmb.h5");
    write_body(&path, &body).unwrap();
    let back = read_body(&path).unwrap();
    assert_eq!(back, body);
    assert_bits_equal(&back, &body);
    assert_eq!(back.modes_t[(0, 0)].to_bits(), (-0.0f64).to_bits());
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn minimal_body_round_trip() {
    // No masses, no rotations, no cells, no interface or fixed nodes, modal reduction.
    let dir = temp_dir("rt-min");
    let mut body = sample_body(20, 3, 7);
    body.node_masses = None;
    body.modes_r = None;
    body.cells.clear();
    body.interface_nodes.clear();
    body.fixed_nodes.clear();
    body.kind = ReductionKind::Modal;
    body.provenance = Default::default();
    body.name = String::new();
    let path = dir.join("min.fmb.h5");
    write_body(&path, &body).unwrap();
    let back = read_body(&path).unwrap();
    assert_eq!(back, body);
    body.kind = ReductionKind::FreeFree;
    write_body(&path, &body).unwrap();
    assert_eq!(read_body(&path).unwrap().kind, ReductionKind::FreeFree);
}

#[test]
fn body_without_modes_round_trips() {
    let dir = temp_dir("rt-zero");
    let mut body = sample_body(20, 0, 9);
    body.kind = ReductionKind::CraigBampton { internal_modes: 0 };
    let path = dir.join("zero.fmb.h5");
    write_body(&path, &body).unwrap();
    let back = read_body(&path).unwrap();
    assert_eq!(back.num_modes(), 0);
    assert_eq!(back, body);
}

#[test]
fn nan_frequency_of_static_modes_survives() {
    // Craig-Bampton constraint modes carry NaN as label frequency (reduction.rs); NaN != NaN, so
    // compare bit patterns (including a non-canonical NaN payload).
    let dir = temp_dir("rt-nan");
    let mut body = sample_body(24, 4, 3);
    body.labels[0].frequency_hz = f64::NAN;
    body.labels[1].frequency_hz = f64::from_bits(0x7ff8_dead_beef_0001);
    body.labels[1].dominant = "static".into();
    let path = dir.join("nan.fmb.h5");
    write_body(&path, &body).unwrap();
    let back = read_body(&path).unwrap();
    assert_bits_equal(&back, &body);
    assert_eq!(back.labels[1].frequency_hz.to_bits(), 0x7ff8_dead_beef_0001);
    assert_eq!(back.labels[1].dominant, "static");
}

#[test]
fn inconsistent_body_is_rejected_before_writing() {
    let dir = temp_dir("rt-bad");
    let path = dir.join("bad.fmb.h5");
    let mut body = sample_body(20, 3, 1);
    body.modes_t = Mat::zeros(59, 3);
    match write_body(&path, &body) {
        Err(BodyFileError::Invalid {
            object, message, ..
        }) => {
            assert_eq!(object, "modes/translation");
            assert!(
                message.contains("59 x 3") && message.contains("60 x 3"),
                "{message}"
            );
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
    assert!(!path.exists());
    let mut body = sample_body(20, 3, 1);
    body.cells[0].nodes[3] = 20;
    let err = write_body(&path, &body).unwrap_err();
    assert!(
        err.to_string().contains("node index 20 out of range"),
        "{err}"
    );
    let mut body = sample_body(20, 3, 1);
    body.labels.pop();
    assert!(matches!(
        write_body(&path, &body),
        Err(BodyFileError::Invalid { .. })
    ));
    assert!(!path.exists());
}

/// The size the brief asks to measure: 12000 nodes x 50 modes, translations and rotations.
#[test]
fn large_body_write_read_timing() {
    let dir = temp_dir("rt-large");
    let body = sample_body(12_000, 50, 5);
    let path = dir.join("large.fmb.h5");
    let t0 = Instant::now();
    write_body(&path, &body).unwrap();
    let tw = t0.elapsed();
    let t1 = Instant::now();
    let back = read_body(&path).unwrap();
    let tr = t1.elapsed();
    let size = std::fs::metadata(&path).unwrap().len();
    eprintln!(
        "12000 nodes x 50 modes (+rotations): write {:.3} s, read {:.3} s, file {:.1} MB",
        tw.as_secs_f64(),
        tr.as_secs_f64(),
        size as f64 / 1e6
    );
    assert_eq!(back, body);
    // Payload: 2 x 36000 x 50 doubles + nodes; the file must not be much larger than that.
    let payload = (2 * 36_000 * 50 + 12_000 * 5) * 8;
    assert!(
        size as f64 / (payload as f64) < 1.05,
        "file {size} B for payload {payload} B"
    );
    // Generous bound against pathological slowness (measured ~0.1-0.3 s, see docs/decisions-bodyfile.md).
    assert!(tw.as_secs_f64() + tr.as_secs_f64() < 20.0);
}

/// The optional geometric stiffness (six centrifugal `K_G,ab`) survives write -> read bit for bit,
/// including a signed zero and a subnormal; `read_body` of such a file gives the same body; a
/// file without the group (as every file written before it existed) reads with `None`.
#[test]
fn geometric_stiffness_round_trip_is_bit_identical() {
    let dir = temp_dir("rt-kg");
    let body = sample_body(20, 5, 11);
    let mut g = sample_geometric(5, 12);
    g.matrices[3][(0, 0)] = -0.0;
    g.matrices[4][(1, 2)] = f64::MIN_POSITIVE / 8.0;
    g.matrices[4][(2, 1)] = f64::MIN_POSITIVE / 8.0;
    let path = dir.join("kg.fmb.h5");
    write_body_file(&path, &body, Some(&g)).unwrap();
    let back = read_body_file(&path).unwrap();
    assert_bits_equal(&back.body, &body);
    let kg = back.geometric.expect("geometric stiffness not read back");
    assert_eq!(kg.load_patterns, InertialLoad::centrifugal());
    assert_eq!(kg.matrices.len(), 6);
    for (a, b) in kg.matrices.iter().zip(&g.matrices) {
        assert_eq!(mat_bits(a), mat_bits(b));
    }
    assert_eq!(kg.matrices[3][(0, 0)].to_bits(), (-0.0f64).to_bits());
    assert_eq!(read_body(&path).unwrap(), body);

    write_body(&path, &body).unwrap();
    let plain = read_body_file(&path).unwrap();
    assert_eq!(plain.geometric, None);
    assert_eq!(plain.body, body);

    // other pattern kinds and a subset are stored too (the engine uses only centrifugal ones)
    let mut g2 = sample_geometric(5, 13);
    g2.load_patterns = vec![
        InertialLoad::Translation(2),
        InertialLoad::AngularAcceleration(0),
        InertialLoad::Centrifugal(1, 2),
    ];
    g2.matrices.truncate(3);
    write_body_file(&path, &body, Some(&g2)).unwrap();
    assert_eq!(read_body_file(&path).unwrap().geometric, Some(g2));
}

/// The writer refuses geometric stiffness that does not fit the body or is not a symmetric,
/// finite matrix per distinct pattern, naming `geometric/stiffness`; nothing is written.
#[test]
fn inconsistent_geometric_stiffness_is_rejected_before_writing() {
    let dir = temp_dir("rt-kg-bad");
    let path = dir.join("bad.fmb.h5");
    let body = sample_body(20, 4, 1);
    let expect = |g: &flexmbs_fe::geometric::GeometricStiffness, fragment: &str| {
        match write_body_file(&path, &body, Some(g)) {
            Err(BodyFileError::Invalid {
                object, message, ..
            }) => {
                assert_eq!(object, "geometric/stiffness");
                assert!(message.contains(fragment), "{message}");
            }
            other => panic!("expected Invalid ({fragment}), got {other:?}"),
        }
        assert!(!path.exists());
    };
    expect(
        &sample_geometric(3, 2),
        "is 3 x 3, expected N_f x N_f = 4 x 4",
    );
    let mut g = sample_geometric(4, 2);
    g.matrices[2][(0, 3)] += 1e-6 * g.matrices[2].norm_max();
    expect(&g, "matrix 2 (centrifugal_xz) is not symmetric");
    let mut g = sample_geometric(4, 2);
    g.matrices[5][(1, 1)] = f64::INFINITY;
    expect(&g, "non-finite entry inf at (1, 1)");
    let mut g = sample_geometric(4, 2);
    g.load_patterns[1] = InertialLoad::Centrifugal(0, 0);
    expect(&g, "centrifugal_xx appears twice");
    let mut g = sample_geometric(4, 2);
    g.load_patterns[1] = InertialLoad::Centrifugal(2, 1);
    expect(&g, "invalid load pattern");
    let mut g = sample_geometric(4, 2);
    g.matrices.pop();
    expect(&g, "5 matrices for 6 load patterns");
    let mut g = sample_geometric(4, 2);
    g.load_patterns.clear();
    g.matrices.clear();
    expect(&g, "no load patterns");
}

/// Bits of node inertias, row-major per node.
fn rotary_bits(r: &[nalgebra::Matrix3<f64>]) -> Vec<u64> {
    r.iter()
        .flat_map(|m| (0..3).flat_map(move |a| (0..3).map(move |b| m[(a, b)].to_bits())))
        .collect()
}

/// The optional node rotary inertias (`nodes/rotary_inertia`) survive write -> read bit for bit,
/// together with the geometric stiffness and alone, including a zero node, a rank-2 node and a
/// subnormal off-diagonal pair; a file without them reads with `None`; `read_body` ignores them.
#[test]
fn rotary_inertia_round_trip_is_bit_identical() {
    let dir = temp_dir("rt-rot");
    let body = sample_body(20, 4, 21);
    let mut r = body_file_support::sample_rotary(20, 22);
    r[5][(0, 1)] = f64::MIN_POSITIVE / 8.0;
    r[5][(1, 0)] = f64::MIN_POSITIVE / 8.0;
    let path = dir.join("rot.fmb.h5");
    for geometric in [Some(sample_geometric(4, 23)), None] {
        let f = BodyFile {
            body: body.clone(),
            geometric,
            rotary_inertia: Some(r.clone()),
            stress: None,
            inertia_gram: None,
        };
        f.write(&path).unwrap();
        let back = read_body_file(&path).unwrap();
        assert_bits_equal(&back.body, &body);
        let rb = back
            .rotary_inertia
            .as_deref()
            .expect("rotary inertias lost");
        assert_eq!(rotary_bits(rb), rotary_bits(&r));
        assert_eq!(back, f);
        assert_eq!(read_body(&path).unwrap(), body);
    }
    BodyFile::plain(body.clone()).write(&path).unwrap();
    let plain = read_body_file(&path).unwrap();
    assert_eq!((plain.geometric, plain.rotary_inertia), (None, None));
    write_body_file(&path, &body, None).unwrap();
    assert_eq!(read_body_file(&path).unwrap().rotary_inertia, None);
}

/// The writer refuses node rotary inertias that do not fit the body or are not finite,
/// symmetric (1e-12 relative) and positive semi-definite, naming `nodes/rotary_inertia` and the
/// node; nothing is written.
#[test]
fn inconsistent_rotary_inertia_is_rejected_before_writing() {
    let dir = temp_dir("rt-rot-bad");
    let path = dir.join("bad.fmb.h5");
    let body = sample_body(20, 3, 1);
    let good = body_file_support::sample_rotary(20, 2);
    let expect = |r: Vec<nalgebra::Matrix3<f64>>, fragment: &str| {
        let f = BodyFile {
            body: body.clone(),
            geometric: None,
            rotary_inertia: Some(r),
            stress: None,
            inertia_gram: None,
        };
        match f.write(&path) {
            Err(BodyFileError::Invalid {
                object, message, ..
            }) => {
                assert_eq!(object, "nodes/rotary_inertia");
                assert!(message.contains(fragment), "{message}");
            }
            other => panic!("expected Invalid ({fragment}), got {other:?}"),
        }
        assert!(!path.exists());
    };
    expect(good[..19].to_vec(), "19 node inertias for 20 nodes");
    let mut r = good.clone();
    r[7][(2, 2)] = f64::INFINITY;
    expect(r, "node 7: non-finite entry inf");
    let mut r = good.clone();
    r[3][(0, 2)] += 1e-9 * r[3].abs().max();
    expect(r, "node 3: not symmetric");
    let mut r = good.clone();
    r[4] = -r[4];
    expect(r, "node 4: not positive semi-definite");
}
