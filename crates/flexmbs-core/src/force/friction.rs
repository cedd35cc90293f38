//! Regularized Coulomb friction on a joint's free axis.

use super::{nonnegative, ForceElement, JointAxis, Wrench};
use crate::element::FrameKinematics;
use crate::ids::FrameId;

/// Coulomb friction on the free axis of a joint between frames `a` and `b`, regularized by a
/// slip velocity `v_s`:
///
/// ```text
/// Q = -Q_c tanh(x_dot / v_s)
/// ```
///
/// (`Q_c`: the friction torque or force at sliding; at `|x_dot| = v_s` 76 % of it, above
/// `3 v_s` more than 99 %). The friction level is a constant, not proportional to the joint's
/// reaction force. Below the slip velocity the joint creeps (a viscous law of slope
/// `Q_c / v_s`): sticking is approximated, not exact.
#[derive(Debug, Clone, PartialEq)]
pub struct JointFriction {
    /// Name.
    pub name: String,
    /// Frames `a`, `b`.
    pub frames: [FrameId; 2],
    /// The axis.
    pub axis: JointAxis,
    /// Sliding friction torque or force `Q_c` (N m or N).
    pub coulomb: f64,
    /// Slip velocity `v_s` (rad/s or m/s, > 0).
    pub slip_velocity: f64,
}

impl JointFriction {
    fn generalized_force(&self, frames: &[FrameKinematics]) -> (f64, super::JointCoordinate) {
        let [a, b] = self.frames;
        let c = self.axis.measure(&frames[a.index()], &frames[b.index()]);
        (-self.coulomb * (c.rate / self.slip_velocity).tanh(), c)
    }
}

impl ForceElement for JointFriction {
    fn name(&self) -> &str {
        &self.name
    }
    fn frames(&self) -> &[FrameId] {
        &self.frames
    }
    fn validate(&self) -> Result<(), String> {
        nonnegative("friction", self.coulomb)?;
        if !(self.slip_velocity.is_finite() && self.slip_velocity > 0.0) {
            return Err(format!(
                "`slip_velocity` = {} must be finite and > 0",
                self.slip_velocity
            ));
        }
        Ok(())
    }
    fn wrenches(&self, _t: f64, frames: &[FrameKinematics], out: &mut [Wrench]) {
        let (q, c) = self.generalized_force(frames);
        c.wrenches(q, out);
    }
    fn output_unit(&self) -> &str {
        self.axis.force_unit()
    }
    fn output(&self, _t: f64, frames: &[FrameKinematics]) -> Option<f64> {
        Some(self.generalized_force(frames).0)
    }
}
