//! The nodal shares of a force at a point of a face's NURBS surface: the weights through which a
//! `surface` contour on that face (the cubic surface through the face's node grid, seed 000
//! (3.23), (3.24)) passes a contact force to the nodes. A static load response to this pattern
//! enriches a modal basis exactly where a contact on the contour acts.

use flexmbs_core::ffr::contour::{box_face_grid, ContourSettings};
use flexmbs_fe::{BoxFace, Mesh, NodeIdx};
use flexmbs_nurbs::{SearchGrid, SearchSettings, SurfaceInterpolator, SurfaceSearch};
use nalgebra::Vector3;

/// The largest distance of the point from the face's surface, relative to the diagonal of the
/// mesh's bounding box (a point off the face is a mistake, not a projection to make).
const MAX_DISTANCE: f64 = 1e-3;

/// The nodes of `face` and their weights in the surface point nearest to `point` (mesh units),
/// built as a `surface` contour with default settings on that face builds its surface (the same
/// node grid, [`box_face_grid`], and the same interpolation). Errors as text.
pub fn face_point_weights(
    mesh: &Mesh,
    face: &str,
    point: [f64; 3],
) -> Result<Vec<(NodeIdx, f64)>, String> {
    let box_face = BoxFace::from_name(face)
        .ok_or_else(|| format!("unknown face `{face}` ({})", BoxFace::NAMES))?;
    let pts: Vec<Vector3<f64>> = mesh.nodes.iter().map(|p| Vector3::from(*p)).collect();
    let (lo, hi) = mesh.bounding_box();
    let diag = (Vector3::from(hi) - Vector3::from(lo)).norm();
    let (grid, ne, nx) = box_face_grid(&pts, box_face).ok_or_else(|| {
        "the nodes on this face do not form a grid of at least 2 x 2 (a structured mesh face)"
            .to_string()
    })?;
    let settings = ContourSettings::default();
    let q: Vec<Vector3<f64>> = grid.iter().map(|&n| pts[n]).collect();
    let nurbs = |e: flexmbs_nurbs::NurbsError| format!("the face's surface: {e}");
    let ip = SurfaceInterpolator::from_grid(
        &q,
        ne,
        nx,
        settings.params,
        [settings.degree; 2],
        settings.closed,
    )
    .map_err(nurbs)?;
    let surface = ip.interpolate(&q).map_err(nurbs)?;
    let grids = [
        SearchGrid::Nodes(ip.eta().params().to_vec()),
        SearchGrid::Nodes(ip.xi().params().to_vec()),
    ];
    let mut search =
        SurfaceSearch::new(&surface, grids, SearchSettings::default()).map_err(nurbs)?;
    let x = Vector3::from(point);
    let p = search
        .full_search(&surface, &mut surface.scratch(), &x)
        .ok_or_else(|| format!("{point:?} has no normal projection onto the face `{face}`"))?;
    if p.distance > MAX_DISTANCE * diag {
        return Err(format!(
            "{point:?} lies {:.3e} from the face `{face}` (at most {:.1e} of the mesh's size)",
            p.distance, MAX_DISTANCE
        ));
    }
    let w = ip.data_weights(p.eta, p.xi).map_err(nurbs)?;
    Ok(grid
        .iter()
        .zip(w)
        .filter(|(_, w)| w.abs() > 1e-14)
        .map(|(&n, w)| (n, w))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbs_fe::mesh::generate::box_mesh;
    use flexmbs_fe::{ElementKind, Material, UnitSystem};

    fn block() -> Mesh {
        let mat = Material {
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        };
        box_mesh(
            [0.5, 0.1, 0.1],
            [10, 2, 2],
            ElementKind::Hex20,
            mat,
            UnitSystem::Si,
        )
        .unwrap()
    }

    /// The weights sum to 1 and their centroid is the point (a flat face: the surface is the
    /// plane, which the interpolation reproduces); a point at a grid node loads that node alone.
    #[test]
    fn weights_reproduce_the_point_on_a_flat_face() {
        let mesh = block();
        let p = [0.2345, 0.1, 0.0321];
        let w = face_point_weights(&mesh, "ymax", p).unwrap();
        let sum: f64 = w.iter().map(|(_, w)| w).sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
        let c = w.iter().fold(Vector3::zeros(), |c, (n, w)| {
            c + *w * Vector3::from(mesh.nodes[*n])
        });
        assert!((c - Vector3::from(p)).norm() < 1e-12, "{c:?}");
        let w = face_point_weights(&mesh, "ymax", [0.25, 0.1, 0.05]).unwrap();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!((w[0].1 - 1.0).abs() < 1e-12);
        assert_eq!(mesh.nodes[w[0].0], [0.25, 0.1, 0.05]);
    }

    #[test]
    fn refuses_points_off_the_face_and_unknown_faces() {
        let mesh = block();
        let e = face_point_weights(&mesh, "ymax", [0.2, 0.05, 0.05]).unwrap_err();
        assert!(e.contains("lies"), "{e}");
        let e = face_point_weights(&mesh, "top", [0.2, 0.1, 0.05]).unwrap_err();
        assert!(e.contains("unknown face"), "{e}");
    }
}
