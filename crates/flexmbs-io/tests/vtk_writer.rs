//! VTU/PVD writer without external readers: input checks and the exact text of small files.

use crate::body_file_support;

use body_file_support::{sample_body, temp_dir};
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::Cell;
use flexmbs_io::vtk::{
    base64, default_mode_scale, write_mode_shapes, write_pvd, write_vtu, write_vtu_with, VtkError,
    VtuEncoding,
};

fn line_cell() -> (Vec<[f64; 3]>, Vec<Cell>) {
    let pts = vec![[0.0, 0.0, 0.0], [1.5, -2.0, 0.25]];
    (
        pts,
        vec![Cell {
            kind: ElementKind::Beam2,
            nodes: vec![0, 1],
        }],
    )
}

#[test]
fn ascii_vtu_has_exact_arrays() {
    let dir = temp_dir("vtkw-ascii");
    let (pts, cells) = line_cell();
    let path = dir.join("line.vtu");
    write_vtu_with(
        &path,
        &pts,
        &cells,
        &[("s", 1, &[1.0, 0.1])],
        &[],
        &[],
        VtuEncoding::Ascii,
    )
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("<Piece NumberOfPoints=\"2\" NumberOfCells=\"1\">"));
    assert!(
        text.contains("format=\"ascii\">\n0 0 0 1.5 -2 0.25\n</DataArray>"),
        "{text}"
    );
    assert!(text.contains("Name=\"types\" NumberOfComponents=\"1\" format=\"ascii\">\n3\n"));
    assert!(text.contains("Name=\"s\" NumberOfComponents=\"1\" format=\"ascii\">\n1 0.1\n"));
}

#[test]
fn base64_vtu_carries_uint64_size_header() {
    let dir = temp_dir("vtkw-b64");
    let (pts, cells) = line_cell();
    let path = dir.join("line.vtu");
    write_vtu(&path, &pts, &cells, &[], &[]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    // types array: 8-byte little-endian length 1, then the byte 3.
    let mut raw = 1u64.to_le_bytes().to_vec();
    raw.push(3);
    assert!(
        text.contains(&format!(
            "format=\"binary\">\n{}\n</DataArray>",
            base64(&raw)
        )),
        "{text}"
    );
    assert!(text.contains("header_type=\"UInt64\""));
}

#[test]
fn inconsistent_input_is_rejected() {
    let dir = temp_dir("vtkw-bad");
    let path = dir.join("bad.vtu");
    let (pts, mut cells) = line_cell();
    let err = write_vtu(&path, &pts, &cells, &[("u", 3, &[0.0; 5])], &[]).unwrap_err();
    assert!(
        err.to_string()
            .contains("point field 'u' has 5 values, expected 3 components x 2 points"),
        "{err}"
    );
    let err = write_vtu(&path, &pts, &cells, &[], &[("c", 0, &[])]).unwrap_err();
    assert!(matches!(err, VtkError::Invalid { .. }));
    cells[0].nodes[1] = 2;
    let err = write_vtu(&path, &pts, &cells, &[], &[]).unwrap_err();
    assert!(
        err.to_string()
            .contains("cell 0 refers to point 2, but there are 2 points"),
        "{err}"
    );
    cells[0].nodes.push(0);
    assert!(write_vtu(&path, &pts, &cells, &[], &[]).is_err());
    assert!(!path.exists());
    assert!(write_pvd(&dir.join("a.pvd"), &[(f64::NAN, "x.vtu")]).is_err());
    let body = sample_body(20, 2, 1);
    assert!(write_mode_shapes(&dir.join("m"), &body, 0.0).is_err());
    assert!(write_mode_shapes(&dir.join("m"), &body, f64::NAN).is_err());
}

#[test]
fn pvd_lists_entries_in_order() {
    let dir = temp_dir("vtkw-pvd");
    let path = dir.join("a.pvd");
    write_pvd(&path, &[(0.0, "f/a.vtu"), (0.5, "f/b&c.vtu")]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"f/a.vtu\"/>\n<DataSet timestep=\"0.5\" group=\"\" part=\"0\" file=\"f/b&amp;c.vtu\"/>"), "{text}");
}

#[test]
fn default_scale_is_a_tenth_of_the_diagonal() {
    let mut body = sample_body(20, 1, 1);
    for (i, p) in body.nodes.iter_mut().enumerate() {
        *p = [
            if i == 0 { 3.0 } else { 0.0 },
            if i == 1 { 4.0 } else { 0.0 },
            0.0,
        ];
    }
    assert!((default_mode_scale(&body) - 0.5).abs() < 1e-15);
}
