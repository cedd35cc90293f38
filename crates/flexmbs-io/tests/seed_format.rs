//! The seed 4-file format (Listings 4.1-4.5): reading a folder laid out exactly like the
//! listings, reduced stiffness, bit-identical write/read round trip, symmetry policy.

use crate::common;

use common::{data, XorShift};
use faer::sparse::Triplet;
use faer::Mat;
use flexmbs_fe::SparseMatrix;
use flexmbs_io::seed::{
    format_u0, parse_stiffness, read_seed_dir, write_seed_dir, SeedBody, SEED_FILES,
};
use std::path::Path;

#[test]
#[allow(clippy::excessive_precision)] // literals copied from Listing 4.3
fn reads_listing_layout_folder() {
    let b = read_seed_dir(&data("seed_ok")).expect("well-formed seed folder");
    assert_eq!(b.num_nodes(), 4);
    assert_eq!(b.num_modes(), 2);
    assert_eq!(b.u0[0], [105.0, 10.0, 5.13000011]);
    assert_eq!(b.u0[3], [95.0, 0.0, 5.13000011]);
    assert_eq!(b.masses[1], 2.393118778799550e-07);
    assert_eq!(b.masses[3], 1.215521535044688e-07);
    assert_eq!(b.modes.nrows(), 12);
    assert_eq!(b.modes[(0, 0)], 0.1);
    assert_eq!(b.modes[(11, 1)], -1.0);
    // Fixed nodes 2 and 3 have zero rows.
    for r in 3..9 {
        assert_eq!((b.modes[(r, 0)], b.modes[(r, 1)]), (0.0, 0.0));
    }
    // K = 1000 (chain Laplacian of nodes 1-2-3-4) (x) I3: row 3a-3+b, column 3c-3+d.
    let k = &b.stiffness;
    assert_eq!((k.nrows(), k.ncols()), (12, 12));
    assert_eq!(k.compute_nnz(), 3 * 10);
    assert_eq!(k.get(0, 0), Some(&1000.0));
    assert_eq!(k.get(3, 0), Some(&-1000.0)); // line "2,1, 1,1"
    assert_eq!(k.get(0, 3), Some(&-1000.0));
    assert_eq!(k.get(7, 7), Some(&2000.0)); // node 3, DOF 2
    assert_eq!(k.get(1, 0), None);
    // k_ff = Phi^T K Phi; with only nodes 1 and 4 moving and L_11 = L_44 = 1, L_14 = 0:
    // k_ff[a][b] = 1000 (phi_a(1).phi_b(1) + phi_a(4).phi_b(4)) = [[910, -500], [-500, 2000]].
    let kff = b.k_ff();
    let expect = [[910.0, -500.0], [-500.0, 2000.0]];
    for i in 0..2 {
        for j in 0..2 {
            assert!(
                (kff[(i, j)] - expect[i][j]).abs() < 1e-9,
                "k_ff[{i}][{j}] = {}",
                kff[(i, j)]
            );
        }
    }
}

/// Random body: `nn` nodes, `nf` modes, random sparse symmetric K; values span many decades
/// and include negative zero, subnormals and values near the f64 limits.
fn random_body(rng: &mut XorShift, nn: usize, nf: usize) -> SeedBody {
    let val = |rng: &mut XorShift| -> f64 {
        match rng.below(10) {
            0 => 0.0,
            1 => -0.0,
            2 => 4.9e-324 * (1 + rng.below(1000)) as f64,
            3 => f64::MAX * rng.unit(),
            _ => (rng.unit() - 0.5) * 10f64.powi(rng.below(80) as i32 - 40),
        }
    };
    let u0 = (0..nn).map(|_| [val(rng), val(rng), val(rng)]).collect();
    let modes = Mat::from_fn(3 * nn, nf, |_, _| 0.0);
    let mut modes = modes;
    for i in 0..3 * nn {
        for j in 0..nf {
            modes[(i, j)] = val(rng);
        }
    }
    let masses = (0..nn)
        .map(|_| 10f64.powi(rng.below(20) as i32 - 10) * (0.5 + rng.unit()))
        .collect();
    let n = 3 * nn;
    let mut trip = Vec::new();
    for j in 0..n {
        trip.push(Triplet::new(j, j, val(rng)));
        for i in 0..j {
            if rng.below(3) == 0 {
                let v = val(rng);
                trip.push(Triplet::new(i, j, v));
                trip.push(Triplet::new(j, i, v));
            }
        }
    }
    let k = SparseMatrix::try_new_from_triplets(n, n, &trip).unwrap();
    SeedBody::new(u0, modes, masses, k, Path::new("random")).unwrap()
}

#[test]
fn write_read_round_trip_is_bit_identical() {
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let tmp = flexmbs_io::test_tools::scratch_dir("seed_rt");
    for case in 0..5 {
        let b = random_body(&mut rng, 3 + case * 2, 1 + case);
        write_seed_dir(&tmp, &b).unwrap();
        let r = read_seed_dir(&tmp).unwrap();
        let bits = |v: f64| v.to_bits();
        assert_eq!(b.u0.len(), r.u0.len());
        for (a, c) in b.u0.iter().zip(&r.u0) {
            assert_eq!(a.map(bits), c.map(bits));
        }
        assert_eq!(
            b.masses.iter().map(|v| bits(*v)).collect::<Vec<_>>(),
            r.masses.iter().map(|v| bits(*v)).collect::<Vec<_>>()
        );
        assert_eq!(
            (b.modes.nrows(), b.modes.ncols()),
            (r.modes.nrows(), r.modes.ncols())
        );
        for i in 0..b.modes.nrows() {
            for j in 0..b.modes.ncols() {
                assert_eq!(bits(b.modes[(i, j)]), bits(r.modes[(i, j)]));
            }
        }
        assert_eq!(b.stiffness.col_ptr(), r.stiffness.col_ptr());
        assert_eq!(b.stiffness.row_idx(), r.stiffness.row_idx());
        let kb: Vec<u64> = b.stiffness.val().iter().map(|v| bits(*v)).collect();
        let kr: Vec<u64> = r.stiffness.val().iter().map(|v| bits(*v)).collect();
        assert_eq!(kb, kr);
    }
    std::fs::remove_dir_all(&tmp).ok();
}

#[test]
fn writer_uses_listing_layout() {
    let b = read_seed_dir(&data("seed_ok")).unwrap();
    let u0 = format_u0(&b.u0);
    let first = u0.lines().next().unwrap();
    assert_eq!(
        first,
        "1.0500000000000000e+02\t1.0000000000000000e+01\t5.1300001100000001e+00\t% node: 1"
    );
    let tmp = flexmbs_io::test_tools::scratch_dir("seed_layout");
    write_seed_dir(&tmp, &b).unwrap();
    let modes = std::fs::read_to_string(tmp.join(SEED_FILES[1])).unwrap();
    assert_eq!(
        modes.lines().nth(4).unwrap(),
        "0.0000000000000000e+00\t0.0000000000000000e+00\t% node: 2, DOF: 2"
    );
    let k = std::fs::read_to_string(tmp.join(SEED_FILES[3])).unwrap();
    assert_eq!(
        k.lines().nth(1).unwrap(),
        "2,1, 1,1, -1.0000000000000000e+03"
    );
    // Same entries, same order as the hand-written listing file.
    let orig = std::fs::read_to_string(data("seed_ok/stiffnessMatrix.dat")).unwrap();
    let idx = |s: &str| {
        s.lines()
            .map(|l| l.rsplit_once(", ").unwrap().0.to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(idx(&k), idx(&orig));
    std::fs::remove_dir_all(&tmp).ok();
}

#[test]
fn stiffness_one_triangle_is_mirrored_and_mismatch_rejected() {
    let f = Path::new("stiffnessMatrix.dat");
    // Upper triangle only: mirrored.
    let k = parse_stiffness("1,1, 1,1, 4.0\n1,1, 1,2, -1.5\n1,2, 1,2, 3.0\n", f, 1).unwrap();
    assert_eq!(k.get(1, 0), Some(&-1.5));
    assert_eq!(k.get(0, 1), Some(&-1.5));
    // Both triangles agreeing within 1e-9 relative: accepted (mean).
    let k = parse_stiffness("1,1, 1,2, -1.0\n1,2, 1,1, -1.0000000001\n", f, 1).unwrap();
    assert!((k.get(0, 1).unwrap() + 1.00000000005).abs() < 1e-15);
    // 1e-6 relative mismatch: rejected, located on the second entry's line.
    let e = parse_stiffness("1,1, 1,2, -1.0\n% c\n1,2, 1,1, -1.000001\n", f, 1).unwrap_err();
    assert_eq!(e.line(), Some(3), "{e}");
    assert!(e.to_string().contains("not symmetric"), "{e}");
}

#[test]
fn cross_file_inconsistencies_are_reported_with_both_numbers() {
    let e = read_seed_dir(&data("bad/seed_mode_rows")).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("modeShapeMatrix.dat")
            && msg.contains("9 mode-shape rows")
            && msg.contains("= 12"),
        "{msg}"
    );
    let e = read_seed_dir(&data("bad/seed_mass_count")).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("mij.dat") && msg.contains("3 masses") && msg.contains("4 nodes"),
        "{msg}"
    );
}
