//! Contact kinematics of a pair of contours (seed 000 §3.1): the contact points, the normal gap
//! `g_N` (3.4), the contact frame (normal `n`, tangents `t_1`, `t_2`), the relative velocities
//! `g_N_dot`, `g_T_dot` (3.8); the generalized force directions `W_N`, `W_T` are
//! `d^T J_Cb - d^T J_Ca` for `d` = `n`, `t_1`, `t_2` ([`super::Contour::add_direction`]).
//!
//! Convention: `n` is the outward normal of contour `a` at its contact point `C_a`, pointing
//! towards contour `b`, and `g_N = n^T (r_Cb - r_Ca)` is positive when the contours are apart
//! (the seed's (3.4) with `n = n^(1) = -n^(2)`). A row `g_dot = d^T (v_Cb - v_Ca)` in terms of
//! the frames' Jacobians: the contact point `C` of a rigid contour on frame `f` is the point
//! offset by `s = r_C - r_f` from the frame origin, `v_C = J_T u + (J_R u) x s`, so
//! `d^T v_C = d^T J_T u + (s x d)^T J_R u`; a flexible contour's contact point moves as a
//! material point of its body (`v_C = J_C u`, [`super::flexible`]).
//!
//! Pair functions are looked up in a dispatch table over ([`ContourKind`], [`ContourKind`])
//! ([`pair_function`]); a contact whose contours come in the other order is swapped once when
//! the model is compiled ([`canonical_order`]).

use super::contour::{CircleContour, Contour, ContourKind, ContourScratch, SphereContour};
use crate::element::{ElementScratch, FrameKinematics};
use nalgebra::Vector3;

/// Contact points, contact frame and contact-point velocities of a pair of contours at one
/// state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Normal gap `g_N` (3.4): > 0 apart, < 0 penetrating; `+inf` when a flexible contour has
    /// no normal projection of the other contour (the point lies beyond its edge: no contact).
    pub gap: f64,
    /// Contact point on contour `a` (global).
    pub point_a: Vector3<f64>,
    /// Contact point on contour `b` (global).
    pub point_b: Vector3<f64>,
    /// Unit normal, outward of `a`, towards `b`.
    pub normal: Vector3<f64>,
    /// Unit tangents `t_1`, `t_2` (with `n` a right-handed orthonormal frame).
    pub tangents: [Vector3<f64>; 2],
    /// Velocity of the material point of contour `a` at `point_a`.
    pub velocity_a: Vector3<f64>,
    /// Velocity of the material point of contour `b` at `point_b`.
    pub velocity_b: Vector3<f64>,
    /// Contour coordinates `(eta_a, xi_a, eta_b, xi_b)` of flexible contours (0 for rigid ones).
    pub coordinates: [f64; 4],
}

impl ContactGeometry {
    /// Geometry with every entry zero (buffers).
    pub const ZERO: Self = Self {
        gap: 0.0,
        point_a: Vector3::new(0.0, 0.0, 0.0),
        point_b: Vector3::new(0.0, 0.0, 0.0),
        normal: Vector3::new(0.0, 0.0, 1.0),
        tangents: [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 1.0, 0.0)],
        velocity_a: Vector3::new(0.0, 0.0, 0.0),
        velocity_b: Vector3::new(0.0, 0.0, 0.0),
        coordinates: [0.0; 4],
    };

    /// No contact (a flexible contour without a normal projection of the other contour).
    pub const OPEN: Self = Self {
        gap: f64::INFINITY,
        ..Self::ZERO
    };

    /// Whether the pair has a contact point at all (a finite gap).
    pub fn has_contact_point(&self) -> bool {
        self.gap.is_finite()
    }

    /// Direction `k` of the contact frame: 0 the normal, 1 and 2 the tangents.
    pub fn direction(&self, k: usize) -> Vector3<f64> {
        if k == 0 {
            self.normal
        } else {
            self.tangents[k - 1]
        }
    }

    /// Relative velocity of the material contact points `v_Cb - v_Ca` (global).
    pub fn relative_velocity(&self) -> Vector3<f64> {
        self.velocity_b - self.velocity_a
    }

    /// `g_N_dot = n^T (v_Cb - v_Ca)` and `g_T_dot = T^T (v_Cb - v_Ca)` (3.8).
    pub fn gap_velocities(&self) -> (f64, [f64; 2]) {
        let v = self.relative_velocity();
        (
            self.normal.dot(&v),
            [self.tangents[0].dot(&v), self.tangents[1].dot(&v)],
        )
    }
}

/// The velocity of a point `p` fixed in the frame with kinematics `k`.
pub fn frame_point_velocity(k: &FrameKinematics, p: &Vector3<f64>) -> Vector3<f64> {
    k.velocity + k.angular_velocity.cross(&(p - k.position))
}

/// One contour of a pair as a pair function sees it: the contour, its frame's kinematics, the
/// evaluated state of its owner body (flexible contours) and its evaluation buffers.
pub struct Side<'a> {
    /// The contour.
    pub contour: &'a dyn Contour,
    /// Kinematics of the contour's frame.
    pub frame: &'a FrameKinematics,
    /// The owner body's evaluated state (`None` on the ground or for a node-owned frame).
    pub body: Option<&'a ElementScratch>,
    /// The contour's buffers in this contact.
    pub scratch: &'a mut ContourScratch,
}

/// Contact kinematics of one contour pair. Pair functions of rigid contours leave the
/// velocities zero (the caller fills them from the frames); flexible ones set them.
pub type PairFn = fn(a: Side<'_>, b: Side<'_>) -> ContactGeometry;

/// The dispatch table: the pair function for contours of kinds `(a, b)` in this order, `None`
/// for an unsupported (or reversed, see [`canonical_order`]) pair.
pub fn pair_function(a: ContourKind, b: ContourKind) -> Option<PairFn> {
    use super::flexible as flex;
    use ContourKind::*;
    Some(match (a, b) {
        (Plane, Point) => plane_point,
        (Plane, Sphere) => plane_sphere,
        (Plane, Circle) => plane_circle,
        (Sphere, Point) => sphere_sphere,
        (Sphere, Sphere) => sphere_sphere,
        (NeutralSurface, Point) | (NeutralSurface, Sphere) => flex::surface_sphere,
        (NeutralCurve, Point) | (NeutralCurve, Sphere) => flex::curve_sphere,
        (FlexibleBand, Point) | (FlexibleBand, Sphere) => flex::band_sphere,
        _ => return None,
    })
}

/// Whether a pair of kinds is supported, and whether it must be swapped to the table's order:
/// `Some(false)` as given, `Some(true)` swapped, `None` unsupported.
pub fn canonical_order(a: ContourKind, b: ContourKind) -> Option<bool> {
    if pair_function(a, b).is_some() {
        Some(false)
    } else if pair_function(b, a).is_some() {
        Some(true)
    } else {
        None
    }
}

/// Radius of a sphere or circle contour, 0 for any other (a point).
pub(crate) fn radius(c: &dyn Contour) -> f64 {
    let any = c.as_any();
    if let Some(s) = any.downcast_ref::<SphereContour>() {
        s.radius
    } else if let Some(s) = any.downcast_ref::<CircleContour>() {
        s.radius
    } else {
        0.0
    }
}

/// Plane `a` and a point (or sphere of radius `r`) centred at `c`: `g_N = n^T (c - o) - r`.
fn plane_offset_point(ka: &FrameKinematics, c: Vector3<f64>, r: f64) -> ContactGeometry {
    let n = ka.rotation.column(2).into_owned();
    let d = n.dot(&(c - ka.position));
    ContactGeometry {
        gap: d - r,
        point_a: c - d * n,
        point_b: c - r * n,
        normal: n,
        tangents: [
            ka.rotation.column(0).into_owned(),
            ka.rotation.column(1).into_owned(),
        ],
        ..ContactGeometry::ZERO
    }
}

fn plane_point(a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    plane_offset_point(a.frame, b.frame.position, 0.0)
}

fn plane_sphere(a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    plane_offset_point(a.frame, b.frame.position, radius(b.contour))
}

/// Plane and circle: the rim point closest to the plane, `c - r d / |d|` with `d` the plane
/// normal projected into the circle's plane (a circle parallel to the plane: the rim point
/// along the circle's x axis).
fn plane_circle(a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    let (ka, kb, b) = (a.frame, b.frame, b.contour);
    let n = ka.rotation.column(2).into_owned();
    let axis = kb.rotation.column(2).into_owned();
    let d = n - n.dot(&axis) * axis;
    let dn = d.norm();
    let dir = if dn > 1e-12 {
        d / dn
    } else {
        kb.rotation.column(0).into_owned()
    };
    let p = kb.position - radius(b) * dir;
    let mut g = plane_offset_point(ka, p, 0.0);
    g.point_b = p;
    g
}

/// Sphere `a` (radius `r_a`) and sphere or point `b`: `n = (c_b - c_a) / |c_b - c_a|`,
/// `g_N = |c_b - c_a| - r_a - r_b` (coincident centres: `n` = the z axis of frame `a`).
fn sphere_sphere(a: Side<'_>, b: Side<'_>) -> ContactGeometry {
    let (ra, rb) = (radius(a.contour), radius(b.contour));
    let (ka, kb) = (a.frame, b.frame);
    let d = kb.position - ka.position;
    let dist = d.norm();
    let n = if dist > 0.0 {
        d / dist
    } else {
        ka.rotation.column(2).into_owned()
    };
    ContactGeometry {
        gap: dist - ra - rb,
        point_a: ka.position + ra * n,
        point_b: kb.position - rb * n,
        normal: n,
        tangents: orthonormal_tangents(&n),
        ..ContactGeometry::ZERO
    }
}

/// Two unit tangents completing the unit `n` to a right-handed orthonormal frame
/// `(n, t_1, t_2)`: `t_1` perpendicular to `n` and to the coordinate axis least aligned with it.
pub fn orthonormal_tangents(n: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let (ax, ay, az) = (n.x.abs(), n.y.abs(), n.z.abs());
    let e = if ax <= ay && ax <= az {
        Vector3::x()
    } else if ay <= az {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let t1 = e.cross(n).normalize();
    [t1, n.cross(&t1)]
}
