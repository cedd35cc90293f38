//! The six faces of a mesh's axis-aligned bounding box, by the names model files use.

/// A face of a mesh's axis-aligned bounding box. Model files name them `xmin` ... `zmax` (a
/// surface contour's or a static load's `face`), and generated solid meshes carry node sets of
/// the same names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BoxFace {
    /// The face at the smallest x.
    XMin,
    /// The face at the largest x.
    XMax,
    /// The face at the smallest y.
    YMin,
    /// The face at the largest y.
    YMax,
    /// The face at the smallest z.
    ZMin,
    /// The face at the largest z.
    ZMax,
}

impl BoxFace {
    /// All six, in the order `xmin, xmax, ymin, ymax, zmin, zmax`.
    pub const ALL: [BoxFace; 6] = [
        BoxFace::XMin,
        BoxFace::XMax,
        BoxFace::YMin,
        BoxFace::YMax,
        BoxFace::ZMin,
        BoxFace::ZMax,
    ];

    /// The names a model file may give, for error messages: `xmin, xmax, ymin, ymax, zmin, zmax`.
    pub const NAMES: &'static str = "xmin, xmax, ymin, ymax, zmin, zmax";

    /// The face called `name` (`xmin` ... `zmax`), `None` for any other text.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The face's name in model files and node sets.
    pub fn name(self) -> &'static str {
        match self {
            BoxFace::XMin => "xmin",
            BoxFace::XMax => "xmax",
            BoxFace::YMin => "ymin",
            BoxFace::YMax => "ymax",
            BoxFace::ZMin => "zmin",
            BoxFace::ZMax => "zmax",
        }
    }

    /// The coordinate axis normal to the face: 0 (x), 1 (y) or 2 (z).
    pub fn axis(self) -> usize {
        self as usize / 2
    }

    /// True for the face at the largest coordinate of its axis.
    pub fn is_max(self) -> bool {
        self as usize % 2 == 1
    }

    /// The face plane's coordinate along [`BoxFace::axis`] for the bounding box `(lo, hi)`.
    pub fn plane(self, lo: [f64; 3], hi: [f64; 3]) -> f64 {
        if self.is_max() {
            hi[self.axis()]
        } else {
            lo[self.axis()]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_axes_and_planes_agree() {
        let (lo, hi) = ([-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]);
        for (i, f) in BoxFace::ALL.into_iter().enumerate() {
            assert_eq!(BoxFace::from_name(f.name()), Some(f));
            assert_eq!(f.name().as_bytes()[0], b"xyz"[f.axis()]);
            assert_eq!(f.is_max(), f.name().ends_with("max"));
            assert_eq!(f.plane(lo, hi), if i % 2 == 1 { hi } else { lo }[i / 2]);
            assert!(BoxFace::NAMES.contains(f.name()));
        }
        for bad in ["Xmin", "x", "xmid", ""] {
            assert_eq!(BoxFace::from_name(bad), None);
        }
    }
}
