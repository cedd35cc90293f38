//! The optional `stress` group of the reduced-body file: a bit-identical round trip, files
//! without it read as `None`, malformed contents refused with the dataset named.

use crate::body_file_support;

use body_file_support::{sample_body, temp_dir, Rng};
use faer::Mat;
use flexmbs_fe::stress::{ModalStress, NodeStressKind};
use flexmbs_io::body_file::{read_body_file, BodyFile, BodyFileError};
use hdf5_pure::File;

fn sample_stress(n: usize, nf: usize, seed: u64) -> ModalStress {
    let mut rng = Rng::new(seed);
    let kinds: Vec<NodeStressKind> = (0..n)
        .map(|i| match i % 3 {
            0 => NodeStressKind::None,
            1 => NodeStressKind::Solid,
            _ => NodeStressKind::Beam,
        })
        .collect();
    let fields = Mat::from_fn(6 * n, nf, |_, _| rng.next() * 1e8);
    ModalStress { kinds, fields }
}

#[test]
fn stress_round_trip_is_bit_identical_and_optional() {
    let dir = temp_dir("stress-rt");
    let path = dir.join("s.fmb.h5");
    let body = sample_body(20, 3, 7);
    let s = sample_stress(20, 3, 11);
    BodyFile {
        stress: Some(s.clone()),
        ..BodyFile::plain(body.clone())
    }
    .write(&path)
    .unwrap();
    let back = read_body_file(&path).unwrap().stress.unwrap();
    assert_eq!(back.kinds, s.kinds);
    for c in 0..3 {
        for r in 0..120 {
            assert_eq!(back.fields[(r, c)].to_bits(), s.fields[(r, c)].to_bits());
        }
    }
    // a file without the group (as written before it existed) reads as None
    BodyFile::plain(body).write(&path).unwrap();
    assert!(read_body_file(&path).unwrap().stress.is_none());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn malformed_stress_is_refused_naming_the_dataset() {
    let dir = temp_dir("stress-bad");
    let path = dir.join("s.fmb.h5");
    let body = sample_body(20, 3, 7);
    // writer: wrong shape, non-finite entry, wrong number of kinds
    let mut bad_shape = sample_stress(20, 3, 1);
    bad_shape.fields = Mat::zeros(6 * 20, 2);
    let mut nan = sample_stress(20, 3, 1);
    nan.fields[(17, 1)] = f64::NAN;
    let mut kinds = sample_stress(20, 3, 1);
    kinds.kinds.pop();
    for (s, text) in [
        (bad_shape, "stress/modal"),
        (nan, "non-finite entry NaN at (17, 1)"),
        (kinds, "19 node kinds for 20 nodes"),
    ] {
        let f = BodyFile {
            stress: Some(s),
            ..BodyFile::plain(body.clone())
        };
        let e = f.write(&path).unwrap_err();
        assert!(
            matches!(e, BodyFileError::Invalid { .. }) && e.to_string().contains(text),
            "{e}"
        );
    }
    // reader: one dataset without the other, and an unknown kind code
    let good = BodyFile {
        stress: Some(sample_stress(20, 3, 1)),
        ..BodyFile::plain(body.clone())
    };
    good.write(&path).unwrap();
    let edit = |f: &dyn Fn(&File)| {
        good.write(&path).unwrap();
        let file = File::open_rw(&path).unwrap();
        f(&file);
        file.commit().unwrap();
        read_body_file(&path).unwrap_err().to_string()
    };
    let e = edit(&|f| f.root().delete("stress/node_kind").unwrap());
    assert!(e.contains("missing dataset 'stress/node_kind'"), "{e}");
    let e = edit(&|f| {
        let root = f.root();
        root.delete("stress/node_kind").unwrap();
        root.create_dataset("stress/node_kind", |b| {
            b.with_u8_data(&[7; 20]);
        })
        .unwrap();
    });
    assert!(e.contains("node 0: unknown kind code 7"), "{e}");
    let e = edit(&|f| {
        let root = f.root();
        root.delete("stress/modal").unwrap();
        root.create_dataset("stress/modal", |b| {
            b.with_f64_data(&[0.0; 60]).with_shape(&[20, 3]);
        })
        .unwrap();
    });
    assert!(e.contains("'stress/modal' has shape [20, 3]"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
