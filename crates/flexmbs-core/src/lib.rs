//! The flexmbs multibody engine.
#![warn(missing_docs)]

pub mod ffr;
pub mod rotation;
