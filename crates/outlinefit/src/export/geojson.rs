//! The outline as GeoJSON (RFC 7946), for GIS software and for any program that reads
//! polygons.
//!
//! A `FeatureCollection` with one `Feature` per shape: a `Polygon` whose first ring is the
//! outer border and whose other rings are its holes. GeoJSON has no curves, so each ring
//! is the drawn outline flattened within the bound (so within twice the bound of the
//! fitted curves), closed (its last position repeats the first). Coordinates have y up and
//! the origin at the image's bottom-left corner, in the options' unit (pixels by
//! default), and the rings turn as RFC 7946 asks: outer borders counter-clockwise, holes
//! clockwise. Each feature's properties give its `fill` colour and the indices of its
//! contours in the JSON report (`contour`, `holes`).

use super::options::ExportOptions;
use super::shapes::{drawn_loop, flatten, holes_of, signed_area2, Drawn, FlipY};
use crate::geom::Point;
use crate::trace::TraceResult;
use serde_json::{json, Value};

/// Writes the outline as a GeoJSON document (see the module docs).
pub fn to_geojson(result: &TraceResult, opts: &ExportOptions) -> String {
    let bound = opts.effective_bound();
    let straight = opts.half_unit();
    let flip = FlipY {
        height: f64::from(result.image.height),
        per_pixel: opts.size.unit_per_pixel(),
    };
    let scale = 10f64.powi(opts.precision_in(opts.size.unit) as i32);
    let round = |x: f64| {
        let r = (x * scale).round() / scale;
        if r == 0.0 {
            0.0
        } else {
            r
        }
    };
    let ring = |i: usize, outer: bool| -> Option<Value> {
        let Drawn::Loop(l) = drawn_loop(&result.contours[i], result.merged_of(i), bound, straight)
        else {
            return None;
        };
        let mut points: Vec<Point> = flatten(&l, bound)
            .into_iter()
            .map(|p| {
                let q = flip.apply(p);
                Point::new(round(q.x), round(q.y))
            })
            .collect();
        points.dedup();
        while points.len() > 1 && points.last() == points.first() {
            points.pop();
        }
        if points.len() < 3 {
            return None;
        }
        // Counter-clockwise (positive area, y up) for outer borders, clockwise for holes.
        if (signed_area2(&points) > 0.0) != outer {
            points.reverse();
        }
        points.push(points[0]);
        Some(json!(points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()))
    };
    let (holes, _) = holes_of(result);
    let fill = opts.fill.to_string();
    let mut features = Vec::new();
    for (i, c) in result.contours.iter().enumerate() {
        if c.is_hole {
            continue;
        }
        let Some(outer) = ring(i, true) else {
            continue;
        };
        let mut rings = vec![outer];
        let mut kept = Vec::new();
        for &k in &holes[i] {
            if let Some(r) = ring(k, false) {
                rings.push(r);
                kept.push(k);
            }
        }
        features.push(json!({
            "type": "Feature",
            "properties": { "fill": fill, "contour": i, "holes": kept },
            "geometry": { "type": "Polygon", "coordinates": rings },
        }));
    }
    let doc = json!({ "type": "FeatureCollection", "features": features });
    let mut text = doc.to_string();
    text.push('\n');
    text
}
