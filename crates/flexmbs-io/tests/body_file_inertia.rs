//! The optional dataset `inertia/gram` of the reduced-body file: a bit-identical round trip,
//! files without it read as `None`, malformed matrices refused with the dataset named.

use crate::body_file_support;

use body_file_support::{sample_body, temp_dir, Rng};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::body_file::{read_body_file, BodyFile, BodyFileError};
use nalgebra::DMatrix;

/// A Gram matrix consistent with `body`: random symmetric, mass 2.5, its three diagonal mode
/// blocks summing to `m_red`.
fn sample_gram(body: &ReducedBody, seed: u64) -> DMatrix<f64> {
    let nf = body.num_modes();
    let size = 4 + 3 * nf;
    let mut rng = Rng::new(seed);
    let a = DMatrix::from_fn(size, size, |_, _| rng.next());
    let mut g = &a + a.transpose();
    g[(0, 0)] = 2.5;
    for i in 0..nf {
        for j in 0..nf {
            let rest = g[(4 + nf + i, 4 + nf + j)] + g[(4 + 2 * nf + i, 4 + 2 * nf + j)];
            g[(4 + i, 4 + j)] = body.m_red[(i, j)] - rest;
        }
    }
    g
}

#[test]
fn gram_round_trip_is_bit_identical_and_optional() {
    let dir = temp_dir("gram-rt");
    let path = dir.join("g.fmb.h5");
    let body = sample_body(20, 3, 7);
    let g = sample_gram(&body, 5);
    BodyFile {
        inertia_gram: Some(g.clone()),
        ..BodyFile::plain(body.clone())
    }
    .write(&path)
    .unwrap();
    let back = read_body_file(&path).unwrap().inertia_gram.unwrap();
    assert_eq!(back, g);
    BodyFile::plain(body).write(&path).unwrap();
    assert!(read_body_file(&path).unwrap().inertia_gram.is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Wrong size, a non-finite entry, asymmetry beyond 1e-8 relative, a non-positive mass and a
/// modal block that is not `reduced/mass` are refused before writing, naming `inertia/gram`.
#[test]
fn malformed_gram_is_refused_naming_the_dataset() {
    let dir = temp_dir("gram-bad");
    let path = dir.join("g.fmb.h5");
    let body = sample_body(20, 3, 7);
    let good = sample_gram(&body, 5);
    let mut nan = good.clone();
    nan[(2, 3)] = f64::NAN;
    let mut asym = good.clone();
    asym[(1, 7)] += 1e-3;
    let mut massless = good.clone();
    massless[(0, 0)] = 0.0;
    let mut other = good.clone();
    other[(4, 4)] += 1e-3;
    for (g, text) in [
        (DMatrix::zeros(12, 12), "expected (4 + 3 N_f) = 13 square"),
        (nan, "non-finite entry NaN"),
        (asym, "not symmetric"),
        (massless, "total mass G[0, 0] = 0 is not positive"),
        (other, "differs from reduced/mass at (0, 0)"),
    ] {
        let e = BodyFile {
            inertia_gram: Some(g),
            ..BodyFile::plain(body.clone())
        }
        .write(&path)
        .unwrap_err();
        let s = e.to_string();
        assert!(
            matches!(e, BodyFileError::Invalid { .. })
                && s.contains("inertia/gram")
                && s.contains(text),
            "{s}"
        );
        assert!(!path.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
