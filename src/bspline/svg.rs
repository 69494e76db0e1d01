//! A picture of a conversion: the true curve, the spline, its control polygon, the
//! samples (feature points marked differently) and a legend, as plain SVG text.
//!
//! The plot keeps the curve's aspect ratio and draws y upwards (mathematical convention),
//! inside a fixed 800-pixel-wide frame with a `viewBox`.

use super::expr::ParametricCurve;
use super::Conversion;
use crate::export::svg::escape_attribute;
use crate::geom::Point;
use std::fmt::Write;

/// Points of the polylines that draw the curve and the spline.
const POLYLINE_POINTS: usize = 1000;

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

    let all = curve_pts.iter().chain(&spline_pts).chain(&ctrl);
    let (mut lo, mut hi) = (
        Point::new(f64::MAX, f64::MAX),
        Point::new(f64::MIN, f64::MIN),
    );
    for p in all.filter(|p| p.is_finite()) {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    if !(lo.x <= hi.x && lo.y <= hi.y) {
        lo = Point::ZERO;
        hi = Point::new(1.0, 1.0);
    }
    let extent = (hi.x - lo.x).max(hi.y - lo.y).max(1e-12);
    let (width, margin, legend_h) = (800.0, 40.0, 135.0);
    let scale = (width - 2.0 * margin) / extent;
    let plot_h = (hi.y - lo.y) * scale;
    let height = plot_h + 2.0 * margin + legend_h;
    let map = |p: Point| Point::new(margin + (p.x - lo.x) * scale, margin + (hi.y - p.y) * scale);
    let polyline = |pts: &[Point]| {
        let mut s = String::new();
        for p in pts.iter().filter(|p| p.is_finite()) {
            let q = map(*p);
            let _ = write!(s, "{:.3},{:.3} ", q.x, q.y);
        }
        s.trim_end().to_string()
    };

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r##"<polyline id="control-polygon" points="{}" fill="none" stroke="#999" stroke-width="1" stroke-dasharray="4 3"/>"##,
        polyline(&ctrl)
    );
    for p in &ctrl {
        let q = map(*p);
        let _ = writeln!(
            svg,
            r##"<rect x="{:.3}" y="{:.3}" width="6" height="6" fill="none" stroke="#999"/>"##,
            q.x - 3.0,
            q.y - 3.0
        );
    }
    let _ = writeln!(
        svg,
        r##"<polyline id="curve" points="{}" fill="none" stroke="#1f77b4" stroke-width="4" stroke-opacity="0.5"/>"##,
        polyline(&curve_pts)
    );
    let _ = writeln!(
        svg,
        r##"<polyline id="spline" points="{}" fill="none" stroke="#d62728" stroke-width="1.5"/>"##,
        polyline(&spline_pts)
    );
    for (p, feature) in &samples {
        if !p.is_finite() {
            continue;
        }
        let q = map(*p);
        if *feature {
            let _ = writeln!(
                svg,
                r##"<rect class="feature" x="{:.3}" y="{:.3}" width="9" height="9" fill="#ff7f0e" stroke="black"/>"##,
                q.x - 4.5,
                q.y - 4.5
            );
        } else {
            let _ = writeln!(
                svg,
                r#"<circle class="sample" cx="{:.3}" cy="{:.3}" r="3.5" fill="black"/>"#,
                q.x, q.y
            );
        }
    }
    // Legend.
    let ly = plot_h + 2.0 * margin;
    let rows = [
        (
            r##"<line x1="0" y1="0" x2="30" y2="0" stroke="#1f77b4" stroke-width="4" stroke-opacity="0.5"/>"##,
            "curve".to_string(),
        ),
        (
            r##"<line x1="0" y1="0" x2="30" y2="0" stroke="#d62728" stroke-width="1.5"/>"##,
            format!(
                "B-spline, order {}, {} control points fitted to the {} (dashed polygon)",
                conversion.order,
                conversion.control_points.len(),
                conversion.fit.name(),
            ),
        ),
        (
            r#"<circle cx="15" cy="0" r="3.5" fill="black"/>"#,
            format!(
                "other samples: the ends and the auxiliary ones ({}, placed by {})",
                conversion.samples.len() - conversion.feature_points.len(),
                conversion.method
            ),
        ),
        (
            r##"<rect x="10.5" y="-4.5" width="9" height="9" fill="#ff7f0e" stroke="black"/>"##,
            format!(
                "feature points ({}: inflections and curvature maxima)",
                conversion.feature_points.len()
            ),
        ),
        (
            "",
            format!(
                "error: RMSE {:.3e} on the samples (Eq. 1); against the curve at 1000 u: RMSE {:.3e}, max {:.3e}",
                conversion.rmse, conversion.rmse_dense, conversion.max_error_dense
            ),
        ),
    ];
    for (i, (mark, text)) in rows.iter().enumerate() {
        let y = ly + 10.0 + 24.0 * i as f64;
        let _ = writeln!(
            svg,
            r#"<g transform="translate({margin:.0},{y:.1})">{mark}<text x="40" y="5">{}</text></g>"#,
            escape_attribute(text)
        );
    }
    svg.push_str("</svg>\n");
    svg
}
