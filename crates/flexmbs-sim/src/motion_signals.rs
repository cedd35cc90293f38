//! Output signals of accelerations and joint coordinates:
//!
//! - `<frame>.acceleration` (m/s^2) and `<frame>.angular_acceleration` (rad/s^2): the global
//!   acceleration of the frame origin and the frame's global angular acceleration from the
//!   accelerations `u_dot` of the output row, `a = J_T u_dot + J_T_dot u`,
//!   `alpha = J_R u_dot + J_R_dot u` ([`flexmbs_core::FrameKinematics`]);
//! - `<joint>.coordinates` and `<joint>.rates`: the relative coordinates of the joint's frame `b`
//!   in its frame `a` and their time derivatives. A revolute joint gives its angle about the z
//!   axis of `a` (rad; [`revolute_angle`]), unwrapped across +-pi (continuous over any number of
//!   turns, [`JointAngleTracker`]); a prismatic joint its displacement along the x axis of `a` (m;
//!   [`prismatic_displacement`]); every other joint the relative position `d = A_a^T (p_b - p_a)`
//!   (m) and the rotation vector `theta = log(A_a^T A_b)` (rad, `|theta| <= pi`), with the rates
//!   `d_dot = A_a^T (v_b - v_a - omega_a x (p_b - p_a))` and `theta_dot = J_l^-1(theta) A_a^T
//!   (omega_b - omega_a)` (`J_l` the left Jacobian of the rotation vector).
//!
//! [`crate::signals::evaluate_signals`] leaves these signals NaN; [`fill_motion_signals`] writes
//! them (like the stress signals).

use crate::signals::{Signal, SignalKind};
use flexmbs_core::force::{prismatic_displacement, revolute_angle, wrap_angle, JointCoordinate};
use flexmbs_core::superelement::rotvec::{inverse_left_jacobian, log_quaternion};
use flexmbs_core::{FrameId, FrameKinematics, Joint, Model};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// The relative coordinates a joint's `coordinates` and `rates` signals report, by its locked
/// DOFs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointCoordinates {
    /// Revolute (only `rz` free): the angle about z of frame `a`, unwrapped.
    Angle,
    /// Prismatic (only `tx` free): the displacement along x of frame `a`.
    Displacement,
    /// Any other joint: relative position and rotation vector in frame `a`.
    Pose,
}

impl JointCoordinates {
    /// The coordinates of `joint`.
    pub fn of(joint: &Joint) -> Self {
        match joint.locked {
            [true, true, true, true, true, false] => JointCoordinates::Angle,
            [false, true, true, true, true, true] => JointCoordinates::Displacement,
            _ => JointCoordinates::Pose,
        }
    }

    /// Component names.
    pub fn components(self) -> Vec<String> {
        let names: &[&str] = match self {
            JointCoordinates::Angle => &["rz"],
            JointCoordinates::Displacement => &["tx"],
            JointCoordinates::Pose => &["tx", "ty", "tz", "rx", "ry", "rz"],
        };
        names.iter().map(|s| s.to_string()).collect()
    }

    /// Unit of the coordinates (`rate = true`: of their rates).
    pub fn unit(self, rate: bool) -> &'static str {
        match (self, rate) {
            (JointCoordinates::Angle, false) => "rad",
            (JointCoordinates::Angle, true) => "rad/s",
            (JointCoordinates::Displacement, false) => "m",
            (JointCoordinates::Displacement, true) => "m/s",
            (JointCoordinates::Pose, false) => "m | rad",
            (JointCoordinates::Pose, true) => "m/s | rad/s",
        }
    }
}

/// The signal (unit, components, kind) of the frame quantity `what` of frame `f`, if `what` is
/// `acceleration` or `angular_acceleration`.
pub fn frame_signal(what: &str, f: FrameId) -> Option<(String, Vec<String>, SignalKind)> {
    let xyz = || ["x", "y", "z"].iter().map(|c| c.to_string()).collect();
    match what {
        "acceleration" => Some(("m/s^2".into(), xyz(), SignalKind::Acceleration(f))),
        "angular_acceleration" => {
            Some(("rad/s^2".into(), xyz(), SignalKind::AngularAcceleration(f)))
        }
        _ => None,
    }
}

/// The signal (unit, components, kind) of the joint quantity `what` of joint `j`, if `what` is
/// `coordinates` or `rates`.
pub fn joint_signal(
    model: &Model,
    j: usize,
    what: &str,
) -> Option<(String, Vec<String>, SignalKind)> {
    let c = JointCoordinates::of(&model.joints[j]);
    match what {
        "coordinates" => Some((
            c.unit(false).into(),
            c.components(),
            SignalKind::JointCoordinates(j),
        )),
        "rates" => Some((
            c.unit(true).into(),
            c.components(),
            SignalKind::JointRates(j),
        )),
        _ => None,
    }
}

/// The relative pose `(d, theta)` of frame `kb` in frame `ka` and its rates `(d_dot,
/// theta_dot)` (module documentation).
pub fn relative_pose(ka: &FrameKinematics, kb: &FrameKinematics) -> ([f64; 6], [f64; 6]) {
    let at = ka.rotation.transpose();
    let r = kb.position - ka.position;
    let d = at * r;
    let d_dot = at * (kb.velocity - ka.velocity - ka.angular_velocity.cross(&r));
    let rel: Matrix3<f64> = at * kb.rotation;
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rel));
    let theta = log_quaternion(&q);
    let w_rel: Vector3<f64> = at * (kb.angular_velocity - ka.angular_velocity);
    let theta_dot = inverse_left_jacobian(&theta) * w_rel;
    (
        [d.x, d.y, d.z, theta.x, theta.y, theta.z],
        [
            d_dot.x,
            d_dot.y,
            d_dot.z,
            theta_dot.x,
            theta_dot.y,
            theta_dot.z,
        ],
    )
}

/// The continuous angle of one revolute joint.
#[derive(Debug, Clone, Copy)]
struct TrackedAngle {
    joint: usize,
    /// Last observation `(t, unwrapped angle, rate)`, `None` before the first.
    last: Option<(f64, f64, f64)>,
}

/// Unwraps the angles of the revolute joints whose `coordinates` are output: observed at every
/// accepted step and output row, each new angle is taken on the branch (`+ 2 pi k`) nearest to
/// the prediction `phi_prev + (t - t_prev) (rate_prev + rate) / 2`, so the angle is continuous
/// over any number of turns as long as it changes by less than pi between observations beyond
/// this prediction. No allocation after construction.
#[derive(Debug, Clone, Default)]
pub struct JointAngleTracker {
    angles: Vec<TrackedAngle>,
    /// Frames `a` and `b` of the tracked joints (updated before [`Self::observe`]).
    frames: Vec<FrameId>,
}

impl JointAngleTracker {
    /// A tracker of the revolute joints with a `coordinates` signal in `signals`.
    pub fn new(model: &Model, signals: &[Signal]) -> Self {
        let mut t = Self::default();
        for s in signals {
            if let SignalKind::JointCoordinates(j) = s.kind {
                let joint = &model.joints[j];
                if JointCoordinates::of(joint) == JointCoordinates::Angle
                    && t.angles.iter().all(|a| a.joint != j)
                {
                    t.angles.push(TrackedAngle {
                        joint: j,
                        last: None,
                    });
                    t.frames.extend([joint.frame_a, joint.frame_b]);
                }
            }
        }
        t
    }

    /// [`Self::new`], continuing the angles `(joint index, rad)` stored at the restart time `t0`
    /// (a restart from a results file): the first observation is taken on the branch nearest to
    /// the stored angle. Joints that are not tracked are ignored.
    pub fn restarted(model: &Model, signals: &[Signal], t0: f64, angles: &[(usize, f64)]) -> Self {
        let mut t = Self::new(model, signals);
        for &(j, angle) in angles {
            if let Some(a) = t.angles.iter_mut().find(|a| a.joint == j) {
                a.last = Some((t0, angle, 0.0));
            }
        }
        t
    }

    /// True if no angle is tracked.
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }

    /// The frames [`Self::observe`] reads.
    pub fn frames(&self) -> &[FrameId] {
        &self.frames
    }

    /// Observes the tracked angles at time `t` (frames [`Self::frames`] up to date).
    pub fn observe(&mut self, model: &Model, t: f64, frames: &[FrameKinematics]) {
        for a in &mut self.angles {
            let joint = &model.joints[a.joint];
            let c = revolute_angle(&frames[joint.frame_a.0], &frames[joint.frame_b.0]);
            let angle = match a.last {
                None => c.value,
                Some((t0, phi0, rate0)) => {
                    let predicted = phi0 + 0.5 * (t - t0) * (rate0 + c.rate);
                    if predicted.is_finite() {
                        predicted + wrap_angle(c.value - predicted)
                    } else {
                        c.value
                    }
                }
            };
            if angle.is_finite() {
                a.last = Some((t, angle, c.rate));
            }
        }
    }

    /// The unwrapped angle of joint `j` at the last observation.
    fn angle(&self, j: usize) -> Option<f64> {
        self.angles
            .iter()
            .find(|a| a.joint == j)
            .and_then(|a| a.last.map(|l| l.1))
    }
}

/// Writes the acceleration and joint-coordinate signals into their places in `out` (laid out by
/// [`crate::signals::evaluate_signals`], which leaves them NaN): `frames` evaluated at the output
/// row with Jacobians, `u_dot` its accelerations (`None`: unknown, left NaN), `angles` observed
/// at the row. No allocation.
pub fn fill_motion_signals(
    signals: &[Signal],
    model: &Model,
    u_dot: Option<&[f64]>,
    frames: &[FrameKinematics],
    angles: &JointAngleTracker,
    out: &mut [f64],
) {
    let mut at = 0;
    for s in signals {
        let n = s.components.len();
        let Some(dst) = out.get_mut(at..at + n) else {
            return;
        };
        at += n;
        match s.kind {
            SignalKind::Acceleration(f) | SignalKind::AngularAcceleration(f) => {
                let Some(ud) = u_dot else { continue };
                let k = &frames[f.0];
                let translation = matches!(s.kind, SignalKind::Acceleration(_));
                let (jac, bias) = if translation {
                    (&k.jac_t, k.bias_acc)
                } else {
                    (&k.jac_r, k.bias_ang_acc)
                };
                let mut a = bias;
                for (c, g) in model.frame_cols(f).iter().enumerate() {
                    for r in 0..3 {
                        a[r] += jac[(r, c)] * ud[g];
                    }
                }
                dst.copy_from_slice(a.as_slice());
            }
            SignalKind::JointCoordinates(j) | SignalKind::JointRates(j) => {
                let joint = &model.joints[j];
                let (ka, kb) = (&frames[joint.frame_a.0], &frames[joint.frame_b.0]);
                let rates = matches!(s.kind, SignalKind::JointRates(_));
                let one = |c: JointCoordinate| if rates { c.rate } else { c.value };
                match JointCoordinates::of(joint) {
                    JointCoordinates::Angle if rates => dst[0] = revolute_angle(ka, kb).rate,
                    JointCoordinates::Angle => {
                        dst[0] = angles
                            .angle(j)
                            .unwrap_or_else(|| revolute_angle(ka, kb).value)
                    }
                    JointCoordinates::Displacement => dst[0] = one(prismatic_displacement(ka, kb)),
                    JointCoordinates::Pose => {
                        let (x, v) = relative_pose(ka, kb);
                        dst.copy_from_slice(if rates { &v } else { &x });
                    }
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frame kinematics of a pose moving along `p(t)`, `R(t) = exp(w t) R0` with the global
    /// angular velocity `w`.
    fn moving(
        t: f64,
        p0: Vector3<f64>,
        v: Vector3<f64>,
        r0: Matrix3<f64>,
        w: Vector3<f64>,
    ) -> FrameKinematics {
        let mut k = FrameKinematics::new(0);
        k.position = p0 + v * t + 0.3 * v.cross(&w) * t * t;
        k.velocity = v + 0.6 * v.cross(&w) * t;
        k.rotation = Rotation3::from_scaled_axis(w * t).into_inner() * r0;
        k.angular_velocity = w;
        k
    }

    /// `relative_pose`: the position is `A_a^T (p_b - p_a)`, the rotation vector reproduces
    /// `A_a^T A_b`, and both rates equal central finite differences of the coordinates
    /// (step 1e-6, 1e-8 absolute), at a relative rotation of about 2.2 rad.
    #[test]
    fn relative_pose_rates_are_the_derivatives() {
        let ra = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.2, 0.5)).into_inner();
        let rb = Rotation3::from_scaled_axis(Vector3::new(-1.0, 1.5, 1.2)).into_inner();
        let (wa, wb) = (Vector3::new(0.4, -0.7, 1.1), Vector3::new(-2.0, 0.5, 0.8));
        let (pa, pb) = (Vector3::new(0.1, 0.2, -0.3), Vector3::new(1.0, -0.5, 0.4));
        let (va, vb) = (Vector3::new(0.5, 0.0, -1.0), Vector3::new(-0.3, 2.0, 0.7));
        let at = |t: f64| relative_pose(&moving(t, pa, va, ra, wa), &moving(t, pb, vb, rb, wb));
        let t = 0.37;
        let (x, v) = at(t);
        let ka = moving(t, pa, va, ra, wa);
        let kb = moving(t, pb, vb, rb, wb);
        let d = ka.rotation.transpose() * (kb.position - ka.position);
        let theta = Vector3::new(x[3], x[4], x[5]);
        let rel = ka.rotation.transpose() * kb.rotation;
        let back = Rotation3::from_scaled_axis(theta).into_inner();
        assert!((back - rel).abs().max() < 1e-12, "{back} vs {rel}");
        assert!(theta.norm() > 1.0 && theta.norm() < std::f64::consts::PI);
        for i in 0..3 {
            assert!((x[i] - d[i]).abs() < 1e-14);
        }
        let h = 1e-6;
        let (xp, _) = at(t + h);
        let (xm, _) = at(t - h);
        for i in 0..6 {
            let fd = (xp[i] - xm[i]) / (2.0 * h);
            assert!((v[i] - fd).abs() < 1e-8, "component {i}: {} vs {fd}", v[i]);
        }
    }
}
