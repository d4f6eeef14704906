//! Line plots of curves, written as SVG and PNG with an embedded font (DejaVu Sans, see
//! `assets/fonts/`), so no system font library is needed.

use super::{write_atomic, ReportError};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        // Registration only fails on a corrupt font, which the test below would catch.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// a line through the points
    Line,
    /// markers at the points
    Points,
    /// a dashed line (reference curves: theory)
    Dashed,
    /// a thin pale line (the members of an ensemble)
    Thin,
    /// a filled translucent region whose outline is the series' points (a confidence band)
    Band,
}

/// One curve of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// legend text
    pub label: String,
    /// abscissae
    pub x: Vec<f64>,
    /// ordinates
    pub y: Vec<f64>,
    /// how it is drawn
    pub style: Style,
}

impl Series {
    /// A line series.
    pub fn line(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style: Style::Line,
        }
    }
    /// A marker series.
    pub fn points(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style: Style::Points,
        }
    }
    /// A dashed line series.
    pub fn dashed(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style: Style::Dashed,
        }
    }
    /// A thin pale line series (one member of an ensemble).
    pub fn thin(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style: Style::Thin,
        }
    }
    /// The band between `low` and `high` over `x` (all of one length): its outline runs along
    /// `high` forward and back along `low`.
    pub fn band(label: &str, x: &[f64], low: &[f64], high: &[f64]) -> Self {
        let xs = x.iter().chain(x.iter().rev()).copied().collect();
        let ys = high.iter().chain(low.iter().rev()).copied().collect();
        Series {
            label: label.into(),
            x: xs,
            y: ys,
            style: Style::Band,
        }
    }
}

/// A plot: title, axis labels (with units) and curves.
#[derive(Debug, Clone)]
pub struct Plot {
    /// title above the axes
    pub title: String,
    /// x-axis label, with unit
    pub x_label: String,
    /// y-axis label, with unit
    pub y_label: String,
    /// the curves
    pub series: Vec<Series>,
    /// logarithmic axes (points with a non-positive coordinate are left out)
    pub log_log: bool,
}

impl Plot {
    /// A plot with no curves yet.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Plot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            log_log: false,
        }
    }

    /// Both axes logarithmic (error against cost).
    pub fn log_log(mut self) -> Self {
        self.log_log = true;
        self
    }

    fn shown(&self, x: f64, y: f64) -> bool {
        x.is_finite() && y.is_finite() && (!self.log_log || (x > 0.0 && y > 0.0))
    }

    /// Add a curve.
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// Write `<stem>.svg` and `<stem>.png` in `dir`.
    pub fn write(&self, dir: &Path, stem: &str) -> Result<(), ReportError> {
        register_font();
        let svg_path = dir.join(format!("{stem}.svg"));
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (800, 560)).into_drawing_area();
            self.draw(&root, &svg_path)?;
        }
        write_atomic(&svg_path, svg.as_bytes())?;

        // The bitmap backend encodes to a file itself: draw into a temporary name, then rename.
        let png_path = dir.join(format!("{stem}.png"));
        let tmp = dir.join(format!(".{stem}.tmp{}.png", std::process::id()));
        let drawn = {
            let root = BitMapBackend::new(&tmp, (1000, 700)).into_drawing_area();
            self.draw(&root, &png_path)
        };
        if let Err(e) = drawn {
            let _ = std::fs::remove_file(&tmp);
            return Err(e);
        }
        super::finish_temp(&tmp, &png_path, Ok(()))
    }

    /// Write the plot ([`Plot::write`]) as `<stem>.svg` and `<stem>.png` in `dir`, returning
    /// the two file names under `rel` (the folder as the caller lists it, e.g. `plots`). A
    /// plot that cannot be written does not stop the caller: the failure, naming the file and
    /// the OS's reason, goes into `warnings` and no file is returned.
    pub fn write_or_warn(
        &self,
        dir: &Path,
        stem: &str,
        rel: &str,
        warnings: &mut Vec<String>,
    ) -> Vec<String> {
        match self.write(dir, stem) {
            Ok(()) => vec![format!("{rel}/{stem}.svg"), format!("{rel}/{stem}.png")],
            Err(e) => {
                warnings.push(format!(
                    "plot not written ({e}); the other results are kept"
                ));
                Vec::new()
            }
        }
    }

    fn bounds(&self) -> ((f64, f64), (f64, f64)) {
        let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
        let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &self.series {
            for (&x, &y) in s.x.iter().zip(&s.y) {
                if self.shown(x, y) {
                    xr = (xr.0.min(x), xr.1.max(x));
                    yr = (yr.0.min(y), yr.1.max(y));
                }
            }
        }
        let log = self.log_log;
        let pad = |r: (f64, f64)| {
            if !r.0.is_finite() {
                return if log { (0.1, 10.0) } else { (0.0, 1.0) };
            }
            if log {
                // a fifth of a decade each side, at least a decade in all
                let (lo, hi) = (r.0.log10() - 0.2, r.1.log10() + 0.2);
                let mid = 0.5 * (lo + hi);
                let half = (0.5 * (hi - lo)).max(0.5);
                return (10f64.powf(mid - half), 10f64.powf(mid + half));
            }
            let span = (r.1 - r.0).max(1e-12 * r.0.abs().max(1.0));
            (r.0 - 0.04 * span, r.1 + 0.04 * span)
        };
        (pad(xr), pad(yr))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, plotters::coord::Shift>,
        path: &Path,
    ) -> Result<(), ReportError> {
        let err = |e: String| ReportError::Plot {
            path: path.display().to_string(),
            reason: e,
        };
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let ((x0, x1), (y0, y1)) = self.bounds();
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72);
        if self.log_log {
            let chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| err(e.to_string()))?;
            self.draw_series(chart, &err)?;
        } else {
            let chart = builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(e.to_string()))?;
            self.draw_series(chart, &err)?;
        }
        root.present().map_err(|e| err(e.to_string()))
    }

    /// The mesh, the curves and the legend, on linear or logarithmic axes.
    fn draw_series<'a, DB, X, Y>(
        &self,
        mut chart: ChartContext<'a, DB, Cartesian2d<X, Y>>,
        err: &dyn Fn(String) -> ReportError,
    ) -> Result<(), ReportError>
    where
        DB: DrawingBackend + 'a,
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        // curves take the palette's colours in turn; a band takes the colour of the curve
        // that follows it (the mean it surrounds), ensemble members a fixed grey
        let pale = RGBAColor(128, 128, 128, 0.6);
        let mut curves = 0;
        for s in &self.series {
            let color = Palette99::pick(curves).to_rgba();
            let pts: Vec<(f64, f64)> =
                s.x.iter()
                    .zip(&s.y)
                    .filter(|(x, y)| self.shown(**x, **y))
                    .map(|(&x, &y)| (x, y))
                    .collect();
            let anno = match s.style {
                Style::Line => chart
                    .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                    .map_err(|e| err(e.to_string()))?,
                Style::Dashed => chart
                    .draw_series(DashedLineSeries::new(pts, 8, 5, color.stroke_width(2)))
                    .map_err(|e| err(e.to_string()))?,
                Style::Points => chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| err(e.to_string()))?,
                Style::Thin => chart
                    .draw_series(LineSeries::new(pts, pale.stroke_width(1)))
                    .map_err(|e| err(e.to_string()))?,
                Style::Band => chart
                    .draw_series(std::iter::once(Polygon::new(pts, color.mix(0.25).filled())))
                    .map_err(|e| err(e.to_string()))?,
            };
            if !matches!(s.style, Style::Thin | Style::Band) {
                curves += 1;
            }
            // unlabelled series (the second branch of a band, further ensemble members) stay
            // out of the legend
            if s.label.is_empty() {
                continue;
            }
            let anno = anno.label(s.label.clone());
            match s.style {
                Style::Band => anno.legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 20, y + 5)], color.mix(0.25).filled())
                }),
                Style::Thin => anno.legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], pale.stroke_width(2))
                }),
                _ => anno.legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                }),
            };
        }
        if self.series.iter().any(|s| !s.label.is_empty()) {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|e| err(e.to_string()))?;
        }
        Ok(())
    }
}

/// An axis label with three significant digits and no floating-point tail (0.30000000000000004
/// is "0.3"); scientific notation outside 1e-4 … 1e5.
fn tick(v: &f64) -> String {
    let v = *v;
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    let exponent = v.abs().log10().floor();
    if !(-4.0..5.0).contains(&exponent) {
        let s = format!("{v:.2e}");
        return match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m.to_string())),
            None => s,
        };
    }
    let decimals = (2.0 - exponent).max(0.0) as usize;
    trim(format!("{v:.decimals$}"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks_have_no_floating_point_tail() {
        for (v, s) in [
            (0.30000000000000004, "0.3"),
            (0.009000000001, "0.009"),
            (1e-5, "1e-5"),
            (2.5e6, "2.5e6"),
            (1025.0, "1025"),
            (-0.125, "-0.125"),
            (0.0, "0"),
        ] {
            assert_eq!(tick(&v), s);
        }
    }

    use super::*;

    #[test]
    fn a_plot_writes_svg_with_text_and_a_png() {
        let dir = std::env::temp_dir().join(format!("turf-plot-{}", std::process::id()));
        let x: Vec<f64> = (0..50).map(|i| i as f64 / 10.0).collect();
        let y: Vec<f64> = x.iter().map(|v| v.sin()).collect();
        Plot::new("sine", "x (nm)", "y (nN)")
            .with(Series::line("sin", x.clone(), y.clone()))
            .with(Series::dashed(
                "ref",
                x.clone(),
                y.iter().map(|v| 0.5 * v).collect(),
            ))
            .with(Series::points("pts", x.clone(), y.clone()))
            .with(Series::thin(
                "",
                x.clone(),
                y.iter().map(|v| 0.8 * v).collect(),
            ))
            .with(Series::band(
                "band",
                &x,
                &y.iter().map(|v| v - 0.1).collect::<Vec<_>>(),
                &y.iter().map(|v| v + 0.1).collect::<Vec<_>>(),
            ))
            .write(&dir, "sine")
            .unwrap();
        let svg = std::fs::read_to_string(dir.join("sine.svg")).unwrap();
        assert!(svg.contains("sine") && svg.contains("x (nm)"));
        let png = std::fs::read(dir.join("sine.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        std::fs::remove_dir_all(dir).ok();
    }

    #[test]
    fn a_plot_that_cannot_be_written_is_a_warning_and_leaves_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("turf-plot-fail-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        // a folder where the PNG should go: the SVG is written, the PNG's rename fails
        std::fs::create_dir_all(dir.join("p.png")).unwrap();
        let plot = Plot::new("p", "x", "y").with(Series::line("l", vec![0.0, 1.0], vec![0.0, 1.0]));
        let mut warnings = Vec::new();
        let files = plot.write_or_warn(&dir, "p", "plots", &mut warnings);
        assert!(files.is_empty());
        assert_eq!(warnings.len(), 1);
        assert!(
            warnings[0].contains("p.png") && warnings[0].contains("os error"),
            "{warnings:?}"
        );
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(left.iter().all(|n| !n.contains(".tmp")), "{left:?}");
        std::fs::remove_dir_all(dir).ok();
    }
}
