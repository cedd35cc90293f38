//! Reader of Abaqus-format decks as CalculiX reads them (`.inp`) into a [`Mesh`].
//!
//! Supported: `*NODE [, NSET=]`, `*ELEMENT, TYPE=C3D8|C3D8I|C3D20|C3D20R|C3D10|B31 [, ELSET=]`
//! (data split over continuation lines, as for 20-node elements), `*NSET`/`*ELSET` (labels, set
//! names, `GENERATE`), `*MATERIAL, NAME=`, `*ELASTIC` (isotropic), `*DENSITY`,
//! `*SOLID SECTION, ELSET=, MATERIAL=`, `*BEAM SECTION, ELSET=, MATERIAL=, SECTION=RECT|CIRC|PIPE`,
//! `*BOUNDARY` (node or set, first DOF, last DOF, value; `ENCASTRE`, `PINNED`), `*INCLUDE, INPUT=`
//! (relative to the including file). Keywords, parameters, set and material names are
//! case-insensitive (stored upper case, as CalculiX does); `**` starts a comment line. Unknown
//! keywords are skipped with their data lines and reported in [`InpModel::warnings`].
//!
//! Node labels are mapped to dense indices in order of definition; [`Mesh::node_ids`] keeps
//! the labels. A deck carries no units: the caller states them.

use super::{is_comment_or_blank, Keyword};
use crate::error::{excerpt, parse_finite, read_text, IoError};
use flexmbs_fe::mesh::{BeamSection, Element};
use flexmbs_fe::{ElementKind, Mesh, NodeIdx, UnitSystem};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

mod props;

/// Maximum nesting depth of `*INCLUDE` (guards against include cycles).
const MAX_INCLUDE_DEPTH: usize = 16;

/// One prescribed degree of freedom from `*BOUNDARY`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Boundary {
    /// Dense node index into [`Mesh::nodes`].
    pub node: NodeIdx,
    /// DOF 1..=6 (1-3 translations x, y, z; 4-6 rotations).
    pub dof: u8,
    /// Prescribed value (0 for a clamp).
    pub value: f64,
}

/// A deck read into a mesh plus what the mesh type does not hold.
#[derive(Debug, Clone)]
pub struct InpModel {
    /// The mesh (node sets included, keyed by upper-case name).
    pub mesh: Mesh,
    /// Label of each element of `mesh.elements`.
    pub element_labels: Vec<u64>,
    /// Element sets (upper-case name -> element indices into `mesh.elements`).
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// Prescribed DOFs from all `*BOUNDARY` cards, one entry per DOF.
    pub boundaries: Vec<Boundary>,
    /// Skipped keywords and other non-fatal remarks, each located `file:line`.
    pub warnings: Vec<String>,
}

/// A data line with its location (file index, 1-based line).
type DataLine<'d> = ((usize, usize), &'d str);

/// One physical line of the flattened deck.
struct SrcLine {
    file: usize,
    line: usize,
    text: String,
}

/// Reads a deck from disk; `*INCLUDE` files are read relative to the including file.
pub fn read_inp(path: &Path, units: UnitSystem) -> Result<InpModel, IoError> {
    parse_inp(&read_text(path)?, path, units)
}

/// Parses a deck given as text; `*INCLUDE` files are read from disk relative to `file`'s folder.
pub fn parse_inp(text: &str, file: &Path, units: UnitSystem) -> Result<InpModel, IoError> {
    parse_inp_with(text, file, units, &mut |p: &Path| read_text(p))
}

/// Parses a deck given as text; `include` returns the text of an `*INCLUDE`d file (its path
/// resolved relative to the including file). Pure if `include` is.
pub fn parse_inp_with(
    text: &str,
    file: &Path,
    units: UnitSystem,
    include: &mut dyn FnMut(&Path) -> Result<String, IoError>,
) -> Result<InpModel, IoError> {
    let mut files = Vec::new();
    let mut lines = Vec::new();
    flatten(text, file, 0, include, &mut files, &mut lines)?;
    Parser::new(files, units).run(&lines)
}

/// Resolves `*INCLUDE` recursively into one list of located lines.
fn flatten(
    text: &str,
    file: &Path,
    depth: usize,
    include: &mut dyn FnMut(&Path) -> Result<String, IoError>,
    files: &mut Vec<PathBuf>,
    out: &mut Vec<SrcLine>,
) -> Result<(), IoError> {
    let fi = files.len();
    files.push(file.to_path_buf());
    for (i, l) in text.lines().enumerate() {
        if let Some(kw) = Keyword::parse(l).filter(|k| k.name == "INCLUDE") {
            let Some(input) = kw.param("INPUT") else {
                return Err(IoError::parse(
                    file,
                    i + 1,
                    "*INCLUDE, INPUT=<file>",
                    excerpt(l),
                ));
            };
            if depth + 1 >= MAX_INCLUDE_DEPTH {
                return Err(IoError::invalid(
                    file,
                    i + 1,
                    format!("*INCLUDE nested deeper than {MAX_INCLUDE_DEPTH}"),
                ));
            }
            let p = Path::new(input);
            let p = if p.is_absolute() {
                p.to_path_buf()
            } else {
                file.parent().unwrap_or(Path::new("")).join(p)
            };
            let sub = include(&p)?;
            flatten(&sub, &p, depth + 1, include, files, out)?;
        } else {
            out.push(SrcLine {
                file: fi,
                line: i + 1,
                text: l.to_string(),
            });
        }
    }
    Ok(())
}

/// A material being defined.
#[derive(Default)]
struct MatDef {
    at: (usize, usize),
    elastic: Option<(f64, f64)>,
    density: Option<f64>,
}

/// A section card waiting for its element set and material.
struct SectionDef {
    at: (usize, usize),
    elset: String,
    material: String,
    beam: Option<(BeamSection, [f64; 3])>,
}

struct Parser {
    files: Vec<PathBuf>,
    mesh: Mesh,
    node_of: HashMap<u64, (NodeIdx, (usize, usize))>,
    elem_of: HashMap<u64, usize>,
    elem_at: Vec<(usize, usize)>,
    labels: Vec<u64>,
    elsets: BTreeMap<String, Vec<usize>>,
    materials: BTreeMap<String, MatDef>,
    current_material: Option<String>,
    sections: Vec<SectionDef>,
    boundaries: Vec<Boundary>,
    warnings: Vec<String>,
}

/// Splits a data line at commas, trimmed, without the empty token of a trailing comma.
fn fields(l: &str) -> Vec<&str> {
    let mut t: Vec<&str> = l.split(',').map(str::trim).collect();
    while t.last().is_some_and(|s| s.is_empty()) {
        t.pop();
    }
    t
}

fn element_kind(t: &str) -> Option<ElementKind> {
    Some(match t {
        "C3D8" => ElementKind::Hex8,
        "C3D8I" => ElementKind::Hex8I,
        "C3D20" => ElementKind::Hex20,
        "C3D20R" => ElementKind::Hex20R,
        "C3D10" => ElementKind::Tet10,
        "B31" => ElementKind::Beam2,
        _ => return None,
    })
}

impl Parser {
    fn new(files: Vec<PathBuf>, units: UnitSystem) -> Self {
        Self {
            files,
            mesh: Mesh {
                units,
                ..Mesh::default()
            },
            node_of: HashMap::new(),
            elem_of: HashMap::new(),
            elem_at: Vec::new(),
            labels: Vec::new(),
            elsets: BTreeMap::new(),
            materials: BTreeMap::new(),
            current_material: None,
            sections: Vec::new(),
            boundaries: Vec::new(),
            warnings: Vec::new(),
        }
    }

    fn loc(&self, at: (usize, usize)) -> String {
        format!("{}:{}", self.files[at.0].display(), at.1)
    }
    fn perr(
        &self,
        at: (usize, usize),
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> IoError {
        IoError::parse(&self.files[at.0], at.1, expected, found)
    }
    fn ierr(&self, at: (usize, usize), what: impl Into<String>) -> IoError {
        IoError::invalid(&self.files[at.0], at.1, what)
    }
    fn num(&self, at: (usize, usize), tok: &str, what: &str) -> Result<f64, IoError> {
        parse_finite(tok, &self.files[at.0], at.1, what)
    }
    fn label(&self, at: (usize, usize), tok: &str, what: &str) -> Result<u64, IoError> {
        tok.parse::<u64>()
            .map_err(|_| self.perr(at, format!("an integer {what}"), excerpt(tok)))
    }
    fn node(&self, at: (usize, usize), label: u64) -> Result<NodeIdx, IoError> {
        self.node_of
            .get(&label)
            .map(|n| n.0)
            .ok_or_else(|| self.ierr(at, format!("node {label} is not defined")))
    }

    fn run(mut self, lines: &[SrcLine]) -> Result<InpModel, IoError> {
        let mut i = 0;
        while i < lines.len() {
            let l = &lines[i];
            let at = (l.file, l.line);
            i += 1;
            if is_comment_or_blank(&l.text) {
                continue;
            }
            let Some(kw) = Keyword::parse(&l.text) else {
                return Err(self.perr(at, "a keyword line (*KEYWORD)", excerpt(&l.text)));
            };
            let mut data = Vec::new();
            while i < lines.len() && Keyword::parse(&lines[i].text).is_none() {
                if !is_comment_or_blank(&lines[i].text) {
                    data.push(((lines[i].file, lines[i].line), lines[i].text.as_str()));
                }
                i += 1;
            }
            if !matches!(kw.name.as_str(), "ELASTIC" | "DENSITY") && self.is_known(&kw.name) {
                self.current_material = None;
            }
            self.keyword(&kw, at, &data)?;
        }
        self.finish()
    }

    fn is_known(&self, name: &str) -> bool {
        matches!(
            name,
            "NODE"
                | "ELEMENT"
                | "NSET"
                | "ELSET"
                | "MATERIAL"
                | "SOLID SECTION"
                | "BEAM SECTION"
                | "BOUNDARY"
                | "STEP"
        )
    }

    fn keyword(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        match kw.name.as_str() {
            "NODE" => self.nodes(kw, data),
            "ELEMENT" => self.elements(kw, at, data),
            "NSET" => self.nset(kw, at, data),
            "ELSET" => self.elset(kw, at, data),
            "MATERIAL" => {
                let name = self.required(kw, at, "NAME")?.to_uppercase();
                if let Some(prev) = self.materials.get(&name) {
                    return Err(self.ierr(
                        at,
                        format!(
                            "material {name} defined twice (first at {})",
                            self.loc(prev.at)
                        ),
                    ));
                }
                self.materials.insert(
                    name.clone(),
                    MatDef {
                        at,
                        ..MatDef::default()
                    },
                );
                self.current_material = Some(name);
                Ok(())
            }
            "ELASTIC" => self.elastic(kw, at, data),
            "DENSITY" => {
                let (mat, first) = self.material_data(at, data, "*DENSITY")?;
                let f = fields(first.1);
                let rho = self.num(first.0, f.first().copied().unwrap_or(""), "density")?;
                self.materials
                    .get_mut(&mat)
                    .expect("current material exists")
                    .density = Some(rho);
                Ok(())
            }
            "SOLID SECTION" => {
                let elset = self.required(kw, at, "ELSET")?.to_uppercase();
                let material = self.required(kw, at, "MATERIAL")?.to_uppercase();
                self.sections.push(SectionDef {
                    at,
                    elset,
                    material,
                    beam: None,
                });
                Ok(())
            }
            "BEAM SECTION" => self.beam_section(kw, at, data),
            "BOUNDARY" => self.boundary(data),
            "STEP" | "END STEP" | "HEADING" => Ok(()),
            other => {
                self.warnings.push(format!(
                    "{}: keyword *{other} not supported, skipped with its {} data line(s)",
                    self.loc(at),
                    data.len()
                ));
                Ok(())
            }
        }
    }

    fn required<'k>(
        &self,
        kw: &'k Keyword,
        at: (usize, usize),
        key: &str,
    ) -> Result<&'k str, IoError> {
        kw.param(key)
            .filter(|v| !v.is_empty())
            .ok_or_else(|| self.perr(at, format!("*{} with {key}=", kw.name), "no such parameter"))
    }

    fn nodes(&mut self, kw: &Keyword, data: &[((usize, usize), &str)]) -> Result<(), IoError> {
        let set = kw.param("NSET").map(str::to_uppercase);
        for &(at, l) in data {
            let f = fields(l);
            if f.is_empty() || f.len() > 4 {
                return Err(self.perr(
                    at,
                    "node label and up to 3 coordinates",
                    format!("{}: {}", f.len(), excerpt(l)),
                ));
            }
            let label = self.label(at, f[0], "node label")?;
            let mut x = [0.0; 3];
            for k in 1..f.len() {
                x[k - 1] = self.num(at, f[k], ["x", "y", "z"][k - 1])?;
            }
            if let Some(prev) = self.node_of.get(&label) {
                return Err(self.ierr(
                    at,
                    format!(
                        "duplicate node label {label} (first defined at {})",
                        self.loc(prev.1)
                    ),
                ));
            }
            let idx = self.mesh.nodes.len();
            self.mesh.nodes.push(x);
            self.mesh.node_ids.push(label);
            self.node_of.insert(label, (idx, at));
            if let Some(s) = &set {
                self.mesh.node_sets.entry(s.clone()).or_default().push(idx);
            }
        }
        Ok(())
    }

    fn elements(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        let ty = self.required(kw, at, "TYPE")?.to_uppercase();
        let kind = element_kind(&ty).ok_or_else(|| {
            self.perr(
                at,
                "element TYPE C3D8, C3D8I, C3D20, C3D20R, C3D10 or B31",
                excerpt(&ty),
            )
        })?;
        let set = kw.param("ELSET").map(str::to_uppercase);
        let need = 1 + kind.num_nodes();
        let mut buf: Vec<(String, (usize, usize))> = Vec::new();
        let mut start = at;
        for &(lat, l) in data {
            if buf.is_empty() {
                start = lat;
            }
            buf.extend(fields(l).into_iter().map(|t| (t.to_string(), lat)));
            if buf.len() < need {
                continue;
            }
            if buf.len() > need {
                return Err(self.perr(
                    lat,
                    format!(
                        "{need} numbers (element label and {} nodes of {ty})",
                        need - 1
                    ),
                    buf.len().to_string(),
                ));
            }
            let label = self.label(start, &buf[0].0, "element label")?;
            if let Some(&prev) = self.elem_of.get(&label) {
                return Err(self.ierr(
                    start,
                    format!(
                        "duplicate element label {label} (first defined at {})",
                        self.loc(self.elem_at[prev])
                    ),
                ));
            }
            let mut nodes = Vec::with_capacity(need - 1);
            for (t, tat) in &buf[1..] {
                let nl = self.label(*tat, t, "node label")?;
                let n = self.node_of.get(&nl).map(|n| n.0).ok_or_else(|| {
                    self.ierr(
                        *tat,
                        format!("element {label} refers to undefined node {nl}"),
                    )
                })?;
                nodes.push(n);
            }
            let e = self.mesh.elements.len();
            self.mesh.elements.push(Element {
                kind,
                nodes,
                property: usize::MAX,
            });
            self.labels.push(label);
            self.elem_at.push(start);
            self.elem_of.insert(label, e);
            if let Some(s) = &set {
                self.elsets.entry(s.clone()).or_default().push(e);
            }
            buf.clear();
        }
        if !buf.is_empty() {
            return Err(self.perr(
                start,
                format!(
                    "{need} numbers (element label and {} nodes of {ty})",
                    need - 1
                ),
                format!("{} before the next keyword or end of file", buf.len()),
            ));
        }
        Ok(())
    }

    /// Expands the data lines of `*NSET`/`*ELSET` into labels (`GENERATE` ranges) and set names.
    fn set_items(
        &self,
        kw: &Keyword,
        data: &[((usize, usize), &str)],
        mut item: impl FnMut(
            &Self,
            (usize, usize),
            Result<u64, &str>,
            &mut Vec<usize>,
        ) -> Result<(), IoError>,
    ) -> Result<Vec<usize>, IoError> {
        let mut out = Vec::new();
        for &(at, l) in data {
            let f = fields(l);
            if kw.has("GENERATE") {
                if !(2..=3).contains(&f.len()) {
                    return Err(self.perr(
                        at,
                        "first, last[, increment]",
                        format!("{}: {}", f.len(), excerpt(l)),
                    ));
                }
                let a = self.label(at, f[0], "first label")?;
                let b = self.label(at, f[1], "last label")?;
                let inc = if f.len() == 3 {
                    self.label(at, f[2], "increment")?
                } else {
                    1
                };
                if inc == 0 || b < a {
                    return Err(self.ierr(at, format!("bad GENERATE range {a}..{b} step {inc}")));
                }
                let mut v = a;
                while v <= b {
                    item(self, at, Ok(v), &mut out)?;
                    v = match v.checked_add(inc) {
                        Some(n) => n,
                        None => break,
                    };
                }
            } else {
                for t in f.into_iter().filter(|t| !t.is_empty()) {
                    item(self, at, t.parse::<u64>().map_err(|_| t), &mut out)?;
                }
            }
        }
        Ok(out)
    }

    fn nset(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        let name = self.required(kw, at, "NSET")?.to_uppercase();
        let items = self.set_items(kw, data, |p, at, it, out| {
            match it {
                Ok(label) => out.push(p.node(at, label)?),
                Err(set) => {
                    out.extend(p.mesh.node_sets.get(&set.to_uppercase()).ok_or_else(|| {
                        p.ierr(
                            at,
                            format!("'{set}' is neither a node label nor a defined node set"),
                        )
                    })?)
                }
            }
            Ok(())
        })?;
        let s = self.mesh.node_sets.entry(name).or_default();
        for n in items {
            if !s.contains(&n) {
                s.push(n);
            }
        }
        Ok(())
    }

    fn elset(
        &mut self,
        kw: &Keyword,
        at: (usize, usize),
        data: &[((usize, usize), &str)],
    ) -> Result<(), IoError> {
        let name = self.required(kw, at, "ELSET")?.to_uppercase();
        let items = self.set_items(kw, data, |p, at, it, out| {
            match it {
                Ok(label) => out.push(
                    *p.elem_of
                        .get(&label)
                        .ok_or_else(|| p.ierr(at, format!("element {label} is not defined")))?,
                ),
                Err(set) => out.extend(p.elsets.get(&set.to_uppercase()).ok_or_else(|| {
                    p.ierr(
                        at,
                        format!("'{set}' is neither an element label nor a defined element set"),
                    )
                })?),
            }
            Ok(())
        })?;
        let s = self.elsets.entry(name).or_default();
        for e in items {
            if !s.contains(&e) {
                s.push(e);
            }
        }
        Ok(())
    }
}
