//! SVG pictures of disk curves: center lines with their disk envelopes.
//!
//! The envelope of the circles `(C(t), R(t))` is
//! `E±(t) = C − (R R' / |C'|²) C' ± (R √(|C'|² − R'²) / |C'|²) C'⊥`; where `|R'| ≥ |C'|` a
//! disk contains its neighbours and the envelope has no point there, so the band polygon
//! simply skips those samples (the control disks are drawn as dashed circles beside it).

use crate::curve::param_curve::ParamCurve as _;
use crate::curve::wang_ball::DiskWangBall;
use crate::geom::{Bounds, Point};
use crate::svg_writer::{Circle, Document, Group, Path, PathData, Rectangle, Text};

/// Samples per curve for center lines and envelopes.
const SAMPLES: usize = 200;

/// The two envelope curves of a disk curve, sampled (`None` where no envelope point exists).
pub fn envelope(curve: &DiskWangBall, samples: usize) -> Vec<Option<(Point, Point)>> {
    (0..=samples)
        .map(|i| {
            let t = i as f64 / samples as f64;
            let d = curve.eval(t);
            let dc = curve.center_derivative(t);
            let dr = curve.radius_derivative(t);
            envelope_points(d.center, d.radius, dc, dr)
        })
        .collect()
}

/// The closed polygon of the envelope band: the `+` side forwards, then the `−` side
/// backwards, over the samples where both exist. `None` when fewer than two samples have
/// envelope points or some point is not finite.
pub fn envelope_band(curve: &DiskWangBall, samples: usize) -> Option<Vec<Point>> {
    let env: Vec<(Point, Point)> = envelope(curve, samples).into_iter().flatten().collect();
    let band: Vec<Point> = env
        .iter()
        .map(|e| e.0)
        .chain(env.iter().rev().map(|e| e.1))
        .collect();
    (env.len() >= 2 && band.iter().all(|p| p.is_finite())).then_some(band)
}

/// The two envelope points of the circle family at one parameter.
pub fn envelope_points(c: Point, r: f64, dc: Point, dr: f64) -> Option<(Point, Point)> {
    let s = dc.length_squared();
    if s.is_nan() || s <= 0.0 || dr * dr >= s {
        return None;
    }
    let along = c - dc * (r * dr / s);
    let across = dc.perp() * (r * (s - dr * dr).sqrt() / s);
    Some((along + across, along - across))
}

/// One curve to draw and its colour.
pub struct Layer<'a> {
    /// The curve.
    pub curve: &'a DiskWangBall,
    /// A CSS colour.
    pub colour: &'a str,
    /// Legend text.
    pub label: &'a str,
}

/// A picture of disk curves in their own coordinates (y up), the curves fitted to an 800-px
/// square: for each layer in order (later ones on top) the envelope band (translucent), the
/// center line and the control disks (dashed circles), and a legend.
pub fn to_svg(layers: &[Layer<'_>]) -> String {
    // Frame the curves themselves: control disks of merged curves can lie far away (they
    // are drawn where they fall inside the frame).
    let mut frame = Bounds::EMPTY;
    for l in layers {
        for i in 0..=SAMPLES {
            let d = l.curve.eval(i as f64 / SAMPLES as f64);
            frame.add_disk(d.center, d.radius);
        }
    }
    let frame = frame.or_unit();
    let side = frame.extent().max(1e-9);
    let margin = 0.05 * side;
    let scale = 800.0 / (side + 2.0 * margin);
    // Picture coordinates: x right, y down.
    let map = |p: Point| {
        Point::new(
            (p.x - frame.min.x + margin) * scale,
            (frame.max.y - p.y + margin) * scale,
        )
    };
    let width = ((frame.width() + 2.0 * margin) * scale).ceil();
    let height = ((frame.height() + 2.0 * margin) * scale).ceil();
    let total_height = height + 20.0 * layers.len() as f64 + 10.0;
    let mut doc = Document::new(width, total_height, [0.0, 0.0, width, total_height], 2);
    doc.add(
        Rectangle::new()
            .set("width", "100%")
            .set("height", "100%")
            .set("fill", "white"),
    );
    for (k, l) in layers.iter().enumerate() {
        let mut g = Group::new().set("id", format!("curve-{k}"));
        if let Some(band) = envelope_band(l.curve, SAMPLES) {
            let mut d = PathData::new(PRECISION);
            d.polyline(band.into_iter().map(map));
            d.close();
            g = g.add(
                Path::new()
                    .set("d", d.finish())
                    .set("fill", l.colour)
                    .set("fill-opacity", 0.2)
                    .set("stroke", l.colour)
                    .set("stroke-width", 0.8),
            );
        }
        let mut d = PathData::new(PRECISION);
        d.polyline(l.curve.sample(SAMPLES).into_iter().map(map));
        g = g.add(
            Path::new()
                .set("d", d.finish())
                .set("fill", "none")
                .set("stroke", l.colour)
                .set("stroke-width", 2),
        );
        for disk in &l.curve.disks {
            let p = map(disk.center);
            let n = |x: f64| crate::svg_writer::number(x, PRECISION);
            g = g.add(
                Circle::new()
                    .set("cx", n(p.x))
                    .set("cy", n(p.y))
                    .set("r", n((disk.radius.abs() * scale).max(1.5)))
                    .set("fill", "none")
                    .set("stroke", l.colour)
                    .set("stroke-dasharray", "4 3")
                    .set("stroke-width", 0.8),
            );
        }
        doc.add(g);
        let y = height + 20.0 * k as f64 + 15.0;
        doc.add(
            Rectangle::new()
                .set("x", 10)
                .set("y", y - 9.0)
                .set("width", 14)
                .set("height", 10)
                .set("fill", l.colour),
        );
        doc.add(
            Text::new(l.label)
                .set("x", 30)
                .set("y", y)
                .set("font-family", "sans-serif")
                .set("font-size", 13),
        );
    }
    doc.finish()
}

/// Decimals of the picture's coordinates (in an 800-px frame).
const PRECISION: usize = 2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::wang_ball::Disk;

    #[test]
    fn envelope_of_a_constant_radius_line_is_its_offset() {
        let c = DiskWangBall::new(vec![
            Disk::new(Point::new(0.0, 0.0), 0.5),
            Disk::new(Point::new(4.0, 0.0), 0.5),
        ]);
        for e in envelope(&c, 10) {
            let (a, b) = e.unwrap();
            assert!((a.y.abs() - 0.5).abs() < 1e-12 && (b.y.abs() - 0.5).abs() < 1e-12);
            assert!((a.y + b.y).abs() < 1e-12);
        }
    }

    #[test]
    fn envelope_points_touch_their_circle_and_the_next_one() {
        // On a growing-radius line each envelope point is on its circle, and (first order)
        // on the neighbouring circle too.
        let c = DiskWangBall::new(vec![
            Disk::new(Point::new(0.0, 0.0), 0.2),
            Disk::new(Point::new(1.0, 2.0), 0.6),
            Disk::new(Point::new(3.0, 1.0), 0.4),
        ]);
        let t = 0.37;
        let h = 1e-6;
        let (a, _) = envelope(&c, 1000)[370].unwrap();
        let d = c.eval(t);
        assert!((a.distance(d.center) - d.radius).abs() < 1e-12);
        let e = c.eval(t + h);
        assert!((a.distance(e.center) - e.radius).abs() < 1e-9);
    }

    #[test]
    fn picture_has_one_group_per_curve_and_parses() {
        let c = DiskWangBall::new(vec![
            Disk::new(Point::new(0.0, 0.0), 0.2),
            Disk::new(Point::new(1.0, 2.0), 0.3),
        ]);
        let svg = to_svg(&[
            Layer {
                curve: &c,
                colour: "#f00",
                label: "a <1>",
            },
            Layer {
                curve: &c,
                colour: "#00f",
                label: "b",
            },
        ]);
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let groups = doc.descendants().filter(|n| n.has_tag_name("g")).count();
        assert_eq!(groups, 2);
        assert!(svg.contains("a &lt;1&gt;"));
    }
}
