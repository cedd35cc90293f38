//! Eigen solvers.
