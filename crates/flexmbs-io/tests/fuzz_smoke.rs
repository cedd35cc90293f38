//! Stable-Rust stand-in for the cargo-fuzz targets (see `fuzz/README.md`): thousands of
//! pseudo-random mutations (byte flips, byte insertions, truncations, line duplication and
//! deletion, digit/sign swaps) of the corpus files go through every parser; any panic fails the
//! test. Results are not checked (most mutants are invalid), only that parsers return.

use crate::common;

use common::{data, parse_kind, XorShift, KINDS};
use std::path::{Path, PathBuf};

/// Seed inputs per parser kind: the good files and the malformed corpus.
fn corpus() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut add = |kind: &str, p: PathBuf| {
        let mut bytes = std::fs::read(&p).unwrap();
        bytes.truncate(6000); // keep mutants small: the big beam files add nothing new
        out.push((kind.to_string(), bytes));
    };
    for f in [
        "u0.dat",
        "modeShapeMatrix.dat",
        "mij.dat",
        "stiffnessMatrix.dat",
    ] {
        let kind = match f {
            "u0.dat" => "u0",
            "modeShapeMatrix.dat" => "modes",
            "mij.dat" => "mass",
            _ => "stiffness",
        };
        add(kind, data("seed_ok").join(f));
    }
    for (kind, f) in [
        ("sti", "small.sti"),
        ("sti", "small.mas"),
        ("dof", "small.dof"),
        ("dat", "beam_freq.dat"),
        ("frd", "small.frd"),
    ] {
        add(kind, data("good").join(f));
    }
    add("inp", data("ccx/beam_mesh.inp"));
    let mut bad: Vec<_> = std::fs::read_dir(data("bad"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    bad.sort();
    for p in bad {
        let name = p.file_name().unwrap().to_str().unwrap().to_string();
        let kind = name.split("__").next().unwrap().to_string();
        if KINDS.contains(&kind.as_str()) && !name.contains("include") {
            add(&kind, p);
        }
    }
    out
}

/// One random mutation of `b`.
fn mutate(rng: &mut XorShift, b: &mut Vec<u8>) {
    const TOKENS: [&[u8]; 10] = [
        b"-",
        b"e+",
        b",",
        b"\n",
        b"nan",
        b"*",
        b"9999",
        b" -3",
        b".",
        b"99999999999999999999",
    ];
    match rng.below(7) {
        0 if !b.is_empty() => {
            let i = rng.below(b.len());
            b[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(b.len() + 1);
            b.insert(i, rng.next_u64() as u8);
        }
        2 if !b.is_empty() => {
            let i = rng.below(b.len());
            b.truncate(i);
        }
        3 | 4 => {
            // Duplicate or delete a line.
            let text = String::from_utf8_lossy(b).into_owned();
            let mut lines: Vec<&str> = text.lines().collect();
            if !lines.is_empty() {
                let i = rng.below(lines.len());
                if rng.below(2) == 0 {
                    lines.insert(i, lines[i]);
                } else {
                    lines.remove(i);
                }
            }
            *b = lines.join("\n").into_bytes();
        }
        _ => {
            let t = TOKENS[rng.below(TOKENS.len())];
            let i = rng.below(b.len() + 1);
            b.splice(i..i, t.iter().copied());
        }
    }
}

#[test]
fn parsers_never_panic_on_mutated_corpus() {
    let corpus = corpus();
    let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
    let file = Path::new("fuzz.input");
    let per_kind = 2000;
    let mut count = 0;
    for kind in KINDS {
        let seeds: Vec<&Vec<u8>> = corpus
            .iter()
            .filter(|(k, _)| k == kind)
            .map(|(_, b)| b)
            .collect();
        assert!(!seeds.is_empty(), "no corpus for {kind}");
        for _ in 0..per_kind {
            let mut b = seeds[rng.below(seeds.len())].clone();
            for _ in 0..1 + rng.below(4) {
                mutate(&mut rng, &mut b);
            }
            let text = String::from_utf8_lossy(&b);
            let _ = parse_kind(kind, &text, file);
            count += 1;
        }
    }
    println!("{count} mutants parsed without panic");
    assert_eq!(count, per_kind * KINDS.len());
}
