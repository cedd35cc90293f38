//! Flexible contours: neutral NURBS contours of flexible bodies in contact pairs (seed 000
//! §3.2.2, §3.3, §4.4).
//!
//! A flexible contour wraps a neutral contour of [`crate::ffr::contour`] and is attached to its
//! body's reference (floating) frame. Its body's evaluated state is reached only through
//! [`NeutralContourSource`] ([`ElementScratch::contour_source`]): any body type that supplies
//! one (FFR bodies, superelements) carries these contours. Per contact evaluation its pair
//! function
//! 1. updates the deformed contour from the body's evaluated field coordinates (once, O(n_ctrl
//!    n_q), no solve),
//! 2. transforms the other contour's point into body axes, `x̄ = Aᵀ (x - R)`, and finds its
//!    normal projection on the deformed contour by the hierarchical-territory search (warm
//!    start from the last solution, full search on failure; seed Alg. 4-6),
//! 3. evaluates the contact point as a material point of the body: position, velocity, outward
//!    normal and tangents (3.27)-(3.29), and its Jacobian `J_C` (the body's
//!    [`NeutralContourSource::point_jacobian`]; FFR: `[I, -A ū~ H, A Φ(eta, xi)]`) into the
//!    contour's scratch, from which [`Contour::add_direction`] builds the columns of
//!    `W_N`, `W_T`.
//!
//! A point with no normal projection (beyond an open edge) has no contact point: the geometry
//! is [`ContactGeometry::OPEN`] (infinite gap).
//!
//! [`FlexibleBand`] is a band of given width on a 1D neutral contour (a beam's top centre
//! line), offset along a normal that is the body-axes direction `normal` made perpendicular to
//! the deformed centre line. Its contact point moves with the centre line point and the body's
//! rotation; the section's own elastic rotation (torsion of the beam about the line) is not
//! represented: a solid body's nodes carry no rotations to interpolate.

use super::contour::{Contour, ContourKind, ContourScratch};
use super::pair::{orthonormal_tangents, radius, ContactGeometry, Side};
use super::unit_or_zero;
use crate::contour_source::NeutralContourSource;
use crate::element::{ElementScratch, FrameKinematics};
use crate::ffr::contour::{
    ContourError, CurveContourState, FfrCurveContour, FfrSurfaceContour, SurfaceContourState,
};
use crate::ids::FrameId;
use crate::model::Model;
use faer::Mat;
use flexmbs_nurbs::{CurveSearch, SearchGrid, SearchSettings, SurfaceSearch};
use nalgebra::Vector3;
use std::any::Any;
use std::sync::Arc;

/// A 2D neutral contour of a flexible body as a contact contour (kind
/// [`ContourKind::NeutralSurface`]); pairs with points and spheres.
#[derive(Debug, Clone)]
pub struct NeutralSurface {
    /// The body's reference frame.
    pub frame: FrameId,
    contour: Arc<FfrSurfaceContour>,
    prototype: Arc<SurfaceWork>,
}

/// The per-contact buffers of a [`NeutralSurface`].
#[derive(Debug, Clone)]
struct SurfaceWork {
    state: SurfaceContourState,
    search: SurfaceSearch,
    /// `J_C` at the last contact point (3 x n_u of the body).
    jac: Mat<f64>,
}

impl NeutralSurface {
    /// `contour` (built from the body the frame `frame` belongs to) with the contact search
    /// on a coarse grid through the contour's nodes (seed §4.5 `setNodes`) and default Newton
    /// settings.
    pub fn new(frame: FrameId, contour: FfrSurfaceContour) -> Result<Self, ContourError> {
        let interp = contour.interpolator();
        let grids = [
            SearchGrid::Nodes(interp.eta().params().to_vec()),
            SearchGrid::Nodes(interp.xi().params().to_vec()),
        ];
        Self::with_search(frame, contour, grids, SearchSettings::default())
    }

    /// As [`Self::new`] with the coarse search grids `[eta, xi]` and Newton settings given.
    pub fn with_search(
        frame: FrameId,
        contour: FfrSurfaceContour,
        grids: [SearchGrid; 2],
        settings: SearchSettings,
    ) -> Result<Self, ContourError> {
        let state = contour.state()?;
        let search = state.new_search(grids, settings)?;
        let jac = Mat::zeros(3, contour.num_velocities());
        Ok(Self {
            frame,
            contour: Arc::new(contour),
            prototype: Arc::new(SurfaceWork { state, search, jac }),
        })
    }

    /// The neutral contour.
    pub fn contour(&self) -> &FfrSurfaceContour {
        &self.contour
    }
}

/// A 1D neutral contour of a flexible body as a contact contour (kind
/// [`ContourKind::NeutralCurve`]): a tube of `radius` (0: the line itself) around the curve;
/// pairs with points and spheres (normal from the curve to the point).
#[derive(Debug, Clone)]
pub struct NeutralCurve {
    /// The body's reference frame.
    pub frame: FrameId,
    /// Radius of the tube around the curve (>= 0).
    pub radius: f64,
    contour: Arc<FfrCurveContour>,
    prototype: Arc<CurveWork>,
}

/// The per-contact buffers of a [`NeutralCurve`] or [`FlexibleBand`].
#[derive(Debug, Clone)]
struct CurveWork {
    state: CurveContourState,
    search: CurveSearch,
    jac: Mat<f64>,
}

impl NeutralCurve {
    /// `contour` (of the body of `frame`) with a coarse search grid through its nodes.
    pub fn new(
        frame: FrameId,
        contour: FfrCurveContour,
        radius: f64,
    ) -> Result<Self, ContourError> {
        let grid = SearchGrid::Nodes(contour.interpolator().params().to_vec());
        let state = contour.state()?;
        let search = state.new_search(grid, SearchSettings::default())?;
        let jac = Mat::zeros(3, contour.num_velocities());
        Ok(Self {
            frame,
            radius,
            contour: Arc::new(contour),
            prototype: Arc::new(CurveWork { state, search, jac }),
        })
    }

    /// The neutral contour.
    pub fn contour(&self) -> &FfrCurveContour {
        &self.contour
    }
}

/// A band of `width` on a 1D neutral contour, offset by `offset` along its normal (kind
/// [`ContourKind::FlexibleBand`], seed §4.4): the normal at a curve point is the body-axes
/// direction `normal` made perpendicular to the deformed tangent (module documentation for
/// what it neglects); pairs with points and spheres.
#[derive(Debug, Clone)]
pub struct FlexibleBand {
    /// The centre line.
    pub curve: NeutralCurve,
    /// Width (> 0): contact only within `width / 2` of the centre line, across it.
    pub width: f64,
    /// Offset of the band from the centre line along the normal.
    pub offset: f64,
    /// The outward normal's direction in body axes (not along the curve).
    pub normal: Vector3<f64>,
}

fn source(body: Option<&ElementScratch>) -> &dyn NeutralContourSource {
    body.and_then(ElementScratch::contour_source)
        .expect("flexible contour on a contour-source body (checked when the model was compiled)")
}

/// The owner supplies a contour source with the contour's field coordinates and velocity
/// coordinates.
pub(crate) fn check_source_owner(
    owner: &ElementScratch,
    nq: usize,
    nu: usize,
) -> Result<(), String> {
    let Some(s) = owner.contour_source() else {
        return Err(
            "its body supplies no neutral contours (they need a flexible body with a \
                    floating frame: an FFR body or a superelement)"
                .into(),
        );
    };
    let (q, u) = (s.field_coordinates().len(), s.num_velocities());
    if q != nq {
        return Err(format!(
            "the contour was built with {nq} field coordinates (modes), its body has {q}"
        ));
    }
    if u != nu {
        return Err(format!(
            "the contour was built for {nu} velocity coordinates, its body has {u}"
        ));
    }
    Ok(())
}

/// `scale d^T J_C` into the body's columns of `out`.
fn add_jacobian_direction(
    model: &Model,
    frame: FrameId,
    jac: &Mat<f64>,
    d: &Vector3<f64>,
    scale: f64,
    out: &mut [f64],
) {
    let cols = model.frame_cols(frame);
    for j in 0..cols.len() {
        let s = d[0] * jac[(0, j)] + d[1] * jac[(1, j)] + d[2] * jac[(2, j)];
        out[cols.global(j)] += scale * s;
    }
}

macro_rules! flexible_contour_common {
    ($kind:expr, $work:ty) => {
        fn kind(&self) -> ContourKind {
            $kind
        }
        fn as_any(&self) -> &dyn Any {
            self
        }
        fn is_flexible(&self) -> bool {
            true
        }
        fn add_direction(
            &self,
            model: &Model,
            _frame: &FrameKinematics,
            scratch: &ContourScratch,
            _point: &Vector3<f64>,
            d: &Vector3<f64>,
            scale: f64,
            out: &mut [f64],
        ) {
            let jac = &scratch.get::<$work>().jac;
            add_jacobian_direction(model, self.frame(), jac, d, scale, out);
        }
    };
}

impl Contour for NeutralSurface {
    flexible_contour_common!(ContourKind::NeutralSurface, SurfaceWork);
    fn frame(&self) -> FrameId {
        self.frame
    }
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }
    fn check_owner(&self, owner: &ElementScratch) -> Result<(), String> {
        check_source_owner(
            owner,
            self.contour.num_modes(),
            self.contour.num_velocities(),
        )
    }
    fn new_scratch(&self) -> ContourScratch {
        ContourScratch::new(self.prototype.as_ref().clone())
    }
}

impl Contour for NeutralCurve {
    flexible_contour_common!(ContourKind::NeutralCurve, CurveWork);
    fn frame(&self) -> FrameId {
        self.frame
    }
    fn validate(&self) -> Result<(), String> {
        if self.radius >= 0.0 && self.radius.is_finite() {
            Ok(())
        } else {
            Err(format!("radius {} must be finite and >= 0", self.radius))
        }
    }
    fn check_owner(&self, owner: &ElementScratch) -> Result<(), String> {
        check_source_owner(
            owner,
            self.contour.num_modes(),
            self.contour.num_velocities(),
        )
    }
    fn new_scratch(&self) -> ContourScratch {
        ContourScratch::new(self.prototype.as_ref().clone())
    }
}

impl Contour for FlexibleBand {
    flexible_contour_common!(ContourKind::FlexibleBand, CurveWork);
    fn frame(&self) -> FrameId {
        self.curve.frame
    }
    fn validate(&self) -> Result<(), String> {
        if !(self.width > 0.0 && self.width.is_finite()) {
            return Err(format!("width {} must be finite and > 0", self.width));
        }
        if !self.offset.is_finite() {
            return Err(format!("offset {} must be finite", self.offset));
        }
        if !(self.normal.norm() > 0.0 && self.normal.iter().all(|x| x.is_finite())) {
            return Err("the normal direction must be a finite non-zero vector".into());
        }
        Ok(())
    }
    fn check_owner(&self, owner: &ElementScratch) -> Result<(), String> {
        check_source_owner(
            owner,
            self.curve.contour.num_modes(),
            self.curve.contour.num_velocities(),
        )
    }
    fn new_scratch(&self) -> ContourScratch {
        self.curve.new_scratch()
    }
}

/// Neutral surface `a` and point or sphere `b` (radius `r_b`): `g_N = n^T (c_b - r_C) - r_b`
/// (3.4) at the normal projection `C` of the centre `c_b` (seed Alg. 6).
pub(super) fn surface_sphere(a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    let surf = a
        .contour
        .as_any()
        .downcast_ref::<NeutralSurface>()
        .expect("dispatch table: a neutral surface");
    let s = source(a.body);
    let w = a.scratch.get_mut::<SurfaceWork>();
    let (r, r_dot) = (a.frame.position, a.frame.velocity);
    let c = b.frame.position;
    if surf.contour.update(s, &mut w.state).is_err() {
        return ContactGeometry::OPEN;
    }
    let x = s.frame_rotation().transpose() * (c - r);
    let Some(p) = w.state.project(&mut w.search, &x) else {
        return ContactGeometry::OPEN;
    };
    let Ok(pt) = surf.contour.point(&r, &r_dot, s, &mut w.state, p.eta, p.xi) else {
        return ContactGeometry::OPEN;
    };
    if surf
        .contour
        .jacobian_translation(s, &mut w.state, p.eta, p.xi, w.jac.as_mut())
        .is_err()
    {
        return ContactGeometry::OPEN;
    }
    let rb = radius(b.contour);
    let n = pt.normal;
    ContactGeometry {
        gap: n.dot(&(c - pt.position)) - rb,
        point_a: pt.position,
        point_b: c - rb * n,
        normal: n,
        tangents: pt.tangents,
        velocity_a: pt.velocity,
        coordinates: [p.eta, p.xi, 0.0, 0.0],
        ..ContactGeometry::ZERO
    }
}

/// The projection of `c` (global) on a neutral curve: the curve point's kinematics, with its
/// Jacobian in the work buffers. `None`: no normal projection.
fn curve_projection(
    curve: &NeutralCurve,
    a: &mut Side<'_>,
    c: &Vector3<f64>,
) -> Option<(crate::ffr::contour::ContourPoint, f64)> {
    let s = source(a.body);
    let w = a.scratch.get_mut::<CurveWork>();
    let (r, r_dot) = (a.frame.position, a.frame.velocity);
    curve.contour.update(s, &mut w.state).ok()?;
    let x = s.frame_rotation().transpose() * (c - r);
    let p = w.state.project(&mut w.search, &x)?;
    let pt = curve
        .contour
        .point(&r, &r_dot, s, &mut w.state, p.eta)
        .ok()?;
    curve
        .contour
        .jacobian_translation(s, &mut w.state, p.eta, w.jac.as_mut())
        .ok()?;
    Some((pt, p.eta))
}

/// Neutral curve `a` (a tube of radius `r_a`) and point or sphere `b`: `n` from the curve point
/// to the centre, `g_N = |c_b - r_C| - r_a - r_b`, `t_1` the curve tangent.
pub(super) fn curve_sphere(mut a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    let curve = a
        .contour
        .as_any()
        .downcast_ref::<NeutralCurve>()
        .expect("dispatch table: a neutral curve");
    let c = b.frame.position;
    let Some((pt, eta)) = curve_projection(curve, &mut a, &c) else {
        return ContactGeometry::OPEN;
    };
    let d = c - pt.position;
    let dist = d.norm();
    let t = pt.tangents[0];
    let n = if dist > 0.0 {
        d / dist
    } else {
        orthonormal_tangents(&t)[0]
    };
    let (ra, rb) = (curve.radius, radius(b.contour));
    let s = source(a.body);
    let w = a.scratch.get_mut::<CurveWork>();
    add_offset_jacobian(s, &(ra * n), &mut w.jac);
    ContactGeometry {
        gap: dist - ra - rb,
        point_a: pt.position + ra * n,
        point_b: c - rb * n,
        normal: n,
        tangents: [t, unit_or_zero(n.cross(&t))],
        velocity_a: pt.velocity + a.frame.angular_velocity.cross(&(ra * n)),
        coordinates: [eta, 0.0, 0.0, 0.0],
        ..ContactGeometry::ZERO
    }
}

/// Flexible band `a` and point or sphere `b` (module documentation): the centre-line point `C`
/// of the projection of `c_b`, the band normal `n = A (n̄ - (n̄ᵀ t̄) t̄)/|..|` and binormal
/// `b = t x n`; contact within `|bᵀ (c_b - r_C)| <= width / 2`, `g_N = nᵀ (c_b - r_C) - offset
/// - r_b`.
pub(super) fn band_sphere(mut a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    let band = a
        .contour
        .as_any()
        .downcast_ref::<FlexibleBand>()
        .expect("dispatch table: a flexible band");
    let c = b.frame.position;
    let Some((pt, eta)) = curve_projection(&band.curve, &mut a, &c) else {
        return ContactGeometry::OPEN;
    };
    let s = source(a.body);
    let t = pt.tangents[0];
    let nb = s.frame_rotation() * band.normal;
    let n = unit_or_zero(nb - nb.dot(&t) * t);
    let bi = t.cross(&n);
    let d = c - pt.position;
    let lateral = bi.dot(&d);
    if lateral.abs() > 0.5 * band.width || n == Vector3::zeros() {
        return ContactGeometry::OPEN;
    }
    let arm = band.offset * n + lateral * bi;
    let w = a.scratch.get_mut::<CurveWork>();
    add_offset_jacobian(s, &arm, &mut w.jac);
    let rb = radius(b.contour);
    ContactGeometry {
        gap: n.dot(&d) - band.offset - rb,
        point_a: pt.position + arm,
        point_b: c - rb * n,
        normal: n,
        tangents: [t, unit_or_zero(n.cross(&t))],
        velocity_a: pt.velocity + a.frame.angular_velocity.cross(&arm),
        coordinates: [eta, lateral, 0.0, 0.0],
        ..ContactGeometry::ZERO
    }
}

/// Adds the rigid rotation of an arm `d` (global) from the curve point to `J_C` (`v += ω × d`;
/// FFR: the columns of the angular velocity `w` get `-A [Aᵀ d]~ H`).
fn add_offset_jacobian(s: &dyn NeutralContourSource, d: &Vector3<f64>, jac: &mut Mat<f64>) {
    if *d == Vector3::zeros() {
        return;
    }
    s.add_arm_jacobian(d, jac.as_mut());
}
