//! Reader of CalculiX ASCII result files (`.frd`): nodes, elements and displacement results
//! (mode shapes of a `*FREQUENCY` step).
//!
//! Records (fixed columns, Fortran style): `    2C` node block, `    3C` element block,
//! `    1PMODE` mode number, `  100CL` result block header (step value, i.e. the frequency of a
//! modal step, in columns 13-24), `-4  DISP` result name, `-5` component definitions, `-1`
//! records (node label I10 in the long format, I5 in the short one, then values E12.5 written
//! without separating blanks, e.g. `8.66585E-04-5.49481E-07`), `-2` element node continuation,
//! `-3` end of block, `9999` end of file. Only the ASCII formats (0 short, 1 long) are read; the
//! binary format (2) is rejected.
//!
//! The frd 20-node hexahedron lists Abaqus nodes 1-12, 17-20, 13-16; [`FrdElement::nodes`] is
//! converted back to Abaqus order.

use crate::error::{excerpt, read_text, IoError};
use std::path::Path;

/// One element of the `3C` block.
#[derive(Debug, Clone, PartialEq)]
pub struct FrdElement {
    /// Element label.
    pub label: u64,
    /// frd element type (1 he8, 2 pe6, 3 te4, 4 he20, 5 pe15, 6 te10, 7 tr3, 8 tr6, 9 qu4,
    /// 10 qu8, 11 be2, 12 be3).
    pub frd_type: u32,
    /// Node labels in Abaqus order.
    pub nodes: Vec<u64>,
}

/// One displacement result block (one mode of a frequency step).
#[derive(Debug, Clone, PartialEq)]
pub struct FrdMode {
    /// Mode number from the preceding `1PMODE` record, if any.
    pub mode: Option<u32>,
    /// Step value of the block: the frequency [Hz] for a modal step.
    pub frequency_hz: f64,
    /// Displacement (ux, uy, uz) per node label.
    pub disp: Vec<(u64, [f64; 3])>,
}

/// Content of an `.frd` file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrdResult {
    /// Node labels and coordinates (6 significant digits).
    pub nodes: Vec<(u64, [f64; 3])>,
    /// Elements.
    pub elements: Vec<FrdElement>,
    /// Displacement blocks in file order.
    pub modes: Vec<FrdMode>,
}

/// Number of nodes of an frd element type.
fn frd_type_nodes(t: u32) -> Option<usize> {
    Some(match t {
        1 => 8,
        2 => 6,
        3 => 4,
        4 => 20,
        5 => 15,
        6 => 10,
        7 => 3,
        8 => 6,
        9 => 4,
        10 => 8,
        11 => 2,
        12 => 3,
        _ => return None,
    })
}

/// Converts the frd 20-node hexahedron order (Abaqus 1-12, 17-20, 13-16) to Abaqus order.
pub fn frd_hex20_to_abaqus(frd: &[u64]) -> Vec<u64> {
    let mut a = frd[..12].to_vec();
    a.extend_from_slice(&frd[16..20]);
    a.extend_from_slice(&frd[12..16]);
    a
}

struct Reader<'a> {
    lines: Vec<&'a str>,
    i: usize,
    file: &'a Path,
}

impl<'a> Reader<'a> {
    fn err(&self, ln: usize, expected: impl Into<String>, found: impl Into<String>) -> IoError {
        IoError::parse(self.file, ln, expected, found)
    }

    /// Field `[a, b)` of line `ln` (1-based) as trimmed text.
    fn field(&self, ln: usize, a: usize, b: usize, what: &str) -> Result<&'a str, IoError> {
        let l = self.lines[ln - 1];
        l.get(a..b.min(l.len()))
            .filter(|s| !s.trim().is_empty())
            .map(str::trim)
            .ok_or_else(|| self.err(ln, format!("{what} in columns {}-{}", a + 1, b), excerpt(l)))
    }

    fn int(&self, ln: usize, a: usize, b: usize, what: &str) -> Result<u64, IoError> {
        let f = self.field(ln, a, b, what)?;
        f.parse().map_err(|_| {
            self.err(
                ln,
                format!("an integer {what} in columns {}-{}", a + 1, b),
                excerpt(f),
            )
        })
    }

    fn real(&self, ln: usize, a: usize, b: usize, what: &str) -> Result<f64, IoError> {
        let f = self.field(ln, a, b, what)?;
        match f.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.err(
                ln,
                format!("a finite {what} in columns {}-{}", a + 1, b),
                excerpt(f),
            )),
        }
    }

    /// Record key of a line: its first whitespace token (`-1`, `2C`, `100CL`, `1PMODE`, ...).
    fn key(&self, ln: usize) -> &'a str {
        self.lines[ln - 1].split_whitespace().next().unwrap_or("")
    }

    /// Node-label width of a block from its format code (last token of the header line).
    fn width(&self, ln: usize) -> Result<usize, IoError> {
        let l = self.lines[ln - 1];
        match l
            .split_whitespace()
            .last()
            .and_then(|t| t.parse::<u32>().ok())
        {
            Some(0) => Ok(5),
            Some(1) => Ok(10),
            _ => Err(self.err(
                ln,
                "an ASCII block (format code 0 or 1 at the end of the line)",
                excerpt(l),
            )),
        }
    }

    /// Reads `-1 node v1 v2 v3` records up to `-3`; returns them with the line of the `-3`.
    fn node_values(
        &mut self,
        start: usize,
        w: usize,
        what: &str,
    ) -> Result<Vec<(u64, [f64; 3])>, IoError> {
        let mut out = Vec::new();
        loop {
            self.i += 1;
            let ln = self.i;
            if ln > self.lines.len() {
                return Err(self.err(
                    start,
                    format!("{what} block ended by -3"),
                    "end of file (file truncated?)",
                ));
            }
            match self.key(ln) {
                "-3" => return Ok(out),
                "-1" => {
                    let node = self.int(ln, 3, 3 + w, "node label")?;
                    let mut v = [0.0; 3];
                    for (k, x) in v.iter_mut().enumerate() {
                        let a = 3 + w + 12 * k;
                        *x = self.real(ln, a, a + 12, "value")?;
                    }
                    out.push((node, v));
                }
                "-4" | "-5" => {}
                other => {
                    return Err(self.err(
                        ln,
                        format!("a -1 record or -3 in the {what} block"),
                        excerpt(other),
                    ))
                }
            }
        }
    }

    /// Skips a result block this reader does not interpret, up to its `-3`.
    fn skip_block(&mut self, start: usize, what: &str) -> Result<(), IoError> {
        loop {
            self.i += 1;
            if self.i > self.lines.len() {
                return Err(self.err(
                    start,
                    format!("{what} block ended by -3"),
                    "end of file (file truncated?)",
                ));
            }
            if self.key(self.i) == "-3" {
                return Ok(());
            }
        }
    }

    fn elements(&mut self, start: usize, w: usize) -> Result<Vec<FrdElement>, IoError> {
        let mut out: Vec<FrdElement> = Vec::new();
        let mut need = 0usize;
        let mut cur_ln = start;
        loop {
            self.i += 1;
            let ln = self.i;
            if ln > self.lines.len() {
                return Err(self.err(
                    start,
                    "element block ended by -3",
                    "end of file (file truncated?)",
                ));
            }
            let key = self.key(ln);
            if key != "-2" && need > 0 {
                return Err(self.err(
                    cur_ln,
                    format!("{need} more node labels on -2 lines"),
                    excerpt(key),
                ));
            }
            match key {
                "-3" => return Ok(out),
                "-1" => {
                    let label = self.int(ln, 3, 3 + w, "element label")?;
                    let t = self.int(ln, 3 + w, 8 + w, "element type")? as u32;
                    need = frd_type_nodes(t)
                        .ok_or_else(|| self.err(ln, "an frd element type 1..12", t.to_string()))?;
                    cur_ln = ln;
                    out.push(FrdElement {
                        label,
                        frd_type: t,
                        nodes: Vec::with_capacity(need),
                    });
                }
                "-2" => {
                    let l = self.lines[ln - 1];
                    let el = out
                        .last_mut()
                        .ok_or_else(|| self.err(ln, "a -1 element record before -2", "-2"))?;
                    let mut a = 3;
                    while a < l.len() {
                        let f = l.get(a..(a + w).min(l.len())).map(str::trim).unwrap_or("");
                        if !f.is_empty() {
                            if need == 0 {
                                return Err(self.err(
                                    ln,
                                    "no more node labels for this element",
                                    excerpt(f),
                                ));
                            }
                            let n = f
                                .parse::<u64>()
                                .map_err(|_| self.err(ln, "an integer node label", excerpt(f)))?;
                            el.nodes.push(n);
                            need -= 1;
                        }
                        a += w;
                    }
                    if need == 0 && el.frd_type == 4 {
                        el.nodes = frd_hex20_to_abaqus(&el.nodes);
                    }
                }
                other => {
                    return Err(self.err(
                        ln,
                        "a -1, -2 or -3 record in the element block",
                        excerpt(other),
                    ))
                }
            }
        }
    }
}

/// Parses an ASCII `.frd` text.
pub fn parse_frd(text: &str, file: &Path) -> Result<FrdResult, IoError> {
    let mut r = Reader {
        lines: text.lines().collect(),
        i: 0,
        file,
    };
    let mut res = FrdResult::default();
    let mut mode = None;
    let mut ended = false;
    while r.i < r.lines.len() {
        r.i += 1;
        let ln = r.i;
        match r.key(ln) {
            "2C" => {
                let w = r.width(ln)?;
                let n = r.int(ln, 24, 36, "node count")? as usize;
                res.nodes = r.node_values(ln, w, "node")?;
                if res.nodes.len() != n {
                    return Err(IoError::invalid(
                        file,
                        ln,
                        format!(
                            "node block announces {n} nodes but holds {}",
                            res.nodes.len()
                        ),
                    ));
                }
            }
            "3C" => {
                let w = r.width(ln)?;
                let n = r.int(ln, 24, 36, "element count")? as usize;
                res.elements = r.elements(ln, w)?;
                if res.elements.len() != n {
                    return Err(IoError::invalid(
                        file,
                        ln,
                        format!(
                            "element block announces {n} elements but holds {}",
                            res.elements.len()
                        ),
                    ));
                }
            }
            "1PMODE" => {
                let l = r.lines[ln - 1];
                mode = Some(
                    l.split_whitespace()
                        .nth(1)
                        .and_then(|t| t.parse::<u32>().ok())
                        .ok_or_else(|| r.err(ln, "1PMODE and a mode number", excerpt(l)))?,
                );
            }
            "100CL" => {
                let value = r.real(ln, 12, 24, "step value (frequency)")?;
                let n = r.int(ln, 24, 36, "node count")? as usize;
                let w = r.width(ln)?;
                let next = ln + 1;
                let name = if next <= r.lines.len() && r.key(next) == "-4" {
                    r.lines[next - 1].split_whitespace().nth(1).unwrap_or("")
                } else {
                    return Err(r.err(ln, "a -4 record naming the result after 100CL", "none"));
                };
                if !name.eq_ignore_ascii_case("DISP") {
                    r.skip_block(ln, name)?;
                    continue;
                }
                let vals = r.node_values(ln, w, name)?;
                {
                    if vals.len() != n {
                        return Err(IoError::invalid(
                            file,
                            ln,
                            format!("DISP block announces {n} nodes but holds {}", vals.len()),
                        ));
                    }
                    res.modes.push(FrdMode {
                        mode: mode.take(),
                        frequency_hz: value,
                        disp: vals,
                    });
                }
            }
            "9999" => {
                ended = true;
                break;
            }
            _ => {}
        }
    }
    if !ended {
        return Err(IoError::parse(
            file,
            r.lines.len().max(1),
            "the end record 9999",
            "end of file (file truncated?)",
        ));
    }
    Ok(res)
}

/// Reads an ASCII `.frd` file.
pub fn read_frd(path: &Path) -> Result<FrdResult, IoError> {
    parse_frd(&read_text(path)?, path)
}
