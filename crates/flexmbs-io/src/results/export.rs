//! CSV export and plots of result series.

use super::{Results, ResultsError};
use crate::plot::{LinePlot, Series, Style};
use std::fmt::Write as _;
use std::path::Path;

/// The series `names` (all of [`Results::series_names`] when empty) with their values; an unknown
/// name is an error listing close names.
fn selected(results: &Results, names: &[&str]) -> Result<Vec<(String, Vec<f64>)>, ResultsError> {
    let all;
    let names: Vec<&str> = if names.is_empty() {
        all = results.series_names();
        all.iter().map(String::as_str).collect()
    } else {
        names.to_vec()
    };
    names
        .into_iter()
        .map(|n| Ok((n.to_string(), results.series(n)?)))
        .collect()
}

/// A CSV field, quoted (RFC 4180) when it contains a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Writes the series `names` (all series when `names` is empty) as CSV: a header line `t,<names>`
/// and one line per output row; numbers in the shortest notation that reads back to the exact
/// value (`0.1`, `1.0`, `-1e-12`, `NaN`, `inf`; Python's `float` and NumPy parse all of them).
pub fn write_csv(results: &Results, names: &[&str], path: &Path) -> Result<(), ResultsError> {
    let columns = selected(results, names)?;
    let mut s = String::with_capacity(16 * (columns.len() + 1) * (results.rows() + 1));
    s.push('t');
    for (name, _) in &columns {
        s.push(',');
        s.push_str(&csv_field(name));
    }
    s.push('\n');
    for (i, t) in results.time.iter().enumerate() {
        let _ = write!(s, "{t:?}");
        for (_, v) in &columns {
            let _ = write!(s, ",{:?}", v[i]);
        }
        s.push('\n');
    }
    std::fs::write(path, s).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Plots the series `names` (at least one) against time on one chart, written as PNG or SVG
/// according to the extension of `path` (any other extension is an error). The y axis is labelled
/// with the signal unit when all plotted series are components of signals of the same unit.
pub fn plot_series(results: &Results, names: &[&str], path: &Path) -> Result<(), ResultsError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if ext != "png" && ext != "svg" {
        return Err(ResultsError::UnsupportedPlotFormat {
            path: path.to_path_buf(),
            extension: ext,
        });
    }
    if names.is_empty() {
        return Err(ResultsError::NoSeries {
            path: path.to_path_buf(),
        });
    }
    let columns = selected(results, names)?;
    let series = columns
        .into_iter()
        .map(|(name, v)| Series {
            name,
            points: results.time.iter().copied().zip(v).collect(),
            style: Style::Line,
        })
        .collect::<Vec<_>>();
    let units: Vec<Option<&str>> = series
        .iter()
        .map(|s| {
            results
                .layout
                .signals
                .iter()
                .find(|sig| {
                    s.name.len() > sig.name.len()
                        && s.name.starts_with(sig.name.as_str())
                        && s.name[sig.name.len()..].starts_with('.')
                })
                .map(|sig| sig.unit.as_str())
                .or_else(|| builtin_unit(&s.name))
        })
        .collect();
    let y_label = match units.first() {
        Some(Some(u)) if !u.is_empty() && units.iter().all(|x| x == &Some(*u)) => {
            format!("value [{u}]")
        }
        _ if series.len() == 1 => series[0].name.clone(),
        _ => "value".to_string(),
    };
    let plot = LinePlot {
        title: if results.layout.model.is_empty() {
            "results".to_string()
        } else {
            results.layout.model.clone()
        },
        // statics runs (attribute `solver` written by `flexmbs run`) store the load factor as time
        x_label: if results.attribute("solver") == Some("statics") {
            "load factor".into()
        } else {
            "t [s]".into()
        },
        y_label,
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(path)?;
    Ok(())
}

/// Units of the built-in series: energies in J, position drift in m (or rad for rotation rows),
/// step sizes in s. `None` for coordinates, whose units differ by column.
fn builtin_unit(name: &str) -> Option<&'static str> {
    if name.starts_with("energy/") {
        Some("J")
    } else if name == "step/h" {
        Some("s")
    } else {
        None
    }
}
