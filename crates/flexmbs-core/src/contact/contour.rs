//! Contours: the geometry of a body's surface where contact can happen, attached to a frame
//! (like joints and loads). Rigid contours are fixed in their frame: a point, a sphere, a plane
//! and a circle (a disc rim in the frame's x-y plane). Flexible contours (neutral NURBS contours
//! of FFR bodies) implement the same [`Contour`] trait with their own [`ContourKind`] and pair
//! functions in the dispatch table of [`super::pair`].

use crate::ids::FrameId;
use std::any::Any;
use std::fmt::Debug;

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
