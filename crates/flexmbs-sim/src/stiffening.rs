//! Centrifugal geometric stiffening of an FFR body from its FE model (`geometric_stiffening =
//! true`): the unit-load method of [`flexmbs_fe::geometric::geometric_stiffness`] on the prepared
//! mesh and system of the body's FE model file, or the same matrices stored in a reduced-body
//! file (`.fmb.h5`, group `geometric`, written by `flexmbs reduce`), restricted to the selected
//! modes and converted to SI like the reduced body ([`flexmbs_core::ffr::reduced_body_to_si`]).
//! Node-load stiffening (`load_stiffening = true`): the unit-load patterns of the nodes the model
//! attaches frames to, solved on the FE model (inertia relief for a free-free body).

use crate::bodies::BodyGeometry;
use crate::compile::Ctx;
use crate::error::SimError;
use crate::fe_frames::frame_node;
use crate::schema::{BodySpec, FrameSpec};
use flexmbs_core::ffr::{FfrBody, LoadStiffening};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
use flexmbs_fe::geometric_loads::{
    load_geometric_stiffness, LoadGeometricStiffness, NodeLoad, UnitLoad,
};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::UnitSystem;
use flexmbs_io::model::{MassName, MeshSpec};
use flexmbs_reduce::pipeline::PreparedBody;

/// The FE model behind a reduced body read from an FE model file: the pipeline's prepared mesh,
/// boundary conditions and constrained system, and the element mass kind the system uses.
#[derive(Debug, Clone)]
pub struct FeModel {
    /// Mesh, boundary conditions and constrained system (body units).
    pub prepared: PreparedBody,
    /// Element mass kind of the system's mass matrix (inertial loads use the same).
    pub mass: MassKind,
}

impl FeModel {
    /// Mass kind of the system `prepare` assembles for `mesh`/`mass` of an FE model file: the
    /// requested kind, except that matrices exported by CalculiX are consistent
    /// ([`flexmbs_reduce::geometric::system_mass_kind`]).
    pub fn mass_kind(mesh: &MeshSpec, mass: MassName) -> MassKind {
        flexmbs_reduce::geometric::system_mass_kind(mesh, mass)
    }
}

/// Message of a reduced-body file without stored geometric stiffness asked for geometric
/// stiffening.
pub const NO_STORED_STIFFNESS: &str = "the reduced-body file has no geometric stiffness (group \
     `geometric`): re-export it with `flexmbs reduce` from an FE model with supports (fixed \
     nodes), or use the FE model file (.toml) as `source`";

/// Message of a free-free body (no fixed nodes) asked for geometric stiffening.
pub const NEEDS_SUPPORTS: &str =
    "geometric stiffening needs supports (fixed nodes in the FE model)";

/// The six centrifugal geometric stiffness matrices `K_G,ab` of `body` (reduced from `fe`, all
/// its modes, body units), supported on the fixed nodes of the FE model
/// ([`flexmbs_reduce::geometric::centrifugal_geometric_stiffness`], the same computation
/// `flexmbs reduce` stores in a reduced-body file). Errors as text: a body without fixed nodes
/// ([`NEEDS_SUPPORTS`]) or a failure of the FE computation.
pub fn centrifugal_stiffness(
    fe: &FeModel,
    body: &ReducedBody,
) -> Result<GeometricStiffness, String> {
    flexmbs_reduce::geometric::centrifugal_geometric_stiffness(&fe.prepared, fe.mass, body)
        .map_err(|e| format!("geometric stiffness: {e}"))?
        .ok_or_else(|| NEEDS_SUPPORTS.to_string())
}

/// `g` restricted to the basis vectors `cols` (0-based, in the order of the selection).
pub fn select_geometric_modes(g: &GeometricStiffness, cols: &[usize]) -> GeometricStiffness {
    GeometricStiffness {
        load_patterns: g.load_patterns.clone(),
        matrices: g
            .matrices
            .iter()
            .map(|m| faer::Mat::from_fn(cols.len(), cols.len(), |i, j| m[(cols[i], cols[j])]))
            .collect(),
    }
}

/// `g` (units `units`) in SI, scaled exactly like the modal stiffness by
/// [`flexmbs_core::ffr::reduced_body_to_si`]: `K_G` is `Φᵀ K_σ Φ` per (rad/s)² with `K_σ` a
/// stiffness (force/length), so it takes the factor `c² · stiffness_to_si` of `k_ff` (`c` =
/// [`UnitSystem::mode_to_si`]). With mass-normalised modes both factors are 1 in effect
/// (`K_G` is dimensionless), which the SI(mm) test checks.
pub fn geometric_to_si(g: &GeometricStiffness, units: UnitSystem) -> GeometricStiffness {
    let c = units.mode_to_si();
    let fk = c * c * units.stiffness_to_si();
    GeometricStiffness {
        load_patterns: g.load_patterns.clone(),
        matrices: g
            .matrices
            .iter()
            .map(|m| faer::Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * fk))
            .collect(),
    }
}

/// Message of `load_stiffening = true` on a source without an FE model.
pub const LOAD_STIFFENING_NEEDS_FE_MODEL: &str = "load stiffening needs an FE model file (.toml \
     with a built-in mesh or a CalculiX deck) as `source`: the unit-load problems of the node \
     loads are solved on its mesh";

/// The unit-load patterns of `load_stiffening = true` for the mesh nodes `nodes` (indices of the
/// FE system's nodes): a force along each body axis and, at a node with rotations (beam node,
/// rigid interface node), a moment about each; for a body with fixed nodes the frame's
/// translational and angular accelerations; with `centrifugal` (a free-free body with
/// `geometric_stiffening = true`) the six centrifugal patterns, relieved like the node loads.
pub fn load_patterns(fe: &FeModel, nodes: &[usize], centrifugal: bool) -> Vec<UnitLoad> {
    let map = &fe.prepared.system.map;
    let mut pats = Vec::new();
    for &node in nodes {
        for axis in 0..3 {
            pats.push(UnitLoad::Node(NodeLoad::Force { node, axis }));
        }
        if map.dofs.count.get(node).copied().unwrap_or(0) == 6 {
            for axis in 0..3 {
                pats.push(UnitLoad::Node(NodeLoad::Moment { node, axis }));
            }
        }
    }
    if !fe.prepared.bc.fixed.is_empty() {
        for d in 0..3 {
            pats.push(UnitLoad::Inertial(InertialLoad::Translation(d)));
            pats.push(UnitLoad::Inertial(InertialLoad::AngularAcceleration(d)));
        }
    } else if centrifugal {
        pats.extend(
            InertialLoad::centrifugal()
                .into_iter()
                .map(UnitLoad::Inertial),
        );
    }
    pats
}

/// The node-load geometric stiffness of `body` (its selected modes, body units) for
/// [`load_patterns`]: supported on the fixed nodes, or with inertia relief for a free-free body
/// ([`flexmbs_fe::geometric_loads::load_geometric_stiffness`]). Errors as text.
pub fn load_stiffness(
    fe: &FeModel,
    body: &ReducedBody,
    nodes: &[usize],
    centrifugal: bool,
) -> Result<LoadGeometricStiffness, String> {
    let pats = load_patterns(fe, nodes, centrifugal);
    let p = &fe.prepared;
    load_geometric_stiffness(&p.mesh, &p.system, body, fe.mass, &pats)
        .map_err(|e| format!("load geometric stiffness: {e}"))
}

/// `g` (units `units`) in SI: `K_G` scales like `k_ff` ([`geometric_to_si`]) divided by the SI
/// size of its pattern's unit coefficient (a force, a moment, a length per s² for a translational
/// acceleration; angular accelerations and centrifugal coefficients are in rad/s in every unit
/// system).
pub fn load_geometric_to_si(
    g: &LoadGeometricStiffness,
    units: UnitSystem,
) -> LoadGeometricStiffness {
    let c = units.mode_to_si();
    let fk = c * c * units.stiffness_to_si();
    let (f, l) = (units.force_to_si(), units.length_to_si());
    let per = |p: &UnitLoad| match p {
        UnitLoad::Node(NodeLoad::Force { .. }) => f,
        UnitLoad::Node(NodeLoad::Moment { .. }) => f * l,
        UnitLoad::Inertial(InertialLoad::Translation(_)) => l,
        UnitLoad::Inertial(_) => 1.0,
    };
    LoadGeometricStiffness {
        patterns: g.patterns.clone(),
        matrices: g
            .patterns
            .iter()
            .zip(&g.matrices)
            .map(|(p, m)| {
                let s = fk / per(p);
                faer::Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * s)
            })
            .collect(),
        inertia_relief: g.inertia_relief,
    }
}

/// `body` (SI, selected modes of `reduced`, body units) with node-load stiffening
/// (`load_stiffening = true` on `body[i]`, key path `p`): patterns at the mesh nodes of the model
/// file's node frames on this body (`node`, `nearest`, `interface`: resolved with the body's
/// `geometry` like the frames themselves), computed on the FE model `fe`; for a free-free body
/// with `geometric_stiffening = true` also the relieved centrifugal patterns.
#[allow(clippy::too_many_arguments)]
pub fn with_load_stiffening(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    frames: &[FrameSpec],
    geometry: &BodyGeometry,
    fe: Option<&FeModel>,
    reduced: &ReducedBody,
    body: FfrBody,
) -> Result<FfrBody, SimError> {
    let key = format!("{p}.load_stiffening");
    if b.load_stiffening != Some(true) {
        return Ok(body);
    }
    let fe = fe.ok_or_else(|| ctx.err(&key, LOAD_STIFFENING_NEEDS_FE_MODEL))?;
    let mut nodes = Vec::new();
    for (k, f) in frames.iter().enumerate() {
        let named = f.node.is_some() || f.nearest.is_some() || f.interface.is_some();
        if f.body == b.name && named {
            nodes.push(frame_node(ctx, &format!("frame[{k}]"), f, geometry)?);
        }
    }
    nodes.sort_unstable();
    nodes.dedup();
    let relief = fe.prepared.bc.fixed.is_empty();
    let centrifugal = relief && b.geometric_stiffening == Some(true);
    let g = load_stiffness(fe, reduced, &nodes, centrifugal).map_err(|m| ctx.err(&key, m))?;
    let g = load_geometric_to_si(&g, reduced.units);
    let nf = body.nf();
    let ls = LoadStiffening::from_fe(&g.without_centrifugal(), nf)
        .map_err(|e| ctx.err(&key, e.to_string()))?;
    let mut body = body
        .with_load_stiffening(ls)
        .map_err(|e| ctx.err(&key, e.to_string()))?;
    if centrifugal {
        body = body
            .with_geometric_stiffening(&g.centrifugal())
            .map_err(|e| ctx.err(&format!("{p}.geometric_stiffening"), e.to_string()))?;
    }
    Ok(body)
}

/// Node-load stiffening acts in the generalized-alpha and statics solvers (its coefficients come
/// from the joint reactions of the Newton iterates; the static start of `initial = "static"` is a
/// statics solve, so it includes it) and in DOPRI5 (unconstrained: from the loads at each
/// stage): an error at `body[i].load_stiffening` with Moreau.
pub fn check_load_stiffening_solver(
    ctx: &Ctx,
    bodies: &[BodySpec],
    solver: &crate::config::SolverConfig,
) -> Result<(), SimError> {
    let Some(i) = bodies.iter().position(|b| b.load_stiffening == Some(true)) else {
        return Ok(());
    };
    if matches!(
        solver,
        crate::config::SolverConfig::GenAlpha { .. }
            | crate::config::SolverConfig::Statics { .. }
            | crate::config::SolverConfig::Dopri5 { .. }
    ) {
        return Ok(());
    }
    Err(ctx.err(
        &format!("body[{i}].load_stiffening"),
        "load stiffening acts in the generalized-alpha, statics and DOPRI5 solvers only (its \
         coefficients come from the joint reactions and loads of each force evaluation): use \
         `type = \"generalized-alpha\"`",
    ))
}
