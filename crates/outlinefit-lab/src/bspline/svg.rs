//! A picture of a conversion: the true curve, the spline, its control polygon, the
//! samples (feature points marked differently) and a legend, as plain SVG text.
//!
//! The plot keeps the curve's aspect ratio and draws y upwards (mathematical convention),
//! inside a fixed 800-pixel-wide frame with a `viewBox`.

use super::expr::ParametricCurve;
use super::Conversion;
use outlinefit::svg_writer::{number, points_attribute, Document, Text};
use outlinefit::{Bounds, Point};
use svg::node::element::{Circle, Group, Line, Polyline, Rectangle};

/// Points of the polylines that draw the curve and the spline.
const POLYLINE_POINTS: usize = 1000;

/// Decimals of the picture's coordinates (in an 800-px frame).
const PRECISION: usize = 3;

/// The SVG document for `conversion` of `curve`.
pub fn picture(curve: &ParametricCurve, conversion: &Conversion) -> String {
    let (a, b) = conversion.range;
    let spline = conversion.spline();
    let at = |i: usize| a + (b - a) * i as f64 / (POLYLINE_POINTS - 1) as f64;
    let curve_pts: Vec<Point> = (0..POLYLINE_POINTS).map(|i| curve.point(at(i))).collect();
    let spline_pts: Vec<Point> = (0..POLYLINE_POINTS).map(|i| spline.point(at(i))).collect();
    let ctrl: Vec<Point> = spline.control_points.clone();
    let samples: Vec<(Point, bool)> = conversion
        .samples
        .iter()
        .map(|&u| {
            let feature = conversion.feature_points.iter().any(|f| f.u == u);
            (curve.point(u), feature)
        })
        .collect();

    let frame = Bounds::of(curve_pts.iter().chain(&spline_pts).chain(&ctrl).copied()).or_unit();
    let extent = frame.extent().max(1e-12);
    let (width, margin, legend_h) = (800.0, 40.0, 135.0);
    let scale = (width - 2.0 * margin) / extent;
    let plot_h = frame.height() * scale;
    let height = plot_h + 2.0 * margin + legend_h;
    let map = |p: Point| {
        Point::new(
            margin + (p.x - frame.min.x) * scale,
            margin + (frame.max.y - p.y) * scale,
        )
    };
    let polyline = |pts: &[Point]| {
        let mapped: Vec<Point> = pts
            .iter()
            .filter(|p| p.is_finite())
            .map(|&p| map(p))
            .collect();
        points_attribute(&mapped, PRECISION)
    };
    let n = |x: f64| number(x, PRECISION);

    let mut doc = Document::new(width, height, [0.0, 0.0, width, height], 0)
        .set("font-family", "sans-serif")
        .set("font-size", 13);
    doc.add(
        Rectangle::new()
            .set("width", "100%")
            .set("height", "100%")
            .set("fill", "white"),
    );
    doc.add(
        Polyline::new()
            .set("id", "control-polygon")
            .set("points", polyline(&ctrl))
            .set("fill", "none")
            .set("stroke", "#999")
            .set("stroke-width", 1)
            .set("stroke-dasharray", "4 3"),
    );
    for p in &ctrl {
        let q = map(*p);
        doc.add(
            Rectangle::new()
                .set("x", n(q.x - 3.0))
                .set("y", n(q.y - 3.0))
                .set("width", 6)
                .set("height", 6)
                .set("fill", "none")
                .set("stroke", "#999"),
        );
    }
    doc.add(
        Polyline::new()
            .set("id", "curve")
            .set("points", polyline(&curve_pts))
            .set("fill", "none")
            .set("stroke", "#1f77b4")
            .set("stroke-width", 4)
            .set("stroke-opacity", 0.5),
    );
    doc.add(
        Polyline::new()
            .set("id", "spline")
            .set("points", polyline(&spline_pts))
            .set("fill", "none")
            .set("stroke", "#d62728")
            .set("stroke-width", 1.5),
    );
    for (p, feature) in &samples {
        if !p.is_finite() {
            continue;
        }
        let q = map(*p);
        if *feature {
            doc.add(
                feature_mark()
                    .set("x", n(q.x - 4.5))
                    .set("y", n(q.y - 4.5))
                    .set("class", "feature"),
            );
        } else {
            doc.add(
                sample_mark()
                    .set("cx", n(q.x))
                    .set("cy", n(q.y))
                    .set("class", "sample"),
            );
        }
    }
    // Legend.
    let ly = plot_h + 2.0 * margin;
    let curve_line = || {
        Line::new()
            .set("x1", 0)
            .set("y1", 0)
            .set("x2", 30)
            .set("y2", 0)
    };
    let rows: [(Option<Box<dyn svg::Node>>, String); 5] = [
        (
            Some(Box::new(
                curve_line()
                    .set("stroke", "#1f77b4")
                    .set("stroke-width", 4)
                    .set("stroke-opacity", 0.5),
            )),
            "curve".to_string(),
        ),
        (
            Some(Box::new(
                curve_line()
                    .set("stroke", "#d62728")
                    .set("stroke-width", 1.5),
            )),
            format!(
                "B-spline, order {}, {} control points fitted to the {} (dashed polygon)",
                conversion.order,
                conversion.control_points.len(),
                conversion.fit.name(),
            ),
        ),
        (
            Some(Box::new(sample_mark().set("cx", 15).set("cy", 0))),
            format!(
                "other samples: the ends and the auxiliary ones ({}, placed by {})",
                conversion.samples.len() - conversion.feature_points.len(),
                conversion.method
            ),
        ),
        (
            Some(Box::new(feature_mark().set("x", 10.5).set("y", -4.5))),
            format!(
                "feature points ({}: inflections and curvature maxima)",
                conversion.feature_points.len()
            ),
        ),
        (
            None,
            format!(
                "error: RMSE {:.3e} on the samples (Eq. 1); against the curve at 1000 u: RMSE {:.3e}, max {:.3e}",
                conversion.rmse, conversion.rmse_dense, conversion.max_error_dense
            ),
        ),
    ];
    for (i, (mark, text)) in rows.into_iter().enumerate() {
        let y = ly + 10.0 + 24.0 * i as f64;
        let mut row = Group::new().set(
            "transform",
            format!("translate({},{})", number(margin, 0), number(y, 1)),
        );
        if let Some(mark) = mark {
            row = row.add(mark);
        }
        doc.add(row.add(Text::new(text).set("x", 40).set("y", 5)));
    }
    doc.finish()
}

/// The mark of a sample that is not a feature point: a black dot.
fn sample_mark() -> Circle {
    Circle::new().set("r", 3.5).set("fill", "black")
}

/// The mark of a feature point: an orange square.
fn feature_mark() -> Rectangle {
    Rectangle::new()
        .set("width", 9)
        .set("height", 9)
        .set("fill", "#ff7f0e")
        .set("stroke", "black")
}
