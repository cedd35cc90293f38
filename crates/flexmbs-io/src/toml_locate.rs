//! Locating key paths in TOML model files, shared by both kinds of model file (FE body files and
//! multibody model files): from a key path as `serde_path_to_error` prints it (`body[0].mass`,
//! `body.boundary.fixed[1]`) to the byte offset and line of the file that holds it, so that errors
//! found after deserialization name the line as schema errors do.
//!
//! A key path that is not present (a default value) is located at its deepest present ancestor.
//! In TOML a value starts on its key's line, so a key and its value have the same line.

use std::ops::Range;
use toml::de::{DeTable, DeValue};
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
pub fn join_path(base: &str, sub: &str) -> String {
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

/// 1-based line of byte `offset` in `text`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// Line of the deepest present part of key path `path` in `text`: 1 if no part of it is
/// present, 0 if the text does not parse. For one-off lookups; [`SpannedDoc`] parses once.
pub fn line_of_path(text: &str, path: &str) -> usize {
    let Ok(root) = DeTable::parse(text) else {
        return 0;
    };
    SpannedDoc::new(text, root).line_of_path(path).unwrap_or(1)
}

/// A parsed TOML model file with the byte spans of its keys and values.
pub struct SpannedDoc<'i> {
    text: &'i str,
    root: Spanned<DeValue<'i>>,
}

/// A located error: key path, message and byte offset.
#[derive(Debug, Clone)]
pub struct Refined {
    /// Key path.
    pub path: String,
    /// Message.
    pub message: String,
    /// Byte offset of the offending key or value.
    pub offset: usize,
}

impl<'i> SpannedDoc<'i> {
    /// Wraps a parsed document.
    pub fn new(text: &'i str, root: Spanned<DeTable<'i>>) -> Self {
        let span = root.span();
        Self {
            text,
            root: Spanned::new(span, DeValue::Table(root.into_inner())),
        }
    }

    /// The top-level table.
    pub fn top(&self) -> &DeTable<'i> {
        match self.root.get_ref() {
            DeValue::Table(t) => t,
            _ => unreachable!("a document root is a table"),
        }
    }

    /// The value of a top-level key and the offset of the key.
    pub fn top_entry(&self, key: &str) -> Option<(&Spanned<DeValue<'i>>, usize)> {
        entry(self.top(), key).map(|(k, v)| (v, k.start))
    }

    /// The line of a byte offset.
    pub fn line(&self, offset: usize) -> usize {
        line_of(self.text, offset)
    }

    /// The value at `path` (`None` if some key of it is absent).
    pub fn value_at(&self, path: &str) -> Option<&Spanned<DeValue<'i>>> {
        let mut cur = &self.root;
        for seg in segments(path) {
            cur = step(cur, seg)?.1;
        }
        Some(cur)
    }

    /// The byte offset of the deepest part of `path` present in the file: the key itself if
    /// present, else its nearest present ancestor (a default value has no line of its own).
    pub fn offset_of(&self, path: &str) -> Option<usize> {
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
    pub fn line_of_path(&self, path: &str) -> Option<usize> {
        self.offset_of(path).map(|o| self.line(o))
    }

    /// Makes the location of an "unknown variant" or "unknown field" error precise: serde
    /// reports these at the enclosing table, so the offending value or key is looked up below
    /// `r.path` and the path and offset are moved to it. Other errors are returned as they are.
    pub fn locate_unknown(&self, mut r: Refined) -> Refined {
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
        assert_eq!(
            segments("body[1][2]"),
            vec![Key("body"), Index(1), Index(2)]
        );
        assert_eq!(segments("."), vec![]);
        assert_eq!(join_path("a.b", "[2].c"), "a.b[2].c");
        assert_eq!(join_path("a.b", "."), "a.b");
        assert_eq!(join_path("a", "c"), "a.c");
    }

    /// An FE body file: header tables, a multi-line array, an absent key.
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

    /// A multibody model file: arrays of tables (`[[body]]`), whose elements are located at
    /// their header, and the one-off [`line_of_path`] with its fallbacks.
    #[test]
    fn finds_keys_in_arrays_of_tables() {
        let text = "[model]\nname = \"x\"\n\n[[body]]\nname = \"a\"\nmass = 1\n\n[[body]]\nname = \"b\"\nmass = -1\n";
        assert_eq!(line_of_path(text, "body[1].mass"), 10);
        assert_eq!(line_of_path(text, "body[0].mass"), 6);
        assert_eq!(line_of_path(text, "model.name"), 2);
        // missing key: the deepest existing parent, the header of body[1]
        assert_eq!(line_of_path(text, "body[1].inertia"), 8);
        // nothing of the path present: line 1; text that does not parse: 0
        assert_eq!(line_of_path(text, "joint[0]"), 1);
        assert_eq!(line_of_path("[model\n", "model"), 0);
    }

    /// Unknown fields and variants are moved from the enclosing table to the offending key.
    #[test]
    fn locates_unknown_fields_and_variants() {
        let text =
            "[body]\nname = \"b\"\n[body.mesh]\ntype = \"beam\"\nshape = \"blob\"\nsizee = 1\n";
        let doc = SpannedDoc::new(text, DeTable::parse(text).unwrap());
        let at = |path: &str, message: &str| {
            let r = doc.locate_unknown(Refined {
                path: path.into(),
                message: message.into(),
                offset: 0,
            });
            (r.path, doc.line(r.offset))
        };
        assert_eq!(
            at("body", "unknown variant `blob`, expected one of"),
            ("body.mesh.shape".to_string(), 5)
        );
        assert_eq!(
            at("body.mesh", "unknown field `sizee`, expected `size`"),
            ("body.mesh.sizee".to_string(), 6)
        );
        assert_eq!(at("body", "invalid type").0, "body");
    }
}
