//! Typed indices into a compiled [`crate::Model`].
//!
//! Ids are handed out by [`crate::ModelSpec`] when an item is added and stay valid in the
//! compiled model (items are never reordered).

macro_rules! typed_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub usize);

        impl $name {
            /// Position of the item in its model list.
            pub fn index(self) -> usize {
                self.0
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}({})", stringify!($name), self.0)
            }
        }
    };
}

typed_id!(
    /// A body (any [`crate::Element`]: rigid body, FFR body, superelement).
    BodyId
);
typed_id!(
    /// A node: the owner of a block of coordinates, referenced by one or several bodies.
    NodeId
);
typed_id!(
    /// A frame: the attachment point of joints, loads and springs.
    FrameId
);
typed_id!(
    /// A joint (kinematic constraint between two frames).
    JointId
);
typed_id!(
    /// A load (point force/torque, spring-damper).
    LoadId
);
