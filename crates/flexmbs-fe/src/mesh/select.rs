//! Node selection by plane and box (filled in by the mesh work package).
