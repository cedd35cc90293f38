//! Rotation parametrizations (Cardan angles, seed 000 (2.22), (2.31); quaternions).
