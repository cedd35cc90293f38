//! Contours sampled for drawing (the ParaView output of a run): a neutral NURBS surface as a
//! grid of quads, a neutral curve as a polyline, a flexible band as a strip of quads, all at the
//! deformed state (elastic part scaled like the drawn bodies); spheres and circles as circles
//! of line segments; a point as a vertex; a plane (infinite) as a square patch in its frame's
//! x-y plane centred under its partner contour ([`draw_contact_pair`]). Closed (periodic)
//! curves and surfaces are drawn closed: the last sample joined to the first. Allocates: for
//! output, not for a time step.

use super::contour::{CircleContour, Contour, ContourKind, SphereContour};
use super::flexible::{FlexibleBand, NeutralCurve, NeutralSurface};
use super::unit_or_zero;
use super::Contact;
use crate::contour_source::{NeutralContourSource, ScaledSource};
use crate::element::{ElementScratch, FrameKinematics};
use crate::model::{FrameOwner, Model};
use nalgebra::Vector3;

/// A sampled contour: points (global) and the cells between them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContourDrawing {
    /// Sample points.
    pub points: Vec<Vector3<f64>>,
    /// Line segments (indices into `points`).
    pub lines: Vec<[usize; 2]>,
    /// Quadrilaterals (indices into `points`, counter-clockwise in the parameters).
    pub quads: Vec<[usize; 4]>,
    /// Vertices (indices into `points`): point contours.
    pub vertices: Vec<usize>,
}

/// Half-width (m) of the patch drawn for a plane whose partner has no radius (a point).
pub const PLANE_PATCH_HALF_WIDTH: f64 = 0.1;

/// Half-width of a plane's patch, in radii of a sphere or circle partner.
pub const PLANE_PATCH_RADII: f64 = 4.0;

/// The parameters `params` (increasing) with `subdivisions - 1` equally spaced values inserted
/// in every interval (`subdivisions >= 1`): the contour's node parameters come out at every
/// `subdivisions`-th sample.
pub fn refined_parameters(params: &[f64], subdivisions: usize) -> Vec<f64> {
    let k = subdivisions.max(1);
    let mut out = Vec::with_capacity(params.len() * k);
    for w in params.windows(2) {
        for i in 0..k {
            out.push(w[0] + (w[1] - w[0]) * i as f64 / k as f64);
        }
    }
    out.extend(params.last());
    out
}

/// The contour source of the body owning `contour`'s frame, its field coordinates scaled by
/// `scale` (`None`: not on a body that supplies neutral contours).
fn scaled_owner_state<'a>(
    model: &Model,
    contour: &dyn Contour,
    eval: &'a [ElementScratch],
    scale: f64,
) -> Option<ScaledSource<'a>> {
    let FrameOwner::Body(b) = model.frames[contour.frame().0].owner else {
        return None;
    };
    let s = eval.get(b.0)?.contour_source()?;
    Some(ScaledSource::new(s, scale))
}

/// The drawing samples of one parameter direction: [`refined_parameters`] of the node
/// parameters, and for a closed (periodic) direction also the closing interval up to the
/// domain's end, whose end sample (the first point again) is left out: the drawing joins the
/// last sample to the first instead.
fn drawing_samples(params: &[f64], closed: bool, domain_end: f64, subdivisions: usize) -> Vec<f64> {
    if !closed || params.last().is_none_or(|&u| u >= domain_end) {
        return refined_parameters(params, subdivisions);
    }
    let mut with_end = params.to_vec();
    with_end.push(domain_end);
    let mut s = refined_parameters(&with_end, subdivisions);
    s.pop();
    s
}

/// Adds the quads of an `n_a x n_b` grid of points (row-major from `base`) to `out`; a closed
/// direction (`wrap`) also gets the quads joining its last row to its first.
fn grid_quads(base: usize, n_a: usize, n_b: usize, wrap: [bool; 2], out: &mut ContourDrawing) {
    let cells = |n: usize, w: bool| if w && n > 2 { n } else { n.saturating_sub(1) };
    let p = |i: usize, j: usize| base + (i % n_a) * n_b + j % n_b;
    for i in 0..cells(n_a, wrap[0]) {
        for j in 0..cells(n_b, wrap[1]) {
            out.quads
                .push([p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
}

/// Adds a square patch of half-width `half_width` of the plane through `frame` (its x-y plane)
/// to `out`, centred at the projection of `around` onto the plane.
pub fn draw_plane_patch(
    frame: &FrameKinematics,
    around: &Vector3<f64>,
    half_width: f64,
    out: &mut ContourDrawing,
) {
    let a = frame.rotation;
    let (ex, ey, ez) = (
        a.column(0).into_owned(),
        a.column(1).into_owned(),
        a.column(2).into_owned(),
    );
    let c = around - (around - frame.position).dot(&ez) * ez;
    let base = out.points.len();
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        out.points.push(c + half_width * (sx * ex + sy * ey));
    }
    out.quads.push([base, base + 1, base + 2, base + 3]);
}

/// The half-width of the patch drawn for a plane touched by `partner`:
/// [`PLANE_PATCH_RADII`] radii of a sphere or circle, else [`PLANE_PATCH_HALF_WIDTH`].
fn plane_patch_half_width(partner: &dyn Contour) -> f64 {
    let any = partner.as_any();
    let radius = match partner.kind() {
        ContourKind::Sphere => any.downcast_ref::<SphereContour>().map(|s| s.radius),
        ContourKind::Circle => any.downcast_ref::<CircleContour>().map(|c| c.radius),
        _ => None,
    };
    radius.map_or(PLANE_PATCH_HALF_WIDTH, |r| PLANE_PATCH_RADII * r)
}

/// Samples both contours of `contact` into `out` ([`draw_contour`]); a plane is drawn as a
/// patch centred under its partner's frame origin ([`draw_plane_patch`], half-width from
/// the partner: [`PLANE_PATCH_RADII`] radii of a sphere or circle, else
/// [`PLANE_PATCH_HALF_WIDTH`]).
pub fn draw_contact_pair(
    model: &Model,
    contact: &Contact,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    deformation_scale: f64,
    subdivisions: usize,
    out: &mut ContourDrawing,
) {
    let (a, b) = (contact.contour_a.as_ref(), contact.contour_b.as_ref());
    for (c, partner) in [(a, b), (b, a)] {
        if c.kind() == ContourKind::Plane {
            let around = frames[partner.frame().0].position;
            let half = plane_patch_half_width(partner);
            draw_plane_patch(&frames[c.frame().0], &around, half, out);
        } else {
            draw_contour(model, c, frames, eval, deformation_scale, subdivisions, out);
        }
    }
}

/// Adds a circle of `radius` about `centre` in the plane of the unit vectors `e1`, `e2` (`n`
/// segments) to `out`.
fn add_circle(
    centre: Vector3<f64>,
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    radius: f64,
    n: usize,
    out: &mut ContourDrawing,
) {
    let base = out.points.len();
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        out.points
            .push(centre + radius * (a.cos() * e1 + a.sin() * e2));
        out.lines.push([base + k, base + (k + 1) % n]);
    }
}

/// Samples `contour` at the evaluated state (`frames`, `eval`: [`crate::system::evaluate`])
/// into `out` (appended), flexible contours with their elastic deformation scaled by
/// `deformation_scale` and `subdivisions` samples per interval between node parameters
/// (module documentation).
pub fn draw_contour(
    model: &Model,
    contour: &dyn Contour,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    deformation_scale: f64,
    subdivisions: usize,
    out: &mut ContourDrawing,
) {
    let k = &frames[contour.frame().0];
    let (r, r_dot) = (k.position, k.velocity);
    let any = contour.as_any();
    let state = || scaled_owner_state(model, contour, eval, deformation_scale);
    match contour.kind() {
        ContourKind::NeutralSurface => {
            let (Some(c), Some(s)) = (any.downcast_ref::<NeutralSurface>(), state()) else {
                return;
            };
            let c = c.contour();
            let Ok(mut st) = c.state() else { return };
            if c.update(&s, &mut st).is_err() {
                return;
            }
            let (ie, ix) = (c.interpolator().eta(), c.interpolator().xi());
            let closed = [
                ie.knot_vector().is_periodic(),
                ix.knot_vector().is_periodic(),
            ];
            let end = [ie.knot_vector().domain().1, ix.knot_vector().domain().1];
            let eta = drawing_samples(ie.params(), closed[0], end[0], subdivisions);
            let xi = drawing_samples(ix.params(), closed[1], end[1], subdivisions);
            let base = out.points.len();
            for &e in &eta {
                for &x in &xi {
                    let p = c.point(&r, &r_dot, &s, &mut st, e, x);
                    out.points
                        .push(p.map_or(Vector3::repeat(f64::NAN), |p| p.position));
                }
            }
            grid_quads(base, eta.len(), xi.len(), closed, out);
        }
        ContourKind::NeutralCurve | ContourKind::FlexibleBand => {
            let band = any.downcast_ref::<FlexibleBand>();
            let curve = band
                .map(|b| &b.curve)
                .or(any.downcast_ref::<NeutralCurve>());
            let (Some(curve), Some(s)) = (curve, state()) else {
                return;
            };
            let c = curve.contour();
            let Ok(mut st) = c.state() else { return };
            if c.update(&s, &mut st).is_err() {
                return;
            }
            let kv = c.interpolator().knot_vector();
            let closed = kv.is_periodic();
            let eta = drawing_samples(
                c.interpolator().params(),
                closed,
                kv.domain().1,
                subdivisions,
            );
            let base = out.points.len();
            for &e in &eta {
                let Ok(p) = c.point(&r, &r_dot, &s, &mut st, e) else {
                    out.points.push(Vector3::repeat(f64::NAN));
                    continue;
                };
                match band {
                    // the band's two edges: centre line + offset n -/+ width/2 b
                    Some(b) => {
                        let t = p.tangents[0];
                        let nb = s.frame_rotation() * b.normal;
                        let n = unit_or_zero(nb - nb.dot(&t) * t);
                        let bi = t.cross(&n);
                        let mid = p.position + b.offset * n;
                        out.points.push(mid - 0.5 * b.width * bi);
                        out.points.push(mid + 0.5 * b.width * bi);
                    }
                    None => out.points.push(p.position),
                }
            }
            let n = eta.len();
            if band.is_some() {
                grid_quads(base, n, 2, [closed, false], out);
            } else {
                for i in 1..n {
                    out.lines.push([base + i - 1, base + i]);
                }
                if closed && n > 2 {
                    out.lines.push([base + n - 1, base]);
                }
            }
        }
        ContourKind::Sphere => {
            let Some(sp) = any.downcast_ref::<SphereContour>() else {
                return;
            };
            let a = k.rotation;
            let (ex, ey, ez) = (
                a.column(0).into_owned(),
                a.column(1).into_owned(),
                a.column(2).into_owned(),
            );
            let n = 8 * subdivisions.max(1);
            add_circle(r, ex, ey, sp.radius, n, out);
            add_circle(r, ey, ez, sp.radius, n, out);
            add_circle(r, ez, ex, sp.radius, n, out);
        }
        ContourKind::Circle => {
            let Some(ci) = any.downcast_ref::<CircleContour>() else {
                return;
            };
            let a = k.rotation;
            let (ex, ey) = (a.column(0).into_owned(), a.column(1).into_owned());
            add_circle(r, ex, ey, ci.radius, 16 * subdivisions.max(1), out);
        }
        ContourKind::Point => {
            out.vertices.push(out.points.len());
            out.points.push(r);
        }
        ContourKind::Plane => {
            draw_plane_patch(k, &r, PLANE_PATCH_HALF_WIDTH, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn open_and_closed_directions_are_sampled_and_joined() {
        // open: nodes at 0, 0.5, 1 refined twice: 5 samples, 4 segments of quads' rows
        let open = drawing_samples(&[0.0, 0.5, 1.0], false, 1.0, 2);
        assert_eq!(open, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        // closed: the interval from the last node to the domain end is sampled too, its end
        // (= the first point) left out
        let closed = drawing_samples(&[0.0, 0.4, 0.7], true, 1.0, 2);
        assert_eq!(closed, vec![0.0, 0.2, 0.4, 0.55, 0.7, 0.85]);
        // an open 3 x 2 grid has 2 quads; closing the 3-direction adds the seam quad, which
        // joins the last row to the first
        let mut d = ContourDrawing::default();
        grid_quads(10, 3, 2, [false, false], &mut d);
        assert_eq!(d.quads, vec![[10, 12, 13, 11], [12, 14, 15, 13]]);
        let mut d = ContourDrawing::default();
        grid_quads(0, 3, 4, [true, true], &mut d);
        assert_eq!(d.quads.len(), 12, "a closed 3 x 4 torus grid has 12 cells");
        assert!(d.quads.contains(&[11, 3, 0, 8]), "{:?}", d.quads);
        // every edge of the torus grid is shared by exactly two quads
        let mut edges = std::collections::HashMap::new();
        for q in &d.quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 2), "{edges:?}");
    }

    #[test]
    fn plane_patch_lies_in_the_plane_under_the_partner() {
        let mut f = FrameKinematics::new(0);
        f.position = Vector3::new(1.0, 2.0, 3.0);
        f.rotation = *Rotation3::from_euler_angles(0.3, -0.2, 0.7).matrix();
        let ez = f.rotation.column(2).into_owned();
        let around = Vector3::new(0.5, -1.0, 4.0);
        let mut d = ContourDrawing::default();
        draw_plane_patch(&f, &around, 0.25, &mut d);
        assert_eq!(d.quads, vec![[0, 1, 2, 3]]);
        let centre = d.points.iter().sum::<Vector3<f64>>() / 4.0;
        for p in &d.points {
            assert!((p - f.position).dot(&ez).abs() < 1e-14, "in the plane");
            assert!(((p - centre).norm() - 0.25 * 2f64.sqrt()).abs() < 1e-14);
        }
        // the centre is the partner's foot point: around - centre along the normal
        let off = around - centre;
        assert!((off - off.dot(&ez) * ez).norm() < 1e-14, "{off:?}");
        // counter-clockwise about the outward normal z
        let n = (d.points[1] - d.points[0]).cross(&(d.points[2] - d.points[1]));
        assert!(n.dot(&ez) > 0.0);
    }
}
