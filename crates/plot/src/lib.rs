//! PNG figures with plotters: panels of lines and markers on linear or logarithmic axes,
//! with a legend and annotations, labelled with an embedded font (a subset of DejaVu
//! Sans, see `assets/LICENSE-DejaVu.txt`), so no system font is needed.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// Where the legend goes.
pub use plotters::chart::SeriesLabelPosition as LegendAt;
pub use plotters::style::RGBColor;

const FONT: &[u8] = include_bytes!("../assets/DejaVuSans-subset.ttf");
const FAMILY: &str = "sans-serif";

static FONT_SET: Once = Once::new();

/// Registers the embedded font (once per process, and not over a font given to
/// [`register_font_file`]); plotters draws no text without a font.
pub fn register_font() {
    FONT_SET.call_once(|| {
        // The bytes are a valid TrueType font, checked by this crate's test.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// Registers a TrueType font file for all labels instead of the embedded font.
pub fn register_font_file(path: &Path) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| {
        format!(
            "cannot read font {}: {e}; pass another --font FILE.ttf or none",
            path.display()
        )
    })?;
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font(FAMILY, FontStyle::Normal, bytes)
        .map_err(|_| format!("{} is not a usable TrueType font", path.display()))?;
    FONT_SET.call_once(|| {});
    Ok(())
}

/// A viridis-like colour map on [0, 1] (values outside are clamped to the ends; NaN
/// gives light grey, for "no data").
pub fn viridis(v: f64) -> RGBColor {
    if v.is_nan() {
        return RGBColor(230, 230, 230);
    }
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = v.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Colours that stay apart in print: black, red, green, blue, orange, purple, teal, grey.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(127, 127, 127),
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    Line,
    Dashed,
    /// Filled circles of the given radius in pixels.
    Points(u32),
    /// A line with circles on its points.
    LinePoints(u32),
}

/// One labelled series (an empty label keeps it out of the legend).
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub style: Style,
}

impl Series {
    pub fn new(
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        color: RGBColor,
        style: Style,
    ) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            style,
        }
    }
}

/// Extra marks in data coordinates.
#[derive(Debug, Clone)]
pub enum Annotation {
    /// A dashed circle (e.g. a sphere at impact); linear axes only.
    Circle {
        centre: (f64, f64),
        radius: f64,
        color: RGBColor,
    },
    /// Text whose top-left corner is at the point (data coordinates, mapped like the
    /// series on logarithmic axes).
    Text {
        at: (f64, f64),
        text: String,
        color: RGBColor,
    },
    /// A vertical error bar from `lo` to `hi` at `x`, with short caps.
    ErrorBar {
        x: f64,
        lo: f64,
        hi: f64,
        color: RGBColor,
    },
}

/// An axis: its label (with units) and whether it is logarithmic (base 10).
#[derive(Debug, Clone)]
pub struct Axis {
    pub label: String,
    pub log: bool,
    /// Fixed range in data units; `None` fits the data.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    pub fn linear(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            log: false,
            range: None,
        }
    }

    pub fn log(label: impl Into<String>) -> Self {
        Self {
            log: true,
            ..Self::linear(label)
        }
    }

    pub fn with_range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }

    fn map(&self, v: f64) -> Option<f64> {
        if self.log {
            (v > 0.0 && v.is_finite()).then(|| v.log10())
        } else {
            v.is_finite().then_some(v)
        }
    }
}

/// One panel of a figure.
#[derive(Debug, Clone)]
pub struct Panel {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub annotations: Vec<Annotation>,
    pub legend: LegendAt,
}

impl Panel {
    pub fn new(title: impl Into<String>, x: Axis, y: Axis) -> Self {
        Self {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
            annotations: Vec::new(),
            legend: LegendAt::UpperRight,
        }
    }
}

/// Writes `panels` in a grid of `rows` × `cols` into a PNG of `size` pixels.
pub fn write_png(
    path: &Path,
    size: (u32, u32),
    rows: usize,
    cols: usize,
    panels: &[Panel],
) -> Result<(), String> {
    register_font();
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    for (panel, area) in panels.iter().zip(root.split_evenly((rows, cols)).iter()) {
        draw_panel(area, panel)?;
    }
    root.present()
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn data_range(panel: &Panel, axis: &Axis, pick: impl Fn((f64, f64)) -> f64) -> (f64, f64) {
    if let Some((lo, hi)) = axis.range {
        let (lo, hi) = (axis.map(lo).unwrap_or(lo), axis.map(hi).unwrap_or(hi));
        return (lo, hi);
    }
    let mut vals: Vec<f64> = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().filter_map(|&p| axis.map(pick(p))))
        .collect();
    for a in &panel.annotations {
        match a {
            Annotation::Circle { centre, radius, .. } => {
                let c = pick(*centre);
                vals.extend([c - radius, c + radius]);
            }
            Annotation::Text { at, .. } => {
                let at = (panel.x.map(at.0), panel.y.map(at.1));
                if let (Some(x), Some(y)) = at {
                    vals.push(pick((x, y)));
                }
            }
            Annotation::ErrorBar { x, lo, hi, .. } => {
                for y in [lo, hi] {
                    if let (Some(x), Some(y)) = (panel.x.map(*x), panel.y.map(*y)) {
                        vals.push(pick((x, y)));
                    }
                }
            }
        }
    }
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
    (lo - pad, hi + pad)
}

/// Tick label: 10^v on a log axis; on a linear one, as many digits as tell apart ticks
/// about a tenth of `span` (the axis's extent) apart.
fn tick(log: bool, v: f64, span: f64) -> String {
    if log {
        let r = v.round();
        if (v - r).abs() < 1e-6 {
            format!("1e{}", r as i64)
        } else {
            format!("{:.2e}", 10f64.powf(v))
        }
    } else {
        let a = v.abs();
        let step = if span > 0.0 && span.is_finite() {
            span / 10.0
        } else {
            a.max(1.0)
        };
        if a <= 1e-9 * step {
            "0".to_string()
        } else if !(1e-3..1e4).contains(&a) {
            let digits = (a / step).log10().ceil().clamp(1.0, 8.0) as usize;
            format!("{v:.digits$e}", digits = digits.saturating_sub(1).max(1))
        } else {
            let decimals = (-step.log10()).ceil().clamp(0.0, 12.0) as usize;
            let text = format!("{v:.decimals$}");
            if text.contains('.') {
                text.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                text
            }
        }
    }
}

fn draw_panel(area: &DrawingArea<BitMapBackend, Shift>, panel: &Panel) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<_>| e.to_string();
    let (x0, x1) = data_range(panel, &panel.x, |p| p.0);
    let (y0, y1) = data_range(panel, &panel.y, |p| p.1);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FAMILY, 22))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    let (xl, yl) = (panel.x.log, panel.y.log);
    let (xs, ys) = (x1 - x0, y1 - y0);
    let xf = move |v: &f64| tick(xl, *v, xs);
    let yf = move |v: &f64| tick(yl, *v, ys);
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .x_desc(panel.x.label.as_str())
        .y_desc(panel.y.label.as_str())
        .axis_desc_style((FAMILY, 17))
        .label_style((FAMILY, 14))
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .draw()
        .map_err(err)?;
    let mut labelled = false;
    for s in &panel.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter_map(|&(x, y)| Some((panel.x.map(x)?, panel.y.map(y)?)))
            .collect();
        let c = s.color;
        let anno = match s.style {
            Style::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(2))),
            Style::Dashed => chart.draw_series(DashedLineSeries::new(pts, 8, 5, c.stroke_width(2))),
            Style::Points(r) => {
                chart.draw_series(pts.into_iter().map(|p| Circle::new(p, r, c.filled())))
            }
            Style::LinePoints(r) => {
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                    .map_err(err)?;
                chart.draw_series(pts.into_iter().map(|p| Circle::new(p, r, c.filled())))
            }
        }
        .map_err(err)?;
        if !s.label.is_empty() {
            labelled = true;
            let dashed = s.style == Style::Dashed;
            anno.label(s.label.as_str()).legend(move |(x, y)| {
                if dashed {
                    PathElement::new(vec![(x, y), (x + 8, y)], c.stroke_width(2))
                } else {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(3))
                }
            });
        }
    }
    for a in &panel.annotations {
        match a {
            Annotation::Circle {
                centre,
                radius,
                color,
            } => {
                let ring: Vec<(f64, f64)> = (0..=120)
                    .map(|k| {
                        let t = k as f64 * std::f64::consts::TAU / 120.0;
                        (centre.0 + radius * t.cos(), centre.1 + radius * t.sin())
                    })
                    .collect();
                chart
                    .draw_series(DashedLineSeries::new(ring, 6, 4, color.stroke_width(1)))
                    .map_err(err)?;
            }
            Annotation::Text { at, text, color } => {
                let (Some(x), Some(y)) = (panel.x.map(at.0), panel.y.map(at.1)) else {
                    continue;
                };
                chart
                    .draw_series(std::iter::once(Text::new(
                        text.clone(),
                        (x, y),
                        (FAMILY, 15).into_font().color(color),
                    )))
                    .map_err(err)?;
            }
            Annotation::ErrorBar { x, lo, hi, color } => {
                // A lower end at zero on a log axis runs to the bottom of the panel.
                let (Some(xm), Some(top)) = (panel.x.map(*x), panel.y.map(*hi)) else {
                    continue;
                };
                let bottom = panel.y.map(*lo).unwrap_or(y0).max(y0);
                let cap = 0.008 * (x1 - x0);
                let style = color.stroke_width(2);
                chart
                    .draw_series([
                        PathElement::new(vec![(xm, bottom), (xm, top)], style),
                        PathElement::new(vec![(xm - cap, top), (xm + cap, top)], style),
                        PathElement::new(vec![(xm - cap, bottom), (xm + cap, bottom)], style),
                    ])
                    .map_err(err)?;
            }
        }
    }
    if labelled {
        chart
            .configure_series_labels()
            .position(panel.legend.clone())
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FAMILY, 15))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_tick_labels_tell_close_ticks_apart() {
        // Ticks 1e-5 apart about 1.4e-3 (a temperature axis), and about 2e-5 (below the
        // plain range), each label distinct and read back within half a step.
        for (lo, step) in [(1.40e-3, 1e-5), (2.0e-5, 1e-7), (48.5, 0.05), (0.0, 0.5)] {
            let labels: Vec<String> = (0..10)
                .map(|k| tick(false, lo + k as f64 * step, 10.0 * step))
                .collect();
            for (k, l) in labels.iter().enumerate() {
                let v: f64 = l.parse().unwrap();
                assert!(
                    (v - (lo + k as f64 * step)).abs() < 0.5 * step,
                    "{labels:?}"
                );
            }
            let mut unique = labels.clone();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "{labels:?}");
        }
        assert_eq!(tick(false, 0.0, 1.0), "0");
        assert_eq!(tick(false, 2.0, 10.0), "2");
    }

    #[test]
    fn viridis_runs_from_purple_to_yellow_and_greys_out_nan() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), RGBColor(230, 230, 230));
    }

    #[test]
    fn writes_a_labelled_png() {
        let dir = std::env::temp_dir().join(format!("emdstar-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.png");
        let mut p = Panel::new("test", Axis::log("x (m)"), Axis::linear("y (s)"));
        p.series.push(Series::new(
            "a",
            vec![(1e-3, 1.0), (1.0, 2.0)],
            PALETTE[1],
            Style::Line,
        ));
        // One bar reaching down to zero, which a log axis cannot show.
        p.annotations.push(Annotation::ErrorBar {
            x: 0.1,
            lo: 0.0,
            hi: 1.5,
            color: PALETTE[3],
        });
        write_png(&path, (400, 300), 1, 1, &[p]).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
