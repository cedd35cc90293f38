//! CalculiX readers on committed files (no ccx needed): the reference beam deck, a deck using
//! continuation lines, GENERATE, includes and mixed case, and small real `.sti`/`.dof`/`.dat`/
//! `.frd` outputs of ccx 2.20 (cut from the beam runs).

use crate::common;

use common::data;
use flexmbs_fe::{ElementKind, UnitSystem};
use flexmbs_io::calculix::{
    parse_inp, read_ccx_matrices, read_dat_frequencies, read_frd, read_inp, CcxMatrices,
};
use std::path::Path;

#[test]
fn reference_beam_deck() {
    let m = read_inp(&data("ccx/beam_mat.inp"), UnitSystem::Si).unwrap();
    let mesh = &m.mesh;
    assert_eq!(mesh.num_nodes(), 1221);
    assert_eq!(mesh.elements.len(), 160);
    assert!(mesh.elements.iter().all(|e| e.kind == ElementKind::Hex20R));
    // Element 1 spans two lines (continuation after 15 nodes).
    let labels: Vec<u64> = mesh.elements[0]
        .nodes
        .iter()
        .map(|&n| mesh.node_ids[n])
        .collect();
    assert_eq!(
        labels,
        [
            1, 3, 125, 123, 449, 451, 573, 571, 2, 83, 124, 82, 450, 531, 572, 530, 326, 327, 368,
            367
        ]
    );
    assert_eq!(
        mesh.nodes[mesh.node_set("TIPC").unwrap()[0]],
        [1.0, 0.0, 0.0]
    );
    assert_eq!(mesh.node_set("FIX").unwrap().len(), 21);
    assert!(mesh
        .node_set("FIX")
        .unwrap()
        .iter()
        .all(|&n| mesh.nodes[n][0] == 0.0));
    assert_eq!(mesh.node_set("NALL").unwrap().len(), 1221);
    let mat = mesh.properties[0].material();
    assert_eq!((mat.e, mat.nu, mat.rho), (2.1e11, 0.3, 7850.0));
    // *BOUNDARY FIX, 1, 3: 21 nodes x 3 DOFs.
    assert_eq!(m.boundaries.len(), 63);
    assert!(m
        .boundaries
        .iter()
        .all(|b| (1..=3).contains(&b.dof) && b.value == 0.0));
    // The frequency step keywords are skipped with warnings.
    assert!(
        m.warnings.iter().any(|w| w.contains("*FREQUENCY")),
        "{:?}",
        m.warnings
    );
    assert_eq!(m.element_sets["EALL"].len(), 160);
    // Volume check from coordinates: bounding box 1 x 0.02 x 0.02.
    let (lo, hi) = mesh
        .nodes
        .iter()
        .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), x| {
            (
                std::array::from_fn(|k| lo[k].min(x[k])),
                std::array::from_fn(|k| hi[k].max(x[k])),
            )
        });
    assert_eq!((lo, hi), ([0.0, -0.01, -0.01], [1.0, 0.01, 0.01]));
}

#[test]
fn deck_features() {
    let deck = "\
** two C3D8 elements, lower-case keywords, GENERATE, set names in sets
*node, nset=all
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
5, 0., 0., 1.
6, 1., 0., 1.
7, 1., 1., 1.
8, 0., 1., 1.
9, 2., 0., 0.
10, 2., 1., 0.
11, 2., 0., 1.
12, 2., 1., 1.
*Element, Type=C3D8, Elset=Left
1, 1, 2, 3, 4,
5, 6, 7, 8
*ELEMENT, TYPE=C3D8I, ELSET=RIGHT
2, 2, 9, 10, 3, 6, 11, 12, 7
*Elset, elset=Both
left, 2
*NSET, NSET=END, GENERATE
9, 12, 1
*NSET, NSET=ENDS
end, 1, 4
*HEADING
some title text
*Material, name=Alu
*Elastic
70000., 0.33
*Density
2.7e-9
*Solid Section, Elset=BOTH, Material=alu
*Boundary
ENDS, 1, 2
5, ENCASTRE
7, 3, 3, 0.5
*CLOAD
3, 2, 1.0
";
    let m = parse_inp(deck, Path::new("deck.inp"), UnitSystem::SiMm).unwrap();
    let mesh = &m.mesh;
    assert_eq!(mesh.units, UnitSystem::SiMm);
    assert_eq!(mesh.elements.len(), 2);
    assert_eq!(mesh.elements[1].kind, ElementKind::Hex8I);
    assert_eq!(mesh.elements[0].nodes, [0, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(m.element_sets["BOTH"], [0, 1]);
    assert_eq!(mesh.node_sets["END"], [8, 9, 10, 11]);
    assert_eq!(mesh.node_sets["ENDS"], [8, 9, 10, 11, 0, 3]);
    assert_eq!(mesh.properties.len(), 1);
    assert_eq!(mesh.properties[0].material().rho, 2.7e-9);
    assert_eq!(m.boundaries.len(), 6 * 2 + 6 + 1);
    assert_eq!(
        m.boundaries.last().map(|b| (b.node, b.dof, b.value)),
        Some((6, 3, 0.5))
    );
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert!(
        m.warnings[0].starts_with("deck.inp:38: keyword *CLOAD"),
        "{:?}",
        m.warnings
    );
}

#[test]
fn include_errors_are_located_in_the_included_file() {
    let dir = flexmbs_io::test_tools::scratch_dir("inc");
    std::fs::write(dir.join("mesh.inp"), "*NODE\n1, 0, 0, 0\n1, 1, 0, 0\n").unwrap();
    let e = parse_inp(
        "** main\n*INCLUDE, INPUT=mesh.inp\n",
        &dir.join("main.inp"),
        UnitSystem::Si,
    )
    .unwrap_err();
    assert_eq!(e.file().unwrap(), dir.join("mesh.inp"));
    assert_eq!(e.line(), Some(3));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn small_matrix_export() {
    // The 30 x 30 leading block of the clamped beam export (ccx 2.20).
    let m: CcxMatrices = read_ccx_matrices(&data("good/small")).unwrap();
    assert_eq!(m.len(), 30);
    assert_eq!(m.dofs[0], (2, 1));
    assert_eq!(m.dofs[29], (11, 3));
    assert_eq!(m.k.get(0, 0), Some(&1.2683760683761e+09));
    // Lower triangle mirrored from "1 2 -4.0978193283081e-08".
    assert_eq!(m.k.get(1, 0), Some(&-4.0978193283081e-08));
    assert_eq!(m.k.get(0, 1), Some(&-4.0978193283081e-08));
    // Removing node 2 leaves 27 equations with the values of the remaining block.
    let r = m.remove_dofs(|n, _| n != 2);
    assert_eq!(r.len(), 27);
    assert_eq!(r.k.get(0, 0), m.k.get(3, 3));
    assert_eq!(r.m.get(2, 5), m.m.get(5, 8));
}

#[test]
fn frequency_table_and_frd() {
    let d = read_dat_frequencies(&data("good/beam_freq.dat")).unwrap();
    let f: Vec<f64> = d.iter().map(|m| m.frequency_hz).collect();
    assert_eq!(
        f,
        [16.73174, 16.73174, 104.6634, 104.6634, 292.1994, 292.1994]
    );
    for m in &d {
        // omega = 2 pi f and eigenvalue = omega^2, to the 7 printed digits.
        assert!((m.omega / (2.0 * std::f64::consts::PI) / m.frequency_hz - 1.0).abs() < 1e-6);
        assert!((m.omega * m.omega / m.eigenvalue - 1.0).abs() < 2e-6);
    }
    let r = read_frd(&data("good/small.frd")).unwrap();
    assert_eq!(r.nodes.len(), 20);
    assert_eq!(r.nodes[1], (2, [0.0125, -0.01, -0.01]));
    assert_eq!(r.elements.len(), 1);
    // frd order (Abaqus 1-12, 17-20, 13-16) converted back to Abaqus order.
    assert_eq!(
        r.elements[0].nodes,
        [
            1, 3, 125, 123, 449, 451, 573, 571, 2, 83, 124, 82, 450, 531, 572, 530, 326, 327, 368,
            367
        ]
    );
    assert_eq!(r.modes.len(), 2);
    assert_eq!(r.modes[0].mode, Some(1));
    assert_eq!(r.modes[0].frequency_hz, 16.73174120);
    assert_eq!(r.modes[1].frequency_hz, 16.73174126);
    let d2 = r.modes[0].disp.iter().find(|(n, _)| *n == 3).unwrap().1;
    assert_eq!(d2, [8.66585E-04, -5.49481E-07, 1.14201E-03]);
}

#[test]
fn huge_index_does_not_allocate() {
    let e = flexmbs_io::calculix::parse_ccx_matrix(
        "1 1  1.0\n99999999999999 99999999999999  1.0\n",
        Path::new("h.sti"),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("diagonal entry (2, 2) missing: 2 of 99999999999999"),
        "{e}"
    );
}
