//! The points of the ParaView animation: every body's drawn points in the current state, with the
//! elastic deformation separated from the rigid motion (`output.deformation_scale`).

use crate::compile::CompiledModel;
use flexmbs_core::{ElementScratch, FrameKinematics, LocalFrame, Model, State};
use nalgebra::Vector3;

/// Global positions of every body's animation points and their elastic displacements: a point
/// at `p` (body axes) on an FE node moves to `r`, the rigidly moved body would put it at `R + A p`
/// (the same point fixed in the floating frame); the elastic part is the difference (zero for
/// rigid bodies, and for an undeformed body in any rigid motion). Written: `R + A p + k (r - R - A
/// p)` with the deformation scale `k` (`output.deformation_scale`).
pub(crate) fn body_points(
    m: &Model,
    cm: &CompiledModel,
    s: &State,
    eval: &mut [ElementScratch],
    fk: &mut [FrameKinematics],
    out: &mut [Vec<[f64; 3]>],
    elastic: &mut [Vec<[f64; 3]>],
) {
    let k = cm.output.deformation_scale;
    let bodies = cm.bodies.iter().zip(fk.iter_mut());
    for ((info, kin), (pts, el)) in bodies.zip(out.iter_mut().zip(elastic.iter_mut())) {
        let b = &m.bodies[info.id.0];
        // gathered copies for a body whose coordinates are scattered (a superelement at a branch)
        let (q, u) = m.body_coordinates(info.id, &s.q, &s.u);
        let (q, u) = (&q[..], &u[..]);
        let e = &mut eval[info.id.0];
        pts.clear();
        el.clear();
        for (n, p) in info.geometry.points.iter().enumerate() {
            let mut lf = LocalFrame::at(Vector3::from(*p));
            b.element.frame_kinematics(q, u, e, &lf, kin);
            let rigid = kin.position;
            // points past the element's mesh nodes (a superelement's floating frame) are fixed
            // in the body frame
            lf.mesh_node = (info.geometry.fe_nodes && n < b.element.num_mesh_nodes()).then_some(n);
            b.element.frame_kinematics(q, u, e, &lf, kin);
            let d = kin.position - rigid;
            let x = rigid + k * d;
            pts.push([x.x, x.y, x.z]);
            el.push([d.x, d.y, d.z]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbs_core::system;
    use std::path::Path;

    const SPINNING: &str = r#"
[model]
name = "spinning_cantilever"

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.01 s"

[[body]]
name = "beam"
type = "ffr"
source = "parts/cantilever_beam.toml"
position = [0.3, -0.2, 0.5]
orientation = { axis = [1, 2, 3], angle = "50 deg" }
velocity = [1, 2, 3]
angular_velocity = [0.5, -1, 2]
"#;

    fn compiled(scale: f64) -> CompiledModel {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/spinning.toml");
        let text = format!("{SPINNING}\n[output]\ndeformation_scale = {scale:?}\n");
        crate::compile_model(&text, &file).unwrap()
    }

    fn points(cm: &CompiledModel, s: &State) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let m = &cm.model;
        let mut eval: Vec<_> = m.bodies.iter().map(|b| b.element.new_scratch()).collect();
        system::evaluate_elements(m, &s.q, &s.u, &mut eval).unwrap();
        let mut fk: Vec<_> = cm
            .bodies
            .iter()
            .map(|b| FrameKinematics::for_body(m, b.id))
            .collect();
        let (mut pts, mut el) = (vec![Vec::new()], vec![Vec::new()]);
        body_points(m, cm, s, &mut eval, &mut fk, &mut pts, &mut el);
        (pts.remove(0), el.remove(0))
    }

    /// An undeformed FFR body in a general rigid motion (moved, turned, spinning): the elastic
    /// displacement of every point is zero to round-off while the points moved by about 1 m; a
    /// deformed one has a non-zero elastic field, and scale 0 draws the rigidly moved body.
    #[test]
    fn elastic_field_of_a_rigid_motion_is_zero() {
        let cm = compiled(1.0);
        let s = cm.initial.clone();
        let (pts, el) = points(&cm, &s);
        let geometry = &cm.bodies[0].geometry.points;
        let moved = pts
            .iter()
            .zip(geometry)
            .map(|(p, g)| (Vector3::from(*p) - Vector3::from(*g)).norm());
        assert!(moved.fold(0.0, f64::max) > 0.5);
        let largest = el
            .iter()
            .map(|d| Vector3::from(*d).norm())
            .fold(0.0, f64::max);
        assert!(
            largest < 1e-15,
            "elastic displacement {largest:e} of a rigid motion"
        );
        // deform: the first two modal coordinates
        let mut s2 = s.clone();
        let q = cm.model.body_q_mut(cm.bodies[0].id, &mut s2.q);
        let n = q.len();
        q[n - 8] = 1e-3;
        q[n - 7] = -2e-3;
        let (pts1, el1) = points(&cm, &s2);
        let (pts0, _) = points(&compiled(0.0), &s2);
        let (pts3, _) = points(&compiled(3.0), &s2);
        let largest = el1
            .iter()
            .map(|d| Vector3::from(*d).norm())
            .fold(0.0, f64::max);
        assert!(largest > 1e-5, "deformed: {largest:e}");
        for i in 0..pts.len() {
            let (p0, p1, p3) = (
                Vector3::from(pts0[i]),
                Vector3::from(pts1[i]),
                Vector3::from(pts3[i]),
            );
            assert!(
                (p0 - Vector3::from(pts[i])).norm() < 1e-14,
                "scale 0 = rigid body"
            );
            assert!((p1 - p0 - Vector3::from(el1[i])).norm() < 1e-14);
            assert!((p3 - p0 - 3.0 * Vector3::from(el1[i])).norm() < 1e-14);
        }
    }
}
