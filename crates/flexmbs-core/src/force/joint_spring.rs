//! A linear spring-damper on a joint's free axis (rotational: revolute; translational:
//! prismatic) with a preload.

use super::{nonnegative, ForceElement, JointAxis, Wrench};
use crate::element::FrameKinematics;
use crate::ids::FrameId;

/// Spring-damper on the free axis of a joint between frames `a` and `b` (the joint's frames):
/// the generalized force (torque about z of `a`, or force along x of `a`)
///
/// ```text
/// Q = preload - k (x - x0) - d x_dot
/// ```
///
/// with `x` the joint coordinate ([`JointAxis::measure`]; an angle difference is wrapped to
/// `(-pi, pi]`), potential energy `V = k (x - x0)^2 / 2 - preload (x - x0)` and the dissipated
/// power `d x_dot^2`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpringDamper {
    /// Name.
    pub name: String,
    /// Frames `a`, `b`.
    pub frames: [FrameId; 2],
    /// The axis.
    pub axis: JointAxis,
    /// Stiffness `k` (N m/rad or N/m).
    pub stiffness: f64,
    /// Damping `d` (N m s/rad or N s/m).
    pub damping: f64,
    /// Unstressed coordinate `x0` (rad or m).
    pub reference: f64,
    /// Preload (N m or N): the generalized force at `x = x0`, at rest.
    pub preload: f64,
}

impl JointSpringDamper {
    /// The coordinate deflection `x - x0` and rate.
    fn deflection(&self, frames: &[FrameKinematics]) -> (f64, f64, super::JointCoordinate) {
        let [a, b] = self.frames;
        let c = self.axis.measure(&frames[a.index()], &frames[b.index()]);
        (self.axis.difference(c.value, self.reference), c.rate, c)
    }

    /// The generalized force `Q`.
    fn generalized_force(&self, frames: &[FrameKinematics]) -> f64 {
        let (dx, rate, _) = self.deflection(frames);
        self.preload - self.stiffness * dx - self.damping * rate
    }
}

impl ForceElement for JointSpringDamper {
    fn name(&self) -> &str {
        &self.name
    }
    fn frames(&self) -> &[FrameId] {
        &self.frames
    }
    fn validate(&self) -> Result<(), String> {
        nonnegative("stiffness", self.stiffness)?;
        nonnegative("damping", self.damping)?;
        for (n, v) in [("reference", self.reference), ("preload", self.preload)] {
            if !v.is_finite() {
                return Err(format!("`{n}` = {v} must be finite"));
            }
        }
        Ok(())
    }
    fn wrenches(&self, _t: f64, frames: &[FrameKinematics], out: &mut [Wrench]) {
        let (dx, rate, c) = self.deflection(frames);
        c.wrenches(
            self.preload - self.stiffness * dx - self.damping * rate,
            out,
        );
    }
    fn depends_on_velocity(&self) -> bool {
        self.damping != 0.0
    }
    fn force_scale(&self, frames: &[FrameKinematics]) -> f64 {
        self.stiffness * super::position_scale(&self.frames, frames) + self.preload.abs()
    }
    fn potential_energy(&self, frames: &[FrameKinematics]) -> f64 {
        let (dx, _, _) = self.deflection(frames);
        0.5 * self.stiffness * dx * dx - self.preload * dx
    }
    fn nonconservative_power(&self, _t: f64, frames: &[FrameKinematics]) -> f64 {
        let (_, rate, _) = self.deflection(frames);
        -self.damping * rate * rate
    }
    fn output_unit(&self) -> &str {
        self.axis.force_unit()
    }
    fn output(&self, _t: f64, frames: &[FrameKinematics]) -> Option<f64> {
        Some(self.generalized_force(frames))
    }
}
