//! `type = "point_mass"` bodies: a particle (mass only, three translations), and the checks that
//! keep rotational couplings off it (it has no rotations: a joint locking rotations at its frame,
//! a torque on it or a rotational force element would act on nothing there and silently change
//! what the other body does).

use crate::bodies::{box_corners, BodyGeometry, BuiltElement};
use crate::compile::Ctx;
use crate::error::SimError;
use crate::schema::BodySpec;
use crate::units::Dimension;
use flexmbs_core::point_mass::PointMass;
use flexmbs_fe::reduction::Cell;
use flexmbs_fe::ElementKind;
use nalgebra::Vector3;

/// Edge of the cube drawn for a point mass in the animation when `box` is not given (m).
pub const DEFAULT_POINT_MASS_BOX: f64 = 0.02;

/// The particle of a `point_mass` body (`mass`, optional `box` for the animation).
pub(crate) fn point_mass_body(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
) -> Result<(BuiltElement, BodyGeometry), SimError> {
    let mass_q = b
        .mass
        .as_ref()
        .ok_or_else(|| ctx.err(p, "a point mass needs `mass`"))?;
    let mass = ctx.q(mass_q, Dimension::Mass, &format!("{p}.mass"))?;
    if !(mass > 0.0 && mass.is_finite()) {
        let msg = format!("mass must be > 0, got {mass} kg");
        return Err(ctx.err(&format!("{p}.mass"), msg));
    }
    let size = match &b.box_size {
        Some(s) => {
            let v = ctx.vec3(s, Dimension::Length, &format!("{p}.box"))?;
            if !v.iter().all(|x| *x > 0.0 && x.is_finite()) {
                return Err(ctx.err(&format!("{p}.box"), "box edges must be > 0"));
            }
            v
        }
        None => Vector3::repeat(DEFAULT_POINT_MASS_BOX),
    };
    let geometry = BodyGeometry {
        points: box_corners(&size),
        fe_nodes: false,
        node_ids: Vec::new(),
        cells: vec![Cell {
            kind: ElementKind::Hex8,
            nodes: (0..8).collect(),
        }],
        modes: 0,
        rotation: b.rotation,
        interfaces: Vec::new(),
        translation_only: Vec::new(),
        rotating: Vec::new(),
        stress: Err(crate::stress::RIGID_BODY.into()),
    };
    Ok((BuiltElement::PointMass(PointMass::new(mass)), geometry))
}

/// What would couple to a point mass's (non-existent) rotation.
pub(crate) enum RotationalUse<'a> {
    /// A joint (named) that locks a rotation, directly or through an angle drive.
    Joint(&'a str),
    /// A torque load.
    Torque,
    /// A force element (named) with rotational stiffness, damping or a rotational joint axis.
    Force(&'a str),
}

/// Refuses `user` at frame `frame` of the point-mass body `body`, located at `path`.
pub(crate) fn refuse_rotation_on_point_mass(
    ctx: &Ctx,
    path: &str,
    user: RotationalUse,
    frame: &str,
    body: &str,
) -> Result<(), SimError> {
    let (lead, fix) = match user {
        RotationalUse::Joint(j) => (
            format!("joint `{j}` locks rotations"),
            "use `spherical`, or `generic` with translations only (e.g. `locked = [\"ty\", \"tz\"]` \
             for a slider along x)",
        ),
        RotationalUse::Torque => (
            "a torque acts".to_string(),
            "apply forces, or model the body as `rigid` with its inertia",
        ),
        RotationalUse::Force(f) => (
            format!("force element `{f}` acts on rotations"),
            "use translational stiffness and damping only, or a `spring-damper` load",
        ),
    };
    Err(ctx.err(
        path,
        format!(
            "{lead} at frame `{frame}` of the point mass `{body}`, which has no rotations (its \
             frames keep their axes); this would act on the other body alone: {fix}"
        ),
    ))
}
