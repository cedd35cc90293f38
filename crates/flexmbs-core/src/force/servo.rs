//! A PD/PID servo on a joint coordinate following a time function, and the element carrying
//! the integral of its error.

use super::{nonnegative, ForceElement, ForceElementRef, JointAxis, Wrench};
use crate::element::{Element, ElementScratch, FrameKinematics, LocalFrame};
use crate::ids::{FrameId, LoadId};
use crate::load::Load;
use crate::model::ModelSpec;
use crate::node::NodeKind;
use crate::time_function::TimeFunction;
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

/// Gains of a [`JointServo`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ServoGains {
    /// Proportional gain `K_p` (N m/rad or N/m).
    pub kp: f64,
    /// Integral gain `K_i` (N m/(rad s) or N/(m s)); 0: PD servo, no integral state.
    pub ki: f64,
    /// Derivative gain `K_d` (N m s/rad or N s/m).
    pub kd: f64,
}

/// A servo on the free axis of a joint between frames `a` and `b` (the joint's frames) that
/// makes the joint coordinate `x` follow `x_ref(t)`: the drive torque or force
///
/// ```text
/// Q = -K_p e - K_i z - K_d e_dot,   e = x - x_ref(t),   e_dot = x_dot - x_ref'(t)
/// ```
///
/// acts on `b` (and `-Q` on `a`), an ideal actuator without saturation; an angle error is
/// wrapped to `(-pi, pi]`. With `K_i != 0` the integral `z` of the error is the coordinate of a
/// [`ControllerIntegrator`] body whose frame is the servo's third frame; it obeys
/// `tau_i z_ddot + z_dot = e`, an integrator behind a first-order lag `tau_i` (so that it is an
/// ordinary coordinate for every integrator), which at rest gives `e = 0` exactly. Build it with
/// [`add_joint_servo`]. A P servo holding a load `Q_0` settles at `e = Q_0 / K_p`, a PI servo at
/// `e = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointServo {
    /// Name.
    pub name: String,
    /// Frames `a`, `b` and, with an integral part, the [`ControllerIntegrator`]'s frame.
    pub frames: Vec<FrameId>,
    /// The axis.
    pub axis: JointAxis,
    /// Reference `x_ref(t)` (rad or m).
    pub reference: TimeFunction,
    /// Gains.
    pub gains: ServoGains,
}

impl JointServo {
    /// Error, its rate, and the drive force `Q` with the joint coordinate.
    fn drive(&self, t: f64, frames: &[FrameKinematics]) -> (f64, f64, super::JointCoordinate) {
        let (a, b) = (self.frames[0], self.frames[1]);
        let c = self.axis.measure(&frames[a.index()], &frames[b.index()]);
        let e = self.axis.difference(c.value, self.reference.value(t));
        let e_dot = c.rate - self.reference.derivative(t);
        let z = match self.frames.get(2) {
            Some(f) => frames[f.index()].position.x,
            None => 0.0,
        };
        let g = &self.gains;
        (e, -g.kp * e - g.ki * z - g.kd * e_dot, c)
    }
}

impl ForceElement for JointServo {
    fn name(&self) -> &str {
        &self.name
    }
    fn frames(&self) -> &[FrameId] {
        &self.frames
    }
    fn validate(&self) -> Result<(), String> {
        let g = &self.gains;
        nonnegative("kp", g.kp)?;
        nonnegative("ki", g.ki)?;
        nonnegative("kd", g.kd)?;
        let want = if g.ki != 0.0 { 3 } else { 2 };
        if self.frames.len() != want {
            return Err(format!(
                "a servo with ki = {} acts on {want} frames, got {}",
                g.ki,
                self.frames.len()
            ));
        }
        self.reference.validate(None).map_err(|e| e.to_string())
    }
    fn wrenches(&self, t: f64, frames: &[FrameKinematics], out: &mut [Wrench]) {
        let (e, q, c) = self.drive(t, frames);
        c.wrenches(q, out);
        if self.frames.len() == 3 {
            out[2] = Wrench {
                force: Vector3::new(e, 0.0, 0.0),
                moment: Vector3::zeros(),
            };
        }
    }
    fn force_scale(&self, frames: &[FrameKinematics]) -> f64 {
        self.gains.kp * super::position_scale(&self.frames[..2], frames)
    }
    fn nonconservative_power(&self, t: f64, frames: &[FrameKinematics]) -> f64 {
        let (_, q, c) = self.drive(t, frames);
        q * c.rate
    }
    fn output_unit(&self) -> &str {
        self.axis.force_unit()
    }
    fn output(&self, t: f64, frames: &[FrameKinematics]) -> Option<f64> {
        Some(self.drive(t, frames).1)
    }
}

/// Adds `servo` (its `frames` holding `a`, `b`) to `spec`; with `K_i != 0` first a
/// [`ControllerIntegrator`] body `"{name}.integral"` with lag `integral_lag` (s) and its frame,
/// which becomes the servo's third frame. Returns the servo's load id.
pub fn add_joint_servo(spec: &mut ModelSpec, mut servo: JointServo, integral_lag: f64) -> LoadId {
    if servo.gains.ki != 0.0 {
        let name = format!("{}.integral", servo.name);
        let body = spec.add_body(&name, ControllerIntegrator { lag: integral_lag });
        let frame = spec.add_frame(&name, body, Vector3::zeros(), Matrix3::identity());
        servo.frames.truncate(2);
        servo.frames.push(frame);
    }
    spec.add_load(Load::Element(ForceElementRef::new(servo)))
}

/// The state of a servo's integral part: one coordinate `z` (on a `Vector(1)` node) with
/// `tau_i z_ddot = e - z_dot`, `e` applied by the servo as a force along x at the element's
/// frames (whose position is `(z, 0, 0)`). Not a physical body: no kinetic or potential
/// energy, no gravity.
#[derive(Debug, Clone, PartialEq)]
pub struct ControllerIntegrator {
    /// Lag `tau_i` (s, > 0).
    pub lag: f64,
}

impl Element for ControllerIntegrator {
    fn validate(&self) -> Result<(), String> {
        if self.lag.is_finite() && self.lag > 0.0 {
            Ok(())
        } else {
            Err(format!("integral lag {} must be finite and > 0", self.lag))
        }
    }
    fn node_kinds(&self) -> &[NodeKind] {
        &[NodeKind::Vector(1)]
    }
    fn nq(&self) -> usize {
        1
    }
    fn nu(&self) -> usize {
        1
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        q.fill(0.0);
        u.fill(0.0);
    }
    fn set_pose(&self, _q: &mut [f64], _p: &Vector3<f64>, _r: &Matrix3<f64>) {}
    fn set_velocity(&self, _q: &[f64], _u: &mut [f64], _v: &Vector3<f64>, _w: &Vector3<f64>) {}
    fn q_dot(&self, _q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        q_dot[0] = u[0];
    }
    fn mass_matrix(&self, _q: &[f64], _s: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        m[(0, 0)] = self.lag;
    }
    fn forces(
        &self,
        _t: f64,
        _q: &[f64],
        u: &[f64],
        _g: &Vector3<f64>,
        _s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        h[0] = -u[0];
    }
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        _s: &mut ElementScratch,
        f: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        out.position = Vector3::new(q[0], 0.0, 0.0);
        out.rotation = f.rotation;
        out.velocity = Vector3::new(u[0], 0.0, 0.0);
        out.angular_velocity = Vector3::zeros();
        out.bias_acc = Vector3::zeros();
        out.bias_ang_acc = Vector3::zeros();
        out.jac_t.fill(0.0);
        out.jac_r.fill(0.0);
        out.jac_t[(0, 0)] = 1.0;
    }
    fn kinetic_energy(&self, _q: &[f64], _u: &[f64], _s: &mut ElementScratch) -> f64 {
        0.0
    }
    fn gravity_potential(&self, _q: &[f64], _g: &Vector3<f64>, _s: &mut ElementScratch) -> f64 {
        0.0
    }
}
