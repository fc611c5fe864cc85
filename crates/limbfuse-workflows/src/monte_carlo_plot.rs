//! SVG plot of a Monte Carlo study (paper 000 Fig. 9 layout: mean error
//! against uncertainty level, one line per filter).

use std::path::Path;

use plotters::prelude::*;

use crate::monte_carlo::{MonteCarloRow, METHODS};

/// Draws the mean RMSE of each filter against the uncertainty level as SVG
/// text (`path`, the file it is for, names it in errors); the caller writes
/// it (`limbfuse montecarlo --svg`, whole or not at all with its CSV). The
/// `provenance` lines (`key: value`, as the CSV's comments) go in the
/// plot's `<metadata id="limbfuse-provenance">`, one a line.
pub fn render_svg(
    rows: &[MonteCarloRow],
    path: &Path,
    title: &str,
    provenance: &[(&str, String)],
) -> Result<String, String> {
    let mut svg = String::new();
    draw_svg(rows, &mut svg, path, title)?;
    Ok(with_metadata(svg, provenance))
}

/// `svg` with the provenance lines in a `<metadata>` element right after
/// the opening `<svg ...>` tag (SVG's element for data about the drawing:
/// not drawn, kept by editors), XML-escaped.
fn with_metadata(mut svg: String, provenance: &[(&str, String)]) -> String {
    if provenance.is_empty() {
        return svg;
    }
    let Some(end) = svg
        .find("<svg")
        .and_then(|i| svg[i..].find('>').map(|j| i + j + 1))
    else {
        return svg;
    };
    let escape = |l: &str| {
        l.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut meta = String::from("\n<metadata id=\"limbfuse-provenance\">\n");
    for l in limbfuse_io::provenance::lines(provenance) {
        meta += &escape(&l);
        meta.push('\n');
    }
    meta += "</metadata>";
    svg.insert_str(end, &meta);
    svg
}

fn draw_svg(
    rows: &[MonteCarloRow],
    svg: &mut String,
    path: &Path,
    title: &str,
) -> Result<(), String> {
    let max_level = rows
        .iter()
        .map(|r| r.level_pct())
        .fold(0.0, f64::max)
        .max(1.0);
    let max_err = rows.iter().map(|r| r.mean_rmse_deg).fold(0.0, f64::max) * 1.15 + 1e-9;
    let root = SVGBackend::with_string(svg, (720, 440)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: cannot draw the plot: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..max_level, 0.0..max_err)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("parametric uncertainty (%)")
        .y_desc("mean segment RMSE (deg)")
        .draw()
        .map_err(|e| err(&e))?;
    let colours = [RED, BLUE, GREEN];
    for (m, method) in METHODS.iter().enumerate() {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.method == method.name())
            .map(|r| (r.level_pct(), r.mean_rmse_deg))
            .collect();
        let c = colours[m];
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(method.name())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
            .map_err(|e| err(&e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
