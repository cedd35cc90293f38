//! The TOML model file of an FE body: where the mesh comes from, its boundary conditions and the
//! reduction. Reference: `docs/model-file.md`.
//!
//! ```toml
//! [body]
//! name = "cantilever"
//! units = "SI"
//!
//! [body.mesh]
//! type = "box"
//! size = [1.0, 0.02, 0.02]
//! divisions = [40, 2, 2]
//! element = "hex20r"
//! material = { e = 210e9, nu = 0.3, rho = 7850.0 }
//!
//! [body.boundary]
//! fixed = ["xmin"]
//!
//! [body.reduction]
//! method = "modal"
//! modes = 10
//! ```

use crate::toml_locate::SpannedDoc;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::{ElementKind, Material, UnitSystem};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Errors of reading a model file: the file, the key path and what was wrong.
#[derive(Debug, Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Read {
        /// File.
        file: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or schema error at a key path (empty for syntax errors).
    #[error("{file}:{line}: {}{message}", at_key(path))]
    Schema {
        /// File.
        file: PathBuf,
        /// 1-based line (0 if unknown).
        line: usize,
        /// Key path, e.g. `body.mesh.divisions`.
        path: String,
        /// What was wrong.
        message: String,
    },
    /// A value is out of its valid range (used when its line cannot be found; see
    /// [`ModelError::Invalid`]).
    #[error("{file}: at `{path}`: {message}")]
    Value {
        /// File.
        file: PathBuf,
        /// Key path.
        path: String,
        /// What was wrong.
        message: String,
    },
    /// A value is out of its valid range or does not fit the mesh (no such node set, zero-length
    /// beam, ...), located at the line of its key.
    #[error("{file}:{line}: at `{path}`: {message}")]
    Invalid {
        /// File.
        file: PathBuf,
        /// 1-based line of the key (or of its nearest present ancestor, for a default value).
        line: usize,
        /// Key path, e.g. `body.boundary.fixed[0]`.
        path: String,
        /// What was wrong.
        message: String,
    },
    /// The file is not an FE body file at all: a multibody model file, an HDF5 or other binary
    /// file, or a TOML file without a `[body]` table.
    #[error("{file} {what}")]
    WrongKind {
        /// File.
        file: PathBuf,
        /// What the file is and what was expected.
        what: String,
    },
}

/// `at `path`: ` for a non-empty key path.
fn at_key(path: &str) -> String {
    if path.is_empty() {
        String::new()
    } else {
        format!("at `{path}`: ")
    }
}

impl ModelError {
    /// The file the error refers to.
    pub fn file(&self) -> &Path {
        match self {
            ModelError::Read { file, .. }
            | ModelError::Schema { file, .. }
            | ModelError::Value { file, .. }
            | ModelError::Invalid { file, .. }
            | ModelError::WrongKind { file, .. } => file,
        }
    }

    /// The 1-based line the error refers to, if known.
    pub fn line(&self) -> Option<usize> {
        match self {
            ModelError::Schema { line, .. } | ModelError::Invalid { line, .. } if *line > 0 => {
                Some(*line)
            }
            _ => None,
        }
    }

    /// The key path the error refers to (`None` for syntax errors and whole-file errors).
    pub fn key_path(&self) -> Option<&str> {
        match self {
            ModelError::Schema { path, .. }
            | ModelError::Value { path, .. }
            | ModelError::Invalid { path, .. }
                if !path.is_empty() =>
            {
                Some(path)
            }
            _ => None,
        }
    }
}

/// A model file holding one FE body.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeModelFile {
    /// The body.
    pub body: FeBodySpec,
}

/// An FE body: mesh source, boundary conditions and reduction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeBodySpec {
    /// Body name.
    pub name: String,
    /// Unit system of the mesh data (default `SI`; `SI(mm)` = mm, N, t, s).
    #[serde(default)]
    pub units: UnitSystem,
    /// Where the mesh comes from.
    pub mesh: MeshSpec,
    /// Fixed node sets and rigid interfaces.
    #[serde(default)]
    pub boundary: BoundarySpec,
    /// Reduction.
    #[serde(default)]
    pub reduction: ReductionSpec,
}

/// Material constants in the body's unit system.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Young's modulus.
    #[serde(deserialize_with = "crate::fe_quantity::pressure")]
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Density.
    #[serde(deserialize_with = "crate::fe_quantity::density")]
    pub rho: f64,
}

impl From<MaterialSpec> for Material {
    fn from(m: MaterialSpec) -> Self {
        Material {
            e: m.e,
            nu: m.nu,
            rho: m.rho,
        }
    }
}

/// Element names accepted in model files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementName {
    /// 8-node hexahedron, full integration.
    Hex8,
    /// 8-node hexahedron with incompatible modes (default linear element).
    Hex8i,
    /// 20-node hexahedron, full integration.
    Hex20,
    /// 20-node hexahedron, reduced integration (as CalculiX C3D20R).
    Hex20r,
}

impl From<ElementName> for ElementKind {
    fn from(e: ElementName) -> Self {
        match e {
            ElementName::Hex8 => ElementKind::Hex8,
            ElementName::Hex8i => ElementKind::Hex8I,
            ElementName::Hex20 => ElementKind::Hex20,
            ElementName::Hex20r => ElementKind::Hex20R,
        }
    }
}

/// An axis-aligned box `[min, max]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Lower corner.
    #[serde(deserialize_with = "crate::fe_quantity::length3")]
    pub min: [f64; 3],
    /// Upper corner.
    #[serde(deserialize_with = "crate::fe_quantity::length3")]
    pub max: [f64; 3],
}

/// A cross-section profile in the (y, z) plane, extruded along x.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase", deny_unknown_fields)]
pub enum ProfileSpec {
    /// Rectangle `width` (y) x `height` (z).
    Rectangle {
        /// Width in y.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        width: f64,
        /// Height in z.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        height: f64,
    },
    /// T section: flange on top (z max), web centred below.
    T {
        /// Flange width (y).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        flange_width: f64,
        /// Flange thickness (z).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        flange_thickness: f64,
        /// Web width (y).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        web_width: f64,
        /// Web height (z, without the flange).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        web_height: f64,
    },
    /// L section: vertical leg at y = 0, horizontal leg at z = 0.
    L {
        /// Leg length along y.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        width: f64,
        /// Leg length along z.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        height: f64,
        /// Wall thickness.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        thickness: f64,
    },
    /// I section: two flanges and a centred web.
    I {
        /// Flange width (y).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        flange_width: f64,
        /// Flange thickness (z).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        flange_thickness: f64,
        /// Web thickness (y).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        web_thickness: f64,
        /// Total height (z).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        height: f64,
    },
    /// Rectilinear polygon with vertices `[y, z]`.
    Polygon {
        /// Vertices in order.
        #[serde(deserialize_with = "crate::fe_quantity::vertices")]
        vertices: Vec<[f64; 2]>,
    },
}

/// Beam cross-section.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase", deny_unknown_fields)]
pub enum SectionSpec {
    /// Solid rectangle.
    Rectangle {
        /// Width (local y).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        width: f64,
        /// Height (local z).
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        height: f64,
    },
    /// Solid circle.
    Circle {
        /// Diameter.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        diameter: f64,
    },
    /// Circular tube.
    Tube {
        /// Outer radius.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        outer_radius: f64,
        /// Wall thickness.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        wall: f64,
    },
    /// Section constants given directly.
    General {
        /// Area.
        #[serde(deserialize_with = "crate::fe_quantity::area")]
        area: f64,
        /// Second moment about local y.
        #[serde(deserialize_with = "crate::fe_quantity::area_moment")]
        iy: f64,
        /// Second moment about local z.
        #[serde(deserialize_with = "crate::fe_quantity::area_moment")]
        iz: f64,
        /// Torsion constant.
        #[serde(deserialize_with = "crate::fe_quantity::area_moment")]
        j: f64,
        /// Shear factor in y.
        #[serde(default = "five_sixths")]
        ky: f64,
        /// Shear factor in z.
        #[serde(default = "five_sixths")]
        kz: f64,
    },
}

fn five_sixths() -> f64 {
    5.0 / 6.0
}

impl From<SectionSpec> for BeamSection {
    fn from(s: SectionSpec) -> Self {
        match s {
            SectionSpec::Rectangle { width, height } => BeamSection::rectangle(width, height),
            SectionSpec::Circle { diameter } => BeamSection::circle(diameter),
            SectionSpec::Tube { outer_radius, wall } => BeamSection::tube(outer_radius, wall),
            SectionSpec::General {
                area,
                iy,
                iz,
                j,
                ky,
                kz,
            } => BeamSection {
                area,
                iy,
                iz,
                j,
                ky,
                kz,
            },
        }
    }
}

/// Beam theory names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TheoryName {
    /// Euler-Bernoulli.
    #[default]
    EulerBernoulli,
    /// Timoshenko.
    Timoshenko,
}

impl From<TheoryName> for BeamTheory {
    fn from(t: TheoryName) -> Self {
        match t {
            TheoryName::EulerBernoulli => BeamTheory::EulerBernoulli,
            TheoryName::Timoshenko => BeamTheory::Timoshenko,
        }
    }
}

/// How CalculiX matrices are obtained for a deck.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum CcxMatrices {
    /// Assemble the deck's mesh with flexmbs's own elements.
    #[default]
    Flexmbs,
    /// Run `ccx` with `*FREQUENCY, SOLVER=MATRIXSTORAGE` and import its K and M.
    Ccx,
}

/// Source of the mesh.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MeshSpec {
    /// Structured box `[0, size]` with `divisions` elements per axis.
    Box {
        /// Edge lengths.
        #[serde(deserialize_with = "crate::fe_quantity::length3")]
        size: [f64; 3],
        /// Elements per axis.
        divisions: [usize; 3],
        /// Element type (default hex20r).
        #[serde(default = "default_element")]
        element: ElementName,
        /// Material.
        material: MaterialSpec,
    },
    /// Union of axis-aligned boxes (stepped blocks, the complex beam).
    Boxes {
        /// The boxes.
        boxes: Vec<BoxSpec>,
        /// Largest element edge per axis.
        #[serde(deserialize_with = "crate::fe_quantity::length3")]
        element_size: [f64; 3],
        /// Element type.
        #[serde(default = "default_element")]
        element: ElementName,
        /// Material.
        material: MaterialSpec,
    },
    /// A profile extruded along x.
    Profile {
        /// Cross-section.
        profile: ProfileSpec,
        /// Length along x.
        #[serde(deserialize_with = "crate::fe_quantity::length")]
        length: f64,
        /// Largest element edge per axis.
        #[serde(deserialize_with = "crate::fe_quantity::length3")]
        element_size: [f64; 3],
        /// Element type.
        #[serde(default = "default_element")]
        element: ElementName,
        /// Material.
        material: MaterialSpec,
    },
    /// Straight beam of 2-node beam elements.
    Beam {
        /// Start point.
        #[serde(deserialize_with = "crate::fe_quantity::length3")]
        start: [f64; 3],
        /// End point.
        #[serde(deserialize_with = "crate::fe_quantity::length3")]
        end: [f64; 3],
        /// Number of elements.
        elements: usize,
        /// Section.
        section: SectionSpec,
        /// Theory.
        #[serde(default)]
        theory: TheoryName,
        /// Vector in the local x-y plane (default: global y, or global z for beams along y).
        orientation: Option<[f64; 3]>,
        /// Material.
        material: MaterialSpec,
    },
    /// A CalculiX (Abaqus-format) deck.
    Calculix {
        /// Path of the `.inp` deck (relative to the model file).
        deck: PathBuf,
        /// Where K and M come from.
        #[serde(default)]
        matrices: CcxMatrices,
    },
    /// A seed 000 4-file folder (already reduced).
    Seed {
        /// Folder with u0.dat, modeShapeMatrix.dat, mij.dat, stiffnessMatrix.dat.
        dir: PathBuf,
    },
}

fn default_element() -> ElementName {
    ElementName::Hex20r
}

/// A node selection: a node-set name, or a table with one of `plane`, `within`, `nearest`
/// (deserialized in `model_check.rs`, whose errors list these forms).
#[derive(Debug, Clone)]
pub enum NodeSelector {
    /// A named node set (generator sets like `xmin`, CalculiX `*NSET` names).
    Set(String),
    /// Nodes on the plane `axis = value`.
    Plane {
        /// Plane description.
        plane: PlaneSpec,
    },
    /// Nodes inside a box.
    Within {
        /// The box.
        within: BoxSpec,
    },
    /// The node nearest to a point.
    Nearest {
        /// The point.
        nearest: [f64; 3],
    },
}

/// A coordinate plane.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    /// `x`, `y` or `z`.
    pub axis: String,
    /// Coordinate value.
    #[serde(deserialize_with = "crate::fe_quantity::length")]
    pub value: f64,
    /// Tolerance (default 1e-9 x model size).
    #[serde(default, deserialize_with = "crate::fe_quantity::opt_length")]
    pub tol: Option<f64>,
}

/// A rigid interface (RBE2-like).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidSpec {
    /// Name of the interface (usable in `reduction.interface`).
    pub name: String,
    /// Slave nodes.
    pub nodes: NodeSelector,
    /// Interface node location (default: centroid of the nodes).
    #[serde(default, deserialize_with = "crate::fe_quantity::opt_length3")]
    pub point: Option<[f64; 3]>,
}

/// Boundary conditions.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Node selections whose DOFs are all fixed.
    #[serde(default)]
    pub fixed: Vec<NodeSelector>,
    /// Rigid interfaces.
    #[serde(default)]
    pub rigid: Vec<RigidSpec>,
}

/// Reduction methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ReductionMethod {
    /// Normal modes (constrained, or free-free without fixed nodes).
    #[default]
    Modal,
    /// Craig-Bampton with `modes` fixed-interface modes.
    CraigBampton,
    /// Guyan (Craig-Bampton without internal modes).
    Guyan,
}

/// Mass formulation names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum MassName {
    /// Lumped node masses (HRZ), as the seed's FFR body needs.
    #[default]
    Lumped,
    /// Consistent mass.
    Consistent,
}

/// Eigen solver choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SolverName {
    /// Dense below 1500 DOFs, block Lanczos above.
    #[default]
    Auto,
    /// Dense Cholesky + symmetric eigensolver.
    Dense,
    /// Block shift-invert Lanczos.
    Lanczos,
}

/// Reduction settings.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReductionSpec {
    /// Method (default `modal`).
    #[serde(default)]
    pub method: ReductionMethod,
    /// Number of modes (elastic modes for `modal`, fixed-interface modes for `craig-bampton`; default 10).
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Interface: names of rigid interfaces or node selections (Craig-Bampton and Guyan).
    #[serde(default)]
    pub interface: Vec<NodeSelector>,
    /// Mass formulation (default lumped).
    #[serde(default)]
    pub mass: MassName,
    /// Eigen solver (default auto).
    #[serde(default)]
    pub solver: SolverName,
    /// Spectral shift (default automatic).
    pub shift: Option<f64>,
    /// Relative residual tolerance of the eigen solver (default 1e-9).
    #[serde(default = "default_tol")]
    pub tol: f64,
    /// Static load patterns whose static responses `K^-1 f` enrich a modal basis (modal
    /// truncation augmentation; default none): one more basis vector per load, for the local
    /// deformation under a contact or a point load that the lowest modes lack.
    #[serde(default)]
    pub static_loads: Vec<StaticLoadSpec>,
}

/// A static load pattern of [`ReductionSpec::static_loads`]: a total force of unit size along
/// `direction`, shared equally by the selected nodes (`nodes`), or acting at a point of a solid
/// mesh as its consistent nodal loads (`point`); exactly one of the two. With `face` (and
/// `point`), the force acts at the point of the cubic NURBS surface through the face's nodes
/// nearest to `point`, shared by those nodes with the surface's interpolation weights: what a
/// `surface` contour on that face transmits there.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticLoadSpec {
    /// The loaded nodes.
    #[serde(default)]
    pub nodes: Option<NodeSelector>,
    /// The loaded point (body coordinates, length units of the file).
    #[serde(default, deserialize_with = "crate::fe_quantity::opt_length3")]
    pub point: Option<[f64; 3]>,
    /// A bounding-box face (`xmin` ... `zmax`) whose NURBS surface carries the `point`.
    #[serde(default)]
    pub face: Option<String>,
    /// Direction of the force (body axes; normalised).
    pub direction: [f64; 3],
}

fn default_tol() -> f64 {
    1e-9
}

fn default_modes() -> usize {
    10
}

impl Default for ReductionSpec {
    fn default() -> Self {
        Self {
            method: ReductionMethod::Modal,
            modes: default_modes(),
            interface: Vec::new(),
            mass: MassName::Lumped,
            solver: SolverName::Auto,
            shift: None,
            tol: default_tol(),
            static_loads: Vec::new(),
        }
    }
}

/// Parses a model file's text; `file` names it in errors. Syntax errors, unknown keys, wrong types,
/// missing keys and out-of-range values are reported with their line and key path.
pub fn parse_fe_model(text: &str, file: &Path) -> Result<FeModelFile, ModelError> {
    let root = toml::de::DeTable::parse(text)
        .map_err(|e| crate::model_check::syntax_error(text, file, &e))?;
    let doc = SpannedDoc::new(text, root.clone());
    crate::model_check::check_kind(&doc, file)?;
    let de = toml::Deserializer::from(root);
    let _units = crate::fe_quantity::UnitsScope::new(declared_units(text));
    let model: FeModelFile = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let r = crate::model_locate::refine(
            &doc,
            &path,
            inner.message(),
            inner.span().map(|s| s.start),
        );
        ModelError::Schema {
            file: file.to_path_buf(),
            line: doc.line(r.offset),
            path: r.path,
            message: r.message,
        }
    })?;
    crate::model_check::check_values(&model, file).map_err(|e| e.located(&doc))?;
    Ok(model)
}

/// `body.units` as written (SI when absent or not a known name: the schema reports a bad name),
/// needed before the rest is read because unit strings are converted to it.
fn declared_units(text: &str) -> flexmbs_fe::UnitSystem {
    let units = toml::from_str::<toml::Value>(text).ok().and_then(|v| {
        v.get("body")?
            .get("units")
            .and_then(|u| u.as_str().map(str::to_string))
    });
    match units.as_deref() {
        Some("SI(mm)" | "SI_mm" | "mm") => flexmbs_fe::UnitSystem::SiMm,
        _ => flexmbs_fe::UnitSystem::Si,
    }
}

/// Reads and parses a model file. An HDF5 or other binary file, or a multibody model file, is
/// reported as [`ModelError::WrongKind`].
pub fn read_fe_model(path: &Path) -> Result<FeModelFile, ModelError> {
    read_fe_model_text(path).map(|(_, m)| m)
}

/// [`read_fe_model`], also returning the file's text.
pub(crate) fn read_fe_model_text(path: &Path) -> Result<(String, FeModelFile), ModelError> {
    let bytes = crate::source_file::read(path).map_err(|source| ModelError::Read {
        file: path.into(),
        source,
    })?;
    let text = crate::model_check::model_text(&bytes, path)?;
    let model = parse_fe_model(text, path)?;
    Ok((text.to_string(), model))
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
[body]
name = "cantilever"
[body.mesh]
type = "box"
size = [1.0, 0.02, 0.02]
divisions = [40, 2, 2]
element = "hex20r"
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.boundary]
fixed = ["xmin", { plane = { axis = "x", value = 0.0 } }]
[[body.boundary.rigid]]
name = "tip"
nodes = "xmax"
[body.reduction]
method = "craig-bampton"
modes = 4
interface = ["tip"]
"#;

    #[test]
    fn parses_a_complete_model() {
        let m = parse_fe_model(GOOD, Path::new("m.toml")).unwrap();
        assert_eq!(m.body.name, "cantilever");
        assert_eq!(m.body.reduction.method, ReductionMethod::CraigBampton);
        assert_eq!(m.body.boundary.fixed.len(), 2);
        assert!(matches!(
            m.body.mesh,
            MeshSpec::Box {
                divisions: [40, 2, 2],
                ..
            }
        ));
    }

    #[test]
    fn unknown_key_inside_variant_names_path_and_line() {
        let bad = GOOD.replace("divisions = [40, 2, 2]", "divisons = [40, 2, 2]");
        let e = parse_fe_model(&bad, Path::new("m.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("m.toml:"), "{e}");
        assert!(e.contains("divisons") || e.contains("divisions"), "{e}");
    }

    #[test]
    fn wrong_type_names_key_path() {
        let bad = GOOD.replace("modes = 4", "modes = \"four\"");
        let e = parse_fe_model(&bad, Path::new("m.toml")).unwrap_err();
        let s = e.to_string();
        assert!(s.contains("body.reduction.modes"), "{s}");
        assert!(s.contains("m.toml:17") || s.contains("m.toml:"), "{s}");
    }

    #[test]
    fn bad_material_is_a_value_error() {
        let bad = GOOD.replace("nu = 0.3", "nu = 0.7");
        let s = parse_fe_model(&bad, Path::new("m.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            s.contains("body.mesh.material") && s.contains("Poisson"),
            "{s}"
        );
    }

    #[test]
    fn craig_bampton_without_interface_is_rejected() {
        let bad = GOOD.replace("interface = [\"tip\"]", "");
        let s = parse_fe_model(&bad, Path::new("m.toml"))
            .unwrap_err()
            .to_string();
        assert!(s.contains("body.reduction.interface"), "{s}");
    }
}
