//! Floating frame of reference (FFR) body: inertia shape integrals, mass matrix, quadratic velocity vector, Jacobians (seed 000 ch. 2.4).
