//! Single-element comparison with CalculiX 2.20 (`*FREQUENCY, SOLVER=MATRIXSTORAGE`, free-free).
//! Decks and exports live in `tests/data/ccx_single/` (`<type>.inp`, `.sti`, `.mas`, `.dof`); the
//! element connectivity in each deck is nodes 1..n in order. Skipped with a message if missing.

use super::gauss::{hex_rule, tet_rule_4};
use super::test_util::single_solid;
use super::{element_matrices, solid, MassKind};
use crate::mesh::ElementKind;
use crate::Material;
use nalgebra::DMatrix;
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/ccx_single")
}

/// Node coordinates of the `*NODE` block of a deck.
fn read_nodes(text: &str) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    let mut in_nodes = false;
    for line in text.lines() {
        if line.starts_with('*') {
            in_nodes = line.to_uppercase().starts_with("*NODE");
            continue;
        }
        if in_nodes {
            let v: Vec<f64> = line.split(',').map(|s| s.trim().parse().unwrap()).collect();
            out.push([v[1], v[2], v[3]]);
        }
    }
    out
}

/// Full symmetric matrix in node-major (node, direction) order from an upper-triangle export.
fn read_matrix(text: &str, dof: &str, n: usize) -> DMatrix<f64> {
    let eq: Vec<usize> = dof
        .lines()
        .map(|l| {
            let (a, b) = l.trim().split_once('.').unwrap();
            3 * (a.parse::<usize>().unwrap() - 1) + b.parse::<usize>().unwrap() - 1
        })
        .collect();
    let mut m = DMatrix::zeros(3 * n, 3 * n);
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (i, j, v) = (
            eq[f[0].parse::<usize>().unwrap() - 1],
            eq[f[1].parse::<usize>().unwrap() - 1],
            f[2].parse::<f64>().unwrap(),
        );
        m[(i, j)] = v;
        m[(j, i)] = v;
    }
    m
}

fn rel_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let s = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (a - b).iter().fold(0.0f64, |m, v| m.max(v.abs())) / s
}

#[test]
fn single_element_matrices_match_calculix() {
    let mat = Material {
        e: 210000.0,
        nu: 0.3,
        rho: 7.85e-9,
    };
    let dir = data_dir();
    if !dir.join("c3d8.sti").exists() {
        println!("skipped: CalculiX exports not found in {}", dir.display());
        return;
    }
    for (name, kind) in [
        ("c3d8", ElementKind::Hex8),
        ("c3d20", ElementKind::Hex20),
        ("c3d20r", ElementKind::Hex20R),
        ("c3d10", ElementKind::Tet10),
    ] {
        let rd = |ext: &str| std::fs::read_to_string(dir.join(format!("{name}.{ext}"))).unwrap();
        let x = read_nodes(&rd("inp"));
        let (dof, n) = (rd("dof"), x.len());
        let kc = read_matrix(&rd("sti"), &dof, n);
        let mc = read_matrix(&rd("mas"), &dof, n);
        let em = element_matrices(&single_solid(kind, &x, mat), 0, MassKind::Consistent).unwrap();
        let dk = rel_diff(&em.k, &kc);
        let dm = rel_diff(&em.m, &mc);
        println!("{name}: max |K - K_ccx| / max|K_ccx| = {dk:.2e}, same for M = {dm:.2e}");
        // ccx writes 14 significant digits
        assert!(dk < 1e-11, "{name} K differs from CalculiX by {dk:e}");
        match kind {
            ElementKind::Hex20R | ElementKind::Tet10 => {
                // CalculiX integrates the mass with the stiffness rule (C3D20R: 2x2x2, C3D10:
                // 4 points); flexmbs uses exact rules. Reproduce the CalculiX choice to prove it.
                let (shape, rule): (solid::ShapeFn, _) = if kind == ElementKind::Tet10 {
                    (super::tet10::tet10_shape, tet_rule_4())
                } else {
                    (super::hex20::hex20_shape, hex_rule(2))
                };
                let mr = solid::consistent_mass(shape, &x, mat.rho, &rule, 0).unwrap();
                let dr = rel_diff(&mr, &mc);
                println!("{name}: M with the CalculiX (stiffness) rule differs by {dr:.2e}; exact-rule M by {dm:.2e}");
                assert!(
                    dr < 1e-11,
                    "{name}: CalculiX mass rule not reproduced ({dr:e})"
                );
                assert!(
                    dm > 1e-3,
                    "{name}: expected the exact-rule mass to differ from CalculiX"
                );
            }
            _ => assert!(dm < 1e-11, "{name} M differs from CalculiX by {dm:e}"),
        }
    }
}
