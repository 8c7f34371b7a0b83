//! Small SVG line charts for the examples (plotters, SVG backend only: no system fonts).

use plotters::prelude::*;
use std::path::Path;

/// One named line.
pub struct Series<'a> {
    /// Legend.
    pub name: &'a str,
    /// Points.
    pub points: Vec<(f64, f64)>,
}

/// The extent of every point of `series`: (x0, x1, y0, y1), or None for no points.
fn extent(series: &[Series]) -> Option<(f64, f64, f64, f64)> {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in series.iter().flat_map(|s| s.points.iter()) {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    (x0 <= x1).then_some((x0, x1, y0, y1))
}

fn err(e: impl ToString) -> std::io::Error {
    std::io::Error::other(e.to_string())
}

/// The chart's frame, its mesh, `series` and their legend, into the file.
fn draw<X>(
    root: DrawingArea<SVGBackend, plotters::coord::Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    (x, y): (X, std::ops::Range<f64>),
    series: &[Series],
) -> std::io::Result<()>
where
    X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(err)?;
    let colors = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];
    for (i, s) in series.iter().enumerate() {
        let c = colors[i % colors.len()];
        chart
            .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
            .map_err(err)?
            .label(s.name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

fn create_dir(path: &Path) -> std::io::Result<()> {
    match path.parent() {
        Some(dir) => std::fs::create_dir_all(dir),
        None => Ok(()),
    }
}

/// Write an SVG line chart of `series` to `path`. `equal_axes` keeps x and y at one scale
/// (for paths in the plane).
pub fn lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    equal_axes: bool,
) -> std::io::Result<()> {
    create_dir(path)?;
    let (x0, x1, y0, y1) = extent(series).unwrap_or((0.0, 1.0, 0.0, 1.0));
    let pad = |a: f64, b: f64| ((b - a).abs() * 0.05).max(1e-9);
    let (mut px, mut py) = (pad(x0, x1), pad(y0, y1));
    if equal_axes {
        let half = ((x1 - x0).max(y1 - y0)) / 2.0 * 1.05;
        px = half - (x1 - x0) / 2.0;
        py = half - (y1 - y0) / 2.0;
    }
    let size = if equal_axes { (800, 800) } else { (1000, 600) };
    draw(
        SVGBackend::new(path, size).into_drawing_area(),
        title,
        (x_label, y_label),
        ((x0 - px)..(x1 + px), (y0 - py)..(y1 + py)),
        series,
    )
}

/// Write an SVG line chart of `series` to `path` with a logarithmic x axis (every x > 0).
pub fn lines_log_x(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> std::io::Result<()> {
    create_dir(path)?;
    let (x0, x1, y0, y1) = extent(series)
        .filter(|e| e.0 > 0.0)
        .unwrap_or((1.0, 10.0, 0.0, 1.0));
    let py = ((y1 - y0).abs() * 0.05).max(1e-9);
    draw(
        SVGBackend::new(path, (1000, 600)).into_drawing_area(),
        title,
        (x_label, y_label),
        ((x0..x1).log_scale(), (y0 - py)..(y1 + py)),
        series,
    )
}
