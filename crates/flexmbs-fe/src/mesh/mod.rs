//! Finite-element meshes: nodes, elements, element properties and named node sets.
//!
//! Node order inside an element follows Abaqus/CalculiX (`C3D8`, `C3D20`, `C3D10`, `B31`).
//! Internally nodes are addressed by a dense 0-based [`NodeIdx`]; the labels a user or an
//! FE code gave them are kept in [`Mesh::node_ids`].

mod box_face;
pub mod generate;
pub mod profile;
pub mod select;
pub mod tube;

pub use box_face::BoxFace;

use crate::{FeError, Material, UnitSystem};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Dense 0-based node index into [`Mesh::nodes`].
pub type NodeIdx = usize;

/// Element formulations known to the front end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ElementKind {
    /// 8-node hexahedron, full 2x2x2 integration (CalculiX `C3D8`); locks in bending.
    Hex8,
    /// 8-node hexahedron with incompatible (bubble) modes, Wilson-Taylor (like `C3D8I`): no shear locking.
    Hex8I,
    /// 20-node serendipity hexahedron, full 3x3x3 integration (`C3D20`).
    Hex20,
    /// 20-node serendipity hexahedron, reduced 2x2x2 integration (`C3D20R`).
    Hex20R,
    /// 10-node quadratic tetrahedron (`C3D10`).
    Tet10,
    /// 2-node 3D beam, 6 DOF per node; theory and section in its [`Property::Beam`].
    Beam2,
}

impl ElementKind {
    /// Number of nodes of the element.
    pub fn num_nodes(self) -> usize {
        match self {
            ElementKind::Hex8 | ElementKind::Hex8I => 8,
            ElementKind::Hex20 | ElementKind::Hex20R => 20,
            ElementKind::Tet10 => 10,
            ElementKind::Beam2 => 2,
        }
    }
    /// Degrees of freedom per node (3 translations for solids, plus 3 rotations for beams).
    pub fn dofs_per_node(self) -> usize {
        match self {
            ElementKind::Beam2 => 6,
            _ => 3,
        }
    }
    /// Whether this is a solid (continuum) element.
    pub fn is_solid(self) -> bool {
        !matches!(self, ElementKind::Beam2)
    }
}

/// Beam theory of a [`ElementKind::Beam2`] element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum BeamTheory {
    /// Euler-Bernoulli: no shear deformation, cubic Hermite bending.
    #[default]
    EulerBernoulli,
    /// Timoshenko: shear deformation with shear correction factors (exact-stiffness two-node element).
    Timoshenko,
}

/// Cross-section constants of a beam (in the mesh's unit system). Local axes: x along the beam,
/// y and z the principal axes of the section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BeamSection {
    /// Area A.
    pub area: f64,
    /// Second moment of area about the local y axis, I_y = int z^2 dA (bending in the x-z plane).
    pub iy: f64,
    /// Second moment of area about the local z axis, I_z = int y^2 dA (bending in the x-y plane).
    pub iz: f64,
    /// Saint-Venant torsion constant J.
    pub j: f64,
    /// Shear correction factor for shear in local y (Timoshenko only).
    pub ky: f64,
    /// Shear correction factor for shear in local z (Timoshenko only).
    pub kz: f64,
}

impl BeamSection {
    /// Solid rectangle of width `b` (local y) and height `h` (local z); torsion constant from the
    /// Saint-Venant series (Roark), shear factor 5/6.
    pub fn rectangle(b: f64, h: f64) -> Self {
        let (a, c) = if b >= h { (b, h) } else { (h, b) };
        // J = a c^3 [1/3 - 0.21 (c/a)(1 - (c/a)^4/12)], accurate to < 0.5 %. For a square: 0.1406 a^4.
        let r = c / a;
        let j = a * c.powi(3) * (1.0 / 3.0 - 0.21 * r * (1.0 - r.powi(4) / 12.0));
        Self {
            area: b * h,
            iy: b * h.powi(3) / 12.0,
            iz: h * b.powi(3) / 12.0,
            j,
            ky: 5.0 / 6.0,
            kz: 5.0 / 6.0,
        }
    }
    /// Solid circle of diameter `d`: J = I_p, shear factor 6(1+nu)/(7+6nu) at nu = 0.3 is 0.886; 0.9 used.
    pub fn circle(d: f64) -> Self {
        let r = d / 2.0;
        let i = std::f64::consts::PI * r.powi(4) / 4.0;
        Self {
            area: std::f64::consts::PI * r * r,
            iy: i,
            iz: i,
            j: 2.0 * i,
            ky: 0.9,
            kz: 0.9,
        }
    }
    /// Thin-or-thick circular tube of outer radius `ro` and wall `t`; shear factor 0.5 (thin tube).
    pub fn tube(ro: f64, t: f64) -> Self {
        let ri = ro - t;
        let i = std::f64::consts::PI * (ro.powi(4) - ri.powi(4)) / 4.0;
        Self {
            area: std::f64::consts::PI * (ro * ro - ri * ri),
            iy: i,
            iz: i,
            j: 2.0 * i,
            ky: 0.5,
            kz: 0.5,
        }
    }
}

/// Element property: material and, for beams, section and theory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Property {
    /// Continuum element of a linear elastic material.
    Solid {
        /// Material.
        material: Material,
    },
    /// Beam element.
    Beam {
        /// Material.
        material: Material,
        /// Section constants.
        section: BeamSection,
        /// Theory (Euler-Bernoulli or Timoshenko).
        theory: BeamTheory,
        /// A vector in the local x-y plane that fixes the local y axis (not parallel to the beam).
        orientation: [f64; 3],
    },
}

impl Property {
    /// The material of the property.
    pub fn material(&self) -> &Material {
        match self {
            Property::Solid { material } | Property::Beam { material, .. } => material,
        }
    }
}

/// One element: its kind, its nodes (Abaqus order) and the index of its [`Property`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Element {
    /// Formulation.
    pub kind: ElementKind,
    /// Node indices in Abaqus order.
    pub nodes: Vec<NodeIdx>,
    /// Index into [`Mesh::properties`].
    pub property: usize,
}

/// A finite-element mesh in one consistent unit system.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Unit system of coordinates and properties.
    pub units: UnitSystem,
    /// Node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// External node labels (1-based by default, CalculiX labels after import); same length as `nodes`.
    pub node_ids: Vec<u64>,
    /// Elements.
    pub elements: Vec<Element>,
    /// Element properties referenced by [`Element::property`].
    pub properties: Vec<Property>,
    /// Named node sets.
    pub node_sets: BTreeMap<String, Vec<NodeIdx>>,
}

impl Mesh {
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Adds a node with label `index + 1` and returns its index.
    pub fn add_node(&mut self, x: [f64; 3]) -> NodeIdx {
        self.nodes.push(x);
        self.node_ids.push(self.nodes.len() as u64);
        self.nodes.len() - 1
    }

    /// Adds a property and returns its index.
    pub fn add_property(&mut self, p: Property) -> usize {
        self.properties.push(p);
        self.properties.len() - 1
    }

    /// Looks up a node set by name.
    pub fn node_set(&self, name: &str) -> Result<&[NodeIdx], FeError> {
        self.node_sets
            .get(name)
            .map(|v| v.as_slice())
            .ok_or_else(|| FeError::MissingNodeSet(name.to_string()))
    }

    /// Degrees of freedom of each node: 6 if any beam element uses it, 3 if only solids do,
    /// 0 if no element uses it.
    pub fn node_dofs(&self) -> Vec<usize> {
        let mut d = vec![0usize; self.nodes.len()];
        for e in &self.elements {
            for &n in &e.nodes {
                d[n] = d[n].max(e.kind.dofs_per_node());
            }
        }
        d
    }

    /// Structural check: node and property indices in range, node counts match kinds, coordinates
    /// finite, labels unique, materials valid.
    pub fn validate(&self) -> Result<(), FeError> {
        if self.node_ids.len() != self.nodes.len() {
            return Err(FeError::Invalid(format!(
                "mesh has {} nodes but {} node labels",
                self.nodes.len(),
                self.node_ids.len()
            )));
        }
        for (i, x) in self.nodes.iter().enumerate() {
            if x.iter().any(|v| !v.is_finite()) {
                return Err(FeError::Invalid(format!(
                    "node {} has a non-finite coordinate",
                    self.node_ids[i]
                )));
            }
        }
        let mut seen = std::collections::HashSet::with_capacity(self.node_ids.len());
        for id in &self.node_ids {
            if !seen.insert(*id) {
                return Err(FeError::Invalid(format!("duplicate node label {id}")));
            }
        }
        for p in &self.properties {
            p.material().validate()?;
        }
        for (ei, e) in self.elements.iter().enumerate() {
            if e.nodes.len() != e.kind.num_nodes() {
                return Err(FeError::Invalid(format!(
                    "element {ei} ({:?}) has {} nodes, expected {}",
                    e.kind,
                    e.nodes.len(),
                    e.kind.num_nodes()
                )));
            }
            if let Some(&n) = e.nodes.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(FeError::Invalid(format!(
                    "element {ei} refers to node index {n} out of range"
                )));
            }
            match self.properties.get(e.property) {
                None => {
                    return Err(FeError::Invalid(format!(
                        "element {ei} refers to missing property {}",
                        e.property
                    )))
                }
                Some(Property::Beam { .. }) if e.kind.is_solid() => {
                    return Err(FeError::Invalid(format!(
                        "solid element {ei} has a beam property"
                    )))
                }
                Some(Property::Solid { .. }) if !e.kind.is_solid() => {
                    return Err(FeError::Invalid(format!(
                        "beam element {ei} has a solid property"
                    )))
                }
                _ => {}
            }
        }
        for (name, set) in &self.node_sets {
            if let Some(&n) = set.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(FeError::Invalid(format!(
                    "node set '{name}' refers to node index {n} out of range"
                )));
            }
        }
        Ok(())
    }

    /// The same mesh expressed in SI units (coordinates and properties converted).
    pub fn to_si(&self) -> Mesh {
        let u = self.units;
        let l = u.length_to_si();
        let mut m = self.clone();
        m.units = UnitSystem::Si;
        for x in &mut m.nodes {
            for v in x.iter_mut() {
                *v *= l;
            }
        }
        for p in &mut m.properties {
            match p {
                Property::Solid { material } => *material = material.to_si(u),
                Property::Beam {
                    material, section, ..
                } => {
                    *material = material.to_si(u);
                    section.area *= l * l;
                    section.iy *= l.powi(4);
                    section.iz *= l.powi(4);
                    section.j *= l.powi(4);
                }
            }
        }
        m
    }
}
