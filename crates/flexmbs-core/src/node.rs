//! Coordinate maps: where the coordinates of a body (element) or a frame's Jacobian columns lie in
//! the global `q` / `u`.

use std::ops::Range;

/// Global indices of a sequence of element-local coordinates: one contiguous range (every body
/// created by [`crate::ModelSpec::add_body`], the zero-copy case), or an explicit list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DofMap {
    /// Local coordinate `i` is global `range.start + i`.
    Contiguous(Range<usize>),
    /// Local coordinate `i` is global `indices[i]`.
    Scattered(Vec<usize>),
}

impl DofMap {
    /// Number of coordinates.
    pub fn len(&self) -> usize {
        match self {
            DofMap::Contiguous(r) => r.len(),
            DofMap::Scattered(v) => v.len(),
        }
    }

    /// No coordinates (a ground frame).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Global index of local coordinate `i`.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn global(&self, i: usize) -> usize {
        match self {
            DofMap::Contiguous(r) => {
                assert!(i < r.len(), "local coordinate {i} of {}", r.len());
                r.start + i
            }
            DofMap::Scattered(v) => v[i],
        }
    }

    /// The contiguous range, if the map is one.
    pub fn as_range(&self) -> Option<Range<usize>> {
        match self {
            DofMap::Contiguous(r) => Some(r.clone()),
            DofMap::Scattered(_) => None,
        }
    }

    /// Global indices in local order.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        let (range, list) = match self {
            DofMap::Contiguous(r) => (r.clone(), &[][..]),
            DofMap::Scattered(v) => (0..0, v.as_slice()),
        };
        range.chain(list.iter().copied())
    }
}
