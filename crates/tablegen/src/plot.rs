//! PNG heatmaps of a table over (a, b) at fixed c, like Figs. 4 and 5 of
//! Müller & Pöschel 2013 (one row of four panels per c-slice).

use emdstar_contact::RectCoords;
use emdstar_table::Table;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Panel titles, in the order of [`panel_value`].
pub const PANELS: [&str; 4] = ["log10 eps_phi", "eps_rdot", "log10(1 - eps_r)", "eps_t"];

/// The plotted value of panel `k` at one point.
fn panel_value(t: &Table, x: &RectCoords, k: usize) -> f64 {
    let m = t.lookup_rect(x).expect("plot points lie in the box");
    match k {
        0 => m.eps_phi.log10(),
        1 => m.eps_rdot,
        2 => m.one_minus_eps_r.log10(),
        _ => m.eps_t,
    }
}

/// A viridis-like colour map on [0, 1].
fn colour(v: f64) -> RGBColor {
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

/// Registers a TrueType font for the labels (plotters draws no text without one).
pub fn register_font(path: &Path) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| {
        format!(
            "cannot read font {}: {e}; pass --font FILE.ttf",
            path.display()
        )
    })?;
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
        .map_err(|_| format!("{} is not a usable TrueType font", path.display()))
}

/// Writes one PNG per c-slice into `dir` and returns their paths.
pub fn plot(
    table: &Table,
    c_slices: &[f64],
    dir: &Path,
    res: usize,
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let [ax, bx, cx] = *table.axes();
    let mut written = Vec::new();
    for (s, &c) in c_slices.iter().enumerate() {
        if !(cx.min..=cx.max).contains(&c) {
            return Err(format!(
                "c-slice {c} lies outside the table's c range [{}, {}]",
                cx.min, cx.max
            ));
        }
        let path = dir.join(format!("{}_slice{s}.png", table.model()));
        let root = BitMapBackend::new(&path, (1800, 470)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let title = format!("{} model, c = {c:.3}", table.model());
        let root = root
            .titled(&title, ("sans-serif", 24))
            .map_err(|e| e.to_string())?;
        for (k, area) in root.split_evenly((1, 4)).iter().enumerate() {
            let pts: Vec<(f64, f64, f64)> = (0..res * res)
                .map(|i| {
                    let a = ax.min + (i % res) as f64 + 0.5;
                    let b = bx.min + (i / res) as f64 + 0.5;
                    let (a, b) = (
                        ax.min + (a - ax.min) * (ax.max - ax.min) / res as f64,
                        bx.min + (b - bx.min) * (bx.max - bx.min) / res as f64,
                    );
                    (a, b, panel_value(table, &RectCoords { a, b, c }, k))
                })
                .collect();
            let lo = pts.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
            let hi = pts.iter().map(|p| p.2).fold(f64::NEG_INFINITY, f64::max);
            let span = if hi > lo { hi - lo } else { 1.0 };
            let (left, right) = area.split_horizontally(area.dim_in_pixel().0 - 100);
            let mut chart = ChartBuilder::on(&left)
                .caption(PANELS[k], ("sans-serif", 20))
                .margin(8)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(ax.min..ax.max, bx.min..bx.max)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("a = ln(c_phi/c_phi_min)")
                .y_desc("b = ln(l/l_min)")
                .draw()
                .map_err(|e| e.to_string())?;
            let (da, db) = (
                (ax.max - ax.min) / res as f64,
                (bx.max - bx.min) / res as f64,
            );
            chart
                .draw_series(pts.iter().map(|&(a, b, v)| {
                    Rectangle::new(
                        [(a - da / 2.0, b - db / 2.0), (a + da / 2.0, b + db / 2.0)],
                        colour((v - lo) / span).filled(),
                    )
                }))
                .map_err(|e| e.to_string())?;
            let mut bar = ChartBuilder::on(&right)
                .margin_top(40)
                .margin_bottom(48)
                .margin_left(4)
                .right_y_label_area_size(62)
                .build_cartesian_2d(0.0..1.0, lo..lo + span)
                .map_err(|e| e.to_string())?;
            bar.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_labels(6)
                .y_label_style(("sans-serif", 13))
                .y_label_formatter(&|v| format!("{v:.3}"))
                .draw()
                .map_err(|e| e.to_string())?;
            bar.draw_series((0..100).map(|i| {
                let v0 = lo + span * i as f64 / 100.0;
                Rectangle::new(
                    [(0.0, v0), (1.0, v0 + span / 100.0)],
                    colour(i as f64 / 99.0).filled(),
                )
            }))
            .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
        written.push(path.clone());
    }
    Ok(written)
}
