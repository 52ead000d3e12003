//! PNG figures of the hopper example: field maps and curves against time.

use emdstar_plot::viridis;
use plotters::prelude::*;
use std::path::Path;

type Fields = (Vec<f64>, Vec<f64>);
type Series = [(f64, f64, usize, usize)];
/// A named, coloured curve.
type Line<'a> = (&'a str, Vec<(f64, f64)>, RGBColor);

/// Two side-by-side maps (MD, hybrid) of one field over the lower `rows` bins.
fn map_pair(
    path: &Path,
    title: &str,
    md: &[f64],
    hybrid: &[f64],
    (nx, ny, bin): (usize, usize, f64),
    max: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let rows = ny.min(60);
    let root = BitMapBackend::new(path, (900, 900)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(840);
    let panels = top.split_evenly((1, 2));
    for (panel, (data, name)) in panels.iter().zip([(md, "MD"), (hybrid, "hybrid")]) {
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{title}: {name}"), ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..nx as f64 * bin * 1e3, 0.0..rows as f64 * bin * 1e3)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .draw()?;
        for by in 0..rows {
            for bx in 0..nx {
                let v = data[by * nx + bx] / max;
                let (x0, y0) = (bx as f64 * bin * 1e3, by as f64 * bin * 1e3);
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(x0, y0), (x0 + bin * 1e3, y0 + bin * 1e3)],
                    viridis(v).filled(),
                )))?;
            }
        }
    }
    let legend = format!("colour scale: 0 (dark) to {max} (yellow); grey: no particle");
    bottom.draw(&Text::new(legend, (20, 20), ("sans-serif", 18)))?;
    root.present()?;
    Ok(())
}

/// The volume-fraction and velocity-magnitude maps, MD beside hybrid.
pub fn maps(
    out: &Path,
    md: &Fields,
    hybrid: &Fields,
    grid: (usize, usize, f64),
) -> Result<(), Box<dyn std::error::Error>> {
    let phi_max = md.0.iter().chain(&hybrid.0).cloned().fold(0.0, f64::max);
    let v_max =
        md.1.iter()
            .chain(&hybrid.1)
            .cloned()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
    map_pair(
        &out.join("volume_fraction.png"),
        "area fraction",
        &md.0,
        &hybrid.0,
        grid,
        (phi_max * 100.0).ceil() / 100.0,
    )?;
    map_pair(
        &out.join("velocity.png"),
        "|v| (m/s)",
        &md.1,
        &hybrid.1,
        grid,
        v_max.ceil(),
    )?;
    Ok(())
}

fn line_chart(
    path: &Path,
    title: &str,
    y_desc: &str,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::new(path, (800, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let t_max = lines
        .iter()
        .flat_map(|l| l.1.iter().map(|p| p.0))
        .fold(0.0, f64::max);
    let y_max = lines
        .iter()
        .flat_map(|l| l.1.iter().map(|p| p.1))
        .fold(0.0, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_max * 1e3, 0.0..y_max.max(1e-9))?;
    chart
        .configure_mesh()
        .x_desc("t (ms)")
        .y_desc(y_desc)
        .draw()?;
    for (name, points, c) in lines {
        let c = *c;
        chart
            .draw_series(std::iter::once(PathElement::new(
                points.iter().map(|p| (p.0 * 1e3, p.1)).collect::<Vec<_>>(),
                c.stroke_width(2),
            )))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// CPU time per simulated time against time (HAET Fig. 9a) and the number of
/// event-driven particles against time (Fig. 9b).
pub fn curves(out: &Path, md: &Series, hybrid: &Series) -> Result<(), Box<dyn std::error::Error>> {
    let cpu = |s: &Series| -> Vec<(f64, f64)> {
        s.windows(2)
            .map(|w| (w[1].0, (w[1].1 - w[0].1) / (w[1].0 - w[0].0)))
            .collect()
    };
    line_chart(
        &out.join("cpu_time.png"),
        "CPU time per simulated time (process CPU time, 10 ms ticks)",
        "t_CPU / t",
        &[
            ("MD", cpu(md), RGBColor(200, 30, 30)),
            ("hybrid", cpu(hybrid), RGBColor(30, 30, 200)),
        ],
    )?;
    let count = |s: &Series, k: usize| -> Vec<(f64, f64)> {
        s.iter()
            .map(|p| (p.0, if k == 2 { p.2 } else { p.3 } as f64))
            .collect()
    };
    line_chart(
        &out.join("event_driven.png"),
        "particles: event-driven (hybrid) and discharged",
        "particles",
        &[
            ("event-driven", count(hybrid, 2), RGBColor(30, 30, 200)),
            (
                "discharged (hybrid)",
                count(hybrid, 3),
                RGBColor(30, 160, 30),
            ),
            ("discharged (MD)", count(md, 3), RGBColor(200, 30, 30)),
        ],
    )?;
    Ok(())
}
