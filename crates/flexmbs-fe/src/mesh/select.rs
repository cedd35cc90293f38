//! Node selection (by plane, box, nearest point), named node sets, and simple geometric
//! measures of a mesh (bounding box, volume).

use super::{ElementKind, Mesh, NodeIdx, Property};
use crate::FeError;

/// Reference coordinates of the 8 hexahedron corners in `C3D8` order.
const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Determinant of the Jacobian `dx/dxi` of the trilinear map through the 8 `corners` (in `C3D8`
/// order) at the reference point `xi` in `[-1, 1]^3`.
pub fn trilinear_jacobian_det(corners: &[[f64; 3]; 8], xi: [f64; 3]) -> f64 {
    let mut j = [[0.0; 3]; 3]; // j[i][a] = d x_i / d xi_a
    for (x, s) in corners.iter().zip(HEX_CORNERS.iter()) {
        let f = [1.0 + s[0] * xi[0], 1.0 + s[1] * xi[1], 1.0 + s[2] * xi[2]];
        let dn = [
            s[0] * f[1] * f[2] / 8.0,
            f[0] * s[1] * f[2] / 8.0,
            f[0] * f[1] * s[2] / 8.0,
        ];
        for i in 0..3 {
            for a in 0..3 {
                j[i][a] += x[i] * dn[a];
            }
        }
    }
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

impl Mesh {
    /// Nodes whose coordinate along `axis` (0 = x, 1 = y, 2 = z) is within `tol` of `value`,
    /// in increasing index order. An invalid axis gives an empty list.
    pub fn nodes_on_plane(&self, axis: usize, value: f64, tol: f64) -> Vec<NodeIdx> {
        if axis > 2 {
            return Vec::new();
        }
        (0..self.nodes.len())
            .filter(|&n| (self.nodes[n][axis] - value).abs() <= tol)
            .collect()
    }

    /// Nodes inside the box `[min - tol, max + tol]` (bounds inclusive), in increasing index order.
    pub fn nodes_in_box(&self, min: [f64; 3], max: [f64; 3], tol: f64) -> Vec<NodeIdx> {
        (0..self.nodes.len())
            .filter(|&n| {
                (0..3).all(|a| self.nodes[n][a] >= min[a] - tol && self.nodes[n][a] <= max[a] + tol)
            })
            .collect()
    }

    /// The node closest to `x` (Euclidean distance; the lowest index on ties), `None` for a mesh
    /// without nodes.
    pub fn nearest_node(&self, x: [f64; 3]) -> Option<NodeIdx> {
        let d2 = |p: &[f64; 3]| (0..3).map(|a| (p[a] - x[a]).powi(2)).sum::<f64>();
        let mut best: Option<(NodeIdx, f64)> = None;
        for (i, p) in self.nodes.iter().enumerate() {
            let d = d2(p);
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((i, d));
            }
        }
        best.map(|(i, _)| i)
    }

    /// Stores (or replaces) the node set `name`; the nodes are sorted and duplicates removed.
    /// Fails for an empty name or a node index out of range.
    pub fn add_node_set(&mut self, name: &str, mut nodes: Vec<NodeIdx>) -> Result<(), FeError> {
        if name.trim().is_empty() {
            return Err(FeError::Invalid("node set name must not be empty".into()));
        }
        if let Some(&n) = nodes.iter().find(|&&n| n >= self.nodes.len()) {
            return Err(FeError::Invalid(format!(
                "node set '{name}': node index {n} out of range (mesh has {} nodes)",
                self.nodes.len()
            )));
        }
        nodes.sort_unstable();
        nodes.dedup();
        self.node_sets.insert(name.to_string(), nodes);
        Ok(())
    }

    /// Axis-aligned bounding box `(min, max)` of all nodes; `([0; 3], [0; 3])` for a mesh without
    /// nodes (use [`Mesh::try_bounding_box`] to tell that case apart).
    pub fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        self.try_bounding_box().unwrap_or(([0.0; 3], [0.0; 3]))
    }

    /// Axis-aligned bounding box `(min, max)` of all nodes, `None` for a mesh without nodes.
    pub fn try_bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.nodes.first()?;
        let (mut lo, mut hi) = (first, first);
        for p in &self.nodes {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        Some((lo, hi))
    }

    /// Volume of one element, from its corner nodes (straight edges assumed):
    ///
    /// * hexahedra (8 or 20 nodes): the trilinear map through the 8 corners integrated with the
    ///   2x2x2 Gauss rule, which is exact for it (det J has degree <= 2 in each reference
    ///   coordinate); mid-edge nodes of Hex20 are ignored, so curved Hex20 edges are not seen;
    /// * Tet10: the volume of the straight tetrahedron through its 4 corners;
    /// * Beam2: section area times length.
    ///
    /// A non-positive det J at a Gauss point (inverted hexahedron) or a non-positive tetrahedron
    /// volume gives [`FeError::BadJacobian`].
    pub fn element_volume(&self, element: usize) -> Result<f64, FeError> {
        let e = self
            .elements
            .get(element)
            .ok_or_else(|| FeError::Invalid(format!("element index {element} out of range")))?;
        if e.nodes.len() != e.kind.num_nodes() || e.nodes.iter().any(|&n| n >= self.nodes.len()) {
            return Err(FeError::Invalid(format!(
                "element {element} has a wrong node count or node index"
            )));
        }
        let x = |i: usize| self.nodes[e.nodes[i]];
        match e.kind {
            ElementKind::Hex8 | ElementKind::Hex8I | ElementKind::Hex20 | ElementKind::Hex20R => {
                let corners: [[f64; 3]; 8] = std::array::from_fn(x);
                let g = 1.0 / 3f64.sqrt();
                let mut v = 0.0;
                for (point, s) in HEX_CORNERS.iter().enumerate() {
                    let det = trilinear_jacobian_det(&corners, [s[0] * g, s[1] * g, s[2] * g]);
                    if det <= 0.0 {
                        return Err(FeError::BadJacobian {
                            element,
                            point,
                            det,
                        });
                    }
                    v += det; // Gauss weights are 1
                }
                Ok(v)
            }
            ElementKind::Tet10 => {
                let (p0, p1, p2, p3) = (x(0), x(1), x(2), x(3));
                let a = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
                let b = [p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]];
                let c = [p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]];
                let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]);
                if det <= 0.0 {
                    return Err(FeError::BadJacobian {
                        element,
                        point: 0,
                        det,
                    });
                }
                Ok(det / 6.0)
            }
            ElementKind::Beam2 => {
                let (p0, p1) = (x(0), x(1));
                let len = (0..3).map(|a| (p1[a] - p0[a]).powi(2)).sum::<f64>().sqrt();
                match self.properties.get(e.property) {
                    Some(Property::Beam { section, .. }) => Ok(section.area * len),
                    _ => Err(FeError::Invalid(format!(
                        "beam element {element} has no beam property"
                    ))),
                }
            }
        }
    }

    /// Total volume: the sum of [`Mesh::element_volume`] over all elements (beams count as
    /// area times length).
    pub fn volume(&self) -> Result<f64, FeError> {
        (0..self.elements.len())
            .map(|e| self.element_volume(e))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Element, Property};
    use crate::{Material, UnitSystem};

    /// One hexahedron with corners `x` (C3D8 order).
    fn single_hex(x: [[f64; 3]; 8]) -> Mesh {
        let mut m = Mesh::default();
        for p in x {
            m.add_node(p);
        }
        let property = m.add_property(Property::Solid {
            material: Material::steel(),
        });
        m.elements.push(Element {
            kind: ElementKind::Hex8,
            nodes: (0..8).collect(),
            property,
        });
        m
    }

    fn unit_cube() -> [[f64; 3]; 8] {
        HEX_CORNERS.map(|s| s.map(|v| 0.5 * (v + 1.0)))
    }

    #[test]
    fn trilinear_volume_is_exact_for_a_warped_hex() {
        // Lift corner 7 (+,+,+) of the unit cube to z = 1 + d: top surface z = 1 + d x y on
        // [0,1]^2, so V = 1 + d/4 exactly (and 2x2x2 Gauss integrates det J exactly).
        let d = 0.6;
        let mut x = unit_cube();
        x[6][2] += d;
        let v = single_hex(x).volume().unwrap();
        assert!((v - (1.0 + d / 4.0)).abs() < 1e-14, "volume {v}");
        // A parallelepiped (shear x += 0.3 z) keeps its volume 1.
        let sheared = unit_cube().map(|p| [p[0] + 0.3 * p[2], p[1], p[2]]);
        let v = single_hex(sheared).volume().unwrap();
        assert!((v - 1.0).abs() < 1e-14, "volume {v}");
    }

    #[test]
    fn inverted_hex_is_reported() {
        let mut x = unit_cube();
        x.swap(0, 4);
        x.swap(1, 5);
        x.swap(2, 6);
        x.swap(3, 7);
        match single_hex(x).volume() {
            Err(FeError::BadJacobian {
                element: 0, det, ..
            }) => assert!(det < 0.0),
            other => panic!("expected BadJacobian, got {other:?}"),
        }
        // det J of the unit cube is (1/2)^3 everywhere.
        let det = trilinear_jacobian_det(&unit_cube(), [0.2, -0.7, 0.1]);
        assert!((det - 0.125).abs() < 1e-15);
    }

    #[test]
    fn selection_by_plane_box_and_nearest() {
        let mut m = single_hex(unit_cube());
        assert_eq!(m.nodes_on_plane(0, 1.0, 1e-12), vec![1, 2, 5, 6]);
        assert_eq!(m.nodes_on_plane(2, 0.0, 1e-12), vec![0, 1, 2, 3]);
        assert!(m.nodes_on_plane(3, 0.0, 1.0).is_empty());
        assert!(m.nodes_on_plane(0, 0.5, 0.1).is_empty());
        assert_eq!(
            m.nodes_in_box([-0.1, -0.1, 0.5], [1.1, 0.2, 1.1], 0.0),
            vec![4, 5]
        );
        assert_eq!(
            m.nodes_in_box([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 1e-12),
            vec![0]
        );
        assert_eq!(m.nearest_node([0.9, 0.8, 1.3]), Some(6));
        assert_eq!(Mesh::default().nearest_node([0.0; 3]), None);
        assert_eq!(m.try_bounding_box(), Some(([0.0; 3], [1.0; 3])));
        assert_eq!(m.bounding_box(), ([0.0; 3], [1.0; 3]));
        assert_eq!(Mesh::default().try_bounding_box(), None);
        assert_eq!(Mesh::default().bounding_box(), ([0.0; 3], [0.0; 3]));
        m.add_node_set("s", vec![3, 1, 3]).unwrap();
        assert_eq!(m.node_set("s").unwrap(), &[1, 3]);
        assert!(matches!(
            m.add_node_set("bad", vec![8]),
            Err(FeError::Invalid(_))
        ));
        assert!(matches!(
            m.add_node_set(" ", vec![0]),
            Err(FeError::Invalid(_))
        ));
        assert!(m.validate().is_ok());
    }

    #[test]
    fn tet_and_beam_volumes() {
        let mut m = Mesh {
            units: UnitSystem::Si,
            ..Mesh::default()
        };
        let pts = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 3.0, 0.0],
            [0.0, 0.0, 4.0],
        ];
        for p in pts {
            m.add_node(p);
        }
        for i in 0..6 {
            // mid-edge nodes are not used by the volume; place them anywhere valid
            m.add_node([0.1 * i as f64, 0.0, 0.0]);
        }
        let solid = m.add_property(Property::Solid {
            material: Material::steel(),
        });
        m.elements.push(Element {
            kind: ElementKind::Tet10,
            nodes: (0..10).collect(),
            property: solid,
        });
        assert!((m.volume().unwrap() - 4.0).abs() < 1e-14); // 2*3*4/6
        let beam = m.add_property(Property::Beam {
            material: Material::steel(),
            section: crate::mesh::BeamSection::circle(0.1),
            theory: Default::default(),
            orientation: [0.0, 1.0, 0.0],
        });
        m.elements.push(Element {
            kind: ElementKind::Beam2,
            nodes: vec![0, 1],
            property: beam,
        });
        let expected = 4.0 + std::f64::consts::PI * 0.05 * 0.05 * 2.0;
        assert!((m.volume().unwrap() - expected).abs() < 1e-14);
    }
}
