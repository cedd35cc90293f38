//! Structured mesh generators (filled in by the mesh work package).
