//! Bilateral contacts on a curve: a `[[contact]]` with `normal = "bilateral"` between a `curve`
//! (the 1D neutral contour of an ffr body, e.g. a beam's neutral axis) and a `point` or `sphere`
//! becomes a guide ([`flexmbs_core::contact::CurveGuide`]): the point (the sphere's centre) is
//! kept on the curve by two constraint rows along the contour frame's normals, and with
//! `rotations = true` the frame's axes follow the contour frame `(t, n_1, n_2)` (3 more rows).
//! `a.normal` (body axes) is the reference direction of `n_1`; by default the body axis least
//! aligned with the curve's chord. A bilateral contact on a surface or band is refused.

use crate::compile::Ctx;
use crate::contacts::{ContactSpec, ContourName, ContourSpec, NormalName, OwnerFn};
use crate::error::SimError;
use flexmbs_core::contact::{CurveGuide, NeutralCurve};
use flexmbs_core::{FrameId, ModelSpec};
use nalgebra::Vector3;

/// Whether contact `c` is a guide: bilateral with a flexible contour on either side (surfaces
/// and bands are then refused by [`add_guide`]).
pub(crate) fn is_guide(c: &ContactSpec) -> bool {
    let flexible = |s: &ContourSpec| {
        matches!(
            s.kind,
            ContourName::Curve | ContourName::Surface | ContourName::Band
        )
    };
    c.normal == NormalName::Bilateral && (flexible(&c.a) || flexible(&c.b))
}

/// Adds the guide of contact `c` (at key path `p`) to `spec`.
pub(crate) fn add_guide(
    ctx: &Ctx,
    c: &ContactSpec,
    p: &str,
    frame: &dyn Fn(&str, String) -> Result<FrameId, SimError>,
    owner: &OwnerFn<'_>,
    spec: &mut ModelSpec,
) -> Result<(), SimError> {
    let (curve_spec, slider_spec, cp, sp) = if c.a.kind == ContourName::Curve {
        (&c.a, &c.b, format!("{p}.a"), format!("{p}.b"))
    } else if c.b.kind == ContourName::Curve {
        (&c.b, &c.a, format!("{p}.b"), format!("{p}.a"))
    } else {
        let side = if matches!(c.a.kind, ContourName::Surface | ContourName::Band) {
            "a"
        } else {
            "b"
        };
        return Err(ctx.err(
            &format!("{p}.{side}.type"),
            "a bilateral contact on a flexible contour needs a `curve` (the point is kept on a \
             neutral axis); surfaces and bands have no bilateral law",
        ));
    };
    let present = [
        ("restitution", c.restitution.is_some()),
        ("stiffness", c.stiffness.is_some()),
        ("damping", c.damping.is_some()),
        ("friction", c.friction.is_some()),
        ("mu", c.mu.is_some()),
        ("slip_velocity", c.slip_velocity.is_some()),
        ("directions", c.directions.is_some()),
    ];
    ctx.only(p, "a bilateral contact on a curve", &present, &[])?;
    if !matches!(slider_spec.kind, ContourName::Point | ContourName::Sphere) {
        return Err(ctx.err(
            &format!("{sp}.type"),
            "a bilateral contact on a curve keeps a `point` or the centre of a `sphere` on it",
        ));
    }
    let slider_name = slider_spec
        .frame
        .as_ref()
        .ok_or_else(|| ctx.err(&sp, "a point or sphere contour needs `frame`"))?;
    let slider = frame(slider_name, format!("{sp}.frame"))?;
    if curve_spec.radius.is_some() {
        return Err(ctx.err(
            &format!("{cp}.radius"),
            "a bilateral contact keeps the point on the curve itself: no radius",
        ));
    }
    let plain = ContourSpec {
        normal: None,
        ..curve_spec.clone()
    };
    let contour = crate::flexible_contours::flexible_contour(ctx, &plain, &cp, owner)?;
    let curve = contour
        .as_any()
        .downcast_ref::<NeutralCurve>()
        .expect("a curve contour is a NeutralCurve")
        .clone();
    let normal = match curve_spec.normal {
        Some(n) => Vector3::from(n),
        None => least_aligned_axis(&curve),
    };
    spec.add_guide(CurveGuide::new(
        &c.name,
        curve,
        slider,
        normal,
        c.rotations.unwrap_or(false),
    ));
    Ok(())
}

/// The body axis least aligned with the undeformed chord of `curve` (first to last node).
fn least_aligned_axis(curve: &NeutralCurve) -> Vector3<f64> {
    let contour = curve.contour();
    let d = contour
        .state()
        .and_then(|mut s| {
            let (lo, hi) = s.curve.domain();
            Ok(contour.fields(&mut s, hi)?[0] - contour.fields(&mut s, lo)?[0])
        })
        .unwrap_or_else(|_| Vector3::x());
    let a = d.map(f64::abs);
    if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    }
}
