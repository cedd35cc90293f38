//! Every file of `tests/data/bad/` goes through its parser (chosen by the file-name prefix
//! `<kind>__`) and must give a located error: the error names the file, and errors tied to one
//! line carry a line number within the file. Whole-file problems (empty file, missing diagonal,
//! absent table) are listed explicitly and must be `Inconsistent`/`Io` errors naming the file.

mod common;

use common::{data, parse_kind, KINDS};
use flexmbs_io::IoError;

/// Corpus files whose error is about the whole file, not one line.
const WHOLE_FILE: [&str; 4] = [
    "u0__empty.dat",
    "sti__missing_diagonal.sti",
    "dat__no_table.dat",
    "inp__missing_include.inp",
];

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
        let err = match parse_kind(kind, &text, &path) {
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
