//! Force elements: forces between frames that depend on the frames' relative motion (joint
//! spring-dampers, bushings, servos, joint friction) and the open extension point for user
//! forces, [`ForceElement`].
//!
//! A force element enters the model as [`crate::Load::Element`]: it acts on up to
//! [`MAX_FORCE_FRAMES`] frames, returns one global wrench (force at the frame origin, moment)
//! per frame from the frames' kinematics, and is assembled like every load,
//! `h += J_T^T f + J_R^T m` per frame (seed 000 (2.76)). Its tangent is the local central
//! difference of the loads (`system::add_load_tangents`: only the owners of its frames are
//! perturbed, velocity columns only if [`ForceElement::depends_on_velocity`]). A user adds a force by implementing [`ForceElement`] and
//! `ModelSpec::add_load(Load::Element(ForceElementRef::new(my_force)))`; nothing else to
//! change.

mod bushing;
mod friction;
mod joint_coordinate;
mod joint_spring;
mod servo;

pub use bushing::Bushing;
pub use friction::JointFriction;
pub use joint_coordinate::{
    prismatic_displacement, revolute_angle, wrap_angle, JointAxis, JointCoordinate,
};
pub use joint_spring::JointSpringDamper;
pub use servo::{add_joint_servo, ControllerIntegrator, JointServo, ServoGains};

use crate::element::FrameKinematics;
use crate::ids::FrameId;
use nalgebra::Vector3;
use std::sync::Arc;

/// Most frames a force element acts on.
pub const MAX_FORCE_FRAMES: usize = 3;

/// A global wrench on one frame: force at the frame origin and moment (both global axes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    /// Force at the frame origin.
    pub force: Vector3<f64>,
    /// Moment.
    pub moment: Vector3<f64>,
}

/// A force element between frames: the extension point for forces that the built-in loads do
/// not cover.
///
/// Implement [`ForceElement::frames`] and [`ForceElement::wrenches`]; the rest has defaults.
/// `frames` (the argument of every method) holds the kinematics of every frame of the model at
/// the current state, indexed by [`FrameId::index`]: read those of [`ForceElement::frames`].
/// No method may allocate (they run inside a time step).
pub trait ForceElement: std::fmt::Debug + Send + Sync {
    /// Name (for messages and output signals).
    fn name(&self) -> &str;

    /// The frames the element acts on (1 to [`MAX_FORCE_FRAMES`], constant).
    fn frames(&self) -> &[FrameId];

    /// Checked by `ModelSpec::compile`: parameters in range. Err: the reason, in words.
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    /// The wrenches on [`ForceElement::frames`] at time `t`, in the same order, into
    /// `out[..frames().len()]` (global axes; the force acts at the frame origin).
    fn wrenches(&self, t: f64, frames: &[FrameKinematics], out: &mut [Wrench]);

    /// Whether the wrenches depend on the frames' velocities (if not, the tangent has no
    /// velocity columns). Default: true.
    fn depends_on_velocity(&self) -> bool {
        true
    }

    /// Potential energy stored in the element (reported with the springs' energy). Default 0.
    fn potential_energy(&self, _frames: &[FrameKinematics]) -> f64 {
        0.0
    }

    /// Power of the element's non-conservative part into the bodies (damping, friction, drive):
    /// the power of its wrenches plus the rate of its potential energy. Default: the power of
    /// the wrenches (right for an element without potential energy).
    fn nonconservative_power(&self, t: f64, frames: &[FrameKinematics]) -> f64 {
        let mut w = [Wrench::default(); MAX_FORCE_FRAMES];
        self.wrenches(t, frames, &mut w);
        wrench_power(self.frames(), &w, frames)
    }

    /// A scalar the element reports as an output signal (a servo's drive torque or force, a
    /// spring's torque or force), if it has one.
    fn output(&self, _t: f64, _frames: &[FrameKinematics]) -> Option<f64> {
        None
    }

    /// The size of the gross terms whose differences the element's forces are (e.g. a stiff
    /// spring's `k |p|`: its force `k (p_b - p_a)` carries the round-off `k eps |p|`), for
    /// Newton's round-off floor (as [`crate::Element::force_scale`]). Default 0.
    fn force_scale(&self, _frames: &[FrameKinematics]) -> f64 {
        0.0
    }

    /// Unit of [`ForceElement::output`].
    fn output_unit(&self) -> &str {
        ""
    }
}

/// The largest [`ForceElement::force_scale`] of the model's force elements at the frames
/// `frames` (0 without force elements).
pub fn force_element_scale(model: &crate::Model, frames: &[FrameKinematics]) -> f64 {
    model
        .loads
        .iter()
        .map(|l| match l {
            crate::Load::Element(e) => e.force_scale(frames),
            _ => 0.0,
        })
        .fold(0.0, f64::max)
}

/// The largest `|p|_inf` of the origins of `ids` and 1 (the scale of lengths whose differences
/// a force element forms).
pub(crate) fn position_scale(ids: &[FrameId], frames: &[FrameKinematics]) -> f64 {
    ids.iter()
        .map(|id| frames[id.index()].position.amax())
        .fold(1.0, f64::max)
}

/// The power `sum_i f_i . v_i + m_i . omega_i` of wrenches `w` on `ids` (frame kinematics in
/// `frames`).
pub fn wrench_power(ids: &[FrameId], w: &[Wrench], frames: &[FrameKinematics]) -> f64 {
    ids.iter()
        .zip(w)
        .map(|(id, w)| {
            let k = &frames[id.index()];
            w.force.dot(&k.velocity) + w.moment.dot(&k.angular_velocity)
        })
        .sum()
}

/// A shared handle to a [`ForceElement`], the payload of [`crate::Load::Element`]. Two handles
/// are equal when they point to the same element.
#[derive(Debug, Clone)]
pub struct ForceElementRef(pub Arc<dyn ForceElement>);

impl ForceElementRef {
    /// Wraps an element.
    pub fn new(element: impl ForceElement + 'static) -> Self {
        Self(Arc::new(element))
    }
}

impl std::ops::Deref for ForceElementRef {
    type Target = dyn ForceElement;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

impl PartialEq for ForceElementRef {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The checks of `ModelSpec::compile` for a force element whose frames have the owners
/// `owners`: 1 to [`MAX_FORCE_FRAMES`] frames, not all on ground, and its own
/// [`ForceElement::validate`].
pub(crate) fn check_force_element(
    e: &dyn ForceElement,
    owners: &[crate::model::FrameOwner],
) -> Result<(), crate::ModelError> {
    let bad = |reason: String| crate::ModelError::InvalidForceElement {
        element: e.name().to_string(),
        reason,
    };
    if owners.is_empty() || owners.len() > MAX_FORCE_FRAMES {
        return Err(bad(format!(
            "acts on {} frames (1 to {MAX_FORCE_FRAMES})",
            owners.len()
        )));
    }
    if owners
        .iter()
        .all(|o| *o == crate::model::FrameOwner::Ground)
    {
        return Err(bad("all its frames are on ground".into()));
    }
    e.validate().map_err(bad)
}

/// Checks that a parameter is finite and `>= 0`.
pub(crate) fn nonnegative(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(format!("`{name}` = {v} must be finite and >= 0"))
    }
}
