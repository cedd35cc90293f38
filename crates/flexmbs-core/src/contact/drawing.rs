//! Contours sampled for drawing (the ParaView output of a run): a neutral NURBS surface as a
//! grid of quads, a neutral curve as a polyline, a flexible band as a strip of quads, all at the
//! deformed state (elastic part scaled like the drawn bodies); spheres and circles as circles
//! of line segments. Points and planes draw nothing (a point is its contact point; a plane has
//! no extent). Allocates: for output, not for a time step.

use super::contour::{CircleContour, Contour, ContourKind, SphereContour};
use super::flexible::{FlexibleBand, NeutralCurve, NeutralSurface};
use super::unit_or_zero;
use crate::element::{ElementScratch, FrameKinematics};
use crate::ffr::{FfrEval, FfrScratch};
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
}

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

/// The FFR state of the body owning `contour`'s frame, its elastic coordinates scaled by
/// `scale` (`None`: not on an FFR body).
fn scaled_owner_state(
    model: &Model,
    contour: &dyn Contour,
    eval: &[ElementScratch],
    scale: f64,
) -> Option<FfrScratch> {
    let FrameOwner::Body(b) = model.frames[contour.frame().0].owner else {
        return None;
    };
    let mut s = eval.get(b.0)?.try_get::<FfrEval>()?.state.clone();
    s.qf.iter_mut().for_each(|x| *x *= scale);
    s.qfd.iter_mut().for_each(|x| *x *= scale);
    Some(s)
}

/// Adds the quads of an `n_a x n_b` grid of points (row-major from `base`) to `out`.
fn grid_quads(base: usize, n_a: usize, n_b: usize, out: &mut ContourDrawing) {
    for i in 0..n_a.saturating_sub(1) {
        for j in 0..n_b.saturating_sub(1) {
            let p = |i: usize, j: usize| base + i * n_b + j;
            out.quads
                .push([p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)]);
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
            let eta = refined_parameters(c.interpolator().eta().params(), subdivisions);
            let xi = refined_parameters(c.interpolator().xi().params(), subdivisions);
            let base = out.points.len();
            for &e in &eta {
                for &x in &xi {
                    let p = c.point(&r, &r_dot, &s, &mut st, e, x);
                    out.points
                        .push(p.map_or(Vector3::repeat(f64::NAN), |p| p.position));
                }
            }
            grid_quads(base, eta.len(), xi.len(), out);
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
            let eta = refined_parameters(c.interpolator().params(), subdivisions);
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
                        let nb = s.a * b.normal;
                        let n = unit_or_zero(nb - nb.dot(&t) * t);
                        let bi = t.cross(&n);
                        let mid = p.position + b.offset * n;
                        out.points.push(mid - 0.5 * b.width * bi);
                        out.points.push(mid + 0.5 * b.width * bi);
                    }
                    None => out.points.push(p.position),
                }
            }
            if band.is_some() {
                grid_quads(base, eta.len(), 2, out);
            } else {
                for i in 1..eta.len() {
                    out.lines.push([base + i - 1, base + i]);
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
        ContourKind::Point | ContourKind::Plane => {}
    }
}
