//! SVG pictures of disk curves: center lines with their disk envelopes
//! ([`outlinefit::curve::wang_ball::envelope`]); where a disk contains its neighbours the
//! envelope has no point, so the band polygon skips those samples (the control disks are
//! drawn as dashed circles beside it).

use outlinefit::curve::wang_ball::DiskWangBall;
pub use outlinefit::curve::wang_ball::{envelope, envelope_band, envelope_points};
use outlinefit::svg_writer::{Document, PathData, Text};
use outlinefit::ParamCurve as _;
use outlinefit::{Bounds, Point};
use svg::node::element::{Circle, Group, Path, Rectangle};

/// Samples per curve for center lines and envelopes.
const SAMPLES: usize = 200;

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
            let n = |x: f64| outlinefit::svg_writer::number(x, PRECISION);
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
    use outlinefit::curve::wang_ball::Disk;

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
