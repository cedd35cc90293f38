//! Flexible contours of `[[contact]]` tables: neutral NURBS contours of ffr bodies and
//! superelements (`type = "surface"`, `"curve"`, `"band"`; `docs/model-file.md`), built from the
//! body's FE nodes (a bounding-box face or FE node ids) with located errors.

use crate::compile::Ctx;
use crate::contacts::{ContourName, ContourSpec, NodesSpec, OwnerFn};
use crate::error::SimError;
use crate::units::Dimension;
use flexmbs_core::contact::{Contour, FlexibleBand, NeutralCurve, NeutralSurface};
use flexmbs_core::ffr::contour::{
    box_face_grid, ContourSettings, FfrCurveContour, FfrSurfaceContour,
};
use flexmbs_fe::BoxFace;
use nalgebra::Vector3;
use std::collections::HashMap;

/// The flexible contour `c` at key path `p` (module documentation).
pub(crate) fn flexible_contour(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    owner: &OwnerFn<'_>,
) -> Result<Box<dyn Contour>, SimError> {
    let kind = format!("{:?}", c.kind).to_lowercase();
    if c.frame.is_some() {
        return Err(ctx.err(
            &format!("{p}.frame"),
            format!("a {kind} contour belongs to a flexible body: give `body`, not `frame`"),
        ));
    }
    let present = [
        ("radius", c.radius.is_some()),
        ("face", c.face.is_some()),
        ("nodes", c.nodes.is_some()),
        ("through", c.through.is_some()),
        ("width", c.width.is_some()),
        ("offset", c.offset.is_some()),
        ("normal", c.normal.is_some()),
        ("flip_normal", c.flip_normal.is_some()),
    ];
    let allowed: &[&str] = match c.kind {
        ContourName::Surface => &["face", "nodes", "flip_normal"],
        ContourName::Curve => &["nodes", "through", "radius"],
        _ => &["nodes", "through", "width", "offset", "normal"],
    };
    ctx.only(p, &format!("a {kind} contour"), &present, allowed)?;
    let name = c.body.as_ref().ok_or_else(|| {
        ctx.err(
            p,
            format!("a {kind} contour needs `body` (an ffr body or a superelement)"),
        )
    })?;
    let o = owner(name, format!("{p}.body"))?;
    let nodes = NodeIndex::new(o.node_ids);
    let u0: Vec<Vector3<f64>> = (0..o.body.num_nodes())
        .map(|i| o.body.node_position(i))
        .collect();
    let located =
        |key: &str, e: &dyn std::fmt::Display| ctx.err(&format!("{p}.{key}"), e.to_string());
    match c.kind {
        ContourName::Surface => {
            let (grid, ne, nx, key) = surface_grid(ctx, c, p, &u0, &nodes)?;
            let settings = ContourSettings {
                flip_normal: inward(&u0, &grid, nx) != c.flip_normal.unwrap_or(false),
                ..ContourSettings::default()
            };
            let contour = FfrSurfaceContour::new(o.body, &grid, ne, nx, settings)
                .map_err(|e| located(key, &e))?;
            Ok(Box::new(
                NeutralSurface::new(o.frame, contour).map_err(|e| located(key, &e))?,
            ))
        }
        ContourName::Curve | ContourName::Band => {
            let line = match c.through {
                Some(ends) => segment_nodes(ctx, c, p, o.points, ends)?,
                None => line_nodes(ctx, c, p, &nodes)?,
            };
            let curve = FfrCurveContour::new(o.body, &line, ContourSettings::default())
                .map_err(|e| located("nodes", &e))?;
            let radius = match &c.radius {
                Some(q) => ctx.q(q, Dimension::Length, &format!("{p}.radius"))?,
                None => 0.0,
            };
            let curve =
                NeutralCurve::new(o.frame, curve, radius).map_err(|e| located("nodes", &e))?;
            if c.kind == ContourName::Curve {
                return Ok(Box::new(curve));
            }
            band(ctx, c, p, curve)
        }
        _ => unreachable!("rigid contours are built by the contacts module"),
    }
}

/// External FE node id -> node index.
struct NodeIndex(HashMap<u64, usize>, u64, u64);

impl NodeIndex {
    fn new(ids: &[u64]) -> Self {
        let (lo, hi) = (
            ids.iter().copied().min().unwrap_or(0),
            ids.iter().copied().max().unwrap_or(0),
        );
        Self(
            ids.iter().enumerate().map(|(i, &id)| (id, i)).collect(),
            lo,
            hi,
        )
    }

    fn get(&self, ctx: &Ctx, path: &str, id: u64) -> Result<usize, SimError> {
        self.0.get(&id).copied().ok_or_else(|| {
            let msg = format!(
                "node {id} is not a node of the body (ids {} ... {})",
                self.1, self.2
            );
            ctx.err(path, msg)
        })
    }
}

/// The node index matrix of a surface from `face` or `nodes` (exactly one), with the key it came
/// from.
fn surface_grid(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    u0: &[Vector3<f64>],
    nodes: &NodeIndex,
) -> Result<(Vec<usize>, usize, usize, &'static str), SimError> {
    match (&c.face, &c.nodes) {
        (Some(face), None) => {
            let box_face = BoxFace::from_name(face).ok_or_else(|| {
                let msg = format!("unknown face `{face}` ({})", BoxFace::NAMES);
                ctx.err(&format!("{p}.face"), msg)
            })?;
            let (grid, ne, nx) = box_face_grid(u0, box_face).ok_or_else(|| {
                ctx.err(
                    &format!("{p}.face"),
                    "the nodes on this face do not form a grid of at least 2 x 2 (a structured \
                     mesh face is needed; give the node index matrix as `nodes`)",
                )
            })?;
            Ok((grid, ne, nx, "face"))
        }
        (None, Some(NodesSpec::Grid(rows))) => {
            let path = format!("{p}.nodes");
            let nx = rows.first().map_or(0, Vec::len);
            if let Some(i) = rows.iter().position(|r| r.len() != nx) {
                let msg = format!("row {i} has {} nodes, row 0 has {nx}", rows[i].len());
                return Err(ctx.err(&path, msg));
            }
            let grid = rows
                .iter()
                .flatten()
                .map(|&id| nodes.get(ctx, &path, id))
                .collect::<Result<Vec<_>, _>>()?;
            Ok((grid, rows.len(), nx, "nodes"))
        }
        (None, Some(NodesSpec::Line(_))) => Err(ctx.err(
            &format!("{p}.nodes"),
            "a surface needs the node index matrix: rows of node ids, [[1, 2, 3], [4, 5, 6], ...]",
        )),
        (Some(_), Some(_)) => Err(ctx.err(p, "give either `face` or `nodes`, not both")),
        (None, None) => Err(ctx.err(p, "a surface contour needs `face` or `nodes`")),
    }
}

fn bounding_box(points: &[Vector3<f64>]) -> (Vector3<f64>, Vector3<f64>) {
    points.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// Whether the grid's parametric normal `t_eta x t_xi` (from its first corner) points into the
/// body (towards the centroid of its nodes): then the contour's normal is flipped.
fn inward(u0: &[Vector3<f64>], grid: &[usize], nx: usize) -> bool {
    let u = |i: usize| u0[grid[i]];
    let n = (u(nx) - u(0)).cross(&(u(1) - u(0)));
    let centre = grid.iter().map(|&g| u0[g]).sum::<Vector3<f64>>() / grid.len() as f64;
    let centroid = u0.iter().sum::<Vector3<f64>>() / u0.len().max(1) as f64;
    n.dot(&(centre - centroid)) < 0.0
}

/// The ordered node indices of a curve or band.
fn line_nodes(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    nodes: &NodeIndex,
) -> Result<Vec<usize>, SimError> {
    let path = format!("{p}.nodes");
    match &c.nodes {
        Some(NodesSpec::Line(ids)) => ids.iter().map(|&id| nodes.get(ctx, &path, id)).collect(),
        Some(NodesSpec::Grid(_)) => {
            Err(ctx.err(&path, "a curve needs one ordered list of node ids"))
        }
        None => Err(ctx.err(p, "needs `nodes` (ordered FE node ids along the curve)")),
    }
}

/// The nodes within a small tolerance (1e-6 of the body's size) of the segment `ends` (body
/// axes), ordered along it; `nodes` and `through` exclude each other.
fn segment_nodes(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    points: &[[f64; 3]],
    ends: [[f64; 3]; 2],
) -> Result<Vec<usize>, SimError> {
    let path = format!("{p}.through");
    if c.nodes.is_some() {
        return Err(ctx.err(&path, "give either `nodes` or `through`, not both"));
    }
    let (a, b) = (Vector3::from(ends[0]), Vector3::from(ends[1]));
    let len = (b - a).norm();
    if !(len > 0.0 && len.is_finite()) {
        return Err(ctx.err(&path, "the two points must differ"));
    }
    let pts: Vec<Vector3<f64>> = points.iter().map(|x| Vector3::from(*x)).collect();
    let (lo, hi) = bounding_box(&pts);
    let tol = 1e-6 * (hi - lo).norm().max(len);
    let dir = (b - a) / len;
    let mut on: Vec<(f64, usize)> = pts
        .iter()
        .enumerate()
        .filter_map(|(i, x)| {
            let s = dir.dot(&(x - a));
            let off = (x - a - s * dir).norm();
            (off <= tol && s >= -tol && s <= len + tol).then_some((s, i))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    if on.len() < 4 {
        return Err(ctx.err(
            &path,
            format!(
                "{} FE nodes lie on this segment: a cubic curve needs at least 4",
                on.len()
            ),
        ));
    }
    Ok(on.into_iter().map(|(_, i)| i).collect())
}

/// A band on `curve` from `width`, `offset` and `normal`.
fn band(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    curve: NeutralCurve,
) -> Result<Box<dyn Contour>, SimError> {
    let width = c
        .width
        .as_ref()
        .ok_or_else(|| ctx.err(p, "a band needs `width`"))?;
    let width = ctx.q(width, Dimension::Length, &format!("{p}.width"))?;
    if width.is_nan() || width <= 0.0 {
        return Err(ctx.err(&format!("{p}.width"), format!("must be > 0, got {width} m")));
    }
    let offset = match &c.offset {
        Some(q) => ctx.q(q, Dimension::Length, &format!("{p}.offset"))?,
        None => 0.0,
    };
    let normal = Vector3::from(c.normal.ok_or_else(|| {
        ctx.err(
            p,
            "a band needs `normal` (its outward direction in body axes)",
        )
    })?);
    if !(normal.norm() > 0.0 && normal.iter().all(|x| x.is_finite())) {
        return Err(ctx.err(&format!("{p}.normal"), "must be a finite non-zero vector"));
    }
    Ok(Box::new(FlexibleBand {
        curve,
        width,
        offset,
        normal,
    }))
}
