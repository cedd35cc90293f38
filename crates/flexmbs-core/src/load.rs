//! Loads on frames: point forces and torques with time functions, point-to-point
//! spring-dampers. Gravity is a model property ([`crate::ModelSpec::gravity`]) applied by the
//! elements.

use crate::element::FrameKinematics;
use crate::force::{ForceElementRef, Wrench, MAX_FORCE_FRAMES};
use crate::ids::FrameId;
use crate::time_function::TimeFunction;
use nalgebra::Vector3;

/// Coordinates in which a load vector is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LoadCoordinates {
    /// Global axes (fixed direction). Default.
    #[default]
    Global,
    /// Axes of the frame the load acts on (follower load).
    Frame,
}

/// A load.
#[derive(Debug, Clone, PartialEq)]
pub enum Load {
    /// Force `vector * time(t)` at the origin of `frame`.
    Force {
        /// Point of application.
        frame: FrameId,
        /// Force vector at unit time function.
        vector: Vector3<f64>,
        /// Amplitude over time.
        time: TimeFunction,
        /// Axes of `vector`.
        coordinates: LoadCoordinates,
    },
    /// Torque `vector * time(t)` on `frame`.
    Torque {
        /// Frame the torque acts on.
        frame: FrameId,
        /// Torque vector at unit time function.
        vector: Vector3<f64>,
        /// Amplitude over time.
        time: TimeFunction,
        /// Axes of `vector`.
        coordinates: LoadCoordinates,
    },
    /// Linear spring-damper between the origins of two frames, force along their connecting
    /// line: tension `f = k (l - l0) + d l_dot`. Not scaled by the static load factor.
    SpringDamper {
        /// First frame.
        frame_a: FrameId,
        /// Second frame.
        frame_b: FrameId,
        /// Stiffness `k` (>= 0).
        stiffness: f64,
        /// Damping `d` (>= 0).
        damping: f64,
        /// Free length `l0` (>= 0).
        free_length: f64,
    },
    /// A force element ([`crate::force`]: joint spring-dampers, bushings, servos, joint
    /// friction, or a user's [`crate::force::ForceElement`]). Not scaled by the static load
    /// factor.
    Element(ForceElementRef),
}

/// Most frames a load acts on ([`Load::wrenches`]).
pub const MAX_LOAD_FRAMES: usize = crate::force::MAX_FORCE_FRAMES;

/// A force and torque acting on a frame (global), to be mapped with `J_T^T f + J_R^T m`.
pub type FrameWrench = (FrameId, Vector3<f64>, Vector3<f64>);

impl Load {
    /// Global wrenches of this load on its frames at time `t` (`load_factor` scales point
    /// loads); at most [`MAX_LOAD_FRAMES`], written to `out`, returning how many.
    pub fn wrenches(
        &self,
        t: f64,
        load_factor: f64,
        frames: &[FrameKinematics],
        out: &mut [FrameWrench; MAX_LOAD_FRAMES],
    ) -> usize {
        let z = Vector3::zeros();
        match self {
            Load::Force {
                frame,
                vector,
                time,
                coordinates,
            }
            | Load::Torque {
                frame,
                vector,
                time,
                coordinates,
            } => {
                let k = &frames[frame.0];
                let mut v = vector * (time.value(t) * load_factor);
                if *coordinates == LoadCoordinates::Frame {
                    v = k.rotation * v;
                }
                out[0] = if matches!(self, Load::Force { .. }) {
                    (*frame, v, z)
                } else {
                    (*frame, z, v)
                };
                1
            }
            Load::SpringDamper {
                frame_a,
                frame_b,
                stiffness,
                damping,
                free_length,
            } => {
                let (ka, kb) = (&frames[frame_a.0], &frames[frame_b.0]);
                let d = kb.position - ka.position;
                let l = d.norm();
                // At zero length the direction is undefined: no force.
                let n = if l > 0.0 { d / l } else { z };
                let l_dot = n.dot(&(kb.velocity - ka.velocity));
                let f = stiffness * (l - free_length) + damping * l_dot;
                out[0] = (*frame_a, n * f, z);
                out[1] = (*frame_b, -n * f, z);
                2
            }
            Load::Element(e) => {
                let mut w = [Wrench::default(); MAX_FORCE_FRAMES];
                let ids = e.frames();
                e.wrenches(t, frames, &mut w);
                for ((o, id), w) in out.iter_mut().zip(ids).zip(&w) {
                    *o = (*id, w.force, w.moment);
                }
                ids.len()
            }
        }
    }

    /// The frames the load acts on, into `out`, returning how many.
    pub fn frames(&self, out: &mut [FrameId; MAX_LOAD_FRAMES]) -> usize {
        match self {
            Load::Force { frame, .. } | Load::Torque { frame, .. } => {
                out[0] = *frame;
                1
            }
            Load::SpringDamper {
                frame_a, frame_b, ..
            } => {
                out[0] = *frame_a;
                out[1] = *frame_b;
                2
            }
            Load::Element(e) => {
                let ids = e.frames();
                out[..ids.len()].copy_from_slice(ids);
                ids.len()
            }
        }
    }

    /// Whether the load's forces depend on velocities (damped springs, force elements that say
    /// so): only these get velocity columns in the tangent.
    pub fn depends_on_velocity(&self) -> bool {
        match self {
            Load::SpringDamper { damping, .. } => *damping != 0.0,
            Load::Element(e) => e.depends_on_velocity(),
            Load::Force { .. } | Load::Torque { .. } => false,
        }
    }

    /// Potential energy stored in the load (spring: `1/2 k (l - l0)^2`; point loads: 0, their
    /// work is not tracked).
    pub fn potential_energy(&self, frames: &[FrameKinematics]) -> f64 {
        match self {
            Load::SpringDamper {
                frame_a,
                frame_b,
                stiffness,
                free_length,
                ..
            } => {
                let l = (frames[frame_b.0].position - frames[frame_a.0].position).norm();
                0.5 * stiffness * (l - free_length).powi(2)
            }
            Load::Element(e) => e.potential_energy(frames),
            _ => 0.0,
        }
    }
}
