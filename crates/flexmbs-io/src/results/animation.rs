//! ParaView animation of a run: one `.vtu` per output frame and a `.pvd` collection.

use super::{temporary_sibling, ResultsError};
use crate::vtk::{write_pvd, write_vtu_with, VtuEncoding};
use flexmbs_fe::reduction::Cell;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The geometry of one body in the animation: its points in the reference configuration and its
/// cells (indices into `reference_points`, Abaqus node order as in [`crate::vtk`]).
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationBody {
    /// Body name (informational; bodies are told apart by the cell field `body`).
    pub name: String,
    /// Points in the reference configuration (global frame at t = 0).
    pub reference_points: Vec<[f64; 3]>,
    /// Cells of the body.
    pub cells: Vec<Cell>,
}

/// Writer of a ParaView animation: `dir/<name>.pvd` and `dir/<name>_frames/<name>_NNNNNN.vtu`.
///
/// Every frame is one unstructured grid with all bodies merged (points of body 0 first), the point
/// vector field `displacement` (written minus reference position), with
/// [`AnimationWriter::write_frame_elastic`] also `elastic_displacement` (the deformation alone,
/// global axes: the point minus where the rigidly moved body would put it), the cell field `body` (index of
/// the body the cell belongs to, as Float64) and the field data `TimeValue` (the frame time, which
/// ParaView shows). The `.pvd` (file names relative to its directory) is rewritten atomically
/// after the first frame and then whenever [`AnimationWriter::pvd_interval`] of wall time (default
/// 1 s, raised to ten times the duration of the last rewrite) has passed, on
/// [`AnimationWriter::flush`] and when the writer is dropped: an interrupted run leaves a loadable
/// animation that lags at most one interval, and the cost stays linear in the number of frames
/// (rewriting after every frame made it quadratic: 10 000 frames took 20 s).
/// [`AnimationWriter::create`] removes frame files of an earlier run with the same name.
#[derive(Debug)]
pub struct AnimationWriter {
    dir: PathBuf,
    name: String,
    bodies: Vec<AnimationBody>,
    /// Merged reference points.
    reference: Vec<[f64; 3]>,
    /// Merged cells (point indices offset by body).
    cells: Vec<Cell>,
    /// Body index per merged cell.
    body_of_cell: Vec<f64>,
    /// `(time, file relative to dir)` of every frame written.
    entries: Vec<(f64, String)>,
    /// Least wall time between two `.pvd` rewrites.
    pvd_interval: Duration,
    /// Time and duration of the last `.pvd` rewrite.
    last_pvd: Option<(Instant, Duration)>,
    /// Frames written since the last `.pvd` rewrite.
    pvd_dirty: bool,
    /// Extra point fields of the next frame ([`AnimationWriter::set_next_point_fields`]).
    next_fields: Vec<(String, usize, Vec<f64>)>,
    /// Extra parts of the next frame ([`AnimationWriter::set_next_parts`]).
    next_parts: Vec<super::AnimationPart>,
    /// `(time, part, file)` of every extra part written (parts 1, 2, ...).
    part_entries: Vec<(f64, usize, String)>,
}

impl AnimationWriter {
    /// Creates `dir` and `dir/<name>_frames` if needed and checks the bodies (cells with the
    /// right number of nodes, indices in range). `name` must be a plain file name stem.
    pub fn create(
        dir: &Path,
        name: &str,
        bodies: Vec<AnimationBody>,
    ) -> Result<Self, ResultsError> {
        let pvd = dir.join(format!("{name}.pvd"));
        let invalid = |message: String| ResultsError::InvalidAnimation {
            path: pvd.clone(),
            message,
        };
        if name.is_empty()
            || name == "."
            || name == ".."
            || name.contains(['/', '\\'])
            || name.chars().any(char::is_control)
        {
            return Err(invalid(format!(
                "animation name {name:?} must be a plain file name"
            )));
        }
        let mut reference = Vec::new();
        let mut cells = Vec::new();
        let mut body_of_cell = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            let n = body.reference_points.len();
            for (ci, c) in body.cells.iter().enumerate() {
                if c.nodes.len() != c.kind.num_nodes() {
                    return Err(invalid(format!(
                        "body {b} ('{}'), cell {ci} ({:?}) has {} nodes, expected {}",
                        body.name,
                        c.kind,
                        c.nodes.len(),
                        c.kind.num_nodes()
                    )));
                }
                if let Some(&i) = c.nodes.iter().find(|&&i| i >= n) {
                    return Err(invalid(format!(
                        "body {b} ('{}'), cell {ci} refers to point {i}, but the body has {n} points",
                        body.name
                    )));
                }
                cells.push(Cell {
                    kind: c.kind,
                    nodes: c.nodes.iter().map(|&i| i + reference.len()).collect(),
                });
                body_of_cell.push(b as f64);
            }
            if let Some(p) = body
                .reference_points
                .iter()
                .find(|p| !p.iter().all(|x| x.is_finite()))
            {
                return Err(invalid(format!(
                    "body {b} ('{}') has a non-finite reference point {p:?}",
                    body.name
                )));
            }
            reference.extend_from_slice(&body.reference_points);
        }
        let frames = dir.join(format!("{name}_frames"));
        std::fs::create_dir_all(&frames).map_err(|source| ResultsError::Io {
            path: frames.clone(),
            source,
        })?;
        remove_old_frames(&frames, name)?;
        Ok(AnimationWriter {
            dir: dir.to_path_buf(),
            name: name.to_string(),
            bodies,
            reference,
            cells,
            body_of_cell,
            entries: Vec::new(),
            pvd_interval: Duration::from_secs(1),
            last_pvd: None,
            pvd_dirty: false,
            next_fields: Vec::new(),
            next_parts: Vec::new(),
            part_entries: Vec::new(),
        })
    }

    /// Sets the least wall time between two `.pvd` rewrites (`Duration::ZERO`: after every
    /// frame, whatever the rewrite costs).
    pub fn with_pvd_interval(mut self, interval: Duration) -> Self {
        self.pvd_interval = interval;
        self
    }

    /// The least wall time between two `.pvd` rewrites.
    pub fn pvd_interval(&self) -> Duration {
        self.pvd_interval
    }

    /// Extra point fields `(name, components, values)` for the next frame only (merged over the
    /// bodies like the points: `components x` all points values each, e.g. stresses); a wrong
    /// length is an error of that frame's write.
    pub fn set_next_point_fields(&mut self, fields: Vec<(String, usize, Vec<f64>)>) {
        self.next_fields = fields;
    }

    /// Extra parts for the next frame only (contact points, contours: [`super::AnimationPart`]),
    /// written as `<name>_frames/<name>_<part name>_NNNNNN.vtu` and listed in the `.pvd` as parts
    /// 1, 2, ... of the frame's time (the bodies are part 0); a bad part is an error of that
    /// frame's write.
    pub fn set_next_parts(&mut self, parts: Vec<super::AnimationPart>) {
        self.next_parts = parts;
    }

    /// Rewrites the `.pvd` if frames were written since the last rewrite.
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        if self.pvd_dirty {
            self.write_pvd_atomically()?;
        }
        Ok(())
    }

    /// Writes the frame at time `t` (finite, greater than the previous frame's time);
    /// `positions[b]` are the current positions of body b's points (same count as its reference
    /// points). Then rewrites the `.pvd`.
    pub fn write_frame(&mut self, t: f64, positions: &[&[[f64; 3]]]) -> Result<(), ResultsError> {
        self.write_frame_elastic(t, positions, None)
    }

    /// [`AnimationWriter::write_frame`] with the point field `elastic_displacement`:
    /// `elastic[b]` per point of body b (same counts as `positions`).
    pub fn write_frame_elastic(
        &mut self,
        t: f64,
        positions: &[&[[f64; 3]]],
        elastic: Option<&[&[[f64; 3]]]>,
    ) -> Result<(), ResultsError> {
        let invalid = |message: String| ResultsError::InvalidAnimation {
            path: self.pvd_path(),
            message,
        };
        if !t.is_finite() {
            return Err(invalid(format!("frame time {t} is not finite")));
        }
        if let Some(&(last, _)) = self.entries.last() {
            if t <= last {
                return Err(invalid(format!(
                    "frame time {t} is not after the previous frame's time {last}"
                )));
            }
        }
        if positions.len() != self.bodies.len() {
            return Err(invalid(format!(
                "{} position lists for {} bodies",
                positions.len(),
                self.bodies.len()
            )));
        }
        let mut points = Vec::with_capacity(self.reference.len());
        for (b, (body, p)) in self.bodies.iter().zip(positions).enumerate() {
            if p.len() != body.reference_points.len() {
                return Err(invalid(format!(
                    "body {b} ('{}'): {} positions for {} points",
                    body.name,
                    p.len(),
                    body.reference_points.len()
                )));
            }
            points.extend_from_slice(p);
        }
        let displacement: Vec<f64> = points
            .iter()
            .zip(&self.reference)
            .flat_map(|(x, x0)| [x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]])
            .collect();
        let mut elastic_field = Vec::new();
        if let Some(el) = elastic {
            for (b, (e, p)) in el.iter().zip(positions).enumerate() {
                if e.len() != p.len() {
                    return Err(invalid(format!(
                        "body {b}: {} elastic displacements for {} points",
                        e.len(),
                        p.len()
                    )));
                }
                elastic_field.extend(e.iter().flatten());
            }
            if el.len() != positions.len() {
                return Err(invalid(format!(
                    "{} elastic lists for {} bodies",
                    el.len(),
                    positions.len()
                )));
            }
        }
        let k = self.entries.len();
        let rel = format!("{0}_frames/{0}_{k:06}.vtu", self.name);
        let file = self.dir.join(&rel);
        let both: [(&str, usize, &[f64]); 2] = [
            ("displacement", 3, &displacement),
            ("elastic_displacement", 3, &elastic_field),
        ];
        let mut fields = if elastic.is_some() {
            both.to_vec()
        } else {
            both[..1].to_vec()
        };
        let extra = std::mem::take(&mut self.next_fields);
        fields.extend(extra.iter().map(|(n, c, v)| (n.as_str(), *c, v.as_slice())));
        write_vtu_with(
            &file,
            &points,
            &self.cells,
            &fields,
            &[("body", 1, &self.body_of_cell)],
            &[("TimeValue", 1, &[t])],
            VtuEncoding::Base64,
        )?;
        for (i, part) in std::mem::take(&mut self.next_parts).iter().enumerate() {
            part.check()
                .map_err(|message| ResultsError::InvalidAnimation {
                    path: self.pvd_path(),
                    message,
                })?;
            let rel = format!("{0}_frames/{0}_{1}_{k:06}.vtu", self.name, part.name);
            super::animation_parts::write_part_vtu(&self.dir.join(&rel), part, t)?;
            self.part_entries.push((t, i + 1, rel));
        }
        self.entries.push((t, rel));
        self.pvd_dirty = true;
        let due = match self.last_pvd {
            None => true,
            Some(_) if self.pvd_interval.is_zero() => true,
            Some((at, cost)) => at.elapsed() >= self.pvd_interval.max(10 * cost),
        };
        if due {
            self.write_pvd_atomically()?;
        }
        Ok(())
    }

    /// Number of frames written.
    pub fn frames(&self) -> usize {
        self.entries.len()
    }

    /// `dir/<name>.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(format!("{}.pvd", self.name))
    }

    fn write_pvd_atomically(&mut self) -> Result<(), ResultsError> {
        let start = Instant::now();
        self.write_pvd_file()?;
        self.last_pvd = Some((Instant::now(), start.elapsed()));
        self.pvd_dirty = false;
        Ok(())
    }

    fn write_pvd_file(&self) -> Result<(), ResultsError> {
        let pvd = self.pvd_path();
        let tmp = temporary_sibling(&pvd);
        let refs: Vec<(f64, &str)> = self.entries.iter().map(|(t, f)| (*t, f.as_str())).collect();
        let written = if self.part_entries.is_empty() {
            write_pvd(&tmp, &refs).map_err(ResultsError::from)
        } else {
            // bodies (part 0) and the extra parts of each time, in time order
            let mut all: Vec<(f64, usize, &str)> = refs.iter().map(|&(t, f)| (t, 0, f)).collect();
            all.extend(
                self.part_entries
                    .iter()
                    .map(|(t, p, f)| (*t, *p, f.as_str())),
            );
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            super::animation_parts::write_pvd_with_parts(&tmp, &all)
        };
        if let Err(e) = written {
            let _ = std::fs::remove_file(&tmp);
            return Err(e);
        }
        std::fs::rename(&tmp, &pvd).map_err(|source| {
            let _ = std::fs::remove_file(&tmp);
            ResultsError::Io { path: pvd, source }
        })
    }
}

impl Drop for AnimationWriter {
    /// Writes the `.pvd` of the frames not yet listed (errors cannot be reported here: call
    /// [`AnimationWriter::flush`] to see them).
    fn drop(&mut self) {
        if self.pvd_dirty {
            let _ = self.write_pvd_file();
        }
    }
}

/// Removes `<name>_NNNNNN.vtu` files (frames of an earlier run) from `frames`; other files stay.
fn remove_old_frames(frames: &Path, name: &str) -> Result<(), ResultsError> {
    let io = |source| ResultsError::Io {
        path: frames.to_path_buf(),
        source,
    };
    let prefix = format!("{name}_");
    for entry in std::fs::read_dir(frames).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let Some(file) = path.file_name().and_then(|f| f.to_str()) else {
            continue;
        };
        // `<name>_NNNNNN.vtu` and the extra parts' `<name>_<part>_NNNNNN.vtu`
        let is_frame = file
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(".vtu"))
            .map(|r| r.rsplit_once('_').map_or(r, |(_, k)| k))
            .is_some_and(|k| k.len() == 6 && k.bytes().all(|b| b.is_ascii_digit()));
        if is_frame {
            std::fs::remove_file(&path).map_err(|source| ResultsError::Io { path, source })?;
        }
    }
    Ok(())
}
