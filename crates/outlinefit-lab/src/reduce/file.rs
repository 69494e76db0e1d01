//! The curve file `outlinefit reduce` reads, and the SVG picture it draws.
//!
//! A curve file is JSON: `{"control_points": [[x, y], …], "omega": ω, "lambda": […],
//! "mu": […]}`. Only `control_points` is required; without `omega` the curve is a plain
//! Bézier curve (ω = 0), and a missing `lambda` or `mu` takes the middle of the paper's
//! range, C(n+1, j)/2 (as [`SgShape::bezier`]). Unknown fields are an error, so a typo
//! such as `"lamda"` is not silently ignored.

use super::Reduction;
use crate::reduce::sg_bezier::{SgBezier, SgShape};
use crate::{Error, Result};
use outlinefit::svg_writer::{decimals_for, number, points_attribute, Document};
use outlinefit::ParamCurve as _;
use outlinefit::{Bounds, Point};
use serde::Deserialize;
use std::path::Path;
use svg::node::element::{Circle, Polyline, Rectangle, Title};

/// The JSON layout of a curve file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveFile {
    control_points: Vec<[f64; 2]>,
    #[serde(default)]
    omega: Option<f64>,
    #[serde(default)]
    lambda: Option<Vec<f64>>,
    #[serde(default)]
    mu: Option<Vec<f64>>,
}

/// Parses the curve JSON `text`; `what` names it in errors (usually the file's path).
///
/// Errors: [`Error::InvalidInput`] for malformed JSON, missing or unknown fields, no control
/// points, non-finite numbers or shape lists of the wrong lengths for the degree.
pub fn parse_curve_json(text: &str, what: &str) -> Result<SgBezier> {
    let bad = |message: String| Error::InvalidInput {
        what: what.to_string(),
        message,
    };
    let file: CurveFile =
        serde_json::from_str(text).map_err(|e| bad(format!("not a valid curve file: {e}")))?;
    if file.control_points.is_empty() {
        return Err(bad("control_points is empty".to_string()));
    }
    let points: Vec<Point> = file
        .control_points
        .iter()
        .map(|&[x, y]| Point::new(x, y))
        .collect();
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(bad(format!("control point {i} is not finite")));
    }
    let n = points.len() - 1;
    let default = SgShape::bezier(n);
    let shape = SgShape::new(
        n,
        file.omega.unwrap_or(0.0),
        file.lambda.unwrap_or(default.lambda),
        file.mu.unwrap_or(default.mu),
    )
    .map_err(|e| bad(e.to_string()))?;
    SgBezier::new(points, shape).map_err(|e| bad(e.to_string()))
}

/// Reads and parses a curve file (see the module docs).
///
/// Errors: [`Error::Read`] when the file cannot be read, otherwise as
/// [`parse_curve_json`] with the path as `what`.
pub fn read_curve_json(path: &Path) -> Result<SgBezier> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_curve_json(&text, &path.display().to_string())
}

/// An SVG picture of a reduction: the original curve (blue, solid) and the reduced one
/// (red, dashed) as sampled polylines, with both control polygons and their points (light
/// blue and light red). Coordinates are the curves' own (y downwards, as everywhere in
/// outlinefit); the `viewBox` is their bounding box with a 5 % margin, drawn 800 px wide,
/// with coordinates to a hundredth of a drawn pixel.
///
/// Errors: [`Error::InvalidInput`] when a curve's fields are inconsistent.
pub fn reduction_svg(original: &SgBezier, reduced: &Reduction) -> Result<String> {
    for curve in [original, &reduced.curve] {
        curve.validate().map_err(|e| Error::InvalidInput {
            what: "curve".to_string(),
            message: e.to_string(),
        })?;
    }
    let p = original.sample(400);
    let q = reduced.curve.sample(400);
    let frame = Bounds::of(
        p.iter()
            .chain(&q)
            .chain(&original.points)
            .chain(&reduced.curve.points)
            .copied(),
    )
    .or_unit();
    let extent = frame.extent();
    let extent = if extent > 0.0 && extent.is_finite() {
        extent
    } else {
        1.0
    };
    let margin = 0.05 * extent;
    let (x0, y0) = (frame.min.x - margin, frame.min.y - margin);
    let (w, h) = (
        frame.width().max(0.0) + 2.0 * margin,
        frame.height().max(0.0) + 2.0 * margin,
    );
    let width_px = 800.0;
    let height_px = (width_px * h / w).clamp(100.0, 2400.0);
    let precision = decimals_for(w / width_px / 100.0);
    let n = |x: f64| number(x, precision);
    let stroke = 0.004 * extent;
    let dot = n(0.008 * extent);
    let mut doc = Document::new(width_px, height_px.round(), [x0, y0, w, h], precision);
    doc.add(Title::new(format!(
        "degree {} to {} ({}, {}): error {:e}",
        original.degree(),
        reduced.curve.degree(),
        reduced.constraint,
        reduced.method,
        reduced.error
    )));
    doc.add(
        Rectangle::new()
            .set("x", n(x0))
            .set("y", n(y0))
            .set("width", n(w))
            .set("height", n(h))
            .set("fill", "white"),
    );
    let polyline = |pts: &[Point], colour: &str, width: f64, dashes: Option<(f64, f64)>| {
        let line = Polyline::new()
            .set("fill", "none")
            .set("stroke", colour)
            .set("stroke-width", n(width))
            .set("points", points_attribute(pts, precision));
        match dashes {
            Some((on, off)) => line.set("stroke-dasharray", format!("{} {}", n(on), n(off))),
            None => line,
        }
    };
    let dots = |doc: &mut Document, pts: &[Point], colour: &str| {
        for p in pts {
            doc.add(
                Circle::new()
                    .set("cx", n(p.x))
                    .set("cy", n(p.y))
                    .set("r", dot.as_str())
                    .set("fill", colour),
            );
        }
    };
    let (light_blue, light_red) = ("#8fb3e0", "#e8a0a0");
    let half = stroke * 0.5;
    doc.add(polyline(&original.points, light_blue, half, None));
    doc.add(polyline(
        &reduced.curve.points,
        light_red,
        half,
        Some((4.0 * stroke, 2.0 * stroke)),
    ));
    dots(&mut doc, &original.points, light_blue);
    dots(&mut doc, &reduced.curve.points, light_red);
    doc.add(polyline(&p, "#1f5fbf", stroke, None));
    doc.add(polyline(
        &q,
        "#d02020",
        stroke,
        Some((2.0 * stroke, 2.0 * stroke)),
    ));
    Ok(doc.finish())
}
