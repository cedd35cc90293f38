//! Element matrices.
