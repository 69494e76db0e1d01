//! The curve file `outlinefit reduce` reads, and the SVG picture it draws.
//!
//! A curve file is JSON: `{"control_points": [[x, y], …], "omega": ω, "lambda": […],
//! "mu": […]}`. Only `control_points` is required; without `omega` the curve is a plain
//! Bézier curve (ω = 0), and a missing `lambda` or `mu` takes the middle of the paper's
//! range, C(n+1, j)/2 (as [`SgShape::bezier`]). Unknown fields are an error, so a typo
//! such as `"lamda"` is not silently ignored.

use super::Reduction;
use crate::curve::sg_bezier::{SgBezier, SgShape};
use crate::error::{Error, Result};
use crate::geom::Point;
use serde::Deserialize;
use std::fmt::Write as _;
use std::path::Path;

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

/// Points on `curve` at `count + 1` evenly spaced parameters (a polyline for drawing).
fn samples(curve: &SgBezier, count: usize) -> Result<Vec<Point>> {
    (0..=count)
        .map(|i| {
            curve
                .try_eval(i as f64 / count as f64)
                .map_err(|e| Error::InvalidInput {
                    what: "curve".to_string(),
                    message: e.to_string(),
                })
        })
        .collect()
}

/// An SVG picture of a reduction: the original curve (blue, solid) and the reduced one
/// (red, dashed) as sampled polylines, with both control polygons and their points (light
/// blue and light red). Coordinates are the curves' own (y downwards, as everywhere in
/// outlinefit); the `viewBox` is their bounding box with a 5 % margin, drawn 800 px wide.
///
/// Errors: [`Error::InvalidInput`] when a curve's fields are inconsistent.
pub fn reduction_svg(original: &SgBezier, reduced: &Reduction) -> Result<String> {
    let p = samples(original, 400)?;
    let q = samples(&reduced.curve, 400)?;
    let all = p
        .iter()
        .chain(&q)
        .chain(&original.points)
        .chain(&reduced.curve.points);
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for v in all {
        lo = Point::new(lo.x.min(v.x), lo.y.min(v.y));
        hi = Point::new(hi.x.max(v.x), hi.y.max(v.y));
    }
    let extent = (hi.x - lo.x).max(hi.y - lo.y);
    let extent = if extent > 0.0 && extent.is_finite() {
        extent
    } else {
        1.0
    };
    let margin = 0.05 * extent;
    let (x0, y0) = (lo.x - margin, lo.y - margin);
    let (w, h) = (
        (hi.x - lo.x).max(0.0) + 2.0 * margin,
        (hi.y - lo.y).max(0.0) + 2.0 * margin,
    );
    let stroke = 0.004 * extent;
    let dot = 0.008 * extent;
    let width_px = 800.0;
    let height_px = (width_px * h / w).clamp(100.0, 2400.0);
    let mut s = String::new();
    // Writing into a String cannot fail, so the fmt::Results below are ignored.
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width_px}" height="{height_px:.0}" viewBox="{x0} {y0} {w} {h}">"#
    );
    let _ = writeln!(
        s,
        "<title>degree {} to {} ({}, {}): error {:e}</title>",
        original.degree(),
        reduced.curve.degree(),
        reduced.constraint,
        reduced.method,
        reduced.error
    );
    let _ = writeln!(
        s,
        r#"<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="white"/>"#
    );
    let polyline = |s: &mut String, pts: &[Point], style: &str| {
        let coords: Vec<String> = pts.iter().map(|p| format!("{},{}", p.x, p.y)).collect();
        let _ = writeln!(
            s,
            r#"<polyline fill="none" {style} points="{}"/>"#,
            coords.join(" ")
        );
    };
    let dots = |s: &mut String, pts: &[Point], color: &str| {
        for p in pts {
            let _ = writeln!(
                s,
                r#"<circle cx="{}" cy="{}" r="{dot}" fill="{color}"/>"#,
                p.x, p.y
            );
        }
    };
    let half = stroke * 0.5;
    polyline(
        &mut s,
        &original.points,
        &format!(r##"stroke="#8fb3e0" stroke-width="{half}""##),
    );
    polyline(
        &mut s,
        &reduced.curve.points,
        &format!(
            r##"stroke="#e8a0a0" stroke-width="{half}" stroke-dasharray="{} {}""##,
            4.0 * stroke,
            2.0 * stroke
        ),
    );
    dots(&mut s, &original.points, "#8fb3e0");
    dots(&mut s, &reduced.curve.points, "#e8a0a0");
    polyline(
        &mut s,
        &p,
        &format!(r##"stroke="#1f5fbf" stroke-width="{stroke}""##),
    );
    polyline(
        &mut s,
        &q,
        &format!(
            r##"stroke="#d02020" stroke-width="{stroke}" stroke-dasharray="{} {}""##,
            2.0 * stroke,
            2.0 * stroke
        ),
    );
    s.push_str("</svg>\n");
    Ok(s)
}
