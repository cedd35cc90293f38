//! Shared helpers of the reduced-body file tests: a deterministic sample body and a Python runner.
#![allow(dead_code)]

use faer::Mat;
use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::{Cell, ModeLabel, Provenance, ReducedBody, ReductionKind};
use flexmbs_fe::UnitSystem;
use std::path::PathBuf;
use std::process::Command;

/// Deterministic pseudo-random numbers in [-1, 1) with full 52-bit mantissas (xorshift64*), so a
/// lossy path (f32, text) would be caught by a bit comparison.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A Craig-Bampton-like body with `n` nodes and `nf` modes, node masses, rotations, every cell
/// kind, interface and fixed nodes, and a non-ASCII provenance note.
pub fn sample_body(n: usize, nf: usize, seed: u64) -> ReducedBody {
    assert!(n >= 20);
    let mut rng = Rng::new(seed);
    let nodes: Vec<[f64; 3]> = (0..n)
        .map(|_| [rng.next(), rng.next() * 1e3, rng.next() * 1e-3])
        .collect();
    let node_ids: Vec<u64> = (0..n as u64).map(|i| 1000 + 7 * i).collect();
    let masses: Vec<f64> = (0..n).map(|_| rng.next().abs() + 1e-9).collect();
    let modes_t = Mat::from_fn(3 * n, nf, |_, _| rng.next());
    let modes_r = Mat::from_fn(
        3 * n,
        nf,
        |i, _| if i % 3 == 0 { 0.0 } else { rng.next() * 1e-2 },
    );
    // Physically consistent (the reader checks it): K symmetric positive definite, M the lumped
    // projection of the node masses plus a rotational part, frequencies those of (K, M).
    let a = Mat::from_fn(nf, nf, |_, _| rng.next());
    let k_red = Mat::from_fn(nf, nf, |i, j| {
        let aa: f64 = (0..nf).map(|r| a[(r, i)] * a[(r, j)]).sum();
        aa + if i == j { 1e6 * (i + 1) as f64 } else { 0.0 }
    });
    let m_red = Mat::from_fn(nf, nf, |i, j| {
        (0..n)
            .map(|p| {
                let t: f64 = (0..3)
                    .map(|d| masses[p] * modes_t[(3 * p + d, i)] * modes_t[(3 * p + d, j)])
                    .sum();
                let r: f64 = (0..3)
                    .map(|d| 1e-3 * modes_r[(3 * p + d, i)] * modes_r[(3 * p + d, j)])
                    .sum();
                t + r
            })
            .sum()
    });
    let (omega2, _) =
        flexmbs_fe::eigen::dense_generalized(k_red.as_ref(), m_red.as_ref()).expect("sample pair");
    let frequencies_hz = flexmbs_fe::modes::frequencies_hz(&omega2);
    let dominant = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let labels = (0..nf)
        .map(|k| ModeLabel {
            index: k + 1,
            frequency_hz: frequencies_hz[k],
            dominant: dominant[k % 6].to_string(),
            effective_mass_fraction: [
                rng.next().abs() / nf as f64,
                rng.next().abs() / nf as f64,
                0.0,
            ],
        })
        .collect();
    let cells = vec![
        Cell {
            kind: ElementKind::Hex8,
            nodes: (0..8).collect(),
        },
        Cell {
            kind: ElementKind::Hex8I,
            nodes: (1..9).collect(),
        },
        Cell {
            kind: ElementKind::Hex20,
            nodes: (0..20).collect(),
        },
        Cell {
            kind: ElementKind::Hex20R,
            nodes: (0..20).rev().collect(),
        },
        Cell {
            kind: ElementKind::Tet10,
            nodes: (5..15).collect(),
        },
        Cell {
            kind: ElementKind::Beam2,
            nodes: vec![n - 2, n - 1],
        },
    ];
    ReducedBody {
        name: "crank arm".into(),
        units: UnitSystem::SiMm,
        nodes,
        node_ids,
        node_masses: Some(masses),
        modes_t,
        modes_r: Some(modes_r),
        k_red,
        m_red,
        frequencies_hz,
        labels,
        interface_nodes: vec![0, 3, n - 1],
        fixed_nodes: vec![2],
        kind: ReductionKind::CraigBampton {
            internal_modes: nf.saturating_sub(18),
        },
        cells,
        provenance: Provenance {
            source: "built-in beam 1 m x 20 mm".into(),
            program: "flexmbs 0.1.0".into(),
            notes: "Hex20, consistent mass, E = 210 GPa, ν = 0.3 (µm mesh)".into(),
        },
    }
}

/// Six centrifugal geometric stiffness matrices for a body of `nf` modes: exactly symmetric,
/// full-mantissa pseudo-random entries, pattern `xx` set to zero (as for a beam along x).
pub fn sample_geometric(nf: usize, seed: u64) -> GeometricStiffness {
    let mut rng = Rng::new(seed);
    let load_patterns = InertialLoad::centrifugal();
    let matrices = load_patterns
        .iter()
        .enumerate()
        .map(|(p, _)| {
            let a = Mat::from_fn(nf, nf, |_, _| rng.next() * 10f64.powi(p as i32 - 2));
            Mat::from_fn(
                nf,
                nf,
                |i, j| if p == 0 { 0.0 } else { a[(i, j)] + a[(j, i)] },
            )
        })
        .collect();
    GeometricStiffness {
        load_patterns,
        matrices,
    }
}

/// A fresh temporary directory for one test ([`flexmbs_io::test_tools::scratch_dir`]).
pub fn temp_dir(tag: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("bodyfile-{tag}"))
}

/// Whether `python3` can import all `modules`; when not, the test skips with the reason printed,
/// or fails under `FLEXMBS_REQUIRE_TOOLS=1` ([`flexmbs_io::test_tools::python_or_skip`]).
pub fn python_has(modules: &[&str], test: &str) -> bool {
    flexmbs_io::test_tools::python_or_skip(test, modules)
}

/// Runs `python3 -c code args...` and returns stdout; panics with stderr if it fails.
pub fn run_python(code: &str, args: &[&str]) -> String {
    let out = Command::new("python3")
        .arg("-c")
        .arg(code)
        .args(args)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "python failed:\n--- stdout\n{}\n--- stderr\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Node rotary inertias for a body of `n` nodes: node 0 zero (a solid node), node 1 rank 2
/// (`diag(a, b, 0)`), the others `B Bᵀ` with full-mantissa entries (exactly symmetric: the same
/// products are summed in the same order), all positive semi-definite.
pub fn sample_rotary(n: usize, seed: u64) -> Vec<nalgebra::Matrix3<f64>> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|j| match j {
            0 => nalgebra::Matrix3::zeros(),
            1 => nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(
                rng.next().abs(),
                rng.next().abs(),
                0.0,
            )),
            _ => {
                let b = nalgebra::Matrix3::from_fn(|_, _| 1e-3 * rng.next());
                b * b.transpose()
            }
        })
        .collect()
}
