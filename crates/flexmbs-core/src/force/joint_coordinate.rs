//! The relative coordinate of a joint's free axis (the angle of a revolute joint, the
//! displacement of a prismatic joint), its rate, and the wrenches of a generalized force along
//! it: the exact variation of the coordinate, so that a force `Q = -dV/dx` does the work `-dV`.

use super::Wrench;
use crate::element::FrameKinematics;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The free axis of a joint a force element acts along, with the conventions of
/// [`crate::Joint`]: measured from frame `a` to frame `b`, in the axes of `a`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointAxis {
    /// Rotation about the z axis of frame `a` (revolute, cylindrical): the angle
    /// [`revolute_angle`] (rad), generalized force = torque (N m).
    Rotation,
    /// Translation along the x axis of frame `a` (prismatic): the displacement
    /// [`prismatic_displacement`] (m), generalized force = force (N).
    Translation,
}

/// A joint coordinate at a state: value, rate, and the wrenches a unit generalized force along
/// it exerts on frames `a` and `b` (their virtual work is the coordinate's variation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointCoordinate {
    /// The coordinate (rad or m).
    pub value: f64,
    /// Its time derivative.
    pub rate: f64,
    /// Wrench on frame `a` of a unit generalized force.
    pub unit_a: Wrench,
    /// Wrench on frame `b` of a unit generalized force.
    pub unit_b: Wrench,
}

impl JointCoordinate {
    /// The wrenches of the generalized force `q_gen` on `a` and `b` into `out[0]`, `out[1]`.
    pub fn wrenches(&self, q_gen: f64, out: &mut [Wrench]) {
        out[0] = Wrench {
            force: self.unit_a.force * q_gen,
            moment: self.unit_a.moment * q_gen,
        };
        out[1] = Wrench {
            force: self.unit_b.force * q_gen,
            moment: self.unit_b.moment * q_gen,
        };
    }
}

impl JointAxis {
    /// The coordinate of this axis between frames `ka` and `kb`.
    pub fn measure(self, ka: &FrameKinematics, kb: &FrameKinematics) -> JointCoordinate {
        match self {
            JointAxis::Rotation => revolute_angle(ka, kb),
            JointAxis::Translation => prismatic_displacement(ka, kb),
        }
    }

    /// Unit of the coordinate.
    pub fn unit(self) -> &'static str {
        match self {
            JointAxis::Rotation => "rad",
            JointAxis::Translation => "m",
        }
    }

    /// Unit of the generalized force.
    pub fn force_unit(self) -> &'static str {
        match self {
            JointAxis::Rotation => "N m",
            JointAxis::Translation => "N",
        }
    }

    /// The difference `x - x_ref` of two coordinates: for a rotation wrapped to `(-pi, pi]`
    /// ([`wrap_angle`]), so that a reference many turns away is reached the short way.
    pub fn difference(self, x: f64, x_ref: f64) -> f64 {
        match self {
            JointAxis::Rotation => wrap_angle(x - x_ref),
            JointAxis::Translation => x - x_ref,
        }
    }
}

/// `x` wrapped to `(-pi, pi]`.
pub fn wrap_angle(x: f64) -> f64 {
    let y = (x + PI).rem_euclid(2.0 * PI) - PI;
    if y == -PI {
        PI
    } else {
        y
    }
}

/// The rotation angle `phi = atan2(S, C)` of frame `b` relative to frame `a` about the z axis of
/// `a`, with `S = (e_y^a.e_x^b - e_x^a.e_y^b)/2`, `C = (e_x^a.e_x^b + e_y^a.e_y^b)/2` (the
/// definition of the prescribed-angle row of [`crate::Joint`]), in `(-pi, pi]`. Its exact
/// variation is `dphi = n . (dtheta_b - dtheta_a)` with `n = (C n_S - S n_C)/(S^2 + C^2)`
/// (`n = e_z^a` when the z axes are aligned), so the rate is `n . (omega_b - omega_a)` and a
/// torque `Q` acts as the moments `Q n` on `b` and `-Q n` on `a`.
pub fn revolute_angle(ka: &FrameKinematics, kb: &FrameKinematics) -> JointCoordinate {
    let (ra, rb) = (&ka.rotation, &kb.rotation);
    let (xa, ya) = (ra.column(0), ra.column(1));
    let (xb, yb) = (rb.column(0), rb.column(1));
    let s = 0.5 * (ya.dot(&xb) - xa.dot(&yb));
    let c = 0.5 * (xa.dot(&xb) + ya.dot(&yb));
    // d(e_i^a . e_j^b) = (dtheta_b - dtheta_a) . (e_j^b x e_i^a)
    let n_s = 0.5 * (xb.cross(&ya) - yb.cross(&xa));
    let n_c = 0.5 * (xb.cross(&xa) + yb.cross(&ya));
    let r2 = s * s + c * c;
    let n: Vector3<f64> = (n_s * c - n_c * s) / r2;
    let z = Vector3::zeros();
    JointCoordinate {
        value: s.atan2(c),
        rate: n.dot(&(kb.angular_velocity - ka.angular_velocity)),
        unit_a: Wrench {
            force: z,
            moment: -n,
        },
        unit_b: Wrench {
            force: z,
            moment: n,
        },
    }
}

/// The displacement `d = e_x^a . (p_b - p_a)` of frame `b` along the x axis of frame `a` (the
/// free axis of a prismatic joint). Rate `e_x^a . (v_b - v_a) + (omega_a x e_x^a) . r`
/// (`r = p_b - p_a`); a force `Q` acts as `Q e_x^a` at the origin of `b` and `-Q e_x^a` at the
/// origin of `b` on `a` (the force `-Q e_x^a` and the moment `r x (-Q e_x^a)` at the origin of
/// `a`), which is the exact variation of `d`.
pub fn prismatic_displacement(ka: &FrameKinematics, kb: &FrameKinematics) -> JointCoordinate {
    let e: Vector3<f64> = ka.rotation.column(0).into();
    let r = kb.position - ka.position;
    let rate = e.dot(&(kb.velocity - ka.velocity)) + ka.angular_velocity.cross(&e).dot(&r);
    JointCoordinate {
        value: e.dot(&r),
        rate,
        unit_a: Wrench {
            force: -e,
            moment: r.cross(&(-e)),
        },
        unit_b: Wrench {
            force: e,
            moment: Vector3::zeros(),
        },
    }
}
