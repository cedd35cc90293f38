//! Cross-section profiles made of axis-aligned rectangles in the (y, z) plane, their exact
//! section properties, and their extrusion along x into structured hexahedral meshes.
//!
//! A profile is the union of its rectangles (they may touch or overlap). Internally the union is
//! decomposed into disjoint grid cells (grid lines through all rectangle bounds, a cell kept when
//! its centre lies in some rectangle), so area, centroid and second moments are exact sums of
//! rectangle formulas (parallel-axis theorem) even for overlapping input.
//!
//! The standard profiles are placed with the lower-left corner of their bounding box at the
//! origin (`y` from 0 to the total width, `z` from 0 to the total height); use
//! [`Profile::translated`] or [`Profile::centred`] to move them.
//!
//! Only rectilinear shapes are supported; general (curved or slanted) cross-sections need a mesh
//! from an external mesher such as CalculiX `cgx`, imported through the CalculiX reader.

use super::generate::{union_of_boxes, BoxRegion, GEOMETRIC_TOLERANCE};
use super::{BeamSection, ElementKind, Mesh};
use crate::{FeError, Material, UnitSystem};

/// An axis-aligned rectangle `[min[0], max[0]] x [min[1], max[1]]` in the (y, z) plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Lower corner (y, z).
    pub min: [f64; 2],
    /// Upper corner (y, z).
    pub max: [f64; 2],
}

impl Rect {
    /// Area of the rectangle.
    pub fn area(&self) -> f64 {
        (self.max[0] - self.min[0]) * (self.max[1] - self.min[1])
    }
    fn check(&self) -> Result<(), FeError> {
        let finite = self.min.iter().chain(&self.max).all(|v| v.is_finite());
        if !finite || self.min[0] >= self.max[0] || self.min[1] >= self.max[1] {
            return Err(FeError::Invalid(format!(
                "degenerate or non-finite rectangle: min {:?} max {:?} (need min < max in y and z)",
                self.min, self.max
            )));
        }
        Ok(())
    }
}

/// Section properties of a profile. Second moments are about axes through the centroid parallel to
/// y and z, named as in [`BeamSection`]: `iy = int (z - zc)^2 dA`, `iz = int (y - yc)^2 dA`,
/// `iyz = int (y - yc)(z - zc) dA`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProperties {
    /// Area A.
    pub area: f64,
    /// Centroid (yc, zc).
    pub centroid: [f64; 2],
    /// Second moment about the centroidal axis parallel to y.
    pub iy: f64,
    /// Second moment about the centroidal axis parallel to z.
    pub iz: f64,
    /// Product of inertia about the centroid.
    pub iyz: f64,
}

impl SectionProperties {
    /// Principal second moments `(i1, i2, theta)` with `i1 >= i2`: turning the y and z axes by the
    /// angle `theta` (radians, from y towards z) gives axes y', z' with `int z'^2 dA = i1`,
    /// `int y'^2 dA = i2` and zero product of inertia
    /// (`tan 2 theta = -2 iyz / (iy - iz)`, Mohr's circle).
    pub fn principal(&self) -> (f64, f64, f64) {
        let mean = 0.5 * (self.iy + self.iz);
        let half = 0.5 * (self.iy - self.iz);
        let r = half.hypot(self.iyz);
        (
            mean + r,
            mean - r,
            0.5 * (-2.0 * self.iyz).atan2(self.iy - self.iz),
        )
    }

    /// Beam section constants with the given Saint-Venant torsion constant `j` and shear
    /// correction factors. Fails unless y and z are principal axes (`|iyz| <= 1e-12 (iy + iz)`);
    /// for unsymmetric profiles use [`SectionProperties::principal`] and orient the beam
    /// accordingly.
    pub fn beam_section(&self, j: f64, ky: f64, kz: f64) -> Result<BeamSection, FeError> {
        if self.iyz.abs() > 1e-12 * (self.iy + self.iz) {
            return Err(FeError::Invalid(format!(
                "y and z are not principal axes of the profile (iyz = {:e}); rotate by the principal angle {:.6} rad",
                self.iyz,
                self.principal().2
            )));
        }
        if [j, ky, kz].iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(FeError::Invalid(format!(
                "torsion constant and shear factors must be > 0, got j {j}, ky {ky}, kz {kz}"
            )));
        }
        Ok(BeamSection {
            area: self.area,
            iy: self.iy,
            iz: self.iz,
            j,
            ky,
            kz,
        })
    }
}

/// A cross-section: the union of axis-aligned rectangles in the (y, z) plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    rects: Vec<Rect>,
    cells: Vec<Rect>,
}

fn positive(name: &str, v: f64) -> Result<(), FeError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FeError::Invalid(format!(
            "profile: {name} must be finite and > 0, got {v}"
        )))
    }
}

fn rect(y0: f64, y1: f64, z0: f64, z1: f64) -> Rect {
    Rect {
        min: [y0, z0],
        max: [y1, z1],
    }
}

/// Sorted coordinates with values closer than `tol` merged.
fn grid_lines(mut v: Vec<f64>, tol: f64) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup_by(|x, prev| (*x - *prev).abs() <= tol);
    v
}

/// Decomposes a region into disjoint rectangles: the cells of the grid through `ys` x `zs` whose
/// centre satisfies `inside`, merged along y into strips.
fn grid_decomposition(ys: &[f64], zs: &[f64], inside: impl Fn(f64, f64) -> bool) -> Vec<Rect> {
    let mut out = Vec::new();
    for k in 0..zs.len() - 1 {
        let zc = 0.5 * (zs[k] + zs[k + 1]);
        let mut start: Option<usize> = None;
        for i in 0..ys.len() {
            let is_in = i + 1 < ys.len() && inside(0.5 * (ys[i] + ys[i + 1]), zc);
            match (is_in, start) {
                (true, None) => start = Some(i),
                (false, Some(s)) => {
                    out.push(rect(ys[s], ys[i], zs[k], zs[k + 1]));
                    start = None;
                }
                _ => {}
            }
        }
    }
    out
}

impl Profile {
    /// The union of `rects` (touching or overlapping allowed). Fails for an empty list or a
    /// degenerate or non-finite rectangle.
    pub fn from_rectangles(rects: &[Rect]) -> Result<Self, FeError> {
        if rects.is_empty() {
            return Err(FeError::Invalid(
                "profile: the list of rectangles is empty".into(),
            ));
        }
        for (i, r) in rects.iter().enumerate() {
            r.check()
                .map_err(|e| FeError::Invalid(format!("profile rectangle {i}: {e}")))?;
        }
        let tol = GEOMETRIC_TOLERANCE * diagonal(rects);
        let ys = grid_lines(
            rects.iter().flat_map(|r| [r.min[0], r.max[0]]).collect(),
            tol,
        );
        let zs = grid_lines(
            rects.iter().flat_map(|r| [r.min[1], r.max[1]]).collect(),
            tol,
        );
        let cells = grid_decomposition(&ys, &zs, |y, z| {
            rects
                .iter()
                .any(|r| y > r.min[0] && y < r.max[0] && z > r.min[1] && z < r.max[1])
        });
        Ok(Self {
            rects: rects.to_vec(),
            cells,
        })
    }

    /// Solid rectangle, `b` wide (y) and `h` high (z): `[0, b] x [0, h]`.
    pub fn rectangle(b: f64, h: f64) -> Result<Self, FeError> {
        positive("width", b)?;
        positive("height", h)?;
        Self::from_rectangles(&[rect(0.0, b, 0.0, h)])
    }

    /// T-section: a web `web_width` wide (centred in y) and `web_height` high standing on `z = 0`,
    /// carrying a flange `flange_width` x `flange_thickness` on top (`web_width <= flange_width`).
    pub fn t_section(
        flange_width: f64,
        flange_thickness: f64,
        web_width: f64,
        web_height: f64,
    ) -> Result<Self, FeError> {
        check_flanged(flange_width, flange_thickness, web_width, web_height)?;
        let (y0, y1) = (
            0.5 * (flange_width - web_width),
            0.5 * (flange_width + web_width),
        );
        Self::from_rectangles(&[
            rect(y0, y1, 0.0, web_height),
            rect(0.0, flange_width, web_height, web_height + flange_thickness),
        ])
    }

    /// I-section (doubly symmetric): flanges `flange_width` x `flange_thickness` at the bottom and
    /// top, joined by a centred web `web_thickness` wide; `height` is the total height
    /// (`> 2 flange_thickness`, clear web height `height - 2 flange_thickness`).
    pub fn i_section(
        flange_width: f64,
        flange_thickness: f64,
        web_thickness: f64,
        height: f64,
    ) -> Result<Self, FeError> {
        positive("height", height)?;
        let web_height = height - 2.0 * flange_thickness;
        if web_height <= 0.0 {
            return Err(FeError::Invalid(format!(
                "i_section: total height {height} must exceed twice the flange thickness {flange_thickness}"
            )));
        }
        check_flanged(flange_width, flange_thickness, web_thickness, web_height)?;
        let (y0, y1) = (
            0.5 * (flange_width - web_thickness),
            0.5 * (flange_width + web_thickness),
        );
        let top = height - flange_thickness;
        Self::from_rectangles(&[
            rect(0.0, flange_width, 0.0, flange_thickness),
            rect(y0, y1, flange_thickness, top),
            rect(0.0, flange_width, top, height),
        ])
    }

    /// L-section (equal wall thickness): a horizontal leg `[0, width] x [0, thickness]` and a
    /// vertical leg `[0, thickness] x [0, height]`; see [`Profile::l_section_unequal`].
    pub fn l_section(width: f64, height: f64, thickness: f64) -> Result<Self, FeError> {
        Self::l_section_unequal(width, height, thickness, thickness)
    }

    /// L-section (angle) with unequal legs: a horizontal leg `[0, width] x [0,
    /// horizontal_thickness]` and a vertical leg `[0, vertical_thickness] x [0, height]`
    /// (thicknesses smaller than the leg lengths).
    pub fn l_section_unequal(
        width: f64,
        height: f64,
        horizontal_thickness: f64,
        vertical_thickness: f64,
    ) -> Result<Self, FeError> {
        for (n, v) in [
            ("width", width),
            ("height", height),
            ("horizontal leg thickness", horizontal_thickness),
            ("vertical leg thickness", vertical_thickness),
        ] {
            positive(n, v)?;
        }
        if horizontal_thickness >= height || vertical_thickness >= width {
            return Err(FeError::Invalid(format!(
                "l_section: leg thicknesses ({horizontal_thickness}, {vertical_thickness}) must be smaller than height {height} and width {width}"
            )));
        }
        Self::from_rectangles(&[
            rect(0.0, width, 0.0, horizontal_thickness),
            rect(0.0, vertical_thickness, 0.0, height),
        ])
    }

    /// A simple rectilinear polygon (every edge parallel to y or z) given by its vertices `(y, z)`
    /// in either orientation; the closing edge is implied (repeating the first vertex is allowed).
    /// It is decomposed into rectangles with the even-odd rule. Non-rectilinear polygons
    /// (slanted edges) are rejected: general cross-sections need a CalculiX (`cgx`) mesh.
    /// Self-intersecting input is rejected when its decomposition and shoelace areas differ.
    pub fn polygon(vertices: &[[f64; 2]]) -> Result<Self, FeError> {
        let mut v = vertices.to_vec();
        if v.len() > 1 && v.first() == v.last() {
            v.pop();
        }
        if v.len() < 4 {
            return Err(FeError::Invalid(format!(
                "polygon: a rectilinear polygon needs at least 4 vertices, got {}",
                v.len()
            )));
        }
        if v.iter().flatten().any(|c| !c.is_finite()) {
            return Err(FeError::Invalid(
                "polygon: vertex coordinates must be finite".into(),
            ));
        }
        let span = |a: usize| {
            let lo = v.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
            let hi = v.iter().map(|p| p[a]).fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        };
        let tol = GEOMETRIC_TOLERANCE * span(0).hypot(span(1));
        let n = v.len();
        let mut shoelace = 0.0;
        for i in 0..n {
            let (p, q) = (v[i], v[(i + 1) % n]);
            let (dy, dz) = ((q[0] - p[0]).abs(), (q[1] - p[1]).abs());
            if dy > tol && dz > tol {
                return Err(FeError::Invalid(format!(
                    "polygon: edge {i} from {p:?} to {q:?} is not parallel to y or z; only rectilinear \
                     polygons are supported (mesh general cross-sections with CalculiX cgx)"
                )));
            }
            if dy <= tol && dz <= tol {
                return Err(FeError::Invalid(format!(
                    "polygon: edge {i} has zero length (repeated vertex {p:?})"
                )));
            }
            shoelace += p[0] * q[1] - q[0] * p[1];
        }
        let ys = grid_lines(v.iter().map(|p| p[0]).collect(), tol);
        let zs = grid_lines(v.iter().map(|p| p[1]).collect(), tol);
        // Even-odd rule: count the edges parallel to z crossed by the ray from (y, z) towards +y.
        let inside = |y: f64, z: f64| {
            let mut crossings = 0;
            for i in 0..n {
                let (p, q) = (v[i], v[(i + 1) % n]);
                if (q[0] - p[0]).abs() <= tol
                    && p[0] > y
                    && z > p[1].min(q[1])
                    && z < p[1].max(q[1])
                {
                    crossings += 1;
                }
            }
            crossings % 2 == 1
        };
        let cells = grid_decomposition(&ys, &zs, inside);
        let area: f64 = cells.iter().map(Rect::area).sum();
        let expected = 0.5 * shoelace.abs();
        if cells.is_empty() || (area - expected).abs() > 1e-9 * expected.max(area) {
            return Err(FeError::Invalid(format!(
                "polygon: not a simple polygon (self-intersecting or degenerate): decomposed area {area} \
                 differs from shoelace area {expected}"
            )));
        }
        Ok(Self {
            rects: cells.clone(),
            cells,
        })
    }

    /// The rectangles the profile was built from.
    pub fn rectangles(&self) -> &[Rect] {
        &self.rects
    }

    /// A decomposition of the profile into disjoint rectangles (grid cells merged along y).
    pub fn disjoint_rectangles(&self) -> &[Rect] {
        &self.cells
    }

    /// The profile moved by `(dy, dz)`.
    pub fn translated(&self, dy: f64, dz: f64) -> Self {
        let mv = |r: &Rect| rect(r.min[0] + dy, r.max[0] + dy, r.min[1] + dz, r.max[1] + dz);
        Self {
            rects: self.rects.iter().map(mv).collect(),
            cells: self.cells.iter().map(mv).collect(),
        }
    }

    /// The profile moved so that its centroid is at the origin.
    pub fn centred(&self) -> Self {
        let c = self.properties().centroid;
        self.translated(-c[0], -c[1])
    }

    /// Exact area, centroid and centroidal second moments (sum over the disjoint rectangles with
    /// `b h^3 / 12` and the parallel-axis theorem).
    pub fn properties(&self) -> SectionProperties {
        let area: f64 = self.cells.iter().map(Rect::area).sum();
        let mut c = [0.0; 2];
        for r in &self.cells {
            for (a, ca) in c.iter_mut().enumerate() {
                *ca += r.area() * 0.5 * (r.min[a] + r.max[a]);
            }
        }
        c = c.map(|v| v / area);
        let (mut iy, mut iz, mut iyz) = (0.0, 0.0, 0.0);
        for r in &self.cells {
            let (b, h, a) = (r.max[0] - r.min[0], r.max[1] - r.min[1], r.area());
            let dy = 0.5 * (r.min[0] + r.max[0]) - c[0];
            let dz = 0.5 * (r.min[1] + r.max[1]) - c[1];
            iy += b * h.powi(3) / 12.0 + a * dz * dz;
            iz += h * b.powi(3) / 12.0 + a * dy * dy;
            iyz += a * dy * dz;
        }
        SectionProperties {
            area,
            centroid: c,
            iy,
            iz,
            iyz,
        }
    }

    /// Boxes `[x0, x1] x rectangle` of the disjoint rectangles (for combining extrusions with other
    /// boxes in [`union_of_boxes`]).
    pub fn boxes(&self, x0: f64, x1: f64) -> Result<Vec<BoxRegion>, FeError> {
        self.cells
            .iter()
            .map(|r| BoxRegion::new([x0, r.min[0], r.min[1]], [x1, r.max[0], r.max[1]]))
            .collect()
    }
}

fn check_flanged(
    flange_width: f64,
    flange_thickness: f64,
    web_width: f64,
    web_height: f64,
) -> Result<(), FeError> {
    for (n, v) in [
        ("flange width", flange_width),
        ("flange thickness", flange_thickness),
        ("web width", web_width),
        ("web height", web_height),
    ] {
        positive(n, v)?;
    }
    if web_width > flange_width {
        return Err(FeError::Invalid(format!(
            "profile: web width {web_width} must not exceed the flange width {flange_width}"
        )));
    }
    Ok(())
}

fn diagonal(rects: &[Rect]) -> f64 {
    let span = |a: usize| {
        let lo = rects.iter().map(|r| r.min[a]).fold(f64::INFINITY, f64::min);
        let hi = rects
            .iter()
            .map(|r| r.max[a])
            .fold(f64::NEG_INFINITY, f64::max);
        hi - lo
    };
    span(0).hypot(span(1))
}

/// Structured hexahedral mesh of `profile` extruded along x from 0 to `length`, with element
/// edges no longer than `max_size` (x, y, z); see [`union_of_boxes`]. Node sets `xmin` (the
/// section at x = 0), `xmax`, `ymin` ... `zmax`, `all`.
pub fn extrude_profile(
    profile: &Profile,
    length: f64,
    max_size: [f64; 3],
    kind: ElementKind,
    material: Material,
    units: UnitSystem,
) -> Result<Mesh, FeError> {
    positive("extrusion length", length)?;
    union_of_boxes(
        &profile.boxes(0.0, length)?,
        max_size,
        kind,
        material,
        units,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::complex_beam_boxes;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
    }

    #[test]
    fn rectangle_properties() {
        let p = Profile::rectangle(3.0, 5.0).unwrap().properties();
        assert_eq!(p.area, 15.0);
        assert_eq!(p.centroid, [1.5, 2.5]);
        assert!(rel(p.iy, 3.0 * 125.0 / 12.0) < 1e-15 && rel(p.iz, 5.0 * 27.0 / 12.0) < 1e-15);
        assert!(p.iyz.abs() < 1e-15);
        let s = p.beam_section(1.0, 5.0 / 6.0, 5.0 / 6.0).unwrap();
        let r = BeamSection::rectangle(3.0, 5.0);
        assert!(rel(s.iy, r.iy) < 1e-15 && rel(s.iz, r.iz) < 1e-15 && s.area == r.area);
        assert!(p.beam_section(0.0, 1.0, 1.0).is_err());
    }

    #[test]
    fn t_section_against_textbook() {
        // Flange 100 x 20 on a web 20 x 80 (mm). Centroid from the base:
        // zc = (2000*90 + 1600*40)/3600 = 67.78 mm; Iy = I_base - A zc^2 with
        // I_base = bf((hw+tf)^3 - hw^3)/3 + tw hw^3/3 = 3.142e6 mm^4 (textbook value 3.1422e6).
        let (bf, tf, tw, hw) = (100.0, 20.0, 20.0, 80.0);
        let p = Profile::t_section(bf, tf, tw, hw).unwrap().properties();
        let area = bf * tf + tw * hw;
        let zc = (bf * tf * (hw + tf / 2.0) + tw * hw * hw / 2.0) / area;
        let i_base = bf * ((hw + tf).powi(3) - hw.powi(3)) / 3.0 + tw * hw.powi(3) / 3.0;
        assert!(rel(p.area, 3600.0) < 1e-15);
        assert!(rel(p.centroid[1], zc) < 1e-14 && rel(p.centroid[0], 50.0) < 1e-15);
        assert!(rel(p.iy, i_base - area * zc * zc) < 1e-12, "iy {}", p.iy);
        assert!(rel(p.iy, 3_142_222.222_222) < 1e-9);
        assert!(rel(p.iz, tf * bf.powi(3) / 12.0 + hw * tw.powi(3) / 12.0) < 1e-14); // 1.72e6
        assert!(p.iyz.abs() < 1e-9 * p.iy);
        // The benchmark T: flange 20 x 5, web 9.74 x 15 (mm).
        let p = Profile::t_section(20.0, 5.0, 9.74, 15.0)
            .unwrap()
            .properties();
        assert!(rel(p.area, 100.0 + 146.1) < 1e-14);
    }

    #[test]
    fn i_section_against_textbook() {
        // Iy = (bf H^3 - (bf - tw) hw^3)/12, Iz = 2 tf bf^3/12 + hw tw^3/12, centroid at mid-height.
        // IPE 300 without root fillets: h = 300, b = 150, tw = 7.1, tf = 10.7 mm gives
        // Iy = 7.999e7 mm^4 (tables with fillets: 8.356e7).
        let (bf, tf, tw, big_h) = (150.0, 10.7, 7.1, 300.0);
        let hw = big_h - 2.0 * tf;
        let p = Profile::i_section(bf, tf, tw, big_h).unwrap().properties();
        assert!(rel(p.area, 2.0 * bf * tf + tw * hw) < 1e-14);
        assert!(rel(p.centroid[1], big_h / 2.0) < 1e-14 && rel(p.centroid[0], bf / 2.0) < 1e-14);
        assert!(rel(p.iy, (bf * big_h.powi(3) - (bf - tw) * hw.powi(3)) / 12.0) < 1e-12);
        assert!(rel(p.iz, 2.0 * tf * bf.powi(3) / 12.0 + hw * tw.powi(3) / 12.0) < 1e-12);
        assert!(rel(p.iy, 7.998_986_946e7) < 1e-9);
        assert!(p.iyz.abs() < 1e-9 * p.iy);
    }

    #[test]
    fn l_section_and_principal_axes() {
        // Equal angle 100 x 100 x 10: A = 1900, e = (1000*5 + 900*55)/1900 = 28.68 mm from the
        // outer faces, Iy = Iz = I_base - A e^2, principal axes at 45 degrees.
        let p = Profile::l_section(100.0, 100.0, 10.0).unwrap().properties();
        let e = (1000.0 * 5.0 + 900.0 * 55.0) / 1900.0;
        let i_base = 100.0 * 1000.0 / 3.0 + 10.0 * (1e6 - 1000.0) / 3.0;
        let iyz = 1000.0 * (50.0 - e) * (5.0 - e) + 900.0 * (5.0 - e) * (55.0 - e);
        assert!(rel(p.area, 1900.0) < 1e-15);
        assert!(rel(p.centroid[0], e) < 1e-14 && rel(p.centroid[1], e) < 1e-14);
        assert!(rel(p.iy, i_base - 1900.0 * e * e) < 1e-12 && rel(p.iz, p.iy) < 1e-12);
        assert!(rel(p.iyz, iyz) < 1e-12 && p.iyz < 0.0);
        let (i1, i2, theta) = p.principal();
        assert!(rel(i1, p.iy - p.iyz) < 1e-12 && rel(i2, p.iy + p.iyz) < 1e-12);
        assert!(rel(theta, std::f64::consts::FRAC_PI_4) < 1e-12);
        assert!(p.beam_section(1.0, 1.0, 1.0).is_err());
        // Unequal angle 150 x 90 x 12 x 8: the rotated moments match i1, i2 with zero product.
        let p = Profile::l_section_unequal(150.0, 90.0, 12.0, 8.0)
            .unwrap()
            .properties();
        let (i1, i2, t) = p.principal();
        let (s, c) = t.sin_cos();
        let iy_rot = p.iz * s * s + p.iy * c * c - 2.0 * p.iyz * s * c;
        let iz_rot = p.iz * c * c + p.iy * s * s + 2.0 * p.iyz * s * c;
        let iyz_rot = (p.iy - p.iz) * s * c + p.iyz * (c * c - s * s);
        assert!(rel(iy_rot, i1) < 1e-12 && rel(iz_rot, i2) < 1e-12 && iyz_rot.abs() < 1e-12 * i1);
        assert!(i1 >= i2 && i2 > 0.0);
    }

    #[test]
    fn polygons_decompose_into_rectangles() {
        // The L polygon has the properties of l_section (both orientations).
        let l = [
            [0.0, 0.0],
            [100.0, 0.0],
            [100.0, 10.0],
            [10.0, 10.0],
            [10.0, 100.0],
            [0.0, 100.0],
        ];
        let reference = Profile::l_section(100.0, 100.0, 10.0).unwrap().properties();
        let mut cw = l.to_vec();
        cw.reverse();
        cw.push(cw[0]); // explicit closing vertex
        for v in [l.to_vec(), cw] {
            let p = Profile::polygon(&v).unwrap().properties();
            assert!(rel(p.area, reference.area) < 1e-14 && rel(p.iy, reference.iy) < 1e-12);
            assert!(
                rel(p.iyz, reference.iyz) < 1e-12
                    && rel(p.centroid[0], reference.centroid[0]) < 1e-14
            );
        }
        // A U (channel) opening upwards: two separate strips in the upper rows.
        let u = [
            [0.0, 0.0],
            [6.0, 0.0],
            [6.0, 4.0],
            [5.0, 4.0],
            [5.0, 1.0],
            [1.0, 1.0],
            [1.0, 4.0],
            [0.0, 4.0],
        ];
        let pu = Profile::polygon(&u).unwrap();
        let rects = [
            Rect {
                min: [0.0, 0.0],
                max: [6.0, 1.0],
            },
            Rect {
                min: [0.0, 0.0],
                max: [1.0, 4.0],
            },
            Rect {
                min: [5.0, 0.0],
                max: [6.0, 4.0],
            },
        ];
        let pr = Profile::from_rectangles(&rects).unwrap().properties(); // overlapping input
        let p = pu.properties();
        assert!(rel(p.area, 12.0) < 1e-15 && rel(pr.area, 12.0) < 1e-15);
        assert!(
            rel(p.iy, pr.iy) < 1e-14
                && rel(p.iz, pr.iz) < 1e-14
                && rel(p.centroid[1], pr.centroid[1]) < 1e-14
        );
        let total: f64 = pu.disjoint_rectangles().iter().map(Rect::area).sum();
        assert!(rel(total, 12.0) < 1e-15);
        // Rejections: slanted edge, too few vertices, repeated vertex, self-intersection.
        let invalid = |v: &[[f64; 2]]| matches!(Profile::polygon(v), Err(FeError::Invalid(_)));
        assert!(invalid(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0]
        ]));
        assert!(invalid(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]));
        assert!(invalid(&[
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0]
        ]));
        assert!(invalid(&[
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [1.0, 2.0],
            [1.0, -1.0],
            [0.0, -1.0]
        ]));
        assert!(invalid(&[
            [0.0, 0.0],
            [f64::NAN, 0.0],
            [1.0, 1.0],
            [0.0, 1.0]
        ]));
    }

    #[test]
    fn invalid_profiles_are_rejected() {
        let invalid = |r: Result<Profile, FeError>| matches!(r, Err(FeError::Invalid(_)));
        assert!(invalid(Profile::rectangle(0.0, 1.0)));
        assert!(invalid(Profile::t_section(10.0, 1.0, 11.0, 5.0)));
        assert!(invalid(Profile::i_section(10.0, -1.0, 1.0, 5.0)));
        assert!(invalid(Profile::l_section(10.0, 10.0, 10.0)));
        assert!(invalid(Profile::l_section_unequal(10.0, 10.0, 1.0, 10.0)));
        assert!(invalid(Profile::i_section(10.0, 3.0, 1.0, 6.0)));
        assert!(invalid(Profile::from_rectangles(&[])));
        assert!(invalid(Profile::from_rectangles(&[Rect {
            min: [0.0, 0.0],
            max: [1.0, 0.0]
        }])));
    }

    #[test]
    fn centred_profile_has_centroid_at_origin() {
        let p = Profile::t_section(20.0, 5.0, 9.74, 15.0).unwrap();
        let c = p.centred();
        let (pp, pc) = (p.properties(), c.properties());
        assert!(pc.centroid[0].abs() < 1e-13 && pc.centroid[1].abs() < 1e-13);
        assert!(rel(pc.iy, pp.iy) < 1e-12 && rel(pc.iz, pp.iz) < 1e-12);
    }

    #[test]
    fn extruded_profiles() {
        let steel = Material {
            e: 210000.0,
            nu: 0.3,
            rho: 7.987e-9,
        };
        let t = Profile::t_section(20.0, 5.0, 9.74, 15.0).unwrap();
        let area = t.properties().area;
        for kind in [ElementKind::Hex8, ElementKind::Hex20R] {
            let m =
                extrude_profile(&t, 95.0, [5.0, 2.5, 2.5], kind, steel, UnitSystem::SiMm).unwrap();
            m.validate().unwrap();
            assert!(rel(m.volume().unwrap(), 95.0 * area) < 1e-12);
            // section grid: y 0|5.13|14.87|20 -> 3+4+3 cells; web rows z 0..15 -> 6, flange 2.
            // linear section nodes: flange rows 11 * 3 (z = 15, 17.5, 20) + web rows 5 * 6 = 63
            let expected = if kind == ElementKind::Hex8 {
                63
            } else {
                63 + 5 * 6 + 4 * 6 + 10 * 3 + 11 * 2
            };
            assert_eq!(m.node_set("xmin").unwrap().len(), expected, "{kind:?}");
            assert_eq!(m.node_set("xmax").unwrap().len(), expected, "{kind:?}");
            assert_eq!(m.elements.len(), 19 * (4 * 6 + 10 * 2));
        }
        assert!(extrude_profile(
            &t,
            0.0,
            [1.0; 3],
            ElementKind::Hex8,
            steel,
            UnitSystem::SiMm
        )
        .is_err());
        // The complex beam built from the profile equals complex_beam_boxes().
        let mut boxes = vec![BoxRegion::new([0.0; 3], [10.0, 20.0, 34.2]).unwrap()];
        boxes.extend(t.boxes(10.0, 105.0).unwrap());
        let a = union_of_boxes(
            &boxes,
            [5.0; 3],
            ElementKind::Hex20,
            steel,
            UnitSystem::SiMm,
        )
        .unwrap();
        let b = union_of_boxes(
            &complex_beam_boxes(),
            [5.0; 3],
            ElementKind::Hex20,
            steel,
            UnitSystem::SiMm,
        )
        .unwrap();
        assert_eq!(
            (a.num_nodes(), a.elements.len()),
            (b.num_nodes(), b.elements.len())
        );
        assert!(rel(a.volume().unwrap(), b.volume().unwrap()) < 1e-12);
    }
}
