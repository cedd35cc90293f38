//! `[[contact]]` tables of a model file: two contours on frames and the contact law
//! (`docs/model-file.md`, "`[[contact]]`"), compiled into [`flexmbs_core::contact::Contact`]s.
//! Contacts are solved by the `moreau` solver only.

use crate::compile::Ctx;
use crate::error::SimError;
use crate::units::{Dimension, Quantity};
use flexmbs_core::contact::{
    CircleContour, Contact, ContactLaw, Contour, Friction, NormalLaw, PlaneContour, PointContour,
    SphereContour, TangentDirections,
};
use flexmbs_core::contour_source::ContourNodes;
use flexmbs_core::{FrameId, ModelSpec};
use serde::Deserialize;

/// What a flexible contour needs of its body: the body's reference (floating) frame, its
/// contour nodes (an ffr body's FE nodes and modes, a superelement's FE nodes and
/// Craig-Bampton basis) and their ids and positions.
pub(crate) struct FlexibleOwner<'a> {
    /// The body's reference frame.
    pub frame: FrameId,
    /// The nodes (undeformed positions, shape vectors).
    pub body: &'a dyn ContourNodes,
    /// Node ids (external), one per node of `body`.
    pub node_ids: &'a [u64],
    /// Node positions (body axes), one per node of `body`.
    pub points: &'a [[f64; 3]],
}

/// Resolves a body name at a key path to its [`FlexibleOwner`] (an error for unknown and rigid
/// bodies).
pub(crate) type OwnerFn<'a> = dyn Fn(&str, String) -> Result<FlexibleOwner<'a>, SimError> + 'a;

/// `[[contact]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Name.
    pub name: String,
    /// First contour.
    pub a: ContourSpec,
    /// Second contour.
    pub b: ContourSpec,
    /// Normal law.
    pub normal: NormalName,
    /// Coefficient of restitution (unilateral), default 0.
    pub restitution: Option<f64>,
    /// Stiffness (regularized).
    pub stiffness: Option<Quantity>,
    /// Damping (regularized), default 0.
    pub damping: Option<Quantity>,
    /// Friction law, default none.
    pub friction: Option<FrictionName>,
    /// Friction coefficient.
    pub mu: Option<f64>,
    /// Slip velocity of full friction (regularized friction).
    pub slip_velocity: Option<Quantity>,
    /// Friction directions, default spatial.
    pub directions: Option<DirectionsName>,
    /// Bilateral contact on a curve: the frame's axes also follow the contour frame (default
    /// false; `crate::guides`).
    pub rotations: Option<bool>,
}

/// A contour: `{ type, frame, radius }` (rigid) or `{ type, body, face | nodes, ... }`
/// (flexible: neutral contours of an ffr body).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContourSpec {
    /// Contour type.
    #[serde(rename = "type")]
    pub kind: ContourName,
    /// Frame the contour is fixed to (rigid contours).
    pub frame: Option<String>,
    /// Radius (sphere, circle; curve: the tube radius, default 0).
    pub radius: Option<Quantity>,
    /// The ffr body of a flexible contour.
    pub body: Option<String>,
    /// Surface: a face of the body's bounding box, `xmin` ... `zmax`.
    pub face: Option<String>,
    /// Surface: the node index matrix (rows of FE node ids); curve, band: ordered node ids.
    pub nodes: Option<NodesSpec>,
    /// Curve, band: instead of `nodes`, the FE nodes on the segment between two points (body
    /// axes, model length unit), ordered from the first.
    pub through: Option<[[f64; 3]; 2]>,
    /// Band: width.
    pub width: Option<Quantity>,
    /// Band: offset along the normal, default 0.
    pub offset: Option<Quantity>,
    /// Band: the normal direction in body axes.
    pub normal: Option<[f64; 3]>,
    /// Surface: reverse the automatic outward normal.
    pub flip_normal: Option<bool>,
}

/// FE node ids of a flexible contour.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum NodesSpec {
    /// Ordered list (curve, band).
    Line(Vec<u64>),
    /// Rows of the node index matrix (surface).
    Grid(Vec<Vec<u64>>),
}

/// Contour types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContourName {
    /// Frame origin.
    Point,
    /// Sphere at the frame origin.
    Sphere,
    /// Plane through the origin, normal = frame z.
    Plane,
    /// Circle in the frame's x-y plane.
    Circle,
    /// 2D neutral NURBS contour of an ffr body.
    Surface,
    /// 1D neutral NURBS contour of an ffr body.
    Curve,
    /// Flexible band on a 1D neutral contour.
    Band,
}

/// Normal laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NormalName {
    /// Set-valued unilateral with Newton impact.
    Unilateral,
    /// Set-valued bilateral.
    Bilateral,
    /// Spring-damper penalty.
    Regularized,
}

/// Friction laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionName {
    /// Frictionless.
    None,
    /// Set-valued Coulomb.
    Coulomb,
    /// Regularized Coulomb.
    Regularized,
}

/// Friction directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DirectionsName {
    /// `t_1` only.
    Planar,
    /// Both tangents.
    Spatial,
}

/// Adds the contacts of the file to `spec`; `frame` resolves a frame name at a key path.
pub(crate) fn add_contacts(
    ctx: &Ctx,
    contacts: &[ContactSpec],
    frame: &dyn Fn(&str, String) -> Result<FrameId, SimError>,
    owner: &OwnerFn<'_>,
    spec: &mut ModelSpec,
) -> Result<(), SimError> {
    for (i, c) in contacts.iter().enumerate() {
        let p = format!("contact[{i}]");
        if crate::guides::is_guide(c) {
            crate::guides::add_guide(ctx, c, &p, frame, owner, spec)?;
            continue;
        }
        if c.rotations.is_some() {
            return Err(ctx.err(
                &format!("{p}.rotations"),
                "only a bilateral contact on a curve has `rotations`",
            ));
        }
        let a = any_contour(ctx, &c.a, &format!("{p}.a"), frame, owner)?;
        let b = any_contour(ctx, &c.b, &format!("{p}.b"), frame, owner)?;
        let law = law(ctx, c, &p)?;
        spec.add_contact(Contact {
            name: c.name.clone(),
            contour_a: a,
            contour_b: b,
            law,
        });
    }
    Ok(())
}

/// Per contact of the compiled `model` (the file's contacts without the guides, in order):
/// whether the model swapped its contours into the engine's pair order (`a` of the engine is the
/// file's `b`).
pub(crate) fn swapped_contacts(contacts: &[ContactSpec], model: &flexmbs_core::Model) -> Vec<bool> {
    use flexmbs_core::contact::ContourKind as K;
    let kind = |c: &ContourSpec| match c.kind {
        ContourName::Point => K::Point,
        ContourName::Sphere => K::Sphere,
        ContourName::Plane => K::Plane,
        ContourName::Circle => K::Circle,
        ContourName::Surface => K::NeutralSurface,
        ContourName::Curve => K::NeutralCurve,
        ContourName::Band => K::FlexibleBand,
    };
    contacts
        .iter()
        .filter(|c| !crate::guides::is_guide(c))
        .zip(&model.contacts)
        .map(|(c, m)| kind(&c.a) != m.contour_a.kind())
        .collect()
}

fn any_contour(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    frame: &dyn Fn(&str, String) -> Result<FrameId, SimError>,
    owner: &OwnerFn<'_>,
) -> Result<Box<dyn Contour>, SimError> {
    if matches!(
        c.kind,
        ContourName::Surface | ContourName::Curve | ContourName::Band
    ) {
        return crate::flexible_contours::flexible_contour(ctx, c, p, owner);
    }
    let flexible_keys = [
        ("body", c.body.is_some()),
        ("face", c.face.is_some()),
        ("nodes", c.nodes.is_some()),
        ("through", c.through.is_some()),
        ("width", c.width.is_some()),
        ("offset", c.offset.is_some()),
        ("normal", c.normal.is_some()),
        ("flip_normal", c.flip_normal.is_some()),
    ];
    if let Some((key, _)) = flexible_keys.iter().find(|k| k.1) {
        return Err(ctx.err(
            &format!("{p}.{key}"),
            "only flexible contours (surface, curve, band) have this key",
        ));
    }
    let name = c
        .frame
        .as_ref()
        .ok_or_else(|| ctx.err(p, "a rigid contour needs `frame`"))?;
    rigid_contour(ctx, c, p, frame(name, format!("{p}.frame"))?)
}

fn rigid_contour(
    ctx: &Ctx,
    c: &ContourSpec,
    p: &str,
    f: FrameId,
) -> Result<Box<dyn Contour>, SimError> {
    let radius = || -> Result<f64, SimError> {
        let q = c.radius.as_ref().ok_or_else(|| {
            ctx.err(
                p,
                format!("a {:?} contour needs `radius`", c.kind).to_lowercase(),
            )
        })?;
        let r = ctx.q(q, Dimension::Length, &format!("{p}.radius"))?;
        if r <= 0.0 {
            return Err(ctx.err(&format!("{p}.radius"), format!("must be > 0, got {r} m")));
        }
        Ok(r)
    };
    let uses_radius = matches!(c.kind, ContourName::Sphere | ContourName::Circle);
    if !uses_radius && c.radius.is_some() {
        return Err(ctx.err(
            &format!("{p}.radius"),
            "only sphere and circle contours have a radius",
        ));
    }
    Ok(match c.kind {
        ContourName::Point => Box::new(PointContour { frame: f }),
        ContourName::Plane => Box::new(PlaneContour { frame: f }),
        ContourName::Sphere => Box::new(SphereContour {
            frame: f,
            radius: radius()?,
        }),
        ContourName::Circle => Box::new(CircleContour {
            frame: f,
            radius: radius()?,
        }),
        ContourName::Surface | ContourName::Curve | ContourName::Band => {
            unreachable!("flexible contours are built by flexible_contour")
        }
    })
}

fn law(ctx: &Ctx, c: &ContactSpec, p: &str) -> Result<ContactLaw, SimError> {
    let present = [
        ("restitution", c.restitution.is_some()),
        ("stiffness", c.stiffness.is_some()),
        ("damping", c.damping.is_some()),
        ("mu", c.mu.is_some()),
        ("slip_velocity", c.slip_velocity.is_some()),
        ("directions", c.directions.is_some()),
    ];
    let friction = c.friction.unwrap_or(FrictionName::None);
    let mut allowed = match c.normal {
        NormalName::Unilateral => vec!["restitution"],
        NormalName::Bilateral => vec![],
        NormalName::Regularized => vec!["stiffness", "damping"],
    };
    match friction {
        FrictionName::None => {}
        FrictionName::Coulomb => allowed.extend(["mu", "directions"]),
        FrictionName::Regularized => allowed.extend(["mu", "directions", "slip_velocity"]),
    }
    let what = format!(
        "this normal law and friction ({:?}, {friction:?})",
        c.normal
    )
    .to_lowercase();
    ctx.only(p, &what, &present, &allowed)?;
    Ok(ContactLaw {
        normal: normal_law(ctx, c, p)?,
        friction: friction_law(ctx, c, p, friction)?,
    })
}

/// A quantity >= 0 at `p.key` (absent: 0, or an error at `p` if `required`).
fn nonneg(
    ctx: &Ctx,
    q: &Option<Quantity>,
    dim: Dimension,
    p: &str,
    key: &str,
    required: bool,
) -> Result<f64, SimError> {
    let path = format!("{p}.{key}");
    match q {
        None if required => Err(ctx.err(p, format!("needs `{key}`"))),
        None => Ok(0.0),
        Some(q) => {
            let v = ctx.q(q, dim, &path)?;
            if v < 0.0 {
                return Err(ctx.err(&path, format!("must be >= 0, got {v}")));
            }
            Ok(v)
        }
    }
}

fn normal_law(ctx: &Ctx, c: &ContactSpec, p: &str) -> Result<NormalLaw, SimError> {
    Ok(match c.normal {
        NormalName::Unilateral => {
            let e = c.restitution.unwrap_or(0.0);
            if !(0.0..=1.0).contains(&e) {
                let path = format!("{p}.restitution");
                return Err(ctx.err(&path, format!("must be in [0, 1], got {e}")));
            }
            NormalLaw::Unilateral { restitution: e }
        }
        NormalName::Bilateral => NormalLaw::Bilateral,
        NormalName::Regularized => {
            let stiffness = nonneg(
                ctx,
                &c.stiffness,
                Dimension::Stiffness,
                p,
                "stiffness",
                true,
            )?;
            if stiffness == 0.0 {
                return Err(ctx.err(&format!("{p}.stiffness"), "must be > 0"));
            }
            let damping = nonneg(ctx, &c.damping, Dimension::Damping, p, "damping", false)?;
            NormalLaw::Regularized { stiffness, damping }
        }
    })
}

fn friction_law(
    ctx: &Ctx,
    c: &ContactSpec,
    p: &str,
    friction: FrictionName,
) -> Result<Friction, SimError> {
    let directions = match c.directions.unwrap_or(DirectionsName::Spatial) {
        DirectionsName::Planar => TangentDirections::Planar,
        DirectionsName::Spatial => TangentDirections::Spatial,
    };
    let mu = || -> Result<f64, SimError> {
        let mu = c.mu.ok_or_else(|| ctx.err(p, "friction needs `mu`"))?;
        if !(mu >= 0.0 && mu.is_finite()) {
            return Err(ctx.err(&format!("{p}.mu"), format!("must be >= 0, got {mu}")));
        }
        Ok(mu)
    };
    Ok(match friction {
        FrictionName::None => Friction::None,
        FrictionName::Coulomb => Friction::Coulomb {
            mu: mu()?,
            directions,
        },
        FrictionName::Regularized => {
            if c.normal != NormalName::Regularized {
                let path = format!("{p}.friction");
                return Err(ctx.err(
                    &path,
                    "regularized friction needs `normal = \"regularized\"`",
                ));
            }
            let v = nonneg(
                ctx,
                &c.slip_velocity,
                Dimension::Velocity,
                p,
                "slip_velocity",
                true,
            )?;
            if v == 0.0 {
                return Err(ctx.err(&format!("{p}.slip_velocity"), "must be > 0"));
            }
            Friction::Regularized {
                mu: mu()?,
                slip_velocity: v,
                directions,
            }
        }
    })
}

/// Which solver a model's contacts need: the `moreau` solver takes every law;
/// `generalized-alpha` and `statics` (also as `solver.initial = "static"`) take regularized
/// contacts only (normal `regularized`, friction none or `regularized`: forces with their tangent
/// in the Newton iteration); `dopri5` takes none. Guides (bilateral contacts on a flexible
/// contour: constraints) go with every solver. Err: located at the first contact the solver
/// cannot take.
pub(crate) fn check_contact_solver(
    ctx: &Ctx,
    contacts: &[ContactSpec],
    solver: &crate::config::SolverConfig,
    static_start: bool,
) -> Result<(), SimError> {
    use crate::config::SolverConfig;
    if contacts.is_empty() || matches!(solver, SolverConfig::Moreau { .. }) && !static_start {
        return Ok(());
    }
    if matches!(solver, SolverConfig::Dopri5 { .. })
        && !contacts.iter().all(crate::guides::is_guide)
    {
        return Err(ctx.err(
            "solver.type",
            "the model has contacts: they are solved by `type = \"moreau\"` (any law) or \
             `type = \"generalized-alpha\"` and `\"statics\"` (regularized laws)",
        ));
    }
    for (i, c) in contacts.iter().enumerate() {
        // a bilateral contact on a flexible contour is a guide: a constraint every solver takes
        if crate::guides::is_guide(c) {
            continue;
        }
        if c.normal != NormalName::Regularized {
            return Err(ctx.err(
                &format!("contact[{i}].normal"),
                format!(
                    "contact `{}`: a set-valued law (`unilateral`, `bilateral`) needs \
                     `solver.type = \"moreau\"` (without a static start); `generalized-alpha` \
                     and `statics` take `normal = \"regularized\"`",
                    c.name
                ),
            ));
        }
        if c.friction == Some(FrictionName::Coulomb) {
            return Err(ctx.err(
                &format!("contact[{i}].friction"),
                format!(
                    "contact `{}`: set-valued Coulomb friction needs `solver.type = \
                     \"moreau\"`; `generalized-alpha` and `statics` take `friction = \
                     \"regularized\"`",
                    c.name
                ),
            ));
        }
    }
    Ok(())
}
