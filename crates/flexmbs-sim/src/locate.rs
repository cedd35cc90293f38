//! Line numbers of key paths (`joint[2].a`, `body[0].mass`) in a TOML text, so that errors found
//! after deserialization (missing frames, bad values) name the line as schema errors do.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// 1-based line of byte `offset` in `text`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())]
        .bytes()
        .filter(|&b| b == b'\n')
        .count()
        + 1
}

/// One step of a key path.
enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(path: &str) -> Vec<Segment<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => part.split_at(i),
            None => (part, ""),
        };
        if !key.is_empty() {
            out.push(Segment::Key(key));
        }
        while let Some(end) = rest.find(']') {
            if let Ok(i) = rest[1..end].parse() {
                out.push(Segment::Index(i));
            }
            rest = &rest[end + 1..];
        }
    }
    out
}

/// Line of the deepest existing element of `path` in `text` (0 if the text does not parse).
pub fn line_of_path(text: &str, path: &str) -> usize {
    let Ok(root) = DeTable::parse(text) else {
        return 0;
    };
    let mut span = root.span();
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    let mut array: Option<&[Spanned<DeValue<'_>>]> = None;
    for seg in segments(path) {
        let next = match seg {
            Segment::Key(k) => table.and_then(|t| {
                t.iter()
                    .find(|(key, _)| key.get_ref().as_ref() == k)
                    .map(|(key, v)| (key.span(), v))
            }),
            Segment::Index(i) => array.and_then(|a| a.get(i)).map(|v| (v.span(), v)),
        };
        let Some((key_span, value)) = next else {
            break;
        };
        // tables of arrays: the value span of a `[[body]]` entry starts at its first key; the
        // key span of a plain key is the best line for a scalar
        span = match value.get_ref() {
            DeValue::Table(_) | DeValue::Array(_) => value.span(),
            _ => key_span,
        };
        (table, array) = match value.get_ref() {
            DeValue::Table(t) => (Some(t), None),
            DeValue::Array(a) => (None, Some(&a[..])),
            _ => (None, None),
        };
    }
    line_of(text, span.start)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_keys_in_arrays_of_tables() {
        let text = "[model]\nname = \"x\"\n\n[[body]]\nname = \"a\"\nmass = 1\n\n[[body]]\nname = \"b\"\nmass = -1\n";
        assert_eq!(line_of_path(text, "body[1].mass"), 10);
        assert_eq!(line_of_path(text, "body[0].mass"), 6);
        assert_eq!(line_of_path(text, "model.name"), 2);
        // missing key: the deepest existing parent
        assert!(line_of_path(text, "body[1].inertia") >= 8);
    }
}
