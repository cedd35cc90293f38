//! Frames on FE nodes of ffr bodies: which node a frame names (`node`, `nearest`, `interface`),
//! and the refusal of joints that lock rotations at a node whose rotation the body's modes do not
//! describe (a solid-mesh node: only a rigid interface node turns with the deformation there).

use crate::bodies::BodyGeometry;
use crate::compile::Ctx;
use crate::error::SimError;
use crate::schema::FrameSpec;
use crate::units::Dimension;
use flexmbs_fe::reduction::ReducedBody;
use nalgebra::Vector3;

/// Largest distance of a `nearest` point from its node, as a fraction of the body's
/// bounding-box diagonal.
pub const NEAREST_TOL: f64 = 0.05;

/// A named rigid (RBE2-like) interface of an FE model file (`[[body.boundary.rigid]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct FeInterface {
    /// Name in the FE model file.
    pub name: String,
    /// Index of its 6-DOF interface node in the body's node list.
    pub node: usize,
    /// Indices of the mesh nodes it ties rigidly.
    pub slaves: Vec<usize>,
}

/// Per node of a reduced body: true if the node moves in some mode but its rotation is in none
/// (a node with translational DOFs only, such as a solid-mesh node, or a mesh node tied to a
/// rigid interface). A frame on such a node keeps the axes of the floating frame. Fixed nodes
/// (zero rows) are material points of the floating frame, so `false`.
pub fn translation_only_nodes(body: &ReducedBody) -> Vec<bool> {
    let rotating = rotating_nodes(body);
    (0..body.num_nodes())
        .map(|n| nonzero_rows(&body.modes_t, n) && !rotating[n])
        .collect()
}

/// True if node `n`'s three rows of the nodal mode field `m` are not all zero.
fn nonzero_rows(m: &faer::Mat<f64>, n: usize) -> bool {
    (3 * n..3 * n + 3).any(|r| (0..m.ncols()).any(|c| m[(r, c)] != 0.0))
}

/// The node index a frame with `node`, `nearest` or `interface` names on the ffr body `body`
/// with geometry `g` (`p` is the frame's key path).
pub fn frame_node(ctx: &Ctx, p: &str, f: &FrameSpec, g: &BodyGeometry) -> Result<usize, SimError> {
    let body = &f.body;
    let given = [
        ("node", f.node.is_some()),
        ("nearest", f.nearest.is_some()),
        ("interface", f.interface.is_some()),
    ];
    let which: Vec<&str> = given.iter().filter(|(_, s)| *s).map(|(k, _)| *k).collect();
    if which.len() != 1 {
        return Err(ctx.err(p, "give one of `node`, `nearest` and `interface`"));
    }
    let key = format!("{p}.{}", which[0]);
    if !g.fe_nodes {
        return Err(ctx.err(
            &key,
            format!("body `{body}` is rigid: `node`, `nearest` and `interface` need an ffr body"),
        ));
    }
    if f.position.is_some() {
        return Err(ctx.err(&key, "a node frame takes its position from the node: drop `position` (`orientation` may rotate its axes)"));
    }
    if let Some(id) = f.node {
        return g.node_ids.iter().position(|&x| x == id).ok_or_else(|| {
            ctx.err(
                &key,
                format!("body `{body}` has no FE node {id} ({})", node_inventory(g)),
            )
        });
    }
    if let Some(name) = &f.interface {
        return g
            .interfaces
            .iter()
            .find(|i| &i.name == name)
            .map(|i| i.node)
            .ok_or_else(|| ctx.err(&key, unknown_interface_message(body, name, g)));
    }
    let Some(x) = &f.nearest else {
        return Err(ctx.err(p, "give one of `node`, `nearest` and `interface`"));
    };
    let x = ctx.vec3(x, Dimension::Length, &key)?;
    let n = nearest_node(g, &x);
    // a point far off the body is a mistake (unit, axis), not a choice
    let (dist, size) = (
        (Vector3::from(g.points[n]) - x).norm(),
        bounding_box_diagonal(&g.points),
    );
    if dist > NEAREST_TOL * size {
        return Err(ctx.err(
            &key,
            format!(
                "the nearest FE node of body `{body}` (node {}, at {:?} m) is {dist:.4e} m from this point, more than {} of the body size ({size:.4e} m): check the coordinates (body axes, m unless a unit is given)",
                g.node_ids[n], g.points[n], NEAREST_TOL
            ),
        ));
    }
    Ok(n)
}

/// The node nearest to `x`; among nodes at the same distance (to 1e-9 of the body size) one
/// whose rotation the modes describe (a rigid interface node) before a translation-only one.
fn nearest_node(g: &BodyGeometry, x: &Vector3<f64>) -> usize {
    let d = |n: usize| (Vector3::from(g.points[n]) - x).norm();
    let n_min = (0..g.points.len())
        .min_by(|&a, &b| d(a).total_cmp(&d(b)))
        .unwrap_or(0);
    if !g.translation_only.get(n_min).copied().unwrap_or(false) {
        return n_min;
    }
    let tie = d(n_min) + 1e-9 * bounding_box_diagonal(&g.points);
    (0..g.points.len())
        .find(|&n| d(n) <= tie && !g.translation_only[n])
        .unwrap_or(n_min)
}

/// Diagonal of the bounding box of `points`.
pub fn bounding_box_diagonal(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// The body's node ids (range) and rigid interfaces, for messages.
fn node_inventory(g: &BodyGeometry) -> String {
    let (lo, hi) = (
        g.node_ids.iter().min().copied().unwrap_or(0),
        g.node_ids.iter().max().copied().unwrap_or(0),
    );
    let mut s = format!("{} nodes, ids {lo} to {hi}", g.node_ids.len());
    if !g.interfaces.is_empty() {
        let list: Vec<String> = g
            .interfaces
            .iter()
            .map(|i| format!("`{}` (node {})", i.name, g.node_ids[i.node]))
            .collect();
        s.push_str(&format!("; rigid interfaces {}", list.join(", ")));
    }
    s
}

fn unknown_interface_message(body: &str, name: &str, g: &BodyGeometry) -> String {
    if g.interfaces.is_empty() {
        format!(
            "body `{body}` has no rigid interface `{name}`: its source names none ({}). {}",
            node_inventory(g),
            DEFINE_INTERFACE
        )
    } else {
        let names: Vec<&str> = g.interfaces.iter().map(|i| i.name.as_str()).collect();
        format!(
            "body `{body}` has no rigid interface `{name}` (interfaces: {})",
            names.join(", ")
        )
    }
}

/// How to define a rigid interface, for messages.
const DEFINE_INTERFACE: &str = "Define one in the body's FE model file: a \
     `[[body.boundary.rigid]]` table with a `name` and the `nodes` the joint grips (e.g. \
     `nodes = \"xmax\"`, a node set or a node selection), also listed in `[body.reduction] \
     interface` for craig-bampton reduction; then name it on the frame with \
     `interface = \"<name>\"` (a reduced-body file keeps the interface node, without its name: \
     use `node = <id>` there)";

/// What needs the rotation of a frame's node.
#[derive(Debug, Clone, Copy)]
pub enum RotationUse<'a> {
    /// A joint (named) that locks a rotation, directly or through an angle drive.
    Joint(&'a str),
    /// A torque load.
    Torque,
}

/// Refuses a joint that locks a rotation, or a torque, at a frame on a translation-only node of
/// an ffr body (see [`translation_only_nodes`]): the frame's axes would not turn with the body's
/// deformation, so the joint would transmit no slope (the torque would not bend the body). `path`
/// is the key path of the joint side or the load's frame.
pub fn check_rotation_lock_at_node(
    ctx: &Ctx,
    path: &str,
    user: RotationUse,
    frame: &str,
    body: &str,
    g: &BodyGeometry,
    node: usize,
) -> Result<(), SimError> {
    if !g.translation_only.get(node).copied().unwrap_or(false) {
        return Ok(());
    }
    let id = g.node_ids[node];
    let (lead, effect) = match user {
        RotationUse::Joint(joint) => (
            format!("joint `{joint}` locks rotations"),
            "the joint would not transmit the body's slope there",
        ),
        RotationUse::Torque => (
            "a torque acts".to_string(),
            "the torque would turn the body as a whole instead of bending it there",
        ),
    };
    let mut msg = format!(
        "{lead} at frame `{frame}`, which sits on FE node {id} of body `{body}`: a node without \
         rotational degrees of freedom (a solid-mesh node), whose axes do not turn with the \
         body's deformation, so {effect} and the model would be wrong without any error."
    );
    if let Some(i) = g.interfaces.iter().find(|i| i.slaves.contains(&node)) {
        msg.push_str(&format!(
            " Node {id} is tied to the rigid interface `{}`.",
            i.name
        ));
    }
    let here = Vector3::from(g.points[node]);
    let dist = |n: usize| (Vector3::from(g.points[n]) - here).norm();
    let mut named: Vec<&FeInterface> = g.interfaces.iter().collect();
    named.sort_by(|a, b| dist(a.node).total_cmp(&dist(b.node)));
    let describe = |n: usize| format!("at {:?} m, {:.4e} m from node {id}", g.points[n], dist(n));
    if !named.is_empty() {
        let list: Vec<String> = named
            .iter()
            .take(3)
            .map(|i| format!("`interface = \"{}\"` ({})", i.name, describe(i.node)))
            .collect();
        msg.push_str(&format!(
            " Attach the frame to a rigid interface of `{body}` instead (in place of \
             `node`/`nearest`): {}; or use a spherical joint if the rotations are meant to be free",
            list.join(" or ")
        ));
        return Err(ctx.err(path, msg));
    }
    // a reduced-body file keeps the interface nodes (with rotations) but not their names
    let mut rotating: Vec<usize> = (0..g.node_ids.len()).filter(|&n| g.rotating[n]).collect();
    rotating.sort_by(|&a, &b| dist(a).total_cmp(&dist(b)));
    if rotating.is_empty() {
        msg.push_str(&format!(
            " Body `{body}` has no rigid interface. {DEFINE_INTERFACE}; or use a spherical joint \
             if the rotations are meant to be free"
        ));
    } else {
        let list: Vec<String> = rotating
            .iter()
            .take(3)
            .map(|&n| format!("`node = {}` ({})", g.node_ids[n], describe(n)))
            .collect();
        msg.push_str(&format!(
            " Attach the frame to a node with rotations (a rigid interface node) instead: {}; \
             or use a spherical joint if the rotations are meant to be free",
            list.join(" or ")
        ));
    }
    Err(ctx.err(path, msg))
}

/// Per node of a reduced body: true if its rotation appears in some mode.
pub fn rotating_nodes(body: &ReducedBody) -> Vec<bool> {
    (0..body.num_nodes())
        .map(|n| body.modes_r.as_ref().is_some_and(|r| nonzero_rows(r, n)))
        .collect()
}
