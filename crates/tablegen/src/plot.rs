//! PNG heatmaps of a table over (a, b) at fixed c, like Figs. 4 and 5 of
//! Müller & Pöschel 2013 (one row of four panels per c-slice).

use emdstar_contact::RectCoords;
use emdstar_plot::viridis;
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

/// Writes one PNG per c-slice into `dir` and returns their paths.
pub fn plot(
    table: &Table,
    c_slices: &[f64],
    dir: &Path,
    res: usize,
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    emdstar_plot::register_font();
    let [ax, bx, cx] = table.rect();
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
            // Enough decimals that the colour-bar labels differ (ε_ṙ spans 1e-6 at c = 0).
            let digits = ((2.0 - span.log10()).ceil().max(3.0) as usize).min(12);
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
                        viridis((v - lo) / span).filled(),
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
                .y_label_formatter(&|v| format!("{v:.digits$}"))
                .draw()
                .map_err(|e| e.to_string())?;
            bar.draw_series((0..100).map(|i| {
                let v0 = lo + span * i as f64 / 100.0;
                Rectangle::new(
                    [(0.0, v0), (1.0, v0 + span / 100.0)],
                    viridis(i as f64 / 99.0).filled(),
                )
            }))
            .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
        written.push(path.clone());
    }
    Ok(written)
}
