//! Contours: the geometry of a body's surface where contact can happen, attached to a frame
//! (like joints and loads). Rigid contours are fixed in their frame: a point, a sphere, a plane
//! and a circle (a disc rim in the frame's x-y plane). Flexible contours (neutral NURBS contours
//! of FFR bodies, [`super::flexible`]) implement the same [`Contour`] trait with their own
//! [`ContourKind`] and pair functions in the dispatch table of [`super::pair`]; what they
//! evaluate per state (the deformed contour, the search's warm start, the contact point's
//! Jacobian) lives in a [`ContourScratch`], created once per contact side.

use crate::element::{ElementScratch, FrameKinematics};
use crate::ids::FrameId;
use crate::model::Model;
use nalgebra::Vector3;
use std::any::Any;
use std::fmt::Debug;

/// The evaluation buffers of one contour of one contact (its content is private to the contour
/// type; rigid contours keep none). Created by [`Contour::new_scratch`].
pub struct ContourScratch(Box<dyn Any + Send + Sync>);

impl ContourScratch {
    /// Wraps a contour's own buffer type.
    pub fn new<T: Any + Send + Sync>(state: T) -> Self {
        Self(Box::new(state))
    }
    /// A scratch for a contour that keeps none.
    pub fn empty() -> Self {
        Self::new(())
    }
    /// The contour's buffers. Panics if the scratch was created by another contour type (the
    /// contact work buffers keep them in contact order, see [`super::ContactWork`]).
    pub fn get_mut<T: Any>(&mut self) -> &mut T {
        self.0
            .downcast_mut::<T>()
            .expect("contour scratch created by another contour type")
    }
    /// Read access (see [`Self::get_mut`]).
    pub fn get<T: Any>(&self) -> &T {
        self.0
            .downcast_ref::<T>()
            .expect("contour scratch created by another contour type")
    }
}

impl Debug for ContourScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ContourScratch")
    }
}

/// The geometric type of a contour: the key of the pair dispatch table
/// ([`super::pair::pair_function`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ContourKind {
    /// A point at the frame origin ([`PointContour`]).
    Point,
    /// A sphere centred at the frame origin ([`SphereContour`]).
    Sphere,
    /// A plane through the frame origin, outward normal along the frame's z axis
    /// ([`PlaneContour`]).
    Plane,
    /// A circle (disc rim) in the frame's x-y plane centred at its origin ([`CircleContour`]).
    Circle,
    /// A 2D neutral NURBS contour of an FFR body ([`super::flexible::NeutralSurface`]).
    NeutralSurface,
    /// A 1D neutral NURBS contour of an FFR body ([`super::flexible::NeutralCurve`]).
    NeutralCurve,
    /// A band of given width on a 1D neutral contour ([`super::flexible::FlexibleBand`]).
    FlexibleBand,
}

/// A contact contour attached to a frame.
pub trait Contour: Debug + Send + Sync {
    /// The geometric type (selects the pair kinematics).
    fn kind(&self) -> ContourKind;
    /// The frame the contour is fixed to (or, for a flexible contour, a frame of its body).
    fn frame(&self) -> FrameId;
    /// Checks the parameters (`Err`: what is wrong, in words).
    fn validate(&self) -> Result<(), String>;
    /// The concrete type, for the pair functions of the dispatch table.
    fn as_any(&self) -> &dyn Any;

    /// Whether the contour deforms with its body: it is evaluated from the body's evaluated
    /// state (the element scratch), its frame must be the body's reference frame, and the pair
    /// function supplies the contact point's velocity. Default `false` (rigid contours).
    fn is_flexible(&self) -> bool {
        false
    }

    /// Checks the owner body's evaluated state type (flexible contours: an FFR body with the
    /// contour's mode count). `Err`: what is wrong, in words. Default: any owner.
    fn check_owner(&self, _owner: &ElementScratch) -> Result<(), String> {
        Ok(())
    }

    /// Buffers for evaluating this contour in one contact (allocates; created once).
    fn new_scratch(&self) -> ContourScratch {
        ContourScratch::empty()
    }

    /// Adds `scale d^T J_C` to `out` (length nu): the generalized direction of a force along `d`
    /// at the contour's contact point `point`, `J_C` its velocity Jacobian. Default (a point
    /// fixed in `frame`): `d^T J_T + (s x d)^T J_R`, `s = point - r_frame`. Flexible contours
    /// use the Jacobian stored in `scratch` by their pair function.
    #[allow(clippy::too_many_arguments)]
    fn add_direction(
        &self,
        model: &Model,
        frame: &FrameKinematics,
        _scratch: &ContourScratch,
        point: &Vector3<f64>,
        d: &Vector3<f64>,
        scale: f64,
        out: &mut [f64],
    ) {
        let r = (point - frame.position).cross(d);
        let cols = model.frame_cols(self.frame());
        for j in 0..cols.len() {
            let (jt, jr) = (frame.jac_t.col_as_slice(j), frame.jac_r.col_as_slice(j));
            let mut s = 0.0;
            for k in 0..3 {
                s += d[k] * jt[k] + r[k] * jr[k];
            }
            out[cols.global(j)] += scale * s;
        }
    }
}

/// A point at the origin of `frame`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointContour {
    /// The frame.
    pub frame: FrameId,
}

/// A sphere of `radius` centred at the origin of `frame`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereContour {
    /// The frame.
    pub frame: FrameId,
    /// Radius (> 0).
    pub radius: f64,
}

/// An infinite plane through the origin of `frame`; the material lies on the negative side of
/// the frame's z axis (the outward normal), x and y are its tangent directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneContour {
    /// The frame.
    pub frame: FrameId,
}

/// A circle of `radius` in the x-y plane of `frame`, centred at its origin, material inside (a
/// disc or wheel rim; axis = frame z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircleContour {
    /// The frame.
    pub frame: FrameId,
    /// Radius (> 0).
    pub radius: f64,
}

fn check_radius(radius: f64) -> Result<(), String> {
    if radius > 0.0 && radius.is_finite() {
        Ok(())
    } else {
        Err(format!("radius {radius} must be finite and > 0"))
    }
}

macro_rules! rigid_contour {
    ($ty:ty, $kind:expr, $validate:expr) => {
        impl Contour for $ty {
            fn kind(&self) -> ContourKind {
                $kind
            }
            fn frame(&self) -> FrameId {
                self.frame
            }
            fn validate(&self) -> Result<(), String> {
                let check: fn(&$ty) -> Result<(), String> = $validate;
                check(self)
            }
            fn as_any(&self) -> &dyn Any {
                self
            }
        }
    };
}

rigid_contour!(PointContour, ContourKind::Point, |_| Ok(()));
rigid_contour!(SphereContour, ContourKind::Sphere, |c| check_radius(
    c.radius
));
rigid_contour!(PlaneContour, ContourKind::Plane, |_| Ok(()));
rigid_contour!(CircleContour, ContourKind::Circle, |c| check_radius(
    c.radius
));
