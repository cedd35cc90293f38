//! What kind of file a model-file argument is, judged from its content: the one classifier the
//! FE body reader, the multibody compiler and the command line share.

use toml::de::{DeTable, DeValue};

/// The 8-byte signature that starts an HDF5 file (at offset 0, 512, 1024, ...).
pub(crate) const HDF5_SIGNATURE: &[u8; 8] = b"\x89HDF\r\n\x1a\n";

/// What a file given as a model file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelFileKind {
    /// An HDF5 file (a reduced-body file or a results file).
    Hdf5,
    /// Not UTF-8 text (or holds NUL bytes).
    Binary,
    /// TOML with a top-level `model` key (the `[model]` table): a multibody model file.
    Multibody,
    /// TOML without `model` and with one top-level `[body]` table: an FE body file.
    FeBody,
    /// Other text: TOML with neither, or text that does not parse as TOML (a broken file of
    /// either kind).
    Other,
}

/// Classifies a file's bytes (see [`ModelFileKind`]).
pub fn classify_model_file(bytes: &[u8]) -> ModelFileKind {
    let hdf5_at = |o: usize| bytes.get(o..o + 8) == Some(HDF5_SIGNATURE.as_slice());
    if [0usize, 512, 1024, 2048].into_iter().any(hdf5_at) {
        return ModelFileKind::Hdf5;
    }
    match std::str::from_utf8(bytes) {
        Ok(t) if !t.contains('\0') => classify_model_text(t),
        _ => ModelFileKind::Binary,
    }
}

/// Classifies model-file text: [`ModelFileKind::Multibody`], [`ModelFileKind::FeBody`] or
/// [`ModelFileKind::Other`] (also for text that is not TOML).
pub fn classify_model_text(text: &str) -> ModelFileKind {
    DeTable::parse(text)
        .map(|t| classify_toml_table(t.get_ref()))
        .unwrap_or(ModelFileKind::Other)
}

/// Classifies a parsed TOML document by its top-level keys: `model` (any value) makes it a
/// multibody model file; otherwise a `body` table (not the `[[body]]` list of a multibody file)
/// makes it an FE body file.
pub fn classify_toml_table(top: &DeTable<'_>) -> ModelFileKind {
    let value = |key: &str| {
        top.iter()
            .find(|(k, _)| k.get_ref() == key)
            .map(|(_, v)| v.get_ref())
    };
    if value("model").is_some() {
        ModelFileKind::Multibody
    } else if matches!(value("body"), Some(DeValue::Table(_))) {
        ModelFileKind::FeBody
    } else {
        ModelFileKind::Other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classifies_files_by_content() {
        let mut h5 = HDF5_SIGNATURE.to_vec();
        h5.extend_from_slice(&[0, 1, 2, 255]);
        assert_eq!(classify_model_file(&h5), ModelFileKind::Hdf5);
        let mut late = vec![0u8; 512];
        late.extend_from_slice(HDF5_SIGNATURE);
        assert_eq!(classify_model_file(&late), ModelFileKind::Hdf5);
        assert_eq!(classify_model_file(&[0xff, 0xfe, 0]), ModelFileKind::Binary);
        assert_eq!(classify_model_file(b"a = 1\0"), ModelFileKind::Binary);
        assert_eq!(
            classify_model_file(b"[model]\nname = \"m\"\n"),
            ModelFileKind::Multibody
        );
        assert_eq!(
            classify_model_file(b"[body]\nname = \"b\"\n"),
            ModelFileKind::FeBody
        );
    }

    #[test]
    fn classifies_toml_by_top_level_keys() {
        use ModelFileKind::*;
        // `model` decides, whatever else the file holds
        assert_eq!(classify_model_text("model = 1\n[body]\n"), Multibody);
        assert_eq!(
            classify_model_text("[model]\n[[body]]\nname = \"a\"\n"),
            Multibody
        );
        // the multibody body list without [model] is no FE body file
        assert_eq!(classify_model_text("[[body]]\nname = \"a\"\n"), Other);
        assert_eq!(classify_model_text("body = 3\n"), Other);
        assert_eq!(classify_model_text("[mesh]\n"), Other);
        assert_eq!(classify_model_text(""), Other);
        assert_eq!(classify_model_text("[body\n"), Other);
        assert_eq!(classify_model_text("[body.mesh]\ntype = \"x\"\n"), FeBody);
    }
}
