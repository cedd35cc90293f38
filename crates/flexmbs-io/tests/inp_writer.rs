//! A built-in mesh written as a CalculiX deck reads back identically (labels, coordinates to
//! 13 significant digits, element connectivity, node sets, material).

use flexmbs_fe::mesh::generate::box_mesh;
use flexmbs_fe::{ElementKind, Material, UnitSystem};
use flexmbs_io::calculix::parse_inp;
use flexmbs_io::inp_writer::mesh_to_inp;
use std::path::Path;

#[test]
fn written_deck_reads_back() {
    for kind in [ElementKind::Hex8, ElementKind::Hex20R] {
        let mesh = box_mesh(
            [0.3, 0.02, 0.01],
            [3, 2, 1],
            kind,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        let text = mesh_to_inp(&mesh).unwrap();
        let long = text
            .lines()
            .find(|l| !l.starts_with("**") && l.split(',').any(|f| f.trim().len() > 20));
        assert!(long.is_none(), "a field exceeds 20 characters: {long:?}");
        let back = parse_inp(&text, Path::new("written.inp"), UnitSystem::Si)
            .unwrap()
            .mesh;
        assert_eq!(back.node_ids, mesh.node_ids);
        for (a, b) in back.nodes.iter().zip(&mesh.nodes) {
            for d in 0..3 {
                assert!((a[d] - b[d]).abs() <= 1e-12 * b[d].abs().max(1e-3));
            }
        }
        assert_eq!(back.elements.len(), mesh.elements.len());
        for (a, b) in back.elements.iter().zip(&mesh.elements) {
            assert_eq!(a.kind, b.kind);
            assert_eq!(a.nodes, b.nodes);
        }
        assert_eq!(
            back.node_set("XMIN").unwrap(),
            mesh.node_set("xmin").unwrap()
        );
        let m = back.properties[0].material();
        assert!(
            (m.e - 210e9).abs() < 1.0
                && (m.nu - 0.3).abs() < 1e-12
                && (m.rho - 7850.0).abs() < 1e-9
        );
    }
}
