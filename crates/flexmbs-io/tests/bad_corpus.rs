//! Every file of `tests/data/bad/` goes through its parser (chosen by the file-name prefix
//! `<kind>__`) and must give a located error: the error names the file, and errors tied to one
//! line carry a line number within the file. Whole-file problems (empty file, missing diagonal,
//! absent table) are listed explicitly and must be `Inconsistent`/`Io` errors naming the file.
//! FE body model files (`fe__*.toml`) go through parsing and body preparation (meshing, node
//! selections), as `flexmbs check` does, and must also name the key path.

use crate::common;

use common::{data, model_error_as_io, parse_kind, KINDS};
use flexmbs_io::model::ModelError;
use flexmbs_io::model_check::FeModelSource;
use flexmbs_io::IoError;
use flexmbs_reduce::pipeline::prepare;
use std::path::Path;

/// Corpus files whose error is about the whole file, not one line.
const WHOLE_FILE: [&str; 6] = [
    "u0__empty.dat",
    "sti__missing_diagonal.sti",
    "dat__no_table.dat",
    "inp__missing_include.inp",
    "fe__empty.toml",
    "fe__multibody.toml",
];

/// What `flexmbs check` does with an FE body file: parse, then prepare the body (mesh, boundary
/// conditions), with errors located in the model file.
fn check_fe_model(path: &Path) -> Result<(), ModelError> {
    let src = FeModelSource::read(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    prepare(&src.model.body, base, &mut |_| {})
        .map(|_| ())
        .map_err(|e| src.locate(e))
}

#[test]
fn every_bad_file_gives_a_located_error() {
    let mut n = 0;
    let mut dir: Vec<_> = std::fs::read_dir(data("bad"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dir.sort();
    for path in dir.into_iter().filter(|p| p.is_file()) {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let kind = name.split("__").next().unwrap();
        assert!(
            KINDS.contains(&kind),
            "corpus file {name} has no parser prefix"
        );
        let text = std::fs::read_to_string(&path).unwrap();
        let result = if kind == "fe" {
            check_fe_model(&path).map_err(model_error_as_io)
        } else {
            parse_kind(kind, &text, &path)
        };
        let err = match result {
            Ok(()) => panic!("{name}: malformed input accepted"),
            Err(e) => e,
        };
        let msg = err.to_string();
        println!("{msg}");
        if WHOLE_FILE.contains(&name.as_str()) {
            assert!(
                matches!(err, IoError::Inconsistent { .. } | IoError::Io { .. }),
                "{name}: {msg}"
            );
            if let IoError::Io { file, .. } = &err {
                assert!(file.ends_with("does_not_exist.inp"), "{msg}");
            } else {
                assert_eq!(err.file().unwrap(), path, "{msg}");
            }
        } else {
            assert_eq!(
                err.file().unwrap(),
                path,
                "{name}: error names another file: {msg}"
            );
            let line = err
                .line()
                .unwrap_or_else(|| panic!("{name}: no line number: {msg}"));
            let nlines = text.lines().count();
            assert!(
                line >= 1 && line <= nlines,
                "{name}: line {line} outside 1..={nlines}"
            );
            assert!(
                msg.contains(&format!("{name}:{line}: ")),
                "{name}: message not 'file:line: ...': {msg}"
            );
        }
        n += 1;
    }
    assert!(n >= 50, "only {n} corpus files");
}

#[test]
fn specific_messages() {
    let check = |rel: &str, kind: &str, line: usize, needle: &str| {
        let p = data(rel);
        let e = parse_kind(kind, &std::fs::read_to_string(&p).unwrap(), &p).unwrap_err();
        assert_eq!(e.line(), Some(line), "{e}");
        assert!(e.to_string().contains(needle), "'{e}' lacks '{needle}'");
    };
    check(
        "bad/u0__two_columns.dat",
        "u0",
        3,
        "expected 3 numbers (x y z), found 2",
    );
    check("bad/mass__negative.dat", "mass", 3, "positive node mass");
    check("bad/mass__zero.dat", "mass", 2, "positive node mass");
    check(
        "bad/stiffness__duplicate.dat",
        "stiffness",
        4,
        "duplicate entry",
    );
    check(
        "bad/stiffness__node_out_of_range.dat",
        "stiffness",
        2,
        "row node a 5 out of range 1..=4",
    );
    check(
        "bad/sti__lower_triangle.sti",
        "sti",
        6,
        "below the diagonal",
    );
    check("bad/dof__float_token.dof", "dof", 3, "node.direction");
    check(
        "bad/inp__missing_node.inp",
        "inp",
        11,
        "refers to undefined node 9",
    );
    check(
        "bad/inp__duplicate_node.inp",
        "inp",
        10,
        "duplicate node label 3 (first defined at",
    );
    check(
        "bad/inp__missing_material.inp",
        "inp",
        12,
        "material ALU is not defined",
    );
    check(
        "bad/inp__short_element.inp",
        "inp",
        11,
        "21 numbers (element label and 20 nodes of C3D20R)",
    );
    check(
        "bad/frd__truncated.frd",
        "frd",
        12,
        "node block ended by -3",
    );
    check("bad/frd__bad_column.frd", "frd", 15, "columns 26-37");
}

/// Each FE body model-file case: line, key path and a fragment of the message. `None` line/path:
/// a whole-file error.
#[test]
fn fe_model_messages() {
    let cases: [(&str, Option<usize>, Option<&str>, &str); 14] = [
        (
            "fe__zero_len.toml",
            Some(7),
            Some("body.mesh.end"),
            "the beam has zero length",
        ),
        (
            "fe__badsel.toml",
            Some(17),
            Some("body.boundary.fixed[0]"),
            "no node set 'xmin' (known: all, end, start)",
        ),
        (
            "fe__modes500.toml",
            Some(14),
            Some("body.reduction.modes"),
            "at most 120 elastic modes",
        ),
        (
            "fe__modes0.toml",
            Some(14),
            Some("body.reduction.modes"),
            "at least one mode",
        ),
        (
            "fe__elem0.toml",
            Some(8),
            Some("body.mesh.elements"),
            "must be >= 1",
        ),
        (
            "fe__neg_e.toml",
            Some(10),
            Some("body.mesh.material.e"),
            "Young's modulus must be > 0",
        ),
        (
            "fe__nu05.toml",
            Some(10),
            Some("body.mesh.material.nu"),
            "Poisson's ratio must be in (-1, 0.5), got 0.5",
        ),
        (
            "fe__badsel2.toml",
            Some(17),
            Some("body.boundary.fixed[0]"),
            "`nearest` needs a point [x, y, z], got 2 numbers; expected a node selector: a \
             node-set name",
        ),
        (
            "fe__shape.toml",
            Some(9),
            Some("body.mesh.section.shape"),
            "unknown variant `rect`, expected one of `rectangle`",
        ),
        (
            "fe__noheight.toml",
            Some(9),
            Some("body.mesh.section"),
            "missing field `height`",
        ),
        ("fe__dupkey.toml", Some(16), None, "duplicate key `mass`"),
        (
            "fe__empty.toml",
            None,
            None,
            "an FE body file needs a [body] table (name, mesh, boundary, reduction) and a \
             multibody model file needs a [model] table",
        ),
        (
            "fe__multibody.toml",
            None,
            None,
            "is a multibody model file ([model] table), not an FE body file: run it with \
             `flexmbs run`",
        ),
        (
            "fe__body_list.toml",
            Some(2),
            Some("body"),
            "[[body]] is the list of bodies of a multibody model file",
        ),
    ];
    for (name, line, key, needle) in cases {
        let p = data(&format!("bad/{name}"));
        let e = check_fe_model(&p).unwrap_err();
        let s = e.to_string();
        println!("{s}");
        assert_eq!(e.file(), p, "{s}");
        assert_eq!(e.line(), line, "{name}: {s}");
        assert_eq!(e.key_path(), key, "{name}: {s}");
        assert!(s.contains(needle), "{name}: '{s}' lacks '{needle}'");
        assert_eq!(s.matches(needle).count(), 1, "{name}: repeated: {s}");
        if let Some(line) = line {
            assert!(s.contains(&format!("{name}:{line}: ")), "{s}");
        }
        if let Some(key) = key {
            assert!(s.contains(&format!("at `{key}`: ")), "{s}");
        }
    }
}
