//! The time-against-error plot of `sdfc bench --plot`: one point per setting of the sweep,
//! device time across, error up (log scale), the Pareto front joined by a line.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::path::Path;

/// One setting as the plot shows it.
pub struct Point<'a> {
    pub name: &'a str,
    pub time_ms: f64,
    /// The depth error's 99.9th percentile against the reference.
    pub error: f64,
    /// Hit/miss mismatches away from silhouettes (such a point is drawn in red).
    pub misses: usize,
    pub pareto: bool,
    /// Whether its name is written beside it (the table names every point; names of points
    /// that share an error would overlap).
    pub labelled: bool,
}

/// The plot's size in pixels.
pub const SIZE: (u32, u32) = (1024, 640);

/// Depth errors below this are drawn at it (a log axis has no 0).
const ERROR_FLOOR: f64 = 1e-9;

/// Draws `points` under `title` and writes the PNG to `path`.
pub fn write(path: &Path, title: &str, points: &[Point]) -> Result<(), String> {
    let rgb = draw(title, points)?;
    image::save_buffer_with_format(
        path,
        &rgb,
        SIZE.0,
        SIZE.1,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The plot as RGB8 pixels, `SIZE` large.
pub fn draw(title: &str, points: &[Point]) -> Result<Vec<u8>, String> {
    // Registering twice is harmless (the second replaces the first).
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| "the bundled font did not load".to_string())?;
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let error = |p: &Point| p.error.max(ERROR_FLOOR);
        let (t_min, t_max) = points.iter().fold((f64::MAX, 0.0f64), |a, p| {
            (a.0.min(p.time_ms), a.1.max(p.time_ms))
        });
        let (t_min, t_max) = if t_min <= t_max {
            (t_min, t_max)
        } else {
            (0.0, 1.0)
        };
        let pad = ((t_max - t_min) * 0.08).max(t_max * 0.02).max(1e-3);
        let (e_min, e_max) = points.iter().fold((f64::MAX, 0.0f64), |a, p| {
            (a.0.min(error(p)), a.1.max(error(p)))
        });
        let (e_min, e_max) = if e_min <= e_max {
            (e_min / 2.0, e_max * 2.0)
        } else {
            (ERROR_FLOOR, 1.0)
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(72)
            .build_cartesian_2d(
                (t_min - pad).max(0.0)..t_max + pad,
                (e_min..e_max).log_scale(),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("time (ms)")
            .y_desc("depth error, 99.9th percentile (relative)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(err)?;
        let mut front: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.pareto)
            .map(|p| (p.time_ms, error(p)))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(front, BLUE.stroke_width(2)))
            .map_err(err)?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE.stroke_width(2)));
        let middle = (t_min + t_max) / 2.0;
        for p in points {
            let colour = if p.misses > 0 { RED } else { BLUE };
            let style = if p.pareto {
                colour.filled()
            } else {
                colour.stroke_width(2)
            };
            let at = (p.time_ms, error(p));
            chart
                .draw_series([Circle::new(at, 5, style)])
                .map_err(err)?;
            if !p.labelled {
                continue;
            }
            let label = if p.misses > 0 {
                format!("{} ({} misses)", p.name, p.misses)
            } else {
                p.name.to_string()
            };
            // Beside the point, on the side with more room.
            let (h, dx) = if p.time_ms > middle {
                (HPos::Right, -9)
            } else {
                (HPos::Left, 9)
            };
            let font =
                TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(h, VPos::Center));
            chart
                .draw_series([EmptyElement::at(at) + Text::new(label, (dx, 0), font)])
                .map_err(err)?;
        }
        chart
            .configure_series_labels()
            .border_style(BLACK)
            .background_style(WHITE)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(rgb)
}

fn err(e: impl std::fmt::Display) -> String {
    format!("plot: {e}")
}

#[cfg(test)]
mod tests {
    use super::{draw, Point, SIZE};

    /// The plot draws something in the plot area for each point: the pixels around a point's
    /// position differ from the white background, and the two colours appear.
    #[test]
    fn the_plot_draws_points_labels_and_the_front() {
        let points = [
            Point {
                name: "a",
                time_ms: 1.0,
                error: 1e-3,
                misses: 0,
                pareto: true,
                labelled: true,
            },
            Point {
                name: "b",
                time_ms: 2.0,
                error: 1e-5,
                misses: 0,
                pareto: true,
                labelled: true,
            },
            Point {
                name: "c",
                time_ms: 3.0,
                error: 1e-2,
                misses: 4,
                pareto: false,
                labelled: true,
            },
        ];
        let rgb = draw("test", &points).expect("plot");
        assert_eq!(rgb.len(), (SIZE.0 * SIZE.1 * 3) as usize);
        let px = |i: usize| [rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]];
        let n = (SIZE.0 * SIZE.1) as usize;
        let blue = (0..n).filter(|&i| px(i) == [0, 0, 255]).count();
        let red = (0..n).filter(|&i| px(i) == [255, 0, 0]).count();
        let dark = (0..n).filter(|&i| px(i).iter().all(|&c| c < 64)).count();
        assert!(blue > 100, "{blue} blue pixels (front and points)");
        assert!(red > 20, "{red} red pixels (the point with misses)");
        assert!(dark > 500, "{dark} dark pixels (axes and text)");
    }
}
