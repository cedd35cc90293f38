//! Contact kinematics of a pair of contours (seed 000 §3.1): the contact points, the normal gap
//! `g_N` (3.4), the contact frame (normal `n`, tangents `t_1`, `t_2`), the relative velocities
//! `g_N_dot`, `g_T_dot` (3.8) and the generalized force directions `W_N`, `W_T` as
//! [`ConstraintRow`]s (the form of joint rows, so assembly is shared).
//!
//! Convention: `n` is the outward normal of contour `a` at its contact point `C_a`, pointing
//! towards contour `b`, and `g_N = n^T (r_Cb - r_Ca)` is positive when the contours are apart
//! (the seed's (3.4) with `n = n^(1) = -n^(2)`). A row `g_dot = d^T (v_Cb - v_Ca)` in terms of
//! the frames' Jacobians: the contact point `C` of a contour on frame `f` is the point offset
//! by `s = r_C - r_f` from the frame origin, `v_C = J_T u + (J_R u) x s`, so
//! `d^T v_C = d^T J_T u + (s x d)^T J_R u`.
//!
//! Pair functions are looked up in a dispatch table over ([`ContourKind`], [`ContourKind`])
//! ([`pair_function`]); a contact whose contours come in the other order is swapped once when
//! the model is compiled ([`canonical_order`]).

use super::contour::{CircleContour, Contour, ContourKind, SphereContour};
use crate::element::FrameKinematics;
use crate::joint::ConstraintRow;
use nalgebra::Vector3;

/// Contact points and contact frame of a pair of contours at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Normal gap `g_N` (3.4): > 0 apart, < 0 penetrating.
    pub gap: f64,
    /// Contact point on contour `a` (global).
    pub point_a: Vector3<f64>,
    /// Contact point on contour `b` (global).
    pub point_b: Vector3<f64>,
    /// Unit normal, outward of `a`, towards `b`.
    pub normal: Vector3<f64>,
    /// Unit tangents `t_1`, `t_2` (with `n` a right-handed orthonormal frame).
    pub tangents: [Vector3<f64>; 2],
}

impl ContactGeometry {
    /// Geometry with every entry zero (buffers).
    pub const ZERO: Self = Self {
        gap: 0.0,
        point_a: Vector3::new(0.0, 0.0, 0.0),
        point_b: Vector3::new(0.0, 0.0, 0.0),
        normal: Vector3::new(0.0, 0.0, 1.0),
        tangents: [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 1.0, 0.0)],
    };

    /// Row of the relative velocity of the contact points along `d`,
    /// `g_dot = d^T (v_Cb - v_Ca)`, with `g` as its position value (`bias`, `g_t` zero: a
    /// velocity-level row).
    pub fn row(
        &self,
        d: &Vector3<f64>,
        g: f64,
        ka: &FrameKinematics,
        kb: &FrameKinematics,
    ) -> ConstraintRow {
        let (sa, sb) = (self.point_a - ka.position, self.point_b - kb.position);
        ConstraintRow {
            g,
            t_b: *d,
            r_b: sb.cross(d),
            t_a: -d,
            r_a: -sa.cross(d),
            g_t: 0.0,
            bias: 0.0,
        }
    }

    /// The normal row `W_N` (`g` = the gap) and the tangent rows `W_T` (`g` = 0).
    pub fn rows(&self, ka: &FrameKinematics, kb: &FrameKinematics) -> [ConstraintRow; 3] {
        [
            self.row(&self.normal, self.gap, ka, kb),
            self.row(&self.tangents[0], 0.0, ka, kb),
            self.row(&self.tangents[1], 0.0, ka, kb),
        ]
    }

    /// Relative velocity of the material contact points `v_Cb - v_Ca` (global).
    pub fn relative_velocity(&self, ka: &FrameKinematics, kb: &FrameKinematics) -> Vector3<f64> {
        let va = ka.velocity + ka.angular_velocity.cross(&(self.point_a - ka.position));
        let vb = kb.velocity + kb.angular_velocity.cross(&(self.point_b - kb.position));
        vb - va
    }

    /// `g_N_dot = n^T (v_Cb - v_Ca)` and `g_T_dot = T^T (v_Cb - v_Ca)` (3.8).
    pub fn gap_velocities(&self, ka: &FrameKinematics, kb: &FrameKinematics) -> (f64, [f64; 2]) {
        let v = self.relative_velocity(ka, kb);
        (
            self.normal.dot(&v),
            [self.tangents[0].dot(&v), self.tangents[1].dot(&v)],
        )
    }
}

/// Contact kinematics of one contour pair from the kinematics of their frames.
pub type PairFn = fn(
    a: &dyn Contour,
    b: &dyn Contour,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
) -> ContactGeometry;

/// The dispatch table: the pair function for contours of kinds `(a, b)` in this order, `None`
/// for an unsupported (or reversed, see [`canonical_order`]) pair.
pub fn pair_function(a: ContourKind, b: ContourKind) -> Option<PairFn> {
    use ContourKind::*;
    Some(match (a, b) {
        (Plane, Point) => plane_point,
        (Plane, Sphere) => plane_sphere,
        (Plane, Circle) => plane_circle,
        (Sphere, Point) => sphere_sphere,
        (Sphere, Sphere) => sphere_sphere,
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
fn radius(c: &dyn Contour) -> f64 {
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
    }
}

fn plane_point(
    _a: &dyn Contour,
    _b: &dyn Contour,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
) -> ContactGeometry {
    plane_offset_point(ka, kb.position, 0.0)
}

fn plane_sphere(
    _a: &dyn Contour,
    b: &dyn Contour,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
) -> ContactGeometry {
    plane_offset_point(ka, kb.position, radius(b))
}

/// Plane and circle: the rim point closest to the plane, `c - r d / |d|` with `d` the plane
/// normal projected into the circle's plane (a circle parallel to the plane: the rim point
/// along the circle's x axis).
fn plane_circle(
    _a: &dyn Contour,
    b: &dyn Contour,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
) -> ContactGeometry {
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
fn sphere_sphere(
    a: &dyn Contour,
    b: &dyn Contour,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
) -> ContactGeometry {
    let (ra, rb) = (radius(a), radius(b));
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
