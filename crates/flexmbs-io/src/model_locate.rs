//! Locating the errors of FE body model files: from a key path such as
//! `body.boundary.fixed[0]` to the line of the file that holds it, and from a serde error inside
//! the internally tagged `body.mesh` table (whose fields serde buffers, losing their path) to the
//! key that is actually wrong (`body.mesh.section.shape` rather than `body.mesh`).

use crate::model::{
    BoxSpec, CcxMatrices, ElementName, MaterialSpec, ProfileSpec, SectionSpec, TheoryName,
};
use serde::de::DeserializeOwned;
use std::ops::Range;
use std::path::PathBuf;
use toml::de::{DeTable, DeValue, ValueDeserializer};
use toml::Spanned;

/// One step of a key path.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Segment<'p> {
    /// A table key.
    Key(&'p str),
    /// An array index.
    Index(usize),
}

/// Splits a key path as `serde_path_to_error` prints it (`a.b[0].c`; `.` is the root).
fn segments(path: &str) -> Vec<Segment<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if !name.is_empty() {
            out.push(Segment::Key(name));
        }
        while let Some(r) = rest.strip_prefix('[') {
            let Some(end) = r.find(']') else { break };
            if let Ok(i) = r[..end].parse() {
                out.push(Segment::Index(i));
            }
            rest = &r[end + 1..];
        }
    }
    out
}

/// Joins a sub-path (as printed by `serde_path_to_error`, `.` for none) to a base key path.
pub(crate) fn join_path(base: &str, sub: &str) -> String {
    if sub == "." || sub.is_empty() {
        base.to_string()
    } else if base.is_empty() || base == "." {
        sub.to_string()
    } else if sub.starts_with('[') {
        format!("{base}{sub}")
    } else {
        format!("{base}.{sub}")
    }
}

/// 1-based line of a byte offset.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// A parsed model file with the byte spans of its keys and values.
pub(crate) struct SpannedDoc<'i> {
    text: &'i str,
    root: Spanned<DeValue<'i>>,
}

/// A located refinement of an error: key path, message and byte offset.
#[derive(Debug, Clone)]
pub(crate) struct Refined {
    /// Key path.
    pub path: String,
    /// Message.
    pub message: String,
    /// Byte offset of the offending key or value.
    pub offset: usize,
}

impl<'i> SpannedDoc<'i> {
    /// Wraps a parsed document.
    pub(crate) fn new(text: &'i str, root: Spanned<DeTable<'i>>) -> Self {
        let span = root.span();
        Self {
            text,
            root: Spanned::new(span, DeValue::Table(root.into_inner())),
        }
    }

    /// The top-level table.
    pub(crate) fn top(&self) -> &DeTable<'i> {
        match self.root.get_ref() {
            DeValue::Table(t) => t,
            _ => unreachable!("a document root is a table"),
        }
    }

    /// The value of a top-level key and the offset of the key.
    pub(crate) fn top_entry(&self, key: &str) -> Option<(&Spanned<DeValue<'i>>, usize)> {
        entry(self.top(), key).map(|(k, v)| (v, k.start))
    }

    /// The line of a byte offset.
    pub(crate) fn line(&self, offset: usize) -> usize {
        line_of(self.text, offset)
    }

    /// The value at `path` (`None` if some key of it is absent).
    fn value_at(&self, path: &str) -> Option<&Spanned<DeValue<'i>>> {
        let mut cur = &self.root;
        for seg in segments(path) {
            cur = step(cur, seg)?.1;
        }
        Some(cur)
    }

    /// The byte offset of the deepest part of `path` present in the file: the key itself if
    /// present, else its nearest present ancestor (a default value has no line of its own).
    pub(crate) fn offset_of(&self, path: &str) -> Option<usize> {
        let mut cur = &self.root;
        let mut best = None;
        for seg in segments(path) {
            match step(cur, seg) {
                Some((at, next)) => {
                    best = Some(at);
                    cur = next;
                }
                None => break,
            }
        }
        best
    }

    /// The 1-based line of the deepest part of `path` present in the file.
    pub(crate) fn line_of_path(&self, path: &str) -> Option<usize> {
        self.offset_of(path).map(|o| self.line(o))
    }

    /// Makes a serde error at `path` more precise. Inside `body.mesh` (an internally tagged
    /// table, whose fields serde buffers and so reports at `body.mesh` itself) each field is
    /// deserialized on its own to find the one that fails; then an unknown variant or field is
    /// looked up below the error's table. `offset` is the error's own location, if any.
    pub(crate) fn refine(&self, path: &str, message: &str, offset: Option<usize>) -> Refined {
        let mut r = Refined {
            path: path.to_string(),
            message: message.to_string(),
            offset: offset.or_else(|| self.offset_of(path)).unwrap_or(0),
        };
        if path == "body.mesh" {
            if let Some(DeValue::Table(mesh)) = self.value_at(path).map(|v| v.get_ref()) {
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
        let Some(below) = self.value_at(&r.path) else {
            return r;
        };
        let found = if let Some(v) = quoted_after(&r.message, "unknown variant `") {
            find_below(
                below,
                &mut |_, x| matches!(x.get_ref(), DeValue::String(s) if s.as_ref() == v),
            )
        } else if let Some(k) = quoted_after(&r.message, "unknown field `") {
            find_below(below, &mut |key, _| key == Some(k))
        } else {
            None
        };
        if let Some((sub, at)) = found {
            r.path = join_path(&r.path, &sub);
            r.offset = at;
        }
        r
    }
}

/// The entry `key` of a table: the key's span and the value.
fn entry<'a, 'i>(
    t: &'a DeTable<'i>,
    key: &str,
) -> Option<(Range<usize>, &'a Spanned<DeValue<'i>>)> {
    t.iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(k, v)| (k.span(), v))
}

/// One step down a value: the offset of the key or element and the value reached.
fn step<'a, 'i>(
    cur: &'a Spanned<DeValue<'i>>,
    seg: Segment<'_>,
) -> Option<(usize, &'a Spanned<DeValue<'i>>)> {
    match (cur.get_ref(), seg) {
        (DeValue::Table(t), Segment::Key(k)) => entry(t, k).map(|(span, v)| (span.start, v)),
        (DeValue::Array(a), Segment::Index(i)) => a.get(i).map(|v| (v.span().start, v)),
        _ => None,
    }
}

/// The text between `prefix` and the next backquote in `message`.
fn quoted_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    rest.find('`').map(|end| &rest[..end])
}

/// Depth-first search below `v` for an entry accepted by `hit(key, value)`: its sub-path and the
/// offset of its key (or of the element, in arrays).
fn find_below(
    v: &Spanned<DeValue<'_>>,
    hit: &mut dyn FnMut(Option<&str>, &Spanned<DeValue<'_>>) -> bool,
) -> Option<(String, usize)> {
    match v.get_ref() {
        DeValue::Table(t) => {
            for (k, x) in t.iter() {
                if hit(Some(k.get_ref()), x) {
                    return Some((k.get_ref().to_string(), k.span().start));
                }
                if let Some((sub, at)) = find_below(x, hit) {
                    return Some((join_path(k.get_ref(), &sub), at));
                }
            }
            None
        }
        DeValue::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                if hit(None, x) {
                    return Some((format!("[{i}]"), x.span().start));
                }
                if let Some((sub, at)) = find_below(x, hit) {
                    return Some((join_path(&format!("[{i}]"), &sub), at));
                }
            }
            None
        }
        _ => None,
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_key_paths() {
        use Segment::*;
        assert_eq!(
            segments("body.boundary.fixed[0].nearest"),
            vec![
                Key("body"),
                Key("boundary"),
                Key("fixed"),
                Index(0),
                Key("nearest")
            ]
        );
        assert_eq!(segments("."), vec![]);
        assert_eq!(join_path("a.b", "[2].c"), "a.b[2].c");
        assert_eq!(join_path("a.b", "."), "a.b");
        assert_eq!(join_path("a", "c"), "a.c");
    }

    #[test]
    fn finds_lines_of_keys_elements_and_absent_keys() {
        let text = "[body]\nname = \"b\"\n\n[body.boundary]\nfixed = [\"a\",\n  \"b\"]\n";
        let doc = SpannedDoc::new(text, DeTable::parse(text).unwrap());
        assert_eq!(doc.line_of_path("body.name"), Some(2));
        assert_eq!(doc.line_of_path("body.boundary.fixed"), Some(5));
        assert_eq!(doc.line_of_path("body.boundary.fixed[1]"), Some(6));
        // Absent key: its nearest present ancestor.
        assert_eq!(doc.line_of_path("body.boundary.rigid"), Some(4));
        assert_eq!(doc.line_of_path("model"), None);
    }
}
