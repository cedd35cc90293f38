//! Material, section and boundary cards of the deck reader, and the final assembly of the
//! mesh (sections resolved to element properties, then [`Mesh::validate`]).

use super::{fields, Boundary, DataLine, InpModel, Parser, SectionDef};
use crate::calculix::Keyword;
use crate::error::excerpt;
use crate::error::IoError;
use flexmbs_fe::mesh::{BeamSection, BeamTheory, Property};
use flexmbs_fe::{Material, NodeIdx};

impl Parser {
    /// The current material and the first data line of a material option card.
    pub(super) fn material_data<'d>(
        &self,
        at: (usize, usize),
        data: &[((usize, usize), &'d str)],
        card: &str,
    ) -> Result<(String, DataLine<'d>), IoError> {
        let mat = self
            .current_material
            .clone()
            .ok_or_else(|| self.ierr(at, format!("{card} outside a *MATERIAL")))?;
        let first = *data
            .first()
            .ok_or_else(|| self.perr(at, format!("a data line after {card}"), "none"))?;
        Ok((mat, first))
    }

    pub(super) fn elastic(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        if let Some(t) = kw.param("TYPE") {
            if !matches!(t.to_uppercase().as_str(), "ISO" | "ISOTROPIC") {
                return Err(self.perr(at, "*ELASTIC, TYPE=ISO", excerpt(t)));
            }
        }
        let (mat, (lat, l)) = self.material_data(at, data, "*ELASTIC")?;
        let f = fields(l);
        if f.len() < 2 {
            return Err(self.perr(lat, "E, nu", format!("{}: {}", f.len(), excerpt(l))));
        }
        let e = self.num(lat, f[0], "Young's modulus")?;
        let nu = self.num(lat, f[1], "Poisson's ratio")?;
        if data.len() > 1 {
            self.warnings.push(format!(
                "{}: temperature-dependent *ELASTIC: only the first line is used",
                self.loc(at)
            ));
        }
        self.materials
            .get_mut(&mat)
            .expect("current material exists")
            .elastic = Some((e, nu));
        Ok(())
    }

    pub(super) fn beam_section(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        let elset = self.required(kw, at, "ELSET")?.to_uppercase();
        let material = self.required(kw, at, "MATERIAL")?.to_uppercase();
        let shape = self.required(kw, at, "SECTION")?.to_uppercase();
        let &(lat, l) = data
            .first()
            .ok_or_else(|| self.perr(at, "a data line with the section dimensions", "none"))?;
        let f = fields(l);
        let dims = f
            .iter()
            .map(|t| self.num(lat, t, "section dimension"))
            .collect::<Result<Vec<_>, _>>()?;
        if dims.iter().any(|d| *d <= 0.0) {
            return Err(self.ierr(lat, "section dimensions must be positive"));
        }
        let section = match (shape.as_str(), dims.as_slice()) {
            ("RECT", [a, b, ..]) => BeamSection::rectangle(*a, *b),
            ("CIRC", [r, ..]) => BeamSection::circle(2.0 * r),
            ("PIPE", [r, t, ..]) if t < r => BeamSection::tube(*r, *t),
            _ => {
                return Err(self.perr(
                    lat,
                    format!(
                        "dimensions of a {shape} section (RECT: a, b; CIRC: r; PIPE: r, t < r)"
                    ),
                    excerpt(l),
                ))
            }
        };
        let mut orient = [0.0, 0.0, -1.0];
        if let Some(&(oat, ol)) = data.get(1) {
            let f = fields(ol);
            if f.len() != 3 {
                return Err(self.perr(
                    oat,
                    "3 numbers (beam 1-direction)",
                    format!("{}: {}", f.len(), excerpt(ol)),
                ));
            }
            for k in 0..3 {
                orient[k] = self.num(oat, f[k], "direction component")?;
            }
        }
        self.sections.push(SectionDef {
            at,
            elset,
            material,
            beam: Some((section, orient)),
        });
        Ok(())
    }

    pub(super) fn boundary(&mut self, data: &[((usize, usize), &str)]) -> Result<(), IoError> {
        for &(at, l) in data {
            let f = fields(l);
            if f.is_empty() || f.len() > 4 {
                return Err(self.perr(
                    at,
                    "node or set, first DOF[, last DOF[, value]]",
                    excerpt(l),
                ));
            }
            let nodes: Vec<NodeIdx> = match f[0].parse::<u64>() {
                Ok(label) => vec![self.node(at, label)?],
                Err(_) => self
                    .mesh
                    .node_sets
                    .get(&f[0].to_uppercase())
                    .ok_or_else(|| {
                        self.ierr(
                            at,
                            format!("'{}' is neither a node label nor a defined node set", f[0]),
                        )
                    })?
                    .clone(),
            };
            let (first, last, value) = match f.get(1).map(|s| s.to_uppercase()) {
                Some(s) if s == "ENCASTRE" => (1, 6, 0.0),
                Some(s) if s == "PINNED" => (1, 3, 0.0),
                Some(_) => {
                    let a = self.label(at, f[1], "first DOF")?;
                    let b = match f.get(2) {
                        Some(t) => self.label(at, t, "last DOF")?,
                        None => a,
                    };
                    let v = match f.get(3) {
                        Some(t) => self.num(at, t, "prescribed value")?,
                        None => 0.0,
                    };
                    if !(1..=6).contains(&a) || !(a..=6).contains(&b) {
                        return Err(self.ierr(at, format!("DOF range {a}..{b} not within 1..6")));
                    }
                    (a as u8, b as u8, v)
                }
                None => {
                    return Err(self.perr(
                        at,
                        "node or set, first DOF[, last DOF[, value]]",
                        excerpt(l),
                    ))
                }
            };
            for &node in &nodes {
                for dof in first..=last {
                    self.boundaries.push(Boundary { node, dof, value });
                }
            }
        }
        Ok(())
    }

    pub(super) fn finish(mut self) -> Result<InpModel, IoError> {
        for s in std::mem::take(&mut self.sections) {
            let elems = self
                .elsets
                .get(&s.elset)
                .ok_or_else(|| self.ierr(s.at, format!("element set {} is not defined", s.elset)))?
                .clone();
            let m = self.materials.get(&s.material).ok_or_else(|| {
                self.ierr(s.at, format!("material {} is not defined", s.material))
            })?;
            let (e, nu) = m.elastic.ok_or_else(|| {
                self.ierr(m.at, format!("material {} has no *ELASTIC", s.material))
            })?;
            let rho = m.density.ok_or_else(|| {
                self.ierr(m.at, format!("material {} has no *DENSITY", s.material))
            })?;
            let material = Material::new(e, nu, rho)
                .map_err(|err| self.ierr(m.at, format!("material {}: {err}", s.material)))?;
            let prop = match s.beam {
                None => Property::Solid { material },
                Some((section, orientation)) => Property::Beam {
                    material,
                    section,
                    theory: BeamTheory::Timoshenko,
                    orientation,
                },
            };
            let p = self.mesh.add_property(prop);
            for e in elems {
                let (kind, prev) = (self.mesh.elements[e].kind, self.mesh.elements[e].property);
                if prev != usize::MAX {
                    return Err(self.ierr(
                        s.at,
                        format!("element {} already has a section", self.labels[e]),
                    ));
                }
                if kind.is_solid() != s.beam.is_none() {
                    return Err(self.ierr(
                        s.at,
                        format!(
                            "element {} ({kind:?}) does not fit this section type",
                            self.labels[e]
                        ),
                    ));
                }
                self.mesh.elements[e].property = p;
            }
        }
        if let Some(e) = self
            .mesh
            .elements
            .iter()
            .position(|e| e.property == usize::MAX)
        {
            return Err(self.ierr(
                self.elem_at[e],
                format!(
                    "element {} has no *SOLID SECTION or *BEAM SECTION",
                    self.labels[e]
                ),
            ));
        }
        let file = self.files[0].clone();
        self.mesh
            .validate()
            .map_err(|e| IoError::inconsistent(&file, e.to_string()))?;
        Ok(InpModel {
            mesh: self.mesh,
            element_labels: self.labels,
            element_sets: self.elsets,
            boundaries: self.boundaries,
            warnings: self.warnings,
        })
    }
}
