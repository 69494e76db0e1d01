//! The centre-line SVG and its overlay.
//!
//! The SVG has two groups, so that any program can pick either: `strokes`, what the
//! strokes look like (with a constant width, each centre line stroked at its width with
//! round caps and joins; with a variable width, each stroke's envelope filled: one band
//! per piece and a disk at every joint and end, all turning the same way, so the nonzero
//! fill is their union), and `centerlines`, the bare centre lines, one `<path
//! fill="none">` per stroke, drawn as thin lines over the strokes (for plotters,
//! engravers, cutters).

use super::fit::centre_settings;
use super::result::{CenterlineResult, Stroke, StrokeEnd, StrokeWidth};
use crate::curve::wang_ball::envelope_points;
use crate::export::overlay::{add_background, VIEW_SIDE};
use crate::export::svg::pixel_document;
use crate::fit::solve::{fit_segment, segment_error, EndCondition};
use crate::geom::{signed_area, Point};
use crate::svg_writer::{comment, number, push_point, Circle, Group, Path};

/// Decimals of the coordinates.
const PRECISION: usize = 2;

/// The magic number of a quarter circle as a cubic.
const KAPPA: f64 = 0.552_284_749_830_793_4;

/// Width of the bare centre lines, px.
pub const CENTERLINE_WIDTH: f64 = 0.5;

/// Path data built from absolute commands.
struct PathText(String);

impl PathText {
    fn cmd(&mut self, letter: char, points: &[Point]) {
        self.0.push(letter);
        for (k, &p) in points.iter().enumerate() {
            if k > 0 {
                self.0.push(' ');
            }
            push_point(&mut self.0, p, PRECISION);
        }
    }
}

/// The centre line of a stroke as path data.
fn centre_line(stroke: &Stroke, out: &mut PathText) {
    let Some(first) = stroke.segments.first() else {
        return;
    };
    out.cmd('M', &[first.bezier[0]]);
    if stroke.segments.len() == 1 && first.point_count <= 1 {
        out.0.push_str("h0");
        return;
    }
    for seg in &stroke.segments {
        let b = seg.bezier;
        out.cmd('C', &[b[1], b[2], b[3]]);
    }
    if stroke.closed {
        out.0.push('Z');
    }
}

/// A circle as four cubics, turning the way the bands do (signed area > 0 in image
/// coordinates).
fn circle(c: Point, r: f64, out: &mut PathText) {
    let r = r.max(0.0);
    let dirs = [
        Point::new(1.0, 0.0),
        Point::new(0.0, 1.0),
        Point::new(-1.0, 0.0),
        Point::new(0.0, -1.0),
    ];
    let order = [0, 1, 2, 3, 0];
    out.cmd('M', &[c + dirs[order[0]] * r]);
    for w in order.windows(2) {
        let (a, b) = (dirs[w[0]], dirs[w[1]]);
        out.cmd(
            'C',
            &[c + (a + b * KAPPA) * r, c + (b + a * KAPPA) * r, c + b * r],
        );
    }
    out.0.push('Z');
}

/// Cubics through `points` (a side of an envelope) within `bound` px, split in halves
/// where one cubic misses; a polyline where the points are too few to split.
fn side_cubics(points: &[Point], bound: f64, depth: usize, out: &mut PathText) {
    if points.len() >= 4 {
        let sol = fit_segment(
            points,
            EndCondition::Free,
            EndCondition::Free,
            &centre_settings(),
        );
        let err = segment_error(&sol.curve, points, &sol.params);
        if err.max_distance <= bound || depth >= 4 || points.len() < 9 {
            if err.max_distance <= bound {
                let b = sol.curve.points;
                out.cmd('L', &[b[0]]);
                out.cmd('C', &[b[1], b[2], b[3]]);
                return;
            }
        } else {
            let m = points.len() / 2;
            side_cubics(&points[..=m], bound, depth + 1, out);
            side_cubics(&points[m..], bound, depth + 1, out);
            return;
        }
    }
    for &p in points {
        out.cmd('L', &[p]);
    }
}

/// The filled envelope of a stroke: a band per piece, a disk at every joint and end.
fn envelope_path(stroke: &Stroke, bound: f64, out: &mut PathText) {
    let mut disks: Vec<(Point, f64)> = Vec::new();
    for (k, seg) in stroke.segments.iter().enumerate() {
        let c = &seg.curve;
        if k == 0 {
            disks.push((c.center(0.0), c.radius(0.0)));
        }
        disks.push((c.center(1.0), c.radius(1.0)));
        let samples = ((seg.chord_length() / 2.0).ceil() as usize).clamp(12, 400);
        let sides: Option<Vec<(Point, Point)>> = (0..=samples)
            .map(|i| {
                let t = i as f64 / samples as f64;
                let d = c.eval(t);
                envelope_points(
                    d.center,
                    d.radius,
                    c.center_derivative(t),
                    c.radius_derivative(t),
                )
            })
            .collect();
        match sides {
            Some(sides) if seg.point_count > 1 => {
                let plus: Vec<Point> = sides.iter().map(|s| s.0).collect();
                let minus: Vec<Point> = sides.iter().rev().map(|s| s.1).collect();
                let band: Vec<Point> = plus.iter().chain(&minus).copied().collect();
                let (a, b) = if signed_area(&band) >= 0.0 {
                    (plus, minus)
                } else {
                    (
                        minus.into_iter().rev().collect(),
                        plus.into_iter().rev().collect(),
                    )
                };
                out.cmd('M', &[a[0]]);
                side_cubics(&a, bound, 0, out);
                side_cubics(&b, bound, 0, out);
                out.0.push('Z');
            }
            _ => {
                // No envelope (the radius changes faster than the centre moves): the
                // disks themselves, half a pixel apart.
                let steps = (2.0 * seg.chord_length()).ceil().max(1.0) as usize;
                for i in 1..steps {
                    let d = c.eval(i as f64 / steps as f64);
                    disks.push((d.center, d.radius));
                }
            }
        }
    }
    for (c, r) in disks {
        if r > 0.0 {
            circle(c, r, out);
        }
    }
}

/// The traced strokes as an SVG document (see the module docs).
pub fn centerline_svg(result: &CenterlineResult) -> String {
    let mut doc = pixel_document(result.image.width, result.image.height, 1);
    doc.add(comment(&format!(
        "outlinefit {} centre lines: {} strokes, {} pieces (cubic disk Wang-Ball curves), width {}",
        crate::VERSION,
        result.strokes.len(),
        result.segment_count(),
        result.stroke_width.name()
    )));
    let mut strokes = Group::new().set("id", "strokes");
    strokes = match result.stroke_width {
        StrokeWidth::Variable => strokes.set("fill", "black").set("fill-rule", "nonzero"),
        StrokeWidth::Constant => strokes
            .set("fill", "none")
            .set("stroke", "black")
            .set("stroke-linecap", "round")
            .set("stroke-linejoin", "round"),
    };
    let mut lines = Group::new()
        .set("id", "centerlines")
        .set("fill", "none")
        .set("stroke", "black")
        .set("stroke-width", number(CENTERLINE_WIDTH, PRECISION))
        .set("stroke-linecap", "round")
        .set("stroke-linejoin", "round");
    for stroke in &result.strokes {
        let mut centre = PathText(String::new());
        centre_line(stroke, &mut centre);
        match result.stroke_width {
            StrokeWidth::Variable => {
                let mut env = PathText(String::new());
                envelope_path(stroke, 0.05, &mut env);
                strokes = strokes.add(Path::new().set("d", env.0));
            }
            StrokeWidth::Constant => {
                strokes = strokes.add(
                    Path::new()
                        .set("d", centre.0.clone())
                        .set("stroke-width", number(stroke.width_range[1], PRECISION)),
                );
            }
        }
        lines = lines.add(Path::new().set("d", centre.0));
    }
    doc.add(strokes);
    doc.add(lines);
    doc.finish()
}

/// A diagnostic picture: the input, the thinned skeleton's pixels (grey), the measured
/// centres that were fitted (small orange dots), the centre lines (blue), the disks at
/// every joint (green circles), junctions (red) and free ends (orange).
pub fn centerline_overlay_svg(
    result: &CenterlineResult,
    background: Option<&image::GrayImage>,
) -> String {
    let (width, height) = (result.image.width, result.image.height);
    let side = f64::from(width.max(height).max(1));
    let zoom = (VIEW_SIDE / side).ceil().max(1.0) as u64;
    let unit = side / VIEW_SIDE;
    let size = |x: f64| number(x, 4);
    let mut doc = pixel_document(width, height, zoom);
    if let Some(img) = background {
        add_background(&mut doc, img, width, height, 0.5);
    }
    let dots = |points: &mut dyn Iterator<Item = Point>| {
        let mut path = PathText(String::new());
        for p in points {
            path.cmd('M', &[p]);
            path.0.push_str("h0");
        }
        path.0
    };
    let skeleton = dots(&mut result.skeleton.iter().copied());
    let measured = dots(
        &mut result
            .strokes
            .iter()
            .flat_map(|s| s.data.iter().map(|d| d.0)),
    );
    doc.add(
        Path::new()
            .set("id", "skeleton")
            .set("d", skeleton)
            .set("stroke", "#909090")
            .set("stroke-width", size(0.6))
            .set("stroke-linecap", "square"),
    );
    doc.add(
        Path::new()
            .set("id", "measured-centres")
            .set("d", measured)
            .set("stroke", "#ff7f0e")
            .set("stroke-width", size(2.0 * unit))
            .set("stroke-linecap", "round"),
    );
    let mut disks = Group::new()
        .set("id", "disks")
        .set("fill", "none")
        .set("stroke", "#00a651")
        .set("stroke-width", size(unit));
    let mut lines = Group::new()
        .set("id", "centerlines")
        .set("fill", "none")
        .set("stroke", "#1f5fff")
        .set("stroke-width", size(1.5 * unit));
    let mut ends = Group::new().set("id", "ends").set("fill", "#ff7f0e");
    for stroke in &result.strokes {
        let mut centre = PathText(String::new());
        centre_line(stroke, &mut centre);
        lines = lines.add(Path::new().set("d", centre.0));
        for (k, seg) in stroke.segments.iter().enumerate() {
            let c = &seg.curve;
            for t in if k == 0 { vec![0.0, 1.0] } else { vec![1.0] } {
                let d = c.eval(t);
                disks = disks.add(
                    Circle::new()
                        .set("cx", number(d.center.x, PRECISION))
                        .set("cy", number(d.center.y, PRECISION))
                        .set("r", number(d.radius.max(0.0), PRECISION)),
                );
            }
        }
        if !stroke.closed {
            for (end, p) in [
                (stroke.ends[0], stroke.segments.first().map(|s| s.bezier[0])),
                (stroke.ends[1], stroke.segments.last().map(|s| s.bezier[3])),
            ] {
                if let (StrokeEnd::Free, Some(p)) = (end, p) {
                    ends = ends.add(
                        Circle::new()
                            .set("cx", number(p.x, PRECISION))
                            .set("cy", number(p.y, PRECISION))
                            .set("r", size(3.0 * unit)),
                    );
                }
            }
        }
    }
    let mut junctions = Group::new().set("id", "junctions").set("fill", "#e00000");
    for j in &result.junctions {
        junctions = junctions.add(
            Circle::new()
                .set("cx", number(j.centre.x, PRECISION))
                .set("cy", number(j.centre.y, PRECISION))
                .set("r", size(4.0 * unit)),
        );
    }
    doc.add(disks);
    doc.add(lines);
    doc.add(ends);
    doc.add(junctions);
    doc.finish()
}
