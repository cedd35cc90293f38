//! A force at a point of a solid mesh as consistent nodal loads: the shape-function values of the
//! element that contains the point, `f_i = N_i(xi) F` (the work-equivalent load of a point force).
//! Used by the static load patterns of a reduction ([`crate::static_modes`]).

use crate::element::solid::ShapeFn;
use crate::element::{hex20, hex8, tet10};
use crate::{ElementKind, FeError, Mesh, NodeIdx};
use nalgebra::{Matrix3, Vector3};

/// Tolerance on the natural coordinates of a point inside an element (element faces included).
const INSIDE_TOLERANCE: f64 = 1e-9;

/// The nodes and shape-function weights (`sum = 1`) of the point `p` in the first solid element of
/// `mesh` that contains it (a point on a face shared by two elements gets the same weights from
/// either, up to round-off).
///
/// Errors: a point outside every solid element ([`FeError::Invalid`], naming the point), a mesh
/// without solid elements.
pub fn point_weights(mesh: &Mesh, p: [f64; 3]) -> Result<Vec<(NodeIdx, f64)>, FeError> {
    let size = mesh_extent(mesh);
    let mut solid = 0;
    for e in &mesh.elements {
        let Some((shape, start)) = shape_of(e.kind) else {
            continue;
        };
        solid += 1;
        let x: Vec<[f64; 3]> = e.nodes.iter().map(|&i| mesh.nodes[i]).collect();
        if !in_box(&x, p, 1e-9 * size) {
            continue;
        }
        if let Some(xi) = natural_coordinates(shape, &x, p, start, size) {
            if inside(e.kind, xi) {
                let mut n = vec![0.0; x.len()];
                let mut dn = vec![[0.0; 3]; x.len()];
                shape(xi, &mut n, &mut dn);
                return Ok(e.nodes.iter().copied().zip(n).collect());
            }
        }
    }
    if solid == 0 {
        return Err(FeError::Invalid(
            "a point load needs solid elements (hex8, hex8i, hex20, hex20r, tet10); on a beam \
             mesh select the loaded nodes instead"
                .into(),
        ));
    }
    Err(FeError::Invalid(format!(
        "the point {p:?} lies outside the mesh (in no solid element)"
    )))
}

fn shape_of(kind: ElementKind) -> Option<(ShapeFn, [f64; 3])> {
    match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => Some((hex8::hex8_shape, [0.0; 3])),
        ElementKind::Hex20 | ElementKind::Hex20R => Some((hex20::hex20_shape, [0.0; 3])),
        ElementKind::Tet10 => Some((tet10::tet10_shape, [0.25; 3])),
        ElementKind::Beam2 => None,
    }
}

fn inside(kind: ElementKind, xi: [f64; 3]) -> bool {
    let t = INSIDE_TOLERANCE;
    match kind {
        ElementKind::Tet10 => xi.iter().all(|&c| c >= -t) && xi.iter().sum::<f64>() <= 1.0 + t,
        _ => xi.iter().all(|&c| c.abs() <= 1.0 + t),
    }
}

/// The largest extent of the mesh's bounding box (at least 1e-300).
fn mesh_extent(mesh: &Mesh) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in &mesh.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    (0..3).map(|k| hi[k] - lo[k]).fold(1e-300, f64::max)
}

fn in_box(x: &[[f64; 3]], p: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| {
        let lo = x.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min);
        let hi = x.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max);
        p[k] >= lo - tol && p[k] <= hi + tol
    })
}

/// Newton's method on `x(xi) = p` from `start`; `None` if it does not converge (to 1e-12 of the
/// mesh size) in 30 iterations or meets a singular Jacobian.
fn natural_coordinates(
    shape: ShapeFn,
    x: &[[f64; 3]],
    p: [f64; 3],
    start: [f64; 3],
    size: f64,
) -> Option<[f64; 3]> {
    let nn = x.len();
    let (mut n, mut dn) = (vec![0.0; nn], vec![[0.0; 3]; nn]);
    let mut xi = start;
    for _ in 0..30 {
        shape(xi, &mut n, &mut dn);
        let mut r = Vector3::from(p);
        let mut jac = Matrix3::zeros();
        for i in 0..nn {
            for a in 0..3 {
                r[a] -= n[i] * x[i][a];
                for b in 0..3 {
                    jac[(a, b)] += x[i][a] * dn[i][b];
                }
            }
        }
        if r.norm() <= 1e-12 * size {
            return Some(xi);
        }
        let d = jac.try_inverse()? * r;
        for k in 0..3 {
            xi[k] += d[k];
        }
        if xi.iter().any(|c| !c.is_finite() || c.abs() > 10.0) {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::box_mesh;
    use crate::{Material, UnitSystem};

    fn block(kind: ElementKind) -> Mesh {
        box_mesh(
            [0.25, 0.05, 0.05],
            [5, 2, 2],
            kind,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap()
    }

    /// One distorted straight-edged tet10 (corners, then the mid-edge nodes 12, 23, 31, 14, 24,
    /// 34 as Abaqus numbers them).
    fn tet() -> Mesh {
        let c = [
            [0.0, 0.0, 0.0],
            [0.3, 0.02, 0.0],
            [0.05, 0.06, 0.01],
            [0.1, 0.01, 0.07],
        ];
        let mid = |a: usize, b: usize| [0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k]));
        let mut mesh = block(ElementKind::Hex8);
        mesh.nodes = c.to_vec();
        for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
            mesh.nodes.push(mid(a, b));
        }
        mesh.node_ids = (1..=10).collect();
        mesh.elements.truncate(1);
        mesh.elements[0].kind = ElementKind::Tet10;
        mesh.elements[0].nodes = (0..10).collect();
        mesh.node_sets.clear();
        mesh
    }

    /// Partition of unity and reproduction of the point (`sum N_i x_i = p`): the load's
    /// resultant is the force and its moment about any point that of the force at `p`.
    #[test]
    fn weights_reproduce_the_point() {
        let t = tet();
        let n = |i: usize| t.nodes[i];
        let inside = [0, 1, 2].map(|k| 0.25 * (n(0)[k] + n(1)[k] + n(2)[k] + n(3)[k]));
        let w = point_weights(&t, inside).unwrap();
        let x: Vec<f64> = (0..3)
            .map(|k| w.iter().map(|&(i, v)| v * t.nodes[i][k]).sum())
            .collect();
        assert!(
            (0..3).all(|k| (x[k] - inside[k]).abs() < 1e-12),
            "tet10: {x:?}"
        );
        assert!(point_weights(&t, [0.3, 0.06, 0.07]).is_err());
        for kind in [ElementKind::Hex8, ElementKind::Hex20] {
            let mesh = block(kind);
            for p in [
                [0.235, 0.05, 0.025],
                [0.1234, 0.0111, 0.0432],
                [0.0, 0.0, 0.0],
                [0.25, 0.05, 0.05],
            ] {
                let w = point_weights(&mesh, p).unwrap();
                let sum: f64 = w.iter().map(|(_, v)| v).sum();
                assert!((sum - 1.0).abs() < 1e-12, "{kind:?} {p:?}: sum {sum}");
                for k in 0..3 {
                    let x: f64 = w.iter().map(|&(i, v)| v * mesh.nodes[i][k]).sum();
                    assert!((x - p[k]).abs() < 1e-12, "{kind:?} {p:?}: {x} vs {}", p[k]);
                }
            }
        }
    }

    /// At a node the whole force goes to that node.
    #[test]
    fn a_point_at_a_node_loads_the_node() {
        let mesh = block(ElementKind::Hex20);
        let node = 17;
        let w = point_weights(&mesh, mesh.nodes[node]).unwrap();
        for (i, v) in w {
            let expect = if i == node { 1.0 } else { 0.0 };
            assert!((v - expect).abs() < 1e-12, "node {i}: {v}");
        }
    }

    #[test]
    fn a_point_outside_is_refused() {
        let mesh = block(ElementKind::Hex20);
        let e = point_weights(&mesh, [0.3, 0.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("outside the mesh"), "{e}");
    }
}
