//! Extra parts of a ParaView animation frame beside the bodies (contact points, contours): each
//! an unstructured grid of its own (`.vtu`, ASCII, cells of any VTK type: vertices, lines,
//! quads), listed in the `.pvd` with the frame's time and its part number (ParaView shows the
//! parts of one time as the blocks of a multiblock data set).

use super::ResultsError;
use std::fmt::Write as _;
use std::path::Path;

/// VTK cell type of a vertex (`VTK_VERTEX`).
pub const VTK_VERTEX: u8 = 1;
/// VTK cell type of a line segment (`VTK_LINE`).
pub const VTK_LINE: u8 = 3;
/// VTK cell type of a quadrilateral (`VTK_QUAD`).
pub const VTK_QUAD: u8 = 9;

/// One extra part of an animation frame: points, cells `(VTK type, point indices)`, point and
/// cell fields `(name, components, values)`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnimationPart {
    /// Part name (the file name suffix: `<name>_<part>_NNNNNN.vtu`; a plain identifier).
    pub name: String,
    /// Points (global).
    pub points: Vec<[f64; 3]>,
    /// Cells: VTK cell type and point indices.
    pub cells: Vec<(u8, Vec<usize>)>,
    /// Point fields: `components x points` values each.
    pub point_fields: Vec<(String, usize, Vec<f64>)>,
    /// Cell fields: `components x cells` values each.
    pub cell_fields: Vec<(String, usize, Vec<f64>)>,
}

impl AnimationPart {
    /// Checks indices and field lengths: the reason of the first problem.
    pub(super) fn check(&self) -> Result<(), String> {
        let plain = |s: &str| {
            !s.is_empty()
                && s.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        };
        if !plain(&self.name) {
            return Err(format!(
                "part name {:?} must be a plain identifier",
                self.name
            ));
        }
        let n = self.points.len();
        if let Some((i, _)) = self
            .cells
            .iter()
            .enumerate()
            .find(|(_, c)| c.1.iter().any(|&k| k >= n))
        {
            return Err(format!(
                "part '{}': cell {i} refers to a point >= {n}",
                self.name
            ));
        }
        for (what, fields, count) in [
            ("point", &self.point_fields, n),
            ("cell", &self.cell_fields, self.cells.len()),
        ] {
            for (name, c, v) in fields {
                if !plain(name) || *c == 0 || v.len() != c * count {
                    return Err(format!(
                        "part '{}': {what} field '{name}' has {} values for {c} x {count}",
                        self.name,
                        v.len()
                    ));
                }
            }
        }
        if self.points.iter().flatten().any(|x| !x.is_finite()) {
            return Err(format!("part '{}' has a non-finite point", self.name));
        }
        Ok(())
    }
}

/// Appends a `DataArray` of `values` (ASCII, shortest round-trip decimal; non-finite values
/// as `nan`, `inf`, `-inf`).
fn ascii_array(x: &mut String, name: &str, components: usize, kind: &str, values: &[String]) {
    let _ = writeln!(
        x,
        "<DataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
    );
    x.push_str(&values.join(" "));
    x.push_str("\n</DataArray>\n");
}

fn f64_text(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{v:?}")
    }
}

/// Writes `part` at time `t` as an ASCII `.vtu` to `path`.
pub(super) fn write_part_vtu(
    path: &Path,
    part: &AnimationPart,
    t: f64,
) -> Result<(), ResultsError> {
    let mut x = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<FieldData>\n");
    let _ = writeln!(
        x,
        "<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>",
        f64_text(t)
    );
    x.push_str("</FieldData>\n");
    let _ = writeln!(
        x,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<Points>",
        part.points.len(),
        part.cells.len()
    );
    let pts: Vec<String> = part.points.iter().flatten().map(|v| f64_text(*v)).collect();
    ascii_array(&mut x, "Points", 3, "Float64", &pts);
    x.push_str("</Points>\n<Cells>\n");
    let conn: Vec<String> = part
        .cells
        .iter()
        .flat_map(|c| c.1.iter().map(|k| k.to_string()))
        .collect();
    let offsets: Vec<String> = part
        .cells
        .iter()
        .scan(0, |o, c| {
            *o += c.1.len();
            Some(o.to_string())
        })
        .collect();
    let types: Vec<String> = part.cells.iter().map(|c| c.0.to_string()).collect();
    ascii_array(&mut x, "connectivity", 1, "Int64", &conn);
    ascii_array(&mut x, "offsets", 1, "Int64", &offsets);
    ascii_array(&mut x, "types", 1, "UInt8", &types);
    x.push_str("</Cells>\n");
    for (tag, fields) in [
        ("PointData", &part.point_fields),
        ("CellData", &part.cell_fields),
    ] {
        let _ = writeln!(x, "<{tag}>");
        for (name, c, v) in fields {
            let text: Vec<String> = v.iter().map(|v| f64_text(*v)).collect();
            ascii_array(&mut x, name, *c, "Float64", &text);
        }
        let _ = writeln!(x, "</{tag}>");
    }
    x.push_str("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    std::fs::write(path, x).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes a `.pvd` collection with parts: `(time, part, file relative to the .pvd)`.
pub(super) fn write_pvd_with_parts(
    path: &Path,
    entries: &[(f64, usize, &str)],
) -> Result<(), ResultsError> {
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for &(t, part, file) in entries {
        let file = file
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('"', "&quot;");
        let _ = writeln!(
            x,
            "<DataSet timestep=\"{t}\" group=\"\" part=\"{part}\" file=\"{file}\"/>"
        );
    }
    x.push_str("</Collection>\n</VTKFile>\n");
    std::fs::write(path, x).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })
}
