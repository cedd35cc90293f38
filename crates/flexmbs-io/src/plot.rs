//! Line plots to PNG or SVG (plotters with an embedded DejaVu Sans font, no system library).

use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;
use thiserror::Error;

/// A closed interval `(lo, hi)` of an axis.
type Span = (f64, f64);

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Plotting errors.
#[derive(Debug, Error)]
pub enum PlotError {
    /// The backend failed (file not writable, ...).
    #[error("{file}: cannot draw plot: {message}")]
    Draw {
        /// Output file.
        file: PathBuf,
        /// Backend message.
        message: String,
    },
    /// Nothing to plot.
    #[error("{file}: no finite data points to plot")]
    Empty {
        /// Output file.
        file: PathBuf,
    },
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Connected line.
    Line,
    /// Markers only.
    Points,
    /// Line with markers.
    LinePoints,
}

/// One named data series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

/// A 2D line plot.
#[derive(Debug, Clone)]
pub struct LinePlot {
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Series.
    pub series: Vec<Series>,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
}

fn register_font() {
    REGISTER.call_once(|| {
        // The embedded font is valid; a failure here would only lose text, never panic.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

const COLORS: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 0),
    RGBColor(255, 215, 0),
];

impl LinePlot {
    /// Writes the plot; the format follows the extension (`.svg`, otherwise PNG), 900 x 560 pixels.
    pub fn write(&self, path: &Path) -> Result<(), PlotError> {
        register_font();
        let err = |e: String| PlotError::Draw {
            file: path.to_path_buf(),
            message: e,
        };
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
        {
            let root = SVGBackend::new(path, (1000, 620)).into_drawing_area();
            self.draw(&root, path)?;
            root.present().map_err(|e| err(e.to_string()))
        } else {
            let root = BitMapBackend::new(path, (1000, 620)).into_drawing_area();
            self.draw(&root, path)?;
            root.present().map_err(|e| err(e.to_string()))
        }
    }

    fn range(&self, path: &Path) -> Result<(Span, Span), PlotError> {
        let ok = |v: f64, log: bool| v.is_finite() && (!log || v > 0.0);
        let pts = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| ok(p.0, self.log_x) && ok(p.1, self.log_y));
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if x0 > x1 {
            return Err(PlotError::Empty {
                file: path.to_path_buf(),
            });
        }
        let pad = |a: f64, b: f64, log: bool| {
            if log {
                (a / 1.2, b * 1.2)
            } else if b - a <= f64::EPSILON * (a.abs() + b.abs()).max(1.0) {
                (a - 0.5 * a.abs().max(1.0), b + 0.5 * b.abs().max(1.0))
            } else {
                (a - 0.05 * (b - a), b + 0.05 * (b - a))
            }
        };
        // headroom for the legend: the data stays below the legend band at the top
        let (ya, yb) = pad(y0, y1, self.log_y);
        let f = self.legend_fraction();
        let yb = if self.log_y {
            yb * (yb / ya).powf(f / (1.0 - f))
        } else {
            yb + (yb - ya) * f / (1.0 - f)
        };
        Ok((pad(x0, x1, self.log_x), (ya, yb)))
    }

    /// Fraction of the plot height the legend takes (upper right).
    fn legend_fraction(&self) -> f64 {
        (0.04 + 0.06 * self.series.len() as f64).min(0.5)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
        path: &Path,
    ) -> Result<(), PlotError>
    where
        DB::ErrorType: 'static,
    {
        let err = |e: String| PlotError::Draw {
            file: path.to_path_buf(),
            message: e,
        };
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let ((x0, x1), (y0, y1)) = self.range(path)?;
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(75);
        macro_rules! body {
            ($chart:expr) => {{
                let mut chart = $chart.map_err(|e| err(e.to_string()))?;
                chart
                    .configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .x_label_formatter(&|v| tick_label(*v, x1 - x0))
                    .y_label_formatter(&|v| tick_label(*v, y1 - y0))
                    .label_style(("sans-serif", 14))
                    .draw()
                    .map_err(|e| err(e.to_string()))?;
                for (i, s) in self.series.iter().enumerate() {
                    let c = COLORS[i % COLORS.len()];
                    let pts: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|p| p.0.is_finite() && p.1.is_finite())
                        .collect();
                    if matches!(s.style, Style::Line | Style::LinePoints) {
                        chart
                            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                            .map_err(|e| err(e.to_string()))?
                            .label(&s.name)
                            .legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                            });
                    }
                    if matches!(s.style, Style::Points | Style::LinePoints) {
                        let a = chart
                            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
                            .map_err(|e| err(e.to_string()))?;
                        if s.style == Style::Points {
                            a.label(&s.name)
                                .legend(move |(x, y)| Circle::new((x + 9, y), 4, c.filled()));
                        }
                    }
                }
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperRight)
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 14))
                    .draw()
                    .map_err(|e| err(e.to_string()))?;
            }};
        }
        match (self.log_x, self.log_y) {
            (false, false) => body!(builder.build_cartesian_2d(x0..x1, y0..y1)),
            (true, false) => body!(builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1)),
            (false, true) => body!(builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale())),
            (true, true) => {
                body!(builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale()))
            }
        }
        Ok(())
    }
}

/// Axis tick text that keeps the digits that tell ticks apart: fixed-point with enough decimals
/// for a twentieth of the axis span, scientific notation for very small or very large values
/// (plotters' default printed +-1e-5 ticks as "0.0").
fn tick_label(v: f64, span: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.3e}");
    }
    let step = (span / 20.0).abs();
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10().floor()).clamp(0.0, 9.0) as usize
    } else {
        3
    };
    format!("{v:.decimals$}")
}

#[cfg(test)]
mod tick_tests {
    use super::tick_label;

    #[test]
    fn ticks_keep_distinguishing_digits() {
        assert_eq!(tick_label(1e-5, 4e-5), "1.000e-5");
        assert_eq!(tick_label(-2e-5, 4e-5), "-2.000e-5");
        assert_eq!(tick_label(0.0, 1.0), "0");
        assert_eq!(tick_label(0.25, 1.0), "0.25");
        assert_eq!(tick_label(12.0, 50.0), "12");
        assert_eq!(tick_label(0.0876, 0.02), "0.088");
        assert_eq!(tick_label(2.5e6, 1e6), "2.500e6");
        // neighbouring ticks of a narrow range around a large offset stay apart
        assert_ne!(tick_label(100.001, 0.005), tick_label(100.0015, 0.005));
    }
}
