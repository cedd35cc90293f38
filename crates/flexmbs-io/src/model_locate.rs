//! Locating the errors of FE body model files beyond the shared key-path locator
//! ([`crate::toml_locate`]): from a serde error inside the internally tagged `body.mesh` table
//! (whose fields serde buffers, losing their path) to the key that is actually wrong
//! (`body.mesh.section.shape` rather than `body.mesh`).

use crate::model::{
    BoxSpec, CcxMatrices, ElementName, MaterialSpec, ProfileSpec, SectionSpec, TheoryName,
};
use crate::toml_locate::{join_path, Refined, SpannedDoc};
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::PathBuf;
use toml::de::{DeValue, ValueDeserializer};
use toml::Spanned;

/// Makes a serde error at `path` of an FE body file more precise. Inside `body.mesh` (an
/// internally tagged table, whose fields serde buffers and so reports at `body.mesh` itself) each
/// field is deserialized on its own to find the one that fails; then an unknown variant or field
/// is looked up below the error's table ([`SpannedDoc::locate_unknown`]). `offset` is the error's
/// own location, if any.
pub(crate) fn refine(
    doc: &SpannedDoc<'_>,
    path: &str,
    message: &str,
    offset: Option<usize>,
) -> Refined {
    let mut r = Refined {
        path: path.to_string(),
        message: message.to_string(),
        offset: offset.or_else(|| doc.offset_of(path)).unwrap_or(0),
    };
    if path == "body.mesh" {
        if let Some(DeValue::Table(mesh)) = doc.value_at(path).map(|v| v.get_ref()) {
            for (k, v) in mesh.iter() {
                if let Some((sub, msg, span)) = probe_mesh_field(k.get_ref(), v) {
                    r = Refined {
                        path: join_path(&join_path(path, k.get_ref()), &sub),
                        message: msg,
                        offset: span.map(|s| s.start).unwrap_or(k.span().start),
                    };
                    break;
                }
            }
        }
    }
    doc.locate_unknown(r)
}

/// Deserializes one value on its own: `None` if it is a valid `T`, else the error's sub-path,
/// message and span.
fn probe<T: DeserializeOwned>(
    v: &Spanned<DeValue<'_>>,
) -> Option<(String, String, Option<Range<usize>>)> {
    let de = ValueDeserializer::from(v.clone());
    match serde_path_to_error::deserialize::<_, T>(de) {
        Ok(_) => None,
        Err(e) => {
            let sub = e.path().to_string();
            let inner = e.into_inner();
            Some((sub, inner.message().to_string(), inner.span()))
        }
    }
}

/// Checks one field of the `body.mesh` table against the type it has in every mesh variant that
/// has it (see [`crate::model::MeshSpec`]); `None` if it is valid or not a mesh field.
fn probe_mesh_field(
    key: &str,
    v: &Spanned<DeValue<'_>>,
) -> Option<(String, String, Option<Range<usize>>)> {
    match key {
        "size" | "element_size" | "start" | "end" | "orientation" => probe::<[f64; 3]>(v),
        "divisions" => probe::<[usize; 3]>(v),
        "elements" => probe::<usize>(v),
        "length" => probe::<f64>(v),
        "element" => probe::<ElementName>(v),
        "material" => probe::<MaterialSpec>(v),
        "boxes" => probe::<Vec<BoxSpec>>(v),
        "profile" => probe::<ProfileSpec>(v),
        "section" => probe::<SectionSpec>(v),
        "theory" => probe::<TheoryName>(v),
        "matrices" => probe::<CcxMatrices>(v),
        "deck" | "dir" => probe::<PathBuf>(v),
        "type" => probe::<String>(v),
        _ => None,
    }
}
