//! Structured mesh generators: hexahedral meshes of a box and of a union of axis-aligned boxes,
//! and straight beam lines.
//!
//! The solid generators build a rectilinear grid whose lines pass through every box bound, keep
//! the grid cells whose centre lies inside some box, and create each node once, so that boxes
//! that touch or overlap are meshed conformingly. Linear kinds ([`ElementKind::Hex8`],
//! [`ElementKind::Hex8I`]) use the 8 cell corners; quadratic kinds ([`ElementKind::Hex20`],
//! [`ElementKind::Hex20R`]) add the 12 mid-edge nodes (20-node serendipity element). Node order
//! is the Abaqus/CalculiX `C3D8`/`C3D20` order:
//!
//! * corners 1 (-,-,-), 2 (+,-,-), 3 (+,+,-), 4 (-,+,-), 5-8 the same at +z;
//! * mid-edges 9-12 on the bottom face (1-2, 2-3, 3-4, 4-1), 13-16 on the top face
//!   (5-6, 6-7, 7-8, 8-5), 17-20 vertical (1-5, 2-6, 3-7, 4-8).
//!
//! With increasing grid coordinates this order has a positive Jacobian determinant. Only nodes used
//! by elements are created. Every solid mesh gets the node sets `xmin`, `xmax`, `ymin`, `ymax`,
//! `zmin`, `zmax` (nodes on the faces of the bounding box) and `all`.

use super::{BeamSection, BeamTheory, Element, ElementKind, Mesh, NodeIdx, Property};
use crate::{FeError, Material, UnitSystem};
use std::collections::{BTreeSet, HashMap};

pub use super::profile::extrude_profile;

/// Largest number of grid cells a structured generator accepts (guards against a tiny element
/// size exhausting memory).
pub const MAX_GRID_CELLS: usize = 5_000_000;

/// Relative tolerance (times the bounding-box diagonal) under which two grid coordinates are merged
/// and under which nodes are considered to lie on a bounding-box face.
pub const GEOMETRIC_TOLERANCE: f64 = 1e-9;

/// An axis-aligned box `[min, max]` (each `min[i] < max[i]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxRegion {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

impl BoxRegion {
    /// A box from its lower and upper corners; checked by [`BoxRegion::check`].
    pub fn new(min: [f64; 3], max: [f64; 3]) -> Result<Self, FeError> {
        let b = Self { min, max };
        b.check()?;
        Ok(b)
    }

    /// The box `[origin, origin + size]`.
    pub fn from_origin_size(origin: [f64; 3], size: [f64; 3]) -> Result<Self, FeError> {
        Self::new(
            origin,
            [
                origin[0] + size[0],
                origin[1] + size[1],
                origin[2] + size[2],
            ],
        )
    }

    /// Checks that all bounds are finite and `min < max` along every axis (no degenerate box).
    pub fn check(&self) -> Result<(), FeError> {
        for a in 0..3 {
            if !(self.min[a].is_finite() && self.max[a].is_finite()) {
                return Err(FeError::Invalid(format!(
                    "box bounds must be finite, got min {:?} max {:?}",
                    self.min, self.max
                )));
            }
            if self.min[a] >= self.max[a] {
                return Err(FeError::Invalid(format!(
                    "degenerate box: along axis {a} min {} >= max {} (box min {:?} max {:?})",
                    self.min[a], self.max[a], self.min, self.max
                )));
            }
        }
        Ok(())
    }

    /// Volume of the box.
    pub fn volume(&self) -> f64 {
        (0..3).map(|a| self.max[a] - self.min[a]).product()
    }

    /// Whether the point `x` lies strictly inside the box.
    pub fn contains_strictly(&self, x: [f64; 3]) -> bool {
        (0..3).all(|a| x[a] > self.min[a] && x[a] < self.max[a])
    }
}

/// Whether `kind` is a hexahedron this module can generate, and whether it is quadratic.
fn hex_order(kind: ElementKind) -> Result<bool, FeError> {
    match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => Ok(false),
        ElementKind::Hex20 | ElementKind::Hex20R => Ok(true),
        other => Err(FeError::Invalid(format!(
            "structured solid meshes are hexahedral: element kind must be Hex8, Hex8I, Hex20 or Hex20R, got {other:?}"
        ))),
    }
}

/// Structured hexahedral mesh of the box `[0, size[0]] x [0, size[1]] x [0, size[2]]` with
/// `counts[i]` equal elements along axis `i`.
///
/// Node count: `(nx+1)(ny+1)(nz+1)` for Hex8/Hex8I; for Hex20/Hex20R additionally
/// `nx(ny+1)(nz+1) + (nx+1)ny(nz+1) + (nx+1)(ny+1)nz` mid-edge nodes.
pub fn box_mesh(
    size: [f64; 3],
    counts: [usize; 3],
    kind: ElementKind,
    material: Material,
    units: UnitSystem,
) -> Result<Mesh, FeError> {
    let b = BoxRegion::from_origin_size([0.0; 3], size)?;
    let mut grid: [Vec<f64>; 3] = Default::default();
    for a in 0..3 {
        if counts[a] == 0 {
            return Err(FeError::Invalid(format!(
                "box_mesh: element count along axis {a} must be >= 1, got 0"
            )));
        }
        grid[a] = subdivide(b.min[a], b.max[a], counts[a]);
    }
    structured_hex_mesh(&grid, &[b], kind, material, units)
}

/// Structured hexahedral mesh of the union of `boxes` (they may touch or overlap).
///
/// Grid lines along each axis are the box bounds (merged when closer than
/// [`GEOMETRIC_TOLERANCE`] times the bounding-box diagonal); each interval between neighbouring
/// lines is divided into the smallest number of equal parts whose length is `<= max_size[axis]`.
/// A grid cell becomes an element when its centre lies inside some box. The mesh is conforming:
/// nodes on interfaces between boxes are shared.
pub fn union_of_boxes(
    boxes: &[BoxRegion],
    max_size: [f64; 3],
    kind: ElementKind,
    material: Material,
    units: UnitSystem,
) -> Result<Mesh, FeError> {
    if boxes.is_empty() {
        return Err(FeError::Invalid(
            "union_of_boxes: the list of boxes is empty".into(),
        ));
    }
    for (i, b) in boxes.iter().enumerate() {
        b.check()
            .map_err(|e| FeError::Invalid(format!("union_of_boxes: box {i}: {e}")))?;
    }
    for (a, h) in max_size.iter().enumerate() {
        if !(h.is_finite() && *h > 0.0) {
            return Err(FeError::Invalid(format!(
                "union_of_boxes: target element size along axis {a} must be finite and > 0, got {h}"
            )));
        }
    }
    let tol = GEOMETRIC_TOLERANCE * bounding_diagonal(boxes);
    let mut grid: [Vec<f64>; 3] = Default::default();
    for a in 0..3 {
        let mut bounds: Vec<f64> = boxes.iter().flat_map(|b| [b.min[a], b.max[a]]).collect();
        bounds.sort_by(f64::total_cmp);
        bounds.dedup_by(|x, prev| (*x - *prev).abs() <= tol);
        let mut lines = vec![bounds[0]];
        for w in bounds.windows(2) {
            let n = ((w[1] - w[0]) / max_size[a] * (1.0 - 1e-12))
                .ceil()
                .max(1.0);
            if n > MAX_GRID_CELLS as f64 {
                return Err(too_many_cells(n));
            }
            lines.extend_from_slice(&subdivide(w[0], w[1], n as usize)[1..]);
        }
        grid[a] = lines;
    }
    structured_hex_mesh(&grid, boxes, kind, material, units)
}

/// The assumed geometry of the `complex_beam_frequencies` benchmark (seed 000 §5.1; the seed's
/// figure is lost, see `reference/benchmarks.md`), in mm: a root block `[0, 10] x [0, 20] x
/// [0, 34.2]` followed along +x by a 95 mm T-section whose web (9.74 mm wide, centred in y,
/// 15 mm high) stands on `z = 0` and whose flange (20 mm x 5 mm) lies on top of the web
/// (`z` from 15 to 20). The clamped face is `x = 0` (node set `xmin`).
pub fn complex_beam_boxes() -> Vec<BoxRegion> {
    let (w1, w2) = (20.0, 9.74);
    vec![
        BoxRegion {
            min: [0.0, 0.0, 0.0],
            max: [10.0, w1, 34.2],
        },
        BoxRegion {
            min: [10.0, (w1 - w2) / 2.0, 0.0],
            max: [105.0, (w1 + w2) / 2.0, 15.0],
        },
        BoxRegion {
            min: [10.0, 0.0, 15.0],
            max: [105.0, w1, 20.0],
        },
    ]
}

/// `n` equal intervals of `[lo, hi]` as `n + 1` grid coordinates (ends exact).
fn subdivide(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let mut v: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * (i as f64) / (n as f64))
        .collect();
    v[n] = hi;
    v
}

fn bounding_diagonal(boxes: &[BoxRegion]) -> f64 {
    let mut d2 = 0.0;
    for a in 0..3 {
        let lo = boxes.iter().map(|b| b.min[a]).fold(f64::INFINITY, f64::min);
        let hi = boxes
            .iter()
            .map(|b| b.max[a])
            .fold(f64::NEG_INFINITY, f64::max);
        d2 += (hi - lo) * (hi - lo);
    }
    d2.sqrt()
}

fn too_many_cells(n: f64) -> FeError {
    FeError::Invalid(format!(
        "the structured grid would have {n:.3e} cells, more than the limit {MAX_GRID_CELLS}: increase the element size"
    ))
}

/// Offsets, in doubled grid indices, of the 20 nodes of a cell in `C3D20` order (the first 8 are
/// the `C3D8` corners).
const HEX20_OFFSETS: [[usize; 3]; 20] = [
    [0, 0, 0],
    [2, 0, 0],
    [2, 2, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [2, 2, 2],
    [0, 2, 2],
    [1, 0, 0],
    [2, 1, 0],
    [1, 2, 0],
    [0, 1, 0],
    [1, 0, 2],
    [2, 1, 2],
    [1, 2, 2],
    [0, 1, 2],
    [0, 0, 1],
    [2, 0, 1],
    [2, 2, 1],
    [0, 2, 1],
];

/// Meshes the cells of the rectilinear `grid` whose centres lie in some box.
fn structured_hex_mesh(
    grid: &[Vec<f64>; 3],
    boxes: &[BoxRegion],
    kind: ElementKind,
    material: Material,
    units: UnitSystem,
) -> Result<Mesh, FeError> {
    let quadratic = hex_order(kind)?;
    material.validate()?;
    let n = [grid[0].len() - 1, grid[1].len() - 1, grid[2].len() - 1];
    let total = n.iter().map(|&v| v as f64).product::<f64>();
    if total > MAX_GRID_CELLS as f64 {
        return Err(too_many_cells(total));
    }
    // the assembly of K and M (consistent mass) of this many elements, refused before meshing:
    // an interior cell brings 1 corner and (quadratic) 3 mid-edge nodes, whose 3 DOFs couple
    // with 27 (linear) or 81 / 51 (corner / mid-edge, quadratic) nodes: 243 or 2106 matrix
    // entries per cell
    let entries_per_cell = if quadratic { 2106 } else { 243 };
    crate::memory::check_allocation(
        &format!("the assembly of K and M of {total:.0} hex elements"),
        crate::assembly::assembly_bytes((entries_per_cell as f64 * total) as usize),
    )?;
    let mid = |a: usize, i: usize| 0.5 * (grid[a][i] + grid[a][i + 1]);
    let mut cells = Vec::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let c = [mid(0, i), mid(1, j), mid(2, k)];
                if boxes.iter().any(|b| b.contains_strictly(c)) {
                    cells.push([i, j, k]);
                }
            }
        }
    }
    if cells.is_empty() {
        return Err(FeError::Invalid(
            "structured mesh: no grid cell lies inside the region".into(),
        ));
    }
    let per_elem = if quadratic { 20 } else { 8 };
    // Node keys in doubled grid indices: corners even, mid-edge nodes with one odd index.
    let key = |c: &[usize; 3], o: &[usize; 3]| [2 * c[0] + o[0], 2 * c[1] + o[1], 2 * c[2] + o[2]];
    let used: BTreeSet<[usize; 3]> = cells
        .iter()
        .flat_map(|c| HEX20_OFFSETS[..per_elem].iter().map(move |o| key(c, o)))
        .collect();
    let coord = |a: usize, d: usize| {
        if d.is_multiple_of(2) {
            grid[a][d / 2]
        } else {
            mid(a, d / 2)
        }
    };
    let mut mesh = Mesh {
        units,
        ..Mesh::default()
    };
    let mut index: HashMap<[usize; 3], NodeIdx> = HashMap::with_capacity(used.len());
    for k in &used {
        let idx = mesh.add_node([coord(0, k[0]), coord(1, k[1]), coord(2, k[2])]);
        index.insert(*k, idx);
    }
    let property = mesh.add_property(Property::Solid { material });
    mesh.elements = cells
        .iter()
        .map(|c| Element {
            kind,
            nodes: HEX20_OFFSETS[..per_elem]
                .iter()
                .map(|o| index[&key(c, o)])
                .collect(),
            property,
        })
        .collect();
    add_bounding_face_sets(&mut mesh);
    Ok(mesh)
}

/// Adds the node sets `xmin` ... `zmax` (nodes on the bounding-box faces) and `all`.
pub(crate) fn add_bounding_face_sets(mesh: &mut Mesh) {
    let Some((lo, hi)) = mesh.try_bounding_box() else {
        return;
    };
    let diag = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
    let tol = GEOMETRIC_TOLERANCE * diag.max(f64::MIN_POSITIVE);
    for face in super::BoxFace::ALL {
        let nodes = mesh.nodes_on_plane(face.axis(), face.plane(lo, hi), tol);
        mesh.node_sets.insert(face.name().into(), nodes);
    }
    mesh.node_sets
        .insert("all".into(), (0..mesh.num_nodes()).collect());
}

/// A straight line of `n_elements` equal [`ElementKind::Beam2`] elements from `p0` to `p1`.
///
/// `orientation` is a vector in the local x-y plane fixing the local y axis of the section; it
/// must not be parallel to the beam. Node sets: `start` (the node at `p0`), `end` (at `p1`) and
/// `all`.
#[allow(clippy::too_many_arguments)]
pub fn beam_line(
    p0: [f64; 3],
    p1: [f64; 3],
    n_elements: usize,
    section: BeamSection,
    theory: BeamTheory,
    orientation: [f64; 3],
    material: Material,
    units: UnitSystem,
) -> Result<Mesh, FeError> {
    if n_elements == 0 {
        return Err(FeError::Invalid(
            "beam_line: the number of elements must be >= 1".into(),
        ));
    }
    if p0
        .iter()
        .chain(&p1)
        .chain(&orientation)
        .any(|v| !v.is_finite())
    {
        return Err(FeError::Invalid(
            "beam_line: end points and orientation must be finite".into(),
        ));
    }
    material.validate()?;
    let d = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
    let len = norm(d);
    if len == 0.0 {
        return Err(FeError::Invalid(format!(
            "beam_line: start and end point coincide at {p0:?}"
        )));
    }
    let c = [
        d[1] * orientation[2] - d[2] * orientation[1],
        d[2] * orientation[0] - d[0] * orientation[2],
        d[0] * orientation[1] - d[1] * orientation[0],
    ];
    if norm(c) <= 1e-9 * len * norm(orientation) || norm(orientation) == 0.0 {
        return Err(FeError::Invalid(format!(
            "beam_line: orientation {orientation:?} is zero or parallel to the beam axis {d:?}"
        )));
    }
    let s = section;
    let positive = [s.area, s.iy, s.iz, s.j];
    if positive.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(FeError::Invalid(format!(
            "beam_line: section area, iy, iz and j must be finite and > 0, got {section:?}"
        )));
    }
    if theory == BeamTheory::Timoshenko && [s.ky, s.kz].iter().any(|k| !(k.is_finite() && *k > 0.0))
    {
        return Err(FeError::Invalid(format!(
            "beam_line: Timoshenko shear factors must be > 0, got ky {} kz {}",
            s.ky, s.kz
        )));
    }
    let mut mesh = Mesh {
        units,
        ..Mesh::default()
    };
    for i in 0..=n_elements {
        let t = i as f64 / n_elements as f64;
        let x = if i == n_elements {
            p1
        } else {
            [p0[0] + t * d[0], p0[1] + t * d[1], p0[2] + t * d[2]]
        };
        mesh.add_node(x);
    }
    let property = mesh.add_property(Property::Beam {
        material,
        section,
        theory,
        orientation,
    });
    mesh.elements = (0..n_elements)
        .map(|i| Element {
            kind: ElementKind::Beam2,
            nodes: vec![i, i + 1],
            property,
        })
        .collect();
    mesh.node_sets.insert("start".into(), vec![0]);
    mesh.node_sets.insert("end".into(), vec![n_elements]);
    mesh.node_sets
        .insert("all".into(), (0..=n_elements).collect());
    Ok(mesh)
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::select::trilinear_jacobian_det;

    /// Corner pairs of the 12 mid-edge nodes 9..20 (0-based 8..19) of `C3D20`.
    const HEX20_EDGES: [[usize; 2]; 12] = [
        [0, 1],
        [1, 2],
        [2, 3],
        [3, 0],
        [4, 5],
        [5, 6],
        [6, 7],
        [7, 4],
        [0, 4],
        [1, 5],
        [2, 6],
        [3, 7],
    ];

    fn steel_mm() -> Material {
        Material {
            e: 210000.0,
            nu: 0.3,
            rho: 7.987e-9,
        }
    }

    /// Checks every generated solid mesh: validate() passes, no duplicate nodes (all pairwise
    /// distances > 1e-9 of the bounding-box diagonal), no orphan nodes, det J > 0 at every element
    /// centre, and (Hex20) mid-edge nodes at the edge midpoints to 1e-12 of the diagonal.
    fn check_solid_mesh(m: &Mesh) {
        m.validate().unwrap();
        let (lo, hi) = m.bounding_box();
        let diag = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
        let dist =
            |p: [f64; 3], q: [f64; 3]| (0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>().sqrt();
        for i in 0..m.num_nodes() {
            for j in 0..i {
                assert!(
                    dist(m.nodes[i], m.nodes[j]) > 1e-9 * diag,
                    "duplicate nodes {i} {j}"
                );
            }
        }
        assert!(m.node_dofs().iter().all(|&d| d == 3), "orphan node");
        for (ei, e) in m.elements.iter().enumerate() {
            let corners: [[f64; 3]; 8] = std::array::from_fn(|i| m.nodes[e.nodes[i]]);
            let det = trilinear_jacobian_det(&corners, [0.0; 3]);
            assert!(det > 0.0, "element {ei}: det J {det}");
            if e.kind.num_nodes() == 20 {
                for (k, [a, b]) in HEX20_EDGES.iter().enumerate() {
                    let (pa, pb) = (m.nodes[e.nodes[*a]], m.nodes[e.nodes[*b]]);
                    let midpoint = [
                        0.5 * (pa[0] + pb[0]),
                        0.5 * (pa[1] + pb[1]),
                        0.5 * (pa[2] + pb[2]),
                    ];
                    assert!(
                        dist(m.nodes[e.nodes[8 + k]], midpoint) <= 1e-12 * diag,
                        "element {ei} edge {k}"
                    );
                }
            }
        }
    }

    fn hex20_nodes(n: [usize; 3]) -> usize {
        let [x, y, z] = n;
        (x + 1) * (y + 1) * (z + 1)
            + x * (y + 1) * (z + 1)
            + (x + 1) * y * (z + 1)
            + (x + 1) * (y + 1) * z
    }

    #[test]
    fn box_counts_sets_and_volume() {
        let (size, n) = ([2.0, 1.0, 0.5], [4, 3, 2]);
        for kind in [
            ElementKind::Hex8,
            ElementKind::Hex8I,
            ElementKind::Hex20,
            ElementKind::Hex20R,
        ] {
            let m = box_mesh(size, n, kind, Material::steel(), UnitSystem::Si).unwrap();
            check_solid_mesh(&m);
            assert_eq!(m.elements.len(), 24);
            let quad = kind.num_nodes() == 20;
            let nodes = if quad { hex20_nodes(n) } else { 5 * 4 * 3 };
            assert_eq!(m.num_nodes(), nodes, "{kind:?}");
            assert!(m.elements.iter().all(|e| e.kind == kind));
            assert!((m.volume().unwrap() - 1.0).abs() < 1e-14);
            // Face sets: a face with a x b elements has (a+1)(b+1) corner nodes (+ a(b+1) + (a+1)b).
            let face = |a: usize, b: usize| {
                (a + 1) * (b + 1) + if quad { a * (b + 1) + (a + 1) * b } else { 0 }
            };
            for (name, count) in [
                ("xmin", face(3, 2)),
                ("xmax", face(3, 2)),
                ("ymin", face(4, 2)),
                ("ymax", face(4, 2)),
                ("zmin", face(4, 3)),
                ("zmax", face(4, 3)),
            ] {
                let set = m.node_set(name).unwrap();
                assert_eq!(set.len(), count, "{kind:?} {name}");
                let axis = (name.as_bytes()[0] - b'x') as usize;
                let value = if name.ends_with("min") {
                    0.0
                } else {
                    size[axis]
                };
                assert!(set.iter().all(|&i| m.nodes[i][axis] == value));
            }
            assert_eq!(m.node_set("all").unwrap().len(), nodes);
        }
        // hex20 formula for 4x3x2: 60 corners + 4*4*3 + 5*3*3 + 5*4*2 = 60 + 48 + 45 + 40
        assert_eq!(hex20_nodes([4, 3, 2]), 193);
    }

    #[test]
    fn complex_beam_volume_is_exact() {
        let analytic = 10.0 * 20.0 * 34.2 + 95.0 * (20.0 * 5.0 + 9.74 * 15.0);
        let boxes = complex_beam_boxes();
        let sum: f64 = boxes.iter().map(BoxRegion::volume).sum();
        assert!((sum - analytic).abs() <= 1e-12 * analytic); // the boxes are disjoint
        for (kind, h) in [(ElementKind::Hex8I, 2.5), (ElementKind::Hex20, 5.0)] {
            let m = union_of_boxes(&boxes, [h; 3], kind, steel_mm(), UnitSystem::SiMm).unwrap();
            check_solid_mesh(&m);
            let v = m.volume().unwrap();
            assert!(
                (v - analytic).abs() <= 1e-12 * analytic,
                "{kind:?}: {v} vs {analytic}"
            );
            // every element edge is <= h
            for e in &m.elements {
                let (p, q) = (m.nodes[e.nodes[0]], m.nodes[e.nodes[6]]);
                assert!((0..3).all(|a| q[a] - p[a] <= h * (1.0 + 1e-12) && q[a] > p[a]));
            }
            // the clamped face x = 0 is the root block's 20 x 34.2 face only
            let clamp = m.node_set("xmin").unwrap();
            // y lines 0, 5.13, 14.87, 20 and z lines 0, 15, 20, 34.2, intervals split by ceil(L/h):
            // h = 2.5: ny = 3+4+3, nz = 6+2+6; h = 5: ny = 2+2+2, nz = 3+1+3.
            let (ny, nz) = if h == 2.5 { (10, 14) } else { (6, 7) };
            let expected = if kind.num_nodes() == 20 {
                hex20_nodes([0, ny, nz])
            } else {
                (ny + 1) * (nz + 1)
            };
            assert_eq!(clamp.len(), expected, "{kind:?}");
        }
    }

    #[test]
    fn touching_boxes_share_interface_nodes() {
        // Two unit cubes touching at x = 1, h = 0.25: 9 x 5 x 5 nodes, 25 shared on the interface.
        let a = BoxRegion::new([0.0; 3], [1.0; 3]).unwrap();
        let b = BoxRegion::new([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]).unwrap();
        let m = union_of_boxes(
            &[a, b],
            [0.25; 3],
            ElementKind::Hex8,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        check_solid_mesh(&m);
        assert_eq!(m.num_nodes(), 9 * 5 * 5);
        assert_eq!(2 * 125 - m.num_nodes(), 25);
        let interface = m.nodes_on_plane(0, 1.0, 1e-12);
        assert_eq!(interface.len(), 25);
        // each interface node belongs to elements on both sides
        for &n in &interface {
            let sides: Vec<f64> = m
                .elements
                .iter()
                .filter(|e| e.nodes.contains(&n))
                .map(|e| e.nodes.iter().map(|&k| m.nodes[k][0]).sum::<f64>() / 8.0)
                .collect();
            assert!(
                sides.iter().any(|&c| c < 1.0) && sides.iter().any(|&c| c > 1.0),
                "node {n}"
            );
        }
        // Stepped block (smaller box on a face), quadratic: the small face's nodes are all shared.
        let c = BoxRegion::new([1.0, 0.25, 0.0], [3.0, 0.75, 0.5]).unwrap();
        let m = union_of_boxes(
            &[a, c],
            [0.25; 3],
            ElementKind::Hex20,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        check_solid_mesh(&m);
        assert!((m.volume().unwrap() - 1.5).abs() < 1e-14);
        let face = m.nodes_in_box([1.0, 0.25, 0.0], [1.0, 0.75, 0.5], 1e-12);
        assert_eq!(face.len(), hex20_nodes([0, 2, 2])); // a 2 x 2 quadratic face: 9 + 6 + 6 = 21
        for &n in &face {
            let users = m.elements.iter().filter(|e| e.nodes.contains(&n)).count();
            assert!(users >= 2, "interface node {n} used by {users} element(s)");
        }
    }

    #[test]
    fn overlapping_boxes_mesh_their_union() {
        // [0,2]x[0,1]x[0,1] and [1,3]x[0,1]x[0,1] overlap in a unit cube: union volume 3.
        let a = BoxRegion::new([0.0; 3], [2.0, 1.0, 1.0]).unwrap();
        let b = BoxRegion::new([1.0, 0.0, 0.0], [3.0, 1.0, 1.0]).unwrap();
        let m = union_of_boxes(
            &[a, b],
            [0.3, 0.5, 1.0],
            ElementKind::Hex8,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        check_solid_mesh(&m);
        assert!((m.volume().unwrap() - 3.0).abs() < 1e-14);
        assert_eq!(m.elements.len(), 3 * 4 * 2); // each unit interval in x split into ceil(1/0.3) = 4
                                                 // An L-shaped union leaves out the empty corner cells and their nodes.
        let c = BoxRegion::new([0.0, 1.0, 0.0], [1.0, 2.0, 1.0]).unwrap();
        let m = union_of_boxes(
            &[a, c],
            [1.0; 3],
            ElementKind::Hex8,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        check_solid_mesh(&m);
        assert_eq!((m.elements.len(), m.num_nodes()), (3, 16));
    }

    #[test]
    fn invalid_input_is_rejected() {
        let (steel, si, h8) = (Material::steel(), UnitSystem::Si, ElementKind::Hex8);
        let bad = |r: Result<Mesh, FeError>| matches!(r, Err(FeError::Invalid(_)));
        let bm = |size: [f64; 3], n: [usize; 3], kind| box_mesh(size, n, kind, steel, si);
        assert!(bad(bm([1.0, 0.0, 1.0], [1, 1, 1], h8)));
        assert!(bad(bm([1.0, -1.0, 1.0], [1, 1, 1], h8)));
        assert!(bad(bm([1.0, f64::NAN, 1.0], [1, 1, 1], h8)));
        assert!(bad(bm([1.0; 3], [1, 0, 1], h8)));
        assert!(bad(bm([1.0; 3], [1, 1, 1], ElementKind::Tet10)));
        assert!(bad(bm([1.0; 3], [1, 1, 1], ElementKind::Beam2)));
        assert!(bad(bm([1.0; 3], [3000; 3], h8))); // > MAX_GRID_CELLS
        let bad_mat = Material { e: -1.0, ..steel };
        assert!(bad(box_mesh([1.0; 3], [1, 1, 1], h8, bad_mat, si)));
        let unit = BoxRegion {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let flat = BoxRegion {
            min: [0.0; 3],
            max: [1.0, 1.0, 0.0],
        };
        let ub = |b: &[BoxRegion], h: [f64; 3]| union_of_boxes(b, h, h8, steel, si);
        assert!(bad(ub(&[], [1.0; 3])));
        assert!(bad(ub(&[unit, flat], [1.0; 3])));
        assert!(bad(ub(&[unit], [1.0, 0.0, 1.0])));
        assert!(bad(ub(&[unit], [1e-9; 3])));
        assert!(BoxRegion::new([0.0; 3], [1.0, f64::INFINITY, 1.0]).is_err());
    }

    #[test]
    fn beam_line_nodes_elements_and_sets() {
        let s = BeamSection::tube(0.01, 0.001);
        let (p0, p1, z) = ([0.0, 0.0, 0.0], [1.0, 2.0, 2.0], [0.0, 0.0, 1.0]);
        let (ti, eb) = (BeamTheory::Timoshenko, BeamTheory::EulerBernoulli);
        let bl = |p1, n, s, theory, o| {
            beam_line(p0, p1, n, s, theory, o, Material::steel(), UnitSystem::Si)
        };
        let m = bl(p1, 6, s, ti, z).unwrap();
        m.validate().unwrap();
        assert_eq!((m.num_nodes(), m.elements.len()), (7, 6));
        let chain =
            |(i, e): (usize, &Element)| e.kind == ElementKind::Beam2 && e.nodes == [i, i + 1];
        assert!(m.elements.iter().enumerate().all(chain));
        assert_eq!(m.node_set("start").unwrap(), &[0]);
        assert_eq!(m.node_set("end").unwrap(), &[6]);
        assert_eq!(m.nodes[6], p1);
        for i in 0..7 {
            let t = i as f64 / 6.0;
            assert!((0..3).all(|a| (m.nodes[i][a] - t * p1[a]).abs() < 1e-15));
        }
        assert!((m.volume().unwrap() - 3.0 * s.area).abs() < 1e-15); // length 3
        assert!(m.node_dofs().iter().all(|&d| d == 6));
        let err = |r: Result<Mesh, FeError>| matches!(r, Err(FeError::Invalid(_)));
        assert!(err(bl(p1, 0, s, eb, z)));
        assert!(err(bl(p0, 2, s, eb, z)));
        assert!(err(bl(p1, 2, s, eb, [0.5, 1.0, 1.0])));
        assert!(err(bl(p1, 2, s, eb, [0.0; 3])));
        assert!(err(bl(p1, 2, BeamSection { area: 0.0, ..s }, eb, z)));
        let no_k = BeamSection { ky: 0.0, ..s };
        assert!(err(bl(p1, 2, no_k, ti, z)));
        assert!(bl(p1, 2, no_k, eb, z).is_ok());
    }
}
