//! Superelement beam components of a model file (`[[body]] type = "superelement_beam"`; reference:
//! `docs/model-file.md`, "Superelement beams"): a straight beam of given material and section
//! split into a chain of superelements (seed 001 ch. 3-4, [`flexmbs_core::superelement`]) whose
//! interface points are shared `Pose` nodes. Every interface point is a named frame
//! (`<body>.i<k>` or the names in `interfaces`), every superelement a body named `<body>.s<k>`
//! whose frame is its floating frame. A component whose first interface names the last interface
//! of the component before it continues that chain through the shared node (no Lagrange
//! multiplier); `fixed` clamps interface points to ground with fixed joints.

use crate::bodies::BodyGeometry;
use crate::compile::{BodyInfo, Ctx};
use crate::error::SimError;
use crate::schema::{BodySpec, BodyType, ModelFile, RotationName};
use crate::units::{Dimension, Quantity};
use flexmbs_core::contour_source::NodeTable;
use flexmbs_core::superelement::{
    beam_segment_basis, beam_segment_contour_nodes, even_elements, BeamSegmentSpec,
    FictitiousForces, FrameLocation, Superelement, TransformMatrices,
};
use flexmbs_core::{BodyId, FrameId, Joint, ModelSpec, NodeId, NodeKind};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::Cell;
use flexmbs_fe::{ElementKind, Material};
use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;
use std::collections::HashMap;

/// `frame` of a superelement beam: where each superelement's floating frame sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameName {
    /// At the undeformed centre of mass (seed 001's choice, default).
    CentreOfMass,
    /// At the first interface point of each superelement (the "traditional" variant).
    Interface,
}

/// `matrices` of a superelement beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MatricesName {
    /// Deformed transformation matrices, exact variation (default).
    Exact,
    /// Undeformed matrices (seed 001 (3.20)-(3.26)).
    Approximated,
}

/// `fictitious_forces` of a superelement beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FictitiousName {
    /// Neglected, as in seed 001 ch. 5 (default).
    Neglected,
    /// The velocity terms implied by the mass matrix `Pᵀ M_CB P`.
    FromMcb,
}

/// The keys only superelement beams use, with whether `b` sets them (the other body types refuse
/// them with [`Ctx::only`]).
pub fn superelement_keys_present(b: &BodySpec) -> [(&'static str, bool); 14] {
    [
        ("material", b.material.is_some()),
        ("section", b.section.is_some()),
        ("theory", b.theory.is_some()),
        ("direction", b.direction.is_some()),
        ("length", b.length.is_some()),
        ("segments", b.segments.is_some()),
        ("lengths", b.lengths.is_some()),
        ("elements", b.elements.is_some()),
        ("internal_modes", b.internal_modes.is_some()),
        ("frame", b.frame.is_some()),
        ("matrices", b.matrices.is_some()),
        ("fictitious_forces", b.fictitious_forces.is_some()),
        ("interfaces", b.interfaces.is_some()),
        ("fixed", b.fixed.is_some()),
    ]
}

/// An interface point of the model: its node, frame and initial pose.
#[derive(Debug, Clone)]
pub(crate) struct InterfacePoint {
    pub(crate) node: NodeId,
    pub(crate) frame: FrameId,
    pub(crate) position: Vector3<f64>,
    pub(crate) rotation: Matrix3<f64>,
    /// Key path of the component entry that created it.
    pub(crate) owner: String,
}

/// A compiled superelement beam component.
#[derive(Debug, Clone)]
pub struct Component {
    /// Component (body entry) name.
    pub name: String,
    /// Interface names, start to end.
    pub interfaces: Vec<String>,
    /// The superelements' bodies.
    pub segments: Vec<BodyId>,
}

/// A fixed joint to ground that `fixed` asks for (added after the file's joints so that their
/// indices stay those of `[[joint]]`).
#[derive(Debug, Clone)]
pub struct PendingJoint {
    /// The joint.
    pub joint: Joint,
}

/// What [`add_superelement_beams`] built.
#[derive(Debug, Default)]
pub struct SuperelementBuild {
    /// One body per superelement, with its floating frame.
    pub bodies: Vec<BodyInfo>,
    /// The components (file order).
    pub components: Vec<Component>,
    /// Fixed joints to add after the file's joints.
    pub fixed: Vec<PendingJoint>,
    /// Interface frames by name.
    pub(crate) interfaces: HashMap<String, InterfacePoint>,
    /// FE body files of `superelement` bodies, each read and reduced once.
    pub(crate) fe_sources: crate::superelement_fe_body::FeSourceCache,
    /// The FE nodes of every beam superelement (by body name `<body>.s<k>`), for neutral
    /// contours.
    pub(crate) contour_nodes: HashMap<String, SegmentNodes>,
}

/// The FE nodes of a beam superelement for neutral contours: node `i` (id `i + 1`) at
/// `x = i L / n_e` along the segment, in its floating frame.
#[derive(Debug, Clone)]
pub(crate) struct SegmentNodes {
    /// Positions and shape vectors.
    pub table: NodeTable,
    /// Node ids `1 ..= n_e + 1`.
    pub ids: Vec<u64>,
    /// Positions as arrays (the `through` selection).
    pub points: Vec<[f64; 3]>,
}

impl SuperelementBuild {
    /// The component named `name`.
    pub fn component(&self, name: &str) -> Option<&Component> {
        self.components.iter().find(|c| c.name == name)
    }

    /// Frame of interface `name` (an interface of any component).
    pub fn interface_frame(&self, name: &str) -> Option<FrameId> {
        self.interfaces.get(name).map(|i| i.frame)
    }

    /// The node of interface `name`.
    pub fn interface_node(&self, name: &str) -> Option<NodeId> {
        self.interfaces.get(name).map(|i| i.node)
    }

    /// Why a `[[frame]]` with `node`, `nearest` or `interface` may not sit on body `body`, if it
    /// is a superelement.
    pub fn segment_node_frame_message(&self, body: &str) -> Option<String> {
        // a `superelement_beam` body's superelements `<name>.s<k>`, or a `superelement` body
        let c = self.components.iter().find(|c| {
            body == c.name
                || body
                    .strip_prefix(c.name.as_str())
                    .is_some_and(|s| s.starts_with(".s"))
        })?;
        Some(format!(
            "`{body}` is a superelement of `{}`: frames on its points use `body = \"{}\"` with \
             `interface` (one of {})",
            c.name,
            c.name,
            c.interfaces.join(", ")
        ))
    }

    /// Why a joint may not use a frame fixed in the floating frame of superelement `body`, if
    /// `body` is one.
    pub fn floating_frame_joint_message(&self, frame: &str, body: &str) -> Option<String> {
        // a `superelement_beam` body's superelements `<name>.s<k>`, or a `superelement` body
        let c = self.components.iter().find(|c| {
            body == c.name
                || body
                    .strip_prefix(c.name.as_str())
                    .is_some_and(|s| s.starts_with(".s"))
        })?;
        Some(format!(
            "frame `{frame}` is fixed in the floating frame of superelement `{body}`, which is \
             not a material point (it is recovered from the interface poses): attach joints to \
             an interface point of `{}` ({})",
            c.name,
            c.interfaces.join(", ")
        ))
    }
}

/// The validated inputs of one component.
struct ComponentInput {
    material: Material,
    section: BeamSection,
    theory: BeamTheory,
    lengths: Vec<f64>,
    elements: usize,
    internal_modes: usize,
    frame: FrameLocation,
    matrices: TransformMatrices,
    fictitious: FictitiousForces,
    rotation: Matrix3<f64>,
    names: Vec<String>,
}

/// Adds every `superelement_beam` entry of `mf` to `spec` in file order: nodes, bodies, frames
/// (also inserted into `frames`), initial poses and velocities; fixed joints are returned.
pub fn add_superelement_beams(
    ctx: &Ctx,
    mf: &ModelFile,
    spec: &mut ModelSpec,
    frames: &mut HashMap<String, FrameId>,
) -> Result<SuperelementBuild, SimError> {
    let mut build = SuperelementBuild::default();
    for (i, b) in mf.body.iter().enumerate() {
        let p = format!("body[{i}]");
        if b.kind == BodyType::Superelement {
            crate::superelement_fe_body::add_fe_superelement(
                ctx, mf, &p, b, spec, frames, &mut build,
            )?;
            continue;
        }
        if b.kind != BodyType::SuperelementBeam {
            continue;
        }
        let input = component_input(ctx, mf, &p, b)?;
        add_component(ctx, &p, b, &input, spec, frames, &mut build)?;
    }
    Ok(build)
}

/// Checks the keys of a superelement beam entry and converts them to SI.
fn component_input(
    ctx: &Ctx,
    mf: &ModelFile,
    p: &str,
    b: &BodySpec,
) -> Result<ComponentInput, SimError> {
    check_keys(ctx, p, b)?;
    let material = beam_material(ctx, p, b)?;
    let section = beam_section(ctx, p, b)?;
    let lengths = segment_lengths(ctx, p, b)?;
    let elements = b.elements.unwrap_or(2);
    if elements == 0 {
        return Err(ctx.err(
            &format!("{p}.elements"),
            "needs at least 1 FE element per superelement",
        ));
    }
    let internal_modes = b.internal_modes.unwrap_or(0);
    let spec0 = BeamSegmentSpec {
        length: 1.0,
        material,
        section,
        theory: BeamTheory::EulerBernoulli,
        elements,
        internal_modes,
        frame: FrameLocation::CentreOfMass,
    };
    let interior_dofs = 6 * (even_elements(&spec0) - 1);
    if internal_modes > interior_dofs {
        return Err(ctx.err(
            &format!("{p}.internal_modes"),
            format!(
                "{internal_modes} internal modes, but a superelement of {} FE elements has only \
                 {interior_dofs} interior DOFs: raise `elements` or lower `internal_modes`",
                even_elements(&spec0)
            ),
        ));
    }
    let names = interface_names(ctx, mf, p, b, lengths.len())?;
    Ok(ComponentInput {
        material,
        section,
        theory: b.theory.unwrap_or_default().into(),
        lengths,
        elements,
        internal_modes,
        frame: match b.frame.unwrap_or(FrameName::CentreOfMass) {
            FrameName::CentreOfMass => FrameLocation::CentreOfMass,
            FrameName::Interface => FrameLocation::FirstInterface,
        },
        matrices: match b.matrices.unwrap_or(MatricesName::Exact) {
            MatricesName::Exact => TransformMatrices::Exact,
            MatricesName::Approximated => TransformMatrices::Approximated,
        },
        fictitious: match b.fictitious_forces.unwrap_or(FictitiousName::Neglected) {
            FictitiousName::Neglected => FictitiousForces::Neglected,
            FictitiousName::FromMcb => FictitiousForces::FromMcb,
        },
        rotation: beam_axes(ctx, p, b)?,
        names,
    })
}

/// Refuses the keys of rigid and ffr bodies.
fn check_keys(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<(), SimError> {
    let allowed: Vec<&str> = superelement_keys_present(b).iter().map(|k| k.0).collect();
    check_superelement_keys(ctx, p, b, "a superelement_beam body", &allowed)
}

/// Refuses, for a superelement body of kind `kind` (`superelement_beam` or `superelement`), every
/// key of rigid and ffr bodies and every superelement key not in `allowed`, and a `rotation`
/// (its interface points rotate by quaternions).
pub(crate) fn check_superelement_keys(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    kind: &str,
    allowed: &[&str],
) -> Result<(), SimError> {
    let mut present = vec![
        ("mass", b.mass.is_some()),
        ("inertia", b.inertia.is_some()),
        ("inertia_matrix", b.inertia_matrix.is_some()),
        ("box", b.box_size.is_some()),
        ("source", b.source.is_some()),
        ("units", b.units.is_some()),
        ("modes", b.modes.is_some()),
        ("damping", b.damping.is_some()),
        ("geometric_stiffening", b.geometric_stiffening.is_some()),
        ("load_stiffening", b.load_stiffening.is_some()),
        ("rotary_inertia", b.rotary_inertia.is_some()),
        ("modal_coordinates", b.modal_coordinates.is_some()),
        ("modal_velocities", b.modal_velocities.is_some()),
    ];
    present.extend(superelement_keys_present(b));
    ctx.only(p, kind, &present, allowed)?;
    if b.rotation != RotationName::Cardan {
        return Err(ctx.err(
            &format!("{p}.rotation"),
            format!(
                "{kind} has no rotation coordinates of its own (its interface points rotate by \
                 quaternions): remove `rotation`"
            ),
        ));
    }
    Ok(())
}

/// `material`: `e > 0`, `rho > 0`, `-1 < nu < 0.5`.
fn beam_material(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<Material, SimError> {
    let m = b.material.ok_or_else(|| {
        ctx.err(
            p,
            "a superelement_beam body needs `material = { e, nu, rho }`",
        )
    })?;
    let ok = m.e > 0.0 && m.rho > 0.0 && m.nu > -1.0 && m.nu < 0.5;
    if !(ok && m.e.is_finite() && m.rho.is_finite()) {
        return Err(ctx.err(
            &format!("{p}.material"),
            format!(
                "needs e > 0, rho > 0 and -1 < nu < 0.5 (SI), got e = {}, nu = {}, rho = {}",
                m.e, m.nu, m.rho
            ),
        ));
    }
    Ok(m.into())
}

/// `section`: area, second moments and torsion constant positive and finite.
fn beam_section(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<BeamSection, SimError> {
    let s: BeamSection = b
        .section
        .ok_or_else(|| {
            ctx.err(
                p,
                "a superelement_beam body needs `section = { shape = ... }`",
            )
        })?
        .into();
    let values = [
        ("area", s.area),
        ("iy", s.iy),
        ("iz", s.iz),
        ("j", s.j),
        ("ky", s.ky),
        ("kz", s.kz),
    ];
    if let Some((what, v)) = values.iter().find(|(_, v)| !(*v > 0.0 && v.is_finite())) {
        return Err(ctx.err(
            &format!("{p}.section"),
            format!("the section's {what} is {v:e} (SI): it must be positive (a tube needs 0 < wall < outer_radius)"),
        ));
    }
    Ok(s)
}

/// The superelement lengths: `segments` equal parts of `length`, or `lengths`.
fn segment_lengths(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<Vec<f64>, SimError> {
    match (&b.segments, &b.length, &b.lengths) {
        (Some(n), Some(l), None) => {
            if *n == 0 {
                return Err(ctx.err(&format!("{p}.segments"), "needs at least 1 superelement"));
            }
            let total = ctx.q(l, Dimension::Length, &format!("{p}.length"))?;
            if total <= 0.0 {
                return Err(ctx.err(
                    &format!("{p}.length"),
                    format!("must be > 0, got {total} m"),
                ));
            }
            Ok(vec![total / *n as f64; *n])
        }
        (None, None, Some(list)) => {
            if list.is_empty() {
                return Err(ctx.err(&format!("{p}.lengths"), "needs at least 1 superelement"));
            }
            let quantity = |(k, q): (usize, &Quantity)| {
                let path = format!("{p}.lengths[{k}]");
                let v = ctx.q(q, Dimension::Length, &path)?;
                if v <= 0.0 {
                    return Err(ctx.err(&path, format!("must be > 0, got {v} m")));
                }
                Ok(v)
            };
            list.iter().enumerate().map(quantity).collect()
        }
        _ => Err(ctx.err(
            p,
            "a superelement_beam body needs either `length` with `segments` (equal \
             superelements) or `lengths` (one per superelement), not both",
        )),
    }
}

/// The beam axes (columns): `orientation` (x = beam axis), or `direction` with the local y axis
/// in the plane of the axis and global y (global z for a beam along y), as FE beam meshes.
fn beam_axes(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<Matrix3<f64>, SimError> {
    match (&b.orientation, &b.direction) {
        (Some(_), Some(_)) => Err(ctx.err(
            &format!("{p}.direction"),
            "give `direction` or `orientation`, not both",
        )),
        (Some(o), None) => crate::config::orientation(ctx, o, &format!("{p}.orientation")),
        (None, None) => Ok(Matrix3::identity()),
        (None, Some(d)) => {
            let x = Vector3::from(*d);
            if !(x.norm() > 0.0 && x.norm().is_finite()) {
                return Err(ctx.err(
                    &format!("{p}.direction"),
                    "the beam axis must be a non-zero vector",
                ));
            }
            let x = x.normalize();
            let up = if x.y.abs() > 1.0 - 1e-9 {
                Vector3::z()
            } else {
                Vector3::y()
            };
            let y = (up - x * x.dot(&up)).normalize();
            Ok(Matrix3::from_columns(&[x, y, x.cross(&y)]))
        }
    }
}

/// The interface names: `interfaces` (one per interface point) or `<body>.i0 .. <body>.iN`.
fn interface_names(
    ctx: &Ctx,
    mf: &ModelFile,
    p: &str,
    b: &BodySpec,
    segments: usize,
) -> Result<Vec<String>, SimError> {
    let Some(list) = &b.interfaces else {
        return Ok((0..=segments).map(|k| format!("{}.i{k}", b.name)).collect());
    };
    let path = format!("{p}.interfaces");
    if list.len() != segments + 1 {
        return Err(ctx.err(
            &path,
            format!(
                "{} names for {segments} superelements: give one per interface point ({})",
                list.len(),
                segments + 1
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
        let own = n.strip_prefix(&format!("{}.", b.name));
        if n.is_empty() || n == "ground" || n.contains('/') || (n.contains('.') && own.is_some()) {
            return Err(ctx.err(
                &at,
                format!("invalid interface name `{n}` (not empty, not `ground`, no `/`; `{}.<x>` names are this body's own)", b.name),
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

/// Adds one component: nodes (sharing its first interface with an existing interface point if it
/// names one, and its last interface likewise: a branch or a closed loop), superelement bodies,
/// interface and floating frames, the initial pose and velocity, and the fixed joints of `fixed`.
fn add_component(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    input: &ComponentInput,
    spec: &mut ModelSpec,
    frames: &mut HashMap<String, FrameId>,
    build: &mut SuperelementBuild,
) -> Result<(), SimError> {
    let (shared, closing) = shared_points(ctx, p, input, build)?;
    let start = component_start(ctx, p, b, input, shared.as_ref())?;
    let last = input.lengths.len() - 1;
    if let Some(end) = &closing {
        let x_end = start + input.rotation * Vector3::new(input.lengths.iter().sum(), 0.0, 0.0);
        check_coincident(
            ctx,
            &format!("{p}.interfaces[{}]", last + 1),
            input,
            b,
            end,
            x_end,
        )?;
    }
    let r = input.rotation;
    let (v, w) = initial_velocity(ctx, p, b)?;
    let mut component = Component {
        name: b.name.clone(),
        interfaces: input.names.clone(),
        segments: Vec::new(),
    };
    let mut a = match &shared {
        Some(s) => s.node,
        None => new_interface(ctx, p, 0, &input.names[0], spec, frames, build, start, r)?,
    };
    let mut x = 0.0;
    for (k, &l) in input.lengths.iter().enumerate() {
        // a shared start or end node keeps the axes of the body that created it
        let axes = |s: &Option<InterfacePoint>, at: bool| {
            s.as_ref()
                .filter(|_| at)
                .map(|s| r.transpose() * s.rotation)
        };
        let (r0, r1) = (axes(&shared, k == 0), axes(&closing, k == last));
        let (se, table) = segment(ctx, p, k, input, l, r0, r1)?;
        let name = format!("{}.s{k}", b.name);
        let points = table.positions.iter().map(|x| [x.x, x.y, x.z]).collect();
        let ids = (1..=table.positions.len() as u64).collect();
        let nodes_of = SegmentNodes { table, ids, points };
        build.contour_nodes.insert(name.clone(), nodes_of);
        let mut nodes = vec![a];
        if input.internal_modes > 0 {
            nodes.push(spec.add_node(&format!("{name}.eta"), NodeKind::Vector(se_modes(&se))));
        }
        let xb = start + r * Vector3::new(x + l, 0.0, 0.0);
        let bnode = match (&closing, k == last) {
            (Some(end), true) => end.node,
            _ => new_interface(
                ctx,
                p,
                k + 1,
                &input.names[k + 1],
                spec,
                frames,
                build,
                xb,
                r,
            )?,
        };
        nodes.push(bnode);
        let id = spec.add_body_on(&name, se, &nodes);
        let origin = match input.frame {
            FrameLocation::CentreOfMass => x + 0.5 * l,
            FrameLocation::FirstInterface => x,
        };
        let pos = start + r * Vector3::new(origin, 0.0, 0.0);
        spec.set_initial_pose(id, pos, r);
        if v.norm() > 0.0 || w.norm() > 0.0 {
            spec.set_initial_velocity(id, v + w.cross(&(pos - start)), w);
        }
        let frame = spec.add_frame(&name, id, Vector3::zeros(), Matrix3::identity());
        frames.insert(name.clone(), frame);
        build.bodies.push(BodyInfo {
            name,
            id,
            frame,
            geometry: segment_geometry(l, origin - x),
        });
        component.segments.push(id);
        a = bnode;
        x += l;
    }
    for (k, f) in b.fixed.iter().flatten().enumerate() {
        let joint = fixed_joint(
            ctx,
            &format!("{p}.fixed[{k}]"),
            f,
            &input.names,
            spec,
            build,
        )?;
        build.fixed.push(PendingJoint { joint });
    }
    build.components.push(component);
    Ok(())
}

/// The start point: `position`, or the shared interface point it continues (which `position`
/// must then meet to 1e-9 of the component's length).
fn component_start(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    input: &ComponentInput,
    shared: Option<&InterfacePoint>,
) -> Result<Vector3<f64>, SimError> {
    let start = match (&b.position, shared) {
        (Some(v), _) => ctx.vec3(v, Dimension::Length, &format!("{p}.position"))?,
        (None, Some(s)) => s.position,
        (None, None) => Vector3::zeros(),
    };
    if let Some(s) = shared {
        check_coincident(ctx, &format!("{p}.interfaces[0]"), input, b, s, start)?;
    }
    Ok(start)
}

/// An existing interface point `s` that the component's point at `x` (its start or end) shares
/// must be there to 1e-9 of the component's length.
fn check_coincident(
    ctx: &Ctx,
    path: &str,
    input: &ComponentInput,
    b: &BodySpec,
    s: &InterfacePoint,
    x: Vector3<f64>,
) -> Result<(), SimError> {
    let tol = 1e-9 * input.lengths.iter().sum::<f64>().max(1.0);
    let gap = (s.position - x).norm();
    if gap > tol {
        let (name, end) = match path.ends_with("[0]") {
            true => (&input.names[0], "starts"),
            false => (input.names.last().unwrap_or(&input.names[0]), "ends"),
        };
        return Err(ctx.err(
            path,
            format!(
                "interface `{name}` of `{}` (created at `{}`) is at {:?} m, but this body {end} \
                 at {:?} m ({gap:e} m apart): shared interfaces must coincide at t = 0",
                b.name,
                s.owner,
                s.position.as_slice(),
                x.as_slice()
            ),
        ));
    }
    Ok(())
}

/// The existing interface points this component's first and last interfaces name, if any (a
/// branch from any point, a loop closed onto any point); an interior interface that names an
/// existing point is refused (a superelement chain meets other points only at its ends), as is
/// a component whose first and last interfaces are the same point.
fn shared_points(
    ctx: &Ctx,
    p: &str,
    input: &ComponentInput,
    build: &SuperelementBuild,
) -> Result<(Option<InterfacePoint>, Option<InterfacePoint>), SimError> {
    let last = input.names.len() - 1;
    for (k, n) in input.names.iter().enumerate().take(last).skip(1) {
        if let Some(itf) = build.interfaces.get(n) {
            return Err(ctx.err(
                &format!("{p}.interfaces[{k}]"),
                format!(
                    "interface `{n}` (created at `{}`) is an interior point of this body: a \
                     superelement_beam body shares existing interface points only at its first \
                     and last interface (split it there into two bodies, or connect the points \
                     with a `fixed` joint between interface frames)",
                    itf.owner
                ),
            ));
        }
    }
    let start = build.interfaces.get(&input.names[0]).cloned();
    let end = build.interfaces.get(&input.names[last]).cloned();
    if start.is_some() && input.names[0] == input.names[last] {
        return Err(ctx.err(
            &format!("{p}.interfaces[{last}]"),
            format!(
                "interface `{}` is both the first and the last of this body: a straight \
                 superelement_beam cannot close onto itself (close a loop with several bodies)",
                input.names[0]
            ),
        ));
    }
    Ok((start, end))
}

/// Adds interface point `name` (`interfaces[k]` of the entry at `p`) at `position` with axes
/// `rotation` (superelement beams and FE superelements).
#[allow(clippy::too_many_arguments)]
pub(crate) fn new_interface(
    ctx: &Ctx,
    p: &str,
    k: usize,
    name: &str,
    spec: &mut ModelSpec,
    frames: &mut HashMap<String, FrameId>,
    build: &mut SuperelementBuild,
    position: Vector3<f64>,
    rotation: Matrix3<f64>,
) -> Result<NodeId, SimError> {
    if frames.contains_key(name) {
        return Err(ctx.err(
            &format!("{p}.interfaces[{k}]"),
            format!("`{name}` is already the name of a frame"),
        ));
    }
    let node = spec.add_node(name, NodeKind::Pose);
    let frame = spec.add_node_owned_frame(name, node, Vector3::zeros(), Matrix3::identity());
    frames.insert(name.to_string(), frame);
    build.interfaces.insert(
        name.to_string(),
        InterfacePoint {
            node,
            frame,
            position,
            rotation,
            owner: format!("{p}.interfaces[{k}]"),
        },
    );
    Ok(node)
}

/// The spec of superelement `k` of length `l`.
fn segment_spec(input: &ComponentInput, l: f64) -> BeamSegmentSpec {
    BeamSegmentSpec {
        length: l,
        material: input.material,
        section: input.section,
        theory: input.theory,
        elements: input.elements,
        internal_modes: input.internal_modes,
        frame: input.frame,
    }
}

/// Superelement `k` of the component and its FE nodes for contours; `r0`, `r1`: the undeformed
/// axes of its first and last interface in its floating frame when it meets an existing point
/// at an angle (default: parallel).
fn segment(
    ctx: &Ctx,
    p: &str,
    k: usize,
    input: &ComponentInput,
    l: f64,
    r0: Option<Matrix3<f64>>,
    r1: Option<Matrix3<f64>>,
) -> Result<(Superelement, NodeTable), SimError> {
    let spec = segment_spec(input, l);
    let (mut data, v, _) = beam_segment_basis(&spec, flexmbs_fe::element::MassKind::Consistent)
        .map_err(|e| ctx.err(p, format!("superelement {k}: reduction failed: {e}")))?;
    let table = beam_segment_contour_nodes(&spec, &data, &v);
    if let Some(r0) = r0 {
        data.interfaces[0].rotation = r0;
    }
    if let (Some(r1), Some(last)) = (r1, data.interfaces.last_mut()) {
        last.rotation = r1;
    }
    Superelement::new(data)
        .map(|s| {
            let s = s
                .with_matrices(input.matrices)
                .with_fictitious_forces(input.fictitious);
            (s, table)
        })
        .map_err(|e| ctx.err(p, format!("superelement {k}: {e}")))
}

/// Internal modes of a superelement.
fn se_modes(se: &Superelement) -> usize {
    se.data().internal_modes
}

/// Initial velocity (of the start point, or of an FE superelement's FE origin) and angular
/// velocity (global).
pub(crate) fn initial_velocity(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
) -> Result<(Vector3<f64>, Vector3<f64>), SimError> {
    let v = match &b.velocity {
        Some(v) => ctx.vec3(v, Dimension::Velocity, &format!("{p}.velocity"))?,
        None => Vector3::zeros(),
    };
    let w = match &b.angular_velocity {
        Some(w) => ctx.vec3(
            w,
            Dimension::AngularVelocity,
            &format!("{p}.angular_velocity"),
        )?,
        None => Vector3::zeros(),
    };
    Ok((v, w))
}

/// A fixed joint between a ground frame at the initial pose of interface `f` (one of `names`, or
/// `i<k>`) and the interface frame.
pub(crate) fn fixed_joint(
    ctx: &Ctx,
    path: &str,
    f: &str,
    names: &[String],
    spec: &mut ModelSpec,
    build: &SuperelementBuild,
) -> Result<Joint, SimError> {
    let by_index = f
        .strip_prefix('i')
        .and_then(|k| k.parse::<usize>().ok())
        .filter(|&k| k < names.len());
    let name = match (names.iter().find(|n| *n == f), by_index) {
        (Some(n), _) => n,
        (None, Some(k)) => &names[k],
        (None, None) => {
            return Err(ctx.err(
                path,
                format!(
                    "unknown interface `{f}` (this body's interfaces: {}, or i0 .. i{})",
                    names.join(", "),
                    names.len() - 1
                ),
            ))
        }
    };
    let itf = &build.interfaces[name];
    let ground = spec.add_ground_frame(&format!("{name}.ground"), itf.position, itf.rotation);
    Ok(Joint::fixed(&format!("{name}.fixed"), ground, itf.frame))
}

/// Animation geometry of a superelement of length `l` whose floating frame is `origin` from its
/// first interface: the two interface points (following the interface nodes) and the floating
/// frame origin, joined by two lines.
fn segment_geometry(l: f64, origin: f64) -> BodyGeometry {
    let line = |a, b| Cell {
        kind: ElementKind::Beam2,
        nodes: vec![a, b],
    };
    BodyGeometry {
        points: vec![[-origin, 0.0, 0.0], [l - origin, 0.0, 0.0], [0.0, 0.0, 0.0]],
        fe_nodes: true,
        node_ids: Vec::new(),
        cells: vec![line(0, 2), line(2, 1)],
        modes: 0,
        rotation: RotationName::Quaternion,
        interfaces: Vec::new(),
        translation_only: Vec::new(),
        rotating: Vec::new(),
        stress: Err(NO_STRESS.into()),
    }
}

/// Why a superelement has no stress output.
pub const NO_STRESS: &str =
    "a superelement has no stress output (its FE mesh is not kept in the model)";
