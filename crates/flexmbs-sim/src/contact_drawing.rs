//! Contacts in the ParaView animation: two extra parts of every frame of a model with contacts,
//! `contact_points` (both contact points of every contact that has one, as vertices, with the
//! point fields `gap`, `normal_force` (the last step's normal impulse over its step; 0 in the
//! first frame), `normal` and `contact` (its index)) and `contours` (the contours sampled at the
//! state, deformed like the drawn bodies: quads of surfaces and bands, lines of curves, circles,
//! planes as a square patch under their partner, points as vertices, with the cell field
//! `contact`).

use crate::compile::CompiledModel;
use flexmbs_core::contact::drawing::{draw_contact_pair, ContourDrawing};
use flexmbs_core::contact::ContactWork;
use flexmbs_core::{ElementScratch, FrameKinematics, State};
use flexmbs_io::results::{AnimationPart, VTK_LINE, VTK_QUAD, VTK_VERTEX};

/// Samples per interval between a contour's node parameters.
pub(crate) const CONTOUR_SUBDIVISIONS: usize = 4;

/// The parts `contact_points` and `contours` of the frame at `s` (elements in `eval` and
/// `frames` evaluated there; `h` the last step, 0 for none).
pub(crate) fn contact_parts(
    cm: &CompiledModel,
    s: &State,
    h: f64,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    work: &mut ContactWork,
) -> Vec<AnimationPart> {
    let m = &cm.model;
    let mut points = AnimationPart {
        name: "contact_points".into(),
        ..Default::default()
    };
    let (mut gap, mut force, mut normal, mut index) = (vec![], vec![], vec![], vec![]);
    let mut contours = AnimationPart {
        name: "contours".into(),
        ..Default::default()
    };
    let mut contour_index = Vec::new();
    for (i, (c, w)) in m.contacts.iter().zip(&mut work.sides).enumerate() {
        let geo = c.geometry(m, frames, eval, w);
        if geo.has_contact_point() {
            let f = match (s.contacts.get(i), h > 0.0) {
                (Some(st), true) => st.impulse[0] / h,
                _ => 0.0,
            };
            for p in [geo.point_a, geo.point_b] {
                points.cells.push((VTK_VERTEX, vec![points.points.len()]));
                points.points.push([p.x, p.y, p.z]);
                gap.push(geo.gap);
                force.push(f);
                normal.extend(geo.normal.iter());
                index.push(i as f64);
            }
        }
        let mut d = ContourDrawing::default();
        let scale = cm.output.deformation_scale;
        draw_contact_pair(m, c, frames, eval, scale, CONTOUR_SUBDIVISIONS, &mut d);
        let base = contours.points.len();
        contours
            .points
            .extend(d.points.iter().map(|p| [p.x, p.y, p.z]));
        let lines = d
            .lines
            .iter()
            .map(|l| (VTK_LINE, l.iter().map(|k| base + k).collect()));
        let quads = d
            .quads
            .iter()
            .map(|q| (VTK_QUAD, q.iter().map(|k| base + k).collect()));
        let vertices = d.vertices.iter().map(|&k| (VTK_VERTEX, vec![base + k]));
        for cell in lines.chain(quads).chain(vertices) {
            contours.cells.push(cell);
            contour_index.push(i as f64);
        }
    }
    points.point_fields = vec![
        ("gap".into(), 1, gap),
        ("normal_force".into(), 1, force),
        ("normal".into(), 3, normal),
        ("contact".into(), 1, index.clone()),
    ];
    points.cell_fields = vec![("contact".into(), 1, index)];
    contours.cell_fields = vec![("contact".into(), 1, contour_index)];
    vec![points, contours]
}
