//! Log-log time plots for the benchmarks.

use plotters::prelude::*;

/// One line of a plot: its name, points (x, milliseconds), colour, and whether it
/// is a peer (drawn with triangles) rather than pixgeo (circles).
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub peer: bool,
}

/// pixgeo's colours, in order.
pub const PALETTE: [RGBColor; 6] = [RED, BLUE, MAGENTA, GREEN, CYAN, BLACK];

/// Writes a log-log plot of `series` to `path`.
pub fn plot(
    path: &std::path::Path,
    caption: &str,
    x_desc: &str,
    series: &[Series],
) -> anyhow::Result<()> {
    let font = std::fs::read("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
        .map_err(|e| anyhow::anyhow!("font for the plot (tools/setup --bench installs it): {e}"))?;
    let font: &'static [u8] = Box::leak(font.into_boxed_slice());
    plotters::style::register_font("sans-serif", FontStyle::Normal, font)
        .map_err(|_| anyhow::anyhow!("cannot register the plot font"))?;
    let root = BitMapBackend::new(path, (1100, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let all = || series.iter().flat_map(|s| s.points.iter());
    let (x_lo, x_hi) = all().fold((f64::INFINITY, 0f64), |(lo, hi), p| {
        (lo.min(p.0), hi.max(p.0))
    });
    let (y_lo, y_hi) = all().fold((f64::INFINITY, 0f64), |(lo, hi), p| {
        (lo.min(p.1), hi.max(p.1))
    });
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, ("sans-serif", 26))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x_lo * 0.8..x_hi * 1.25).log_scale(),
            (y_lo * 0.7..y_hi * 1.5).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("milliseconds (log scale)")
        .label_style(("sans-serif", 16))
        .draw()?;
    for s in series {
        let style = ShapeStyle::from(s.color).stroke_width(2);
        chart
            .draw_series(LineSeries::new(s.points.clone(), style))?
            .label(s.name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        if s.peer {
            chart.draw_series(
                s.points
                    .iter()
                    .map(|p| TriangleMarker::new(*p, 4, s.color.filled())),
            )?;
        } else {
            chart.draw_series(
                s.points
                    .iter()
                    .map(|p| Circle::new(*p, 3, s.color.filled())),
            )?;
        }
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    root.present()?;
    Ok(())
}
