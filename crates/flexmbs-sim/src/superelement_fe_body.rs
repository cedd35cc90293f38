//! `[[body]] type = "superelement"`: one superelement from an FE body file (reference:
//! `docs/model-file.md`, "Superelements from FE body files"). The FE file is reduced by
//! Craig-Bampton to its `reduction.interface` points; [`crate::superelement_fe`] builds the data.
//! Every interface point is a `Pose` node and a frame named by `interfaces` (default
//! `<body>.<FE interface name>`); an interface name that an earlier superelement created is
//! shared (its node, no joint). Signals and frames as for `superelement_beam`
//! ([`crate::superelements`]).

use crate::bodies::{BodyGeometry, BodySource};
use crate::compile::{BodyInfo, Ctx};
use crate::error::SimError;
use crate::schema::{BodySpec, ModelFile, RotationName};
use crate::superelement_fe::{superelement_from_reduced, FeFrame};
use crate::superelements::{
    fixed_joint, initial_velocity, new_interface, Component, FictitiousName, FrameName,
    MatricesName, PendingJoint, SuperelementBuild, NO_STRESS,
};
use crate::units::Dimension;
use flexmbs_core::superelement::{FictitiousForces, Superelement, TransformMatrices};
use flexmbs_core::{FrameId, ModelSpec, NodeKind};
use flexmbs_fe::reduction::Cell;
use flexmbs_fe::ElementKind;
use flexmbs_io::model::NodeSelector;
use flexmbs_reduce::pipeline::{prepare, resolve, run_reduction, select_nodes};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// The FE body files read and reduced in one compilation, by resolved path: the superelements of
/// one FE body file (a plate of ten equal pieces) share one reduction.
#[derive(Default)]
pub(crate) struct FeSourceCache(HashMap<PathBuf, Rc<FeSource>>);

impl std::fmt::Debug for FeSourceCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FeSourceCache({} FE body files)", self.0.len())
    }
}

/// The FE model of a superelement body: its reduction and interface names (FE file order).
pub(crate) struct FeSource {
    prepared: flexmbs_reduce::pipeline::PreparedBody,
    reduced: flexmbs_fe::reduction::ReducedBody,
    /// Names of the FE file's interfaces: a rigid interface's or node set's name, else `i<k>`.
    fe_names: Vec<String>,
}

/// Adds the `superelement` body `b` (entry `p`): nodes (shared by name with earlier
/// superelements), the body, its floating frame and interface frames, initial pose and velocity,
/// and the fixed joints of `fixed`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn add_fe_superelement(
    ctx: &Ctx,
    mf: &ModelFile,
    p: &str,
    b: &BodySpec,
    spec: &mut ModelSpec,
    frames: &mut HashMap<String, FrameId>,
    build: &mut SuperelementBuild,
) -> Result<(), SimError> {
    check_keys(ctx, p, b)?;
    let fe = cached_source(ctx, p, b, &mut build.fe_sources)?;
    let names = interface_names(ctx, mf, p, b, &fe.fe_names)?;
    let frame = match b.frame.unwrap_or(FrameName::CentreOfMass) {
        FrameName::CentreOfMass => FeFrame::CentreOfMass,
        FrameName::Interface => FeFrame::FirstInterface,
    };
    let key = format!("{p}.source");
    let mut built =
        superelement_from_reduced(&fe.prepared.system, &fe.reduced, &fe.fe_names, frame)
            .map_err(|e| ctx.err(&key, e.to_string()))?;
    let position = match &b.position {
        Some(v) => ctx.vec3(v, Dimension::Length, &format!("{p}.position"))?,
        None => Vector3::zeros(),
    };
    let r = match &b.orientation {
        Some(o) => crate::config::orientation(ctx, o, &format!("{p}.orientation"))?,
        None => Matrix3::identity(),
    };
    let origin = position + r * built.origin;
    let size = built
        .data
        .interfaces
        .iter()
        .map(|i| i.position.norm())
        .fold(1e-3, f64::max);
    // shared interfaces: same place, and their axes as the body that created them
    for (k, n) in names.iter().enumerate() {
        if let Some(itf) = build.interfaces.get(n) {
            let at = origin + r * built.data.interfaces[k].position;
            let gap = (at - itf.position).norm();
            if gap > 1e-9 * size {
                return Err(ctx.err(
                    &format!("{p}.interfaces[{k}]"),
                    format!(
                        "interface `{n}` (created at `{}`) is at {:?} m, but this body's \
                         interface {k} is at {:?} m ({gap:e} m apart): shared interfaces must \
                         coincide at t = 0",
                        itf.owner,
                        itf.position.as_slice(),
                        at.as_slice()
                    ),
                ));
            }
            built.data.interfaces[k].rotation = r.transpose() * itf.rotation;
        }
    }
    let matrices = match b.matrices.unwrap_or(MatricesName::Exact) {
        MatricesName::Exact => TransformMatrices::Exact,
        MatricesName::Approximated => TransformMatrices::Approximated,
    };
    let fictitious = match b.fictitious_forces.unwrap_or(FictitiousName::Neglected) {
        FictitiousName::Neglected => FictitiousForces::Neglected,
        FictitiousName::FromMcb => FictitiousForces::FromMcb,
    };
    let geometry = geometry(&built.data);
    let contour_nodes = fe_contour_nodes(&fe.reduced, &built.origin, built.data.interfaces.len());
    build.contour_nodes.insert(b.name.clone(), contour_nodes);
    let itf_local: Vec<Vector3<f64>> = built.data.interfaces.iter().map(|i| i.position).collect();
    let m = built.data.internal_modes;
    let se = Superelement::new(built.data)
        .map_err(|e| ctx.err(&key, e.to_string()))?
        .with_matrices(matrices)
        .with_fictitious_forces(fictitious);
    let mut nodes = Vec::with_capacity(names.len() + 1);
    for (k, n) in names.iter().enumerate() {
        let node = match build.interfaces.get(n) {
            Some(itf) => itf.node,
            None => {
                let x = origin + r * itf_local[k];
                new_interface(ctx, p, k, n, spec, frames, build, x, r)?
            }
        };
        nodes.push(node);
        if k == 0 && m > 0 {
            nodes.push(spec.add_node(&format!("{}.eta", b.name), NodeKind::Vector(m)));
        }
    }
    let id = spec.add_body_on(&b.name, se, &nodes);
    spec.set_initial_pose(id, origin, r);
    let (v, w) = initial_velocity(ctx, p, b)?;
    if v.norm() > 0.0 || w.norm() > 0.0 {
        spec.set_initial_velocity(id, v + w.cross(&(origin - position)), w);
    }
    let frame = spec.add_frame(&b.name, id, Vector3::zeros(), Matrix3::identity());
    frames.insert(b.name.clone(), frame);
    build.bodies.push(BodyInfo {
        name: b.name.clone(),
        id,
        frame,
        geometry,
    });
    for (k, f) in b.fixed.iter().flatten().enumerate() {
        let joint = fixed_joint(ctx, &format!("{p}.fixed[{k}]"), f, &names, spec, build)?;
        build.fixed.push(PendingJoint { joint });
    }
    build.components.push(Component {
        name: b.name.clone(),
        interfaces: names,
        segments: vec![id],
    });
    Ok(())
}

/// The FE nodes of an FE superelement for neutral contours: positions in the floating frame
/// (SI; `points`, for `through`, in FE coordinates) and the translational rows of the Craig-Bampton basis, scaled to SI like the
/// superelement's coordinates (interface translations dimensionless, rotations and internal
/// modes times the length unit).
fn fe_contour_nodes(
    reduced: &flexmbs_fe::reduction::ReducedBody,
    origin: &Vector3<f64>,
    interfaces: usize,
) -> crate::superelements::SegmentNodes {
    let l = reduced.units.length_to_si();
    let n = reduced.modes_t.ncols();
    let positions: Vec<Vector3<f64>> = reduced
        .nodes
        .iter()
        .map(|x| Vector3::from(*x) * l - origin)
        .collect();
    let scale = |j: usize| {
        if j < 6 * interfaces && j % 6 < 3 {
            1.0
        } else {
            l
        }
    };
    let shapes = nalgebra::DMatrix::from_fn(3 * positions.len(), n, |r, c| {
        reduced.modes_t[(r, c)] * scale(c)
    });
    // `through` selects in FE coordinates (SI)
    let points = positions
        .iter()
        .map(|x| {
            let f = x + origin;
            [f.x, f.y, f.z]
        })
        .collect();
    crate::superelements::SegmentNodes {
        table: flexmbs_core::contour_source::NodeTable {
            positions,
            shapes,
            velocities: n,
        },
        ids: reduced.node_ids.clone(),
        points,
    }
}

/// Refuses the keys a superelement body does not use.
fn check_keys(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<(), SimError> {
    let allowed = [
        "source",
        "frame",
        "matrices",
        "fictitious_forces",
        "interfaces",
        "fixed",
    ];
    crate::superelements::check_superelement_keys(ctx, p, b, "a superelement body", &allowed)
}

/// The FE source of body `b` from `cache`, read and reduced by [`load_source`] on first use.
fn cached_source(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    cache: &mut FeSourceCache,
) -> Result<Rc<FeSource>, SimError> {
    let base = ctx.file.parent().unwrap_or(Path::new("."));
    let path = b.source.as_ref().map(|s| resolve(base, s));
    if let Some(hit) = path.as_ref().and_then(|path| cache.0.get(path)) {
        return Ok(Rc::clone(hit));
    }
    let fe = Rc::new(load_source(ctx, p, b)?);
    if let Some(path) = path {
        cache.0.insert(path, Rc::clone(&fe));
    }
    Ok(fe)
}

/// Reads and reduces the FE body file of `source`; errors of the FE file are located at its
/// own line and key.
fn load_source(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<FeSource, SimError> {
    let key = format!("{p}.source");
    let source = b.source.as_ref().ok_or_else(|| {
        ctx.err(
            p,
            "a superelement body needs `source` (an FE body file, .toml, reduced by \
             craig-bampton to its interfaces)",
        )
    })?;
    let base = ctx.file.parent().unwrap_or(Path::new("."));
    let path = resolve(base, source);
    if BodySource::of(&path).map_err(|m| ctx.err(&key, m))? != BodySource::FeModel {
        return Err(ctx.err(
            &key,
            format!(
                "{}: a superelement needs an FE body file (.toml with a mesh and \
                 [body.reduction] method = \"craig-bampton\"), not a reduced-body file or seed \
                 folder",
                path.display()
            ),
        ));
    }
    let src = flexmbs_io::model_check::FeModelSource::read(&path)
        .map_err(|e| ctx.err(&key, e.to_string()))?;
    let fe_spec = src.model.body.clone();
    if let flexmbs_io::model::MeshSpec::Seed { .. } = fe_spec.mesh {
        return Err(ctx.err(
            &key,
            "the FE body file's mesh is a seed folder (already reduced): a superelement needs \
             the FE model",
        ));
    }
    let fe_base = path.parent().unwrap_or(Path::new("."));
    let located =
        |e: flexmbs_reduce::pipeline::PipelineError| ctx.err(&key, src.locate(e).to_string());
    let model_error = |path: &str, message: &str| {
        located(flexmbs_reduce::pipeline::PipelineError::Model {
            path: path.into(),
            message: message.into(),
        })
    };
    if fe_spec.reduction.method == flexmbs_io::model::ReductionMethod::Modal {
        return Err(model_error(
            "body.reduction.method",
            "a superelement needs `method = \"craig-bampton\"` (or \"guyan\"): its coordinates \
             are the interface points of a Craig-Bampton reduction",
        ));
    }
    if fe_spec.reduction.interface.is_empty() {
        return Err(model_error(
            "body.reduction.interface",
            "a superelement needs at least one interface point (`interface = [\"<rigid \
             interface or node set>\", ...]`)",
        ));
    }
    let prepared = prepare(&fe_spec, fe_base, &mut |_| {}).map_err(located)?;
    let mut fe_names = Vec::new();
    for (k, sel) in fe_spec.reduction.interface.iter().enumerate() {
        let fe_key = format!("body.reduction.interface[{k}]");
        let rigid = match sel {
            NodeSelector::Set(n) => prepared.bc.rigid.iter().any(|r| &r.name == n),
            _ => false,
        };
        if !rigid {
            let nodes = select_nodes(&prepared.mesh, sel, &fe_key).map_err(located)?;
            if nodes.len() != 1 {
                return Err(located(flexmbs_reduce::pipeline::PipelineError::Model {
                    path: fe_key,
                    message: format!(
                        "selects {} nodes: a superelement interface is one 6-DOF node (a beam \
                         node) or a node set tied rigidly to one ([[body.boundary.rigid]] with a \
                         name, then `interface = [\"<name>\"]`)",
                        nodes.len()
                    ),
                }));
            }
        }
        fe_names.push(match sel {
            NodeSelector::Set(n) => n.clone(),
            _ => format!("i{k}"),
        });
    }
    let reduced = run_reduction(&fe_spec, &prepared, &mut |_| {}).map_err(located)?;
    Ok(FeSource {
        prepared,
        reduced,
        fe_names,
    })
}

/// The model-file names of the interfaces: `interfaces` (one per FE interface, FE file order) or
/// `<body>.<FE interface name>`.
fn interface_names(
    ctx: &Ctx,
    mf: &ModelFile,
    p: &str,
    b: &BodySpec,
    fe_names: &[String],
) -> Result<Vec<String>, SimError> {
    let Some(list) = &b.interfaces else {
        return Ok(fe_names.iter().map(|n| format!("{}.{n}", b.name)).collect());
    };
    let path = format!("{p}.interfaces");
    if list.len() != fe_names.len() {
        return Err(ctx.err(
            &path,
            format!(
                "{} names for the {} interfaces of the FE body file ({}): give one per interface, \
                 in the FE file's order",
                list.len(),
                fe_names.len(),
                fe_names.join(", ")
            ),
        ));
    }
    let taken = |n: &str| {
        mf.body.iter().any(|x| x.name == n)
            || mf.frame.iter().any(|x| x.name == n)
            || mf.joint.iter().any(|x| x.name == n)
            || mf.force.iter().any(|x| x.name == n)
    };
    for (k, n) in list.iter().enumerate() {
        let at = format!("{path}[{k}]");
        if n.is_empty() || n == "ground" || n.contains('/') {
            return Err(ctx.err(
                &at,
                format!("invalid interface name `{n}` (not empty, not `ground`, no `/`)"),
            ));
        }
        if taken(n) {
            return Err(ctx.err(
                &at,
                format!("`{n}` is already the name of a body, frame, joint or force"),
            ));
        }
        if list[..k].contains(n) {
            return Err(ctx.err(&at, format!("interface `{n}` listed twice")));
        }
    }
    Ok(list.clone())
}

/// Animation geometry: the interface points and the floating-frame origin, joined by lines.
fn geometry(data: &flexmbs_core::superelement::SuperelementData) -> BodyGeometry {
    let mut points: Vec<[f64; 3]> = data
        .interfaces
        .iter()
        .map(|i| [i.position.x, i.position.y, i.position.z])
        .collect();
    let centre = points.len();
    points.push([0.0; 3]);
    let cells = (0..centre)
        .map(|k| Cell {
            kind: ElementKind::Beam2,
            nodes: vec![k, centre],
        })
        .collect();
    BodyGeometry {
        points,
        fe_nodes: true,
        node_ids: Vec::new(),
        cells,
        modes: 0,
        rotation: RotationName::Quaternion,
        interfaces: Vec::new(),
        translation_only: Vec::new(),
        rotating: Vec::new(),
        stress: Err(NO_STRESS.into()),
    }
}
