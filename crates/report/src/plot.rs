//! Log-log line plots as SVG (plotters' SVG backend: pure Rust, no system
//! fonts or libraries needed), for `signorini bench`.

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

/// One line of a plot: a label and its (x, y) points (positive values).
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// The axes of a plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axes {
    /// Logarithmic x and y: only the points with x > 0 and y > 0 are drawn.
    LogLog,
    /// Linear x and y (for loops such as force against slip).
    Linear,
}

/// Writes a plot of the series to `path` (SVG) titled `title`, its axes
/// `axes` labelled `labels` (x, y).
pub fn plot_svg(
    path: &std::path::Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    axes: Axes,
) -> Result<(), String> {
    let keep: fn(f64, f64) -> bool = match axes {
        Axes::LogLog => |x: f64, y: f64| x > 0.0 && y > 0.0,
        Axes::Linear => |_: f64, _: f64| true,
    };
    let Some((x0, x1, y0, y1)) = extent(series, keep) else {
        return Err(match axes {
            Axes::LogLog => format!("{title}: nothing positive to plot"),
            Axes::Linear => format!("{title}: nothing to plot"),
        });
    };
    let lines = series
        .iter()
        .map(|s| {
            let line = (s.points.iter().copied()).filter(|&(x, y)| keep(x, y));
            (s.label.clone(), line.collect())
        })
        .collect();
    match axes {
        Axes::LogLog => {
            let pad = |lo: f64, hi: f64| {
                if hi > lo * 1.01 {
                    (lo / 1.5, hi * 1.5)
                } else {
                    (lo / 2.0, hi * 2.0)
                }
            };
            let ((x0, x1), (y0, y1)) = (pad(x0, x1), pad(y0, y1));
            let ranges = ((x0..x1).log_scale(), (y0..y1).log_scale());
            let legend = Some(SeriesLabelPosition::UpperRight);
            draw_svg(path, title, labels, (70, 1), ranges, lines, legend)
        }
        Axes::Linear => {
            let pad = |lo: f64, hi: f64| {
                let d = (hi - lo).abs().max(1e-300 + 1e-9 * hi.abs().max(lo.abs()));
                (lo - 0.08 * d, hi + 0.08 * d)
            };
            let ((x0, x1), (y0, y1)) = (pad(x0, x1), pad(y0, y1));
            draw_svg(path, title, labels, (80, 2), (x0..x1, y0..y1), lines, None)
        }
    }
}

/// The smallest and largest x and y, (x0, x1, y0, y1), of the series'
/// finite points that `keep` accepts; `None` when there is none.
fn extent(series: &[Series], keep: impl Fn(f64, f64) -> bool) -> Option<(f64, f64, f64, f64)> {
    let mut pts = (series.iter())
        .flat_map(|s| s.points.iter().copied())
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && keep(x, y))
        .peekable();
    pts.peek()?;
    let inf = f64::INFINITY;
    Some(
        pts.fold((inf, -inf, inf, -inf), |(x0, x1, y0, y1), (x, y)| {
            (x0.min(x), x1.max(x), y0.min(y), y1.max(y))
        }),
    )
}

/// The chart of both plots: `title`, the axis labels, a y label area of
/// `area.0` pixels, ticks in scientific notation with `area.1` decimals,
/// each line with its points and a legend entry (at `legend_at`, or where
/// plotters puts it).
fn draw_svg<X, Y>(
    path: &std::path::Path,
    title: &str,
    (x_label, y_label): (&str, &str),
    area: (u32, usize),
    (x_spec, y_spec): (X, Y),
    lines: Vec<(String, Vec<(f64, f64)>)>,
    legend_at: Option<SeriesLabelPosition>,
) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let (y_area, digits) = area;
    let e = |err: &dyn std::fmt::Display| err.to_string();
    let root = SVGBackend::new(path, (800, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| format!("{v:.digits$e}"))
        .y_label_formatter(&|v| format!("{v:.digits$e}"))
        .draw()
        .map_err(|x| e(&x))?;
    for (i, (label, line)) in lines.into_iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(|x| e(&x))?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
            });
        chart
            .draw_series(line.into_iter().map(|p| Circle::new(p, 3, color.filled())))
            .map_err(|x| e(&x))?;
    }
    let mut labels = chart.configure_series_labels();
    labels.background_style(WHITE.mix(0.85)).border_style(BLACK);
    if let Some(at) = legend_at {
        labels.position(at);
    }
    labels.draw().map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_an_svg_with_every_series_label() {
        let dir = crate::test_dir("plot");
        let path = dir.join("p.svg");
        let series = vec![
            Series {
                label: "condensed".into(),
                points: vec![(1e3, 1e-2), (4e3, 2.5e-3)],
            },
            Series {
                label: "direct".into(),
                points: vec![(1e3, 1e-1), (4e3, 9e-2)],
            },
        ];
        plot_svg(&path, "t", ("x", "y"), &series, Axes::LogLog).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("condensed") && svg.contains("direct"));
        let zero = [Series {
            label: "z".into(),
            points: vec![(0.0, 1.0)],
        }];
        assert!(plot_svg(&path, "t", ("x", "y"), &zero, Axes::LogLog).is_err());
        plot_svg(&path, "t", ("x", "y"), &zero, Axes::Linear).unwrap();
    }
}
