//! A picture of a fit, as the paper's Figures 1, 3 and 5: the data points and the fitted
//! surface's wireframe in a 3-D chart (plotters), as SVG.

use super::{BezierSurface, P3};
use crate::compare::plot::{drawing, PlotError};
use plotters::prelude::*;

/// Iso-parameter lines drawn in each direction.
const LINES: usize = 13;
/// Samples along each line.
const SAMPLES: usize = 60;
/// Margin around the points' bounding box, as a fraction of its size per axis.
const MARGIN: f64 = 0.15;

/// The points and the wireframe of `surface` (if any) as an SVG document. The chart's
/// vertical axis is the points' z.
pub fn to_svg(
    title: &str,
    points: &[P3],
    surface: Option<&BezierSurface>,
) -> Result<String, PlotError> {
    let wire: Vec<Vec<P3>> = match surface {
        Some(s) => {
            let at = |k: usize, n: usize| k as f64 / (n - 1) as f64;
            let mut lines = Vec::with_capacity(2 * LINES);
            for a in 0..LINES {
                lines.push(
                    (0..SAMPLES)
                        .map(|b| s.eval(at(a, LINES), at(b, SAMPLES)))
                        .collect(),
                );
                lines.push(
                    (0..SAMPLES)
                        .map(|b| s.eval(at(b, SAMPLES), at(a, LINES)))
                        .collect(),
                );
            }
            lines
        }
        None => Vec::new(),
    };
    // The chart frames the points (with a margin); where the surface leaves that box — an
    // unorganized fit is only held by its points, and between or beyond them a polynomial
    // surface may swing far out — its lines are cut.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let framed: Vec<&P3> = if points.is_empty() {
        wire.iter().flatten().collect()
    } else {
        points.iter().collect()
    };
    for p in framed {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    for k in 0..3 {
        if hi[k].is_nan() || hi[k] <= lo[k] {
            (lo[k], hi[k]) = (lo[k] - 0.5, hi[k] + 0.5);
        }
        let margin = MARGIN * (hi[k] - lo[k]);
        (lo[k], hi[k]) = (lo[k] - margin, hi[k] + margin);
    }
    let inside = |p: &P3| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]);
    let pieces: Vec<Vec<P3>> = wire
        .iter()
        .flat_map(|line| {
            line.split(|p| !inside(p))
                .filter(|piece| piece.len() >= 2)
                .map(|piece| piece.to_vec())
                .collect::<Vec<_>>()
        })
        .collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 700)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(10)
            .build_cartesian_3d(lo[0]..hi[0], lo[2]..hi[2], lo[1]..hi[1])
            .map_err(drawing)?;
        chart.with_projection(|mut p| {
            p.pitch = 0.45;
            p.yaw = 0.7;
            p.scale = 0.85;
            p.into_matrix()
        });
        chart
            .configure_axes()
            .light_grid_style(BLACK.mix(0.1))
            .max_light_lines(3)
            .draw()
            .map_err(drawing)?;
        let blue = RGBColor(0x1F, 0x77, 0xB4);
        for line in &pieces {
            chart
                .draw_series(LineSeries::new(
                    line.iter().map(|p| (p[0], p[2], p[1])),
                    blue.mix(0.7).stroke_width(1),
                ))
                .map_err(drawing)?;
        }
        let red = RGBColor(0xD6, 0x27, 0x28);
        chart
            .draw_series(
                points
                    .iter()
                    .map(|p| Circle::new((p[0], p[2], p[1]), 2, red.filled())),
            )
            .map_err(drawing)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}
