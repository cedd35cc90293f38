//! Checks of FE body model files beyond their schema: refusing other kinds of file (a multibody
//! model file, HDF5, binary; classified by [`crate::file_kind`]), value ranges, node selectors,
//! and the location (line and key path) of errors found later, while meshing and applying
//! boundary conditions.

use crate::file_kind::{classify_model_file, classify_toml_table, ModelFileKind};
use crate::model::{
    read_fe_model_text, BoxSpec, FeBodySpec, FeModelFile, MaterialSpec, MeshSpec, ModelError,
    NodeSelector, PlaneSpec, ReductionMethod,
};
use crate::toml_locate::{line_of, SpannedDoc};
use flexmbs_fe::Material;
use serde::de::{self, Deserialize, Deserializer, MapAccess, Visitor};
use std::fmt;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// The text of a model file, or [`ModelError::WrongKind`] for an HDF5 or binary file.
pub(crate) fn model_text<'a>(bytes: &'a [u8], file: &Path) -> Result<&'a str, ModelError> {
    let wrong = |what: &str| ModelError::WrongKind {
        file: file.into(),
        what: what.into(),
    };
    match classify_model_file(bytes) {
        ModelFileKind::Hdf5 => Err(wrong(
            "is an HDF5 file (a reduced-body or results file), not a TOML FE body file; a \
             multibody model can use a reduced-body file as a body's `source`",
        )),
        ModelFileKind::Binary => Err(wrong(
            "is a binary file (not UTF-8 text), not a TOML FE body file",
        )),
        _ => std::str::from_utf8(bytes).map_err(|_| wrong("is not UTF-8 text")),
    }
}

/// A TOML syntax error: its line, and for a duplicate key the key's name.
pub(crate) fn syntax_error(text: &str, file: &Path, e: &toml::de::Error) -> ModelError {
    let mut message = e.message().trim_end().to_string();
    if let Some(span) = e.span() {
        let key = text.get(span.clone()).unwrap_or("").trim();
        if message.starts_with("duplicate key") && !key.is_empty() && !key.contains('\n') {
            message = format!("duplicate key `{key}` (each key may be given once per table)");
        }
    }
    ModelError::Schema {
        file: file.to_path_buf(),
        line: e.span().map(|s| line_of(text, s.start)).unwrap_or(0),
        path: String::new(),
        message,
    }
}

/// What a model file needs, for the messages about the wrong kind of file.
const KINDS_HELP: &str = "an FE body file needs a [body] table (name, mesh, boundary, reduction) \
     and a multibody model file needs a [model] table";

/// Refuses files that are not FE body files: a multibody model file (`[model]`), an empty file,
/// a file without `[body]` or with the multibody `[[body]]` list.
pub(crate) fn check_kind(doc: &SpannedDoc<'_>, file: &Path) -> Result<(), ModelError> {
    if classify_toml_table(doc.top()) == ModelFileKind::Multibody {
        return Err(ModelError::WrongKind {
            file: file.into(),
            what: "is a multibody model file ([model] table), not an FE body file: run it with \
                   `flexmbs run` or `flexmbs check`; an FE body file has a [body] table"
                .into(),
        });
    }
    if doc.top().is_empty() {
        return Err(ModelError::WrongKind {
            file: file.into(),
            what: format!("holds no TOML tables: {KINDS_HELP}"),
        });
    }
    let schema = |offset: usize, message: String| ModelError::Schema {
        file: file.into(),
        line: doc.line(offset),
        path: "body".into(),
        message,
    };
    match doc.top_entry("body") {
        None => {
            let (k, _) = doc.top().iter().next().expect("non-empty table");
            Err(schema(
                k.span().start,
                format!(
                    "missing table [body] (found `{}`): {KINDS_HELP}",
                    k.get_ref()
                ),
            ))
        }
        Some((v, at)) if matches!(v.get_ref(), DeValue::Array(_)) => Err(schema(
            at,
            format!(
                "[[body]] is the list of bodies of a multibody model file, which also needs a \
                 [model] table; an FE body file has one [body] table ({KINDS_HELP})"
            ),
        )),
        Some(_) => Ok(()),
    }
}

impl ModelError {
    /// Adds the line of its key path to a [`ModelError::Value`] (other errors are returned as
    /// they are).
    pub(crate) fn located(self, doc: &SpannedDoc<'_>) -> ModelError {
        match self {
            ModelError::Value {
                file,
                path,
                message,
            } => match doc.line_of_path(&path) {
                Some(line) => ModelError::Invalid {
                    file,
                    line,
                    path,
                    message,
                },
                None => ModelError::Value {
                    file,
                    path,
                    message,
                },
            },
            e => e,
        }
    }
}

/// An FE body model file together with its text, so that errors found after parsing (mesh
/// generation, node selections, reduction) can be located at their key's line.
#[derive(Debug, Clone)]
pub struct FeModelSource {
    /// The model file.
    pub file: PathBuf,
    /// Its text.
    pub text: String,
    /// The parsed model.
    pub model: FeModelFile,
}

/// An error found while processing an FE body file's body (meshing, supports, reduction) that
/// concerns one of its keys: [`FeModelSource::locate`] puts it at that key's line.
pub trait ErrorAtKey {
    /// The key path it concerns (`body` gives the key for errors that know only their stage, such
    /// as reading the mesh files) and the message.
    fn key_and_message(self, body: &FeBodySpec) -> (String, String);
}

impl FeModelSource {
    /// Reads and parses a model file (as [`crate::model::read_fe_model`]).
    pub fn read(path: &Path) -> Result<Self, ModelError> {
        let (text, model) = read_fe_model_text(path)?;
        Ok(Self {
            file: path.to_path_buf(),
            text,
            model,
        })
    }

    /// Turns an error found while processing the body (meshing, supports, reduction: the
    /// pipeline of `flexmbs-reduce`) into a [`ModelError::Invalid`] at the line of the key it
    /// concerns.
    pub fn locate(&self, e: impl ErrorAtKey) -> ModelError {
        let (path, message) = e.key_and_message(&self.model.body);
        let e = ModelError::Value {
            file: self.file.clone(),
            path,
            message,
        };
        match DeTable::parse(&self.text) {
            Ok(root) => e.located(&SpannedDoc::new(&self.text, root)),
            Err(_) => e,
        }
    }
}

/// Range checks of the values that the schema cannot express, each at its own key path.
pub(crate) fn check_values(m: &FeModelFile, file: &Path) -> Result<(), ModelError> {
    let err = |path: &str, message: String| ModelError::Value {
        file: file.into(),
        path: path.into(),
        message,
    };
    let check_material = |mat: &MaterialSpec| match Material::from(*mat).validate() {
        Ok(()) => Ok(()),
        Err(e) => {
            // Same order as `Material::validate`: the first bad constant is the one reported.
            let key = if !(mat.e.is_finite() && mat.e > 0.0) {
                "e"
            } else if !(mat.nu.is_finite() && mat.nu > -1.0 && mat.nu < 0.5) {
                "nu"
            } else {
                "rho"
            };
            Err(err(&format!("body.mesh.material.{key}"), e.to_string()))
        }
    };
    let positive3 = |key: &str, v: &[f64; 3]| {
        if v.iter().all(|x| x.is_finite() && *x > 0.0) {
            Ok(())
        } else {
            Err(err(key, format!("all three values must be > 0, got {v:?}")))
        }
    };
    let finite3 = |key: &str, v: &[f64; 3]| {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(err(
                key,
                format!("all three values must be finite, got {v:?}"),
            ))
        }
    };
    match &m.body.mesh {
        MeshSpec::Box {
            size,
            divisions,
            material,
            ..
        } => {
            positive3("body.mesh.size", size)?;
            if divisions.contains(&0) {
                return Err(err(
                    "body.mesh.divisions",
                    format!("all divisions must be >= 1, got {divisions:?}"),
                ));
            }
            check_material(material)?;
        }
        MeshSpec::Boxes {
            boxes,
            element_size,
            material,
            ..
        } => {
            positive3("body.mesh.element_size", element_size)?;
            if boxes.is_empty() {
                return Err(err("body.mesh.boxes", "at least one box is needed".into()));
            }
            check_material(material)?;
        }
        MeshSpec::Profile {
            length,
            element_size,
            material,
            ..
        } => {
            positive3("body.mesh.element_size", element_size)?;
            if !(length.is_finite() && *length > 0.0) {
                return Err(err(
                    "body.mesh.length",
                    format!("must be > 0, got {length}"),
                ));
            }
            check_material(material)?;
        }
        MeshSpec::Beam {
            start,
            end,
            elements,
            material,
            ..
        } => {
            finite3("body.mesh.start", start)?;
            finite3("body.mesh.end", end)?;
            if start == end {
                return Err(err(
                    "body.mesh.end",
                    format!(
                        "the beam has zero length: `end` equals `start` = {start:?}; give two \
                         distinct points"
                    ),
                ));
            }
            if *elements == 0 {
                return Err(err("body.mesh.elements", "must be >= 1".into()));
            }
            check_material(material)?;
        }
        MeshSpec::Calculix { .. } | MeshSpec::Seed { .. } => {}
    }
    let r = &m.body.reduction;
    if r.modes == 0 && r.method == ReductionMethod::Modal {
        return Err(err(
            "body.reduction.modes",
            "a modal reduction needs at least one mode".into(),
        ));
    }
    if !(r.tol > 0.0 && r.tol < 1e-2) {
        return Err(err(
            "body.reduction.tol",
            format!("must be in (0, 1e-2), got {}", r.tol),
        ));
    }
    if r.method != ReductionMethod::Modal && !r.static_loads.is_empty() {
        return Err(err(
            "body.reduction.static_loads",
            "static load responses enrich a modal basis (method = \"modal\"); a Craig-Bampton \
             basis holds the static responses of its interface nodes already"
                .into(),
        ));
    }
    for (i, l) in r.static_loads.iter().enumerate() {
        if let Some(face) = &l.face {
            if flexmbs_fe::BoxFace::from_name(face).is_none() {
                return Err(err(
                    &format!("body.reduction.static_loads[{i}].face"),
                    format!("unknown face `{face}` ({})", flexmbs_fe::BoxFace::NAMES),
                ));
            }
            if l.point.is_none() {
                return Err(err(
                    &format!("body.reduction.static_loads[{i}]"),
                    "`face` needs `point` (where on the face's surface the force acts)".into(),
                ));
            }
        }
        if l.nodes.is_some() == l.point.is_some() {
            return Err(err(
                &format!("body.reduction.static_loads[{i}]"),
                "give exactly one of `nodes` (a node selection sharing the force) and `point` \
                 ([x, y, z], a force at a point of a solid mesh)"
                    .into(),
            ));
        }
        let n = l.direction.iter().map(|c| c * c).sum::<f64>().sqrt();
        if !(n.is_finite() && n > 0.0) {
            return Err(err(
                &format!("body.reduction.static_loads[{i}].direction"),
                format!("must be a finite nonzero vector, got {:?}", l.direction),
            ));
        }
    }
    if r.method != ReductionMethod::Modal && r.interface.is_empty() {
        return Err(err(
            "body.reduction.interface",
            "Craig-Bampton and Guyan need at least one interface".into(),
        ));
    }
    Ok(())
}

/// The forms a node selector takes, for its error messages.
const SELECTOR_FORMS: &str = "a node selector: a node-set name (\"xmin\", \"start\", a CalculiX \
     *NSET name) or a table with one key: { plane = { axis = \"x\", value = 0.0 } }, \
     { within = { min = [x, y, z], max = [x, y, z] } } or { nearest = [x, y, z] }";

impl<'de> Deserialize<'de> for NodeSelector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(SelectorVisitor)
    }
}

/// Visitor of [`NodeSelector`]: a string or a one-key table.
struct SelectorVisitor;

impl<'de> Visitor<'de> for SelectorVisitor {
    type Value = NodeSelector;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(SELECTOR_FORMS)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<NodeSelector, E> {
        Ok(NodeSelector::Set(v.to_string()))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<NodeSelector, A::Error> {
        let Some(key) = map.next_key::<String>()? else {
            return Err(de::Error::custom(format!(
                "empty table; expected {SELECTOR_FORMS}"
            )));
        };
        let sel = match key.as_str() {
            "plane" => NodeSelector::Plane {
                plane: map.next_value::<PlaneSpec>()?,
            },
            "within" => NodeSelector::Within {
                within: map.next_value::<BoxSpec>()?,
            },
            "nearest" => {
                let q = map.next_value::<Vec<crate::units::Quantity>>()?;
                let p = q
                    .iter()
                    .map(crate::fe_quantity::length_value)
                    .collect::<Result<Vec<f64>, String>>()
                    .map_err(de::Error::custom)?;
                let nearest: [f64; 3] = p.as_slice().try_into().map_err(|_| {
                    de::Error::custom(format!(
                        "`nearest` needs a point [x, y, z], got {} numbers; expected {SELECTOR_FORMS}",
                        p.len()
                    ))
                })?;
                NodeSelector::Nearest { nearest }
            }
            other => {
                return Err(de::Error::custom(format!(
                    "unknown key `{other}`; expected {SELECTOR_FORMS}"
                )))
            }
        };
        if let Some(k) = map.next_key::<String>()? {
            return Err(de::Error::custom(format!(
                "a node selector has one key, found `{key}` and `{k}`; expected {SELECTOR_FORMS}"
            )));
        }
        Ok(sel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_hdf5_as_model_text() {
        let mut h5 = crate::file_kind::HDF5_SIGNATURE.to_vec();
        h5.extend_from_slice(&[0, 1, 2, 255]);
        let e = model_text(&h5, Path::new("b.h5")).unwrap_err().to_string();
        assert!(e.starts_with("b.h5 is an HDF5 file"), "{e}");
    }
}
