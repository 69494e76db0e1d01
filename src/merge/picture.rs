//! SVG pictures of disk curves: center lines with their disk envelopes.
//!
//! The envelope of the circles `(C(t), R(t))` is
//! `E±(t) = C − (R R' / |C'|²) C' ± (R √(|C'|² − R'²) / |C'|²) C'⊥`; where `|R'| ≥ |C'|` a
//! disk contains its neighbours and the envelope has no point there, so the band polygon
//! simply skips those samples (the control disks are drawn as dashed circles beside it).

use crate::curve::wang_ball::DiskWangBall;
use crate::export::svg::escape_attribute;
use crate::geom::Point;
use std::fmt::Write as _;

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
    let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut grow = |p: Point, r: f64| {
        if p.is_finite() && r.is_finite() {
            lo = Point::new(lo.x.min(p.x - r), lo.y.min(p.y - r));
            hi = Point::new(hi.x.max(p.x + r), hi.y.max(p.y + r));
        }
    };
    // Frame the curves themselves: control disks of merged curves can lie far away (they
    // are drawn where they fall inside the frame).
    for l in layers {
        for i in 0..=SAMPLES {
            let d = l.curve.eval(i as f64 / SAMPLES as f64);
            grow(d.center, d.radius.abs());
        }
    }
    if !(lo.x.is_finite() && hi.x.is_finite()) {
        lo = Point::ZERO;
        hi = Point::new(1.0, 1.0);
    }
    let side = (hi.x - lo.x).max(hi.y - lo.y).max(1e-9);
    let margin = 0.05 * side;
    let scale = 800.0 / (side + 2.0 * margin);
    // Picture coordinates: x right, y down.
    let map = |p: Point| Point::new((p.x - lo.x + margin) * scale, (hi.y - p.y + margin) * scale);
    let width = ((hi.x - lo.x + 2.0 * margin) * scale).ceil();
    let height = ((hi.y - lo.y + 2.0 * margin) * scale).ceil();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{}\" viewBox=\"0 0 {width} {}\">",
        height + 20.0 * layers.len() as f64 + 10.0,
        height + 20.0 * layers.len() as f64 + 10.0
    );
    let _ = writeln!(out, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
    for (k, l) in layers.iter().enumerate() {
        let _ = writeln!(out, "<g id=\"curve-{k}\">");
        let env = envelope(l.curve, SAMPLES);
        let upper: Vec<Point> = env.iter().flatten().map(|e| map(e.0)).collect();
        let lower: Vec<Point> = env.iter().flatten().map(|e| map(e.1)).collect();
        if upper.len() >= 2 {
            let mut d = String::new();
            for (i, p) in upper.iter().chain(lower.iter().rev()).enumerate() {
                let _ = write!(d, "{}{:.2} {:.2}", if i == 0 { "M" } else { "L" }, p.x, p.y);
            }
            d.push('Z');
            let _ = writeln!(
                out,
                "<path d=\"{d}\" fill=\"{c}\" fill-opacity=\"0.2\" stroke=\"{c}\" stroke-width=\"0.8\"/>",
                c = l.colour
            );
        }
        let mut d = String::new();
        for i in 0..=SAMPLES {
            let p = map(l.curve.center(i as f64 / SAMPLES as f64));
            let _ = write!(d, "{}{:.2} {:.2}", if i == 0 { "M" } else { "L" }, p.x, p.y);
        }
        let _ = writeln!(
            out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>",
            l.colour
        );
        for disk in &l.curve.disks {
            let p = map(disk.center);
            let _ = writeln!(
                out,
                "<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"{:.2}\" fill=\"none\" stroke=\"{}\" stroke-dasharray=\"4 3\" stroke-width=\"0.8\"/>",
                p.x,
                p.y,
                (disk.radius.abs() * scale).max(1.5),
                l.colour
            );
        }
        let _ = writeln!(out, "</g>");
        let y = height + 20.0 * k as f64 + 15.0;
        let _ = writeln!(
            out,
            "<rect x=\"10\" y=\"{:.0}\" width=\"14\" height=\"10\" fill=\"{}\"/><text x=\"30\" y=\"{:.0}\" font-family=\"sans-serif\" font-size=\"13\">{}</text>",
            y - 9.0,
            l.colour,
            y,
            escape_attribute(l.label)
        );
    }
    out.push_str("</svg>\n");
    out
}

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
