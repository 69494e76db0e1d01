//! The traced outline as an SVG document.
//!
//! One `<path>` per shape: an outer border together with every hole whose `parent` is that
//! border, filled with `fill-rule="evenodd"` (outer borders and holes run in opposite
//! directions, so `nonzero` would work too; `evenodd` does not depend on it). All paths are
//! in one `<g>` that carries the paint, so each path holds only its data. Each closed
//! contour becomes `M x0 y0`, a relative `c` per polynomial cubic (`l`, `h` or `v` where
//! the cubic is a straight line), then `z`, in the compact syntax SVG allows (see
//! `contour_path_data`). Islands inside holes are outer borders of their own and get
//! their own path.
//!
//! SVG cannot draw rational curves, so each rational segment goes through
//! [`approximate_with_cubics`](crate::curve::approx::approximate_with_cubics) with [`ExportOptions::bound`]: polynomial segments are written
//! exactly, rational ones as one or more cubics whose measured distance to the rational
//! curve is within the bound, and G1 joints stay G1. The exact rational data belongs in the
//! JSON report.
//!
//! The document is shown at the input's size in pixels (x right, y down) and is written by
//! `svg_writer`, the writer all pictures share, so identical results give byte-identical
//! files. Points are rounded to `precision` decimals of a pixel, which moves them by at
//! most half a unit of the last decimal (0.005 px by default), on top of the approximation
//! bound; [`ExportOptions::for_tolerance`] picks the fewest decimals that keep this within
//! half the bound. The path data is written in units of that grid, as whole numbers
//! (`1234` for 12.34 px; [`PathUnits::Grid`]), and the `viewBox` is the image in the same
//! units (`0 0 100W 100H` with 2 decimals): one character less per number than decimals
//! in pixel units, about a fifth of a page's bytes.
//!
//! Nothing is dropped silently: a contour with non-finite coordinates, or a hole without an
//! outer border to cut into, is left out with an XML comment saying so (drawn alone, a hole
//! would be filled). Contours without segments have nothing to draw and are skipped.

use super::options::{ExportOptions, Unit};
use super::shapes::{finite_pieces, holes_of, is_straight};
use crate::curve::CubicBez;
use crate::fit::FittedContour;
use crate::geom::Point;
use crate::merge::outline::MergedCurve;
use crate::trace::TraceResult;

use crate::svg_writer::{
    comment, grid_per_unit, number, CompactPath, Document, Group, Path, PathUnits,
};
use svg::Node as _;

/// Width of the line of `stroke_only` outlines, in pixels.
pub(crate) const STROKE_WIDTH: f64 = 1.0;

/// Fewest segments for which [`to_svg`] writes the shapes' path data on the thread pool
/// (a page of text has tens of thousands; a glyph a few dozen).
const PARALLEL_SEGMENTS: usize = 4_000;

/// Writes the traced outline as an SVG document (see the module docs for the layout).
/// Deterministic: the same result and options give the same bytes.
pub fn to_svg(result: &TraceResult, opts: &ExportOptions) -> String {
    let precision = opts.effective_precision();
    let bound = opts.effective_bound();
    let grid = grid_per_unit(precision);
    let mut doc = scaled_document(result.image.width, result.image.height, opts, grid);
    let contours = &result.contours;
    let (holes_of, orphans) = holes_of(result);
    for i in orphans {
        doc.comment(&format!(
            "contour {i} skipped: a hole without an outer border"
        ));
    }
    // The paint is the group's, so that each path carries only its data.
    let fill = opts.fill.to_string();
    let mut group = if opts.stroke_only {
        Group::new()
            .set("fill", "none")
            .set("stroke", fill.as_str())
            .set("stroke-width", number(STROKE_WIDTH * grid, 0))
    } else {
        Group::new()
            .set("fill", fill.as_str())
            .set("fill-rule", "evenodd")
    };
    // Each shape's path data (an outer border and its holes), with the contours it left
    // out; on a page, written on the thread pool and put back in order.
    let shape = |&i: &usize| -> (String, Vec<usize>) {
        let mut data = String::new();
        let mut skipped = Vec::new();
        for k in std::iter::once(i).chain(holes_of[i].iter().copied()) {
            let merged = result.merged_of(k);
            match contour_path_data(&contours[k], merged, bound, precision, PathUnits::Grid) {
                ContourPath::Data(d) => data.push_str(&d),
                ContourPath::Empty => {}
                ContourPath::NonFinite => skipped.push(k),
            }
        }
        (data, skipped)
    };
    let outers: Vec<usize> = (0..contours.len())
        .filter(|&i| !contours[i].is_hole)
        .collect();
    let segments: usize = contours.iter().map(|c| c.segments.len()).sum();
    let shapes: Vec<(String, Vec<usize>)> = if segments >= PARALLEL_SEGMENTS {
        use rayon::prelude::*;
        outers.par_iter().map(shape).collect()
    } else {
        outers.iter().map(shape).collect()
    };
    for (data, skipped) in shapes {
        for k in skipped {
            group.append(comment(&format!(
                "contour {k} skipped: non-finite coordinates"
            )));
        }
        if !data.is_empty() {
            group.append(Path::new().set("d", data));
        }
    }
    doc.add(group);
    doc.finish()
}

/// A document of `width` × `height` pixels whose user unit is `1 / scale` px
/// (`viewBox="0 0 W·scale H·scale"`), shown at the options' size in its unit (`12.7mm`;
/// plain numbers for pixels).
pub(crate) fn scaled_document(
    width: u32,
    height: u32,
    opts: &ExportOptions,
    scale: f64,
) -> Document {
    let (w, h) = (f64::from(width), f64::from(height));
    let doc = Document::new(w, h, [0.0, 0.0, w * scale, h * scale], 0);
    if opts.size == Default::default() {
        return doc;
    }
    let unit = opts.size.unit;
    let k = opts.size.unit_per_pixel();
    let precision = opts.precision_in(unit);
    let suffix = if unit == Unit::Px { "" } else { unit.name() };
    let length = |x: f64| format!("{}{suffix}", number(x * k, precision));
    doc.set("width", length(w)).set("height", length(h))
}

/// A document in input pixel units (`viewBox="0 0 W H"`), shown `zoom` times larger.
pub(crate) fn pixel_document(width: u32, height: u32, zoom: u64) -> Document {
    let (w, h) = (f64::from(width), f64::from(height));
    let z = zoom as f64;
    Document::new(w * z, h * z, [0.0, 0.0, w, h], 0)
}

/// The path data of one contour, or why there is none.
pub(crate) enum ContourPath {
    /// `M … c … z`.
    Data(String),
    /// The contour has no segments.
    Empty,
    /// Some coordinate (of the curves or of their cubic approximation) is not finite.
    NonFinite,
}

/// Path data of one closed contour, written compactly by [`CompactPath`]: `M` to the
/// first point, then relative commands, `c` per cubic or `l`/`h`/`v` where a cubic is
/// straight, and `z`. Every point is first rounded to the grid of `precision`
/// decimals and each relative offset is the difference of two rounded points, so the
/// written path lands exactly on the rounded points (no drift along the contour). Where a
/// segment does not start where the previous one ended (after rounding), an `l` bridges
/// the gap rather than hiding it.
pub(crate) fn contour_path_data(
    contour: &FittedContour,
    merged: &[MergedCurve],
    bound: f64,
    precision: usize,
    units: PathUnits,
) -> ContourPath {
    if contour.segments.is_empty() {
        return ContourPath::Empty;
    }
    let Some(pieces) = finite_pieces(contour, merged, bound) else {
        return ContourPath::NonFinite;
    };
    ContourPath::Data(pieces_path_data(&pieces, precision, units))
}

/// Path data of one closed loop of pieces, each a start point and the cubics that follow
/// it (see [`contour_path_data`]).
pub(crate) fn pieces_path_data(
    pieces: &[(Point, Vec<CubicBez>)],
    precision: usize,
    units: PathUnits,
) -> String {
    let mut w = CompactPath::new(precision, units);
    let mut pen = w.grid(pieces[0].0);
    w.command('M');
    w.number(pen.0);
    w.number(pen.1);
    for (start, cubics) in pieces {
        let start = w.grid(*start);
        if start != pen {
            w.line(pen, start);
            pen = start;
        }
        for c in cubics {
            let end = w.grid(c.points[3]);
            if is_straight(c, w.half_unit()) {
                if end != pen {
                    w.line(pen, end);
                }
            } else {
                w.command('c');
                for p in &c.points[1..3] {
                    let q = w.grid(*p);
                    w.number(q.0 - pen.0);
                    w.number(q.1 - pen.1);
                }
                w.number(end.0 - pen.0);
                w.number(end.1 - pen.1);
            }
            pen = end;
        }
    }
    w.command('z');
    w.finish()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::curve::{approximate_with_cubics, CubicBez, RationalCubic};
    use crate::fit::{FittedSegment, Joint, JointKind, SegmentError};
    use crate::geom::Point;
    use crate::trace::ImageInfo;
    use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4, SQRT_2};

    /// A quarter circle as an exact rational cubic (degree-elevated conic, w = cos 45°).
    pub(crate) fn quarter_arc(center: Point, r: f64, from: f64, to: f64) -> RationalCubic {
        let at = |a: f64| center + Point::new(a.cos(), a.sin()) * r;
        let mid = 0.5 * (from + to);
        let p1 = center + Point::new(mid.cos(), mid.sin()) * (r * SQRT_2);
        RationalCubic::from_conic(at(from), p1, at(to), FRAC_1_SQRT_2)
    }

    fn segment(curve: RationalCubic) -> FittedSegment {
        FittedSegment {
            curve,
            start: 0,
            end: 0,
            point_count: 2,
            params: vec![0.0, 1.0],
            arc_range: [0.0, 0.0],
            error: SegmentError::default(),
            evaluations: 0,
            seconds: 0.0,
            on_search_boundary: None,
            history: Vec::new(),
            drawn: Default::default(),
        }
    }

    /// A circle of four rational quarter arcs; clockwise on screen (outer) unless `hole`.
    pub(crate) fn circle(
        center: Point,
        r: f64,
        hole: bool,
        parent: Option<usize>,
    ) -> FittedContour {
        let q = if hole { -FRAC_PI_2 } else { FRAC_PI_2 };
        let segments: Vec<FittedSegment> = (0..4)
            .map(|k| segment(quarter_arc(center, r, k as f64 * q, (k + 1) as f64 * q)))
            .collect();
        let joints = segments
            .iter()
            .enumerate()
            .map(|(k, s)| Joint {
                kind: if k == 0 {
                    JointKind::Corner
                } else {
                    JointKind::Smooth
                },
                position: s.curve.points[0],
                index: k,
                angle: 0.0,
                beta: 1.0,
            })
            .collect();
        let points = (0..16)
            .map(|k| {
                let a = k as f64 * q / 4.0;
                center + Point::new(a.cos(), a.sin()) * r
            })
            .collect();
        FittedContour {
            points,
            is_hole: hole,
            parent,
            segments,
            joints,
            tolerance: 0.3,
        }
    }

    pub(crate) fn result(width: u32, height: u32, contours: Vec<FittedContour>) -> TraceResult {
        TraceResult {
            merged: Vec::new(),
            image: ImageInfo {
                width,
                height,
                threshold: 127.5,
                threshold_scale: crate::raster::ThresholdScale::Coverage,
                threshold_mode: crate::raster::ThresholdMode::Global,
                bilevel: true,
                from_alpha: false,
                dark_border: false,
                border_foreground: 0.0,
                frame: 0,
                frames: 1,
            },
            contours,
            fidelity: crate::Fidelity::default(),
            seconds: 0.0,
        }
    }

    /// The `d` attributes of every `<path>`.
    fn path_data(svg: &str) -> Vec<String> {
        svg.split("<path")
            .skip(1)
            .map(|p| {
                let start = p.find(" d=\"").unwrap() + 4;
                let end = start + p[start..].find('"').unwrap();
                p[start..end].to_string()
            })
            .collect()
    }

    /// User units per pixel of a document: its `viewBox` width over its `width`.
    fn units_per_pixel(svg: &str) -> f64 {
        let attribute = |name: &str| {
            let start = svg.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            svg[start..start + svg[start..].find('"').unwrap()].to_string()
        };
        let view_box: Vec<f64> = attribute("viewBox")
            .split(' ')
            .map(|x| x.parse().unwrap())
            .collect();
        view_box[2] / attribute("width").parse::<f64>().unwrap()
    }

    /// Path data as absolute (command, numbers) pairs: `M`, `L`, `C` and `Z`, read by
    /// the parser resvg uses, with coordinates in pixels (user units divided by `k`, the
    /// document's [`units_per_pixel`]).
    fn parse_path(d: &str, k: f64) -> Vec<(char, Vec<f64>)> {
        use svgtypes::SimplePathSegment as S;
        svgtypes::SimplifyingPathParser::from(d)
            .map(|s| s.unwrap())
            .map(|s| match s {
                S::MoveTo { x, y } => ('M', vec![x, y]),
                S::LineTo { x, y } => ('L', vec![x, y]),
                S::CurveTo {
                    x1,
                    y1,
                    x2,
                    y2,
                    x,
                    y,
                } => ('C', vec![x1, y1, x2, y2, x, y]),
                S::Quadratic { .. } => panic!("no quadratics are written"),
                S::ClosePath => ('Z', Vec::new()),
            })
            .map(|(c, v)| (c, v.into_iter().map(|x| x / k).collect()))
            .collect()
    }

    #[test]
    fn circle_path_has_every_coordinate_right() {
        let c = circle(Point::new(30.0, 20.0), 12.0, false, None);
        let svg = to_svg(&result(64, 48, vec![c.clone()]), &ExportOptions::default());
        let data = path_data(&svg);
        assert_eq!(data.len(), 1);
        // Whole numbers of hundredths of a pixel.
        assert!(
            svg.contains("viewBox=\"0 0 6400 4800\" width=\"64\""),
            "{svg}"
        );
        assert_eq!(units_per_pixel(&svg), 100.0);
        assert!(!data[0].contains('.'), "{}", data[0]);
        let cmds = parse_path(&data[0], 100.0);
        // M, one C per quarter (a quarter circle of radius 12 needs one cubic), Z.
        let letters: String = cmds.iter().map(|c| c.0).collect();
        assert_eq!(letters, "MCCCCZ");
        assert_eq!(cmds[0].1, vec![42.0, 20.0]);
        let expected: Vec<CubicBez> = c
            .segments
            .iter()
            .flat_map(|s| approximate_with_cubics(&s.curve, 0.02))
            .collect();
        for (cmd, cubic) in cmds[1..5].iter().zip(&expected) {
            assert_eq!(cmd.1.len(), 6);
            for (k, p) in cubic.points[1..].iter().enumerate() {
                assert!((cmd.1[2 * k] - p.x).abs() <= 0.005 + 1e-9);
                assert!((cmd.1[2 * k + 1] - p.y).abs() <= 0.005 + 1e-9);
            }
        }
        // The written curve is a circle to within bound + rounding.
        for cmd in &cmds[1..5] {
            let v = &cmd.1;
            let end = Point::new(v[4], v[5]);
            assert!((end.distance(Point::new(30.0, 20.0)) - 12.0).abs() < 1e-2);
        }
        let mut pen = Point::new(cmds[0].1[0], cmds[0].1[1]);
        for cmd in &cmds[1..5] {
            let v = &cmd.1;
            let cubic = CubicBez::new(
                pen,
                Point::new(v[0], v[1]),
                Point::new(v[2], v[3]),
                Point::new(v[4], v[5]),
            );
            for j in 0..=32 {
                let r = cubic.eval(j as f64 / 32.0).distance(Point::new(30.0, 20.0));
                assert!((r - 12.0).abs() < 0.02 + 0.01, "{r}");
            }
            pen = cubic.points[3];
        }
    }

    #[test]
    fn outer_and_hole_share_one_evenodd_path() {
        let outer = circle(Point::new(32.0, 32.0), 25.0, false, None);
        let hole = circle(Point::new(32.0, 32.0), 10.0, true, Some(0));
        let island = circle(Point::new(32.0, 32.0), 4.0, false, Some(1));
        let svg = to_svg(
            &result(64, 64, vec![outer, hole, island]),
            &ExportOptions::default(),
        );
        assert!(svg.starts_with(
            "<svg height=\"64\" viewBox=\"0 0 6400 6400\" width=\"64\" xmlns=\"http://www.w3.org/2000/svg\">\n\
             <g fill=\"#000000\" fill-rule=\"evenodd\">\n<path d=\"M"
        ));
        assert!(svg.ends_with("</g>\n</svg>\n"));
        let data = path_data(&svg);
        assert_eq!(data.len(), 2, "{svg}");
        assert_eq!(data[0].matches('M').count(), 2);
        assert_eq!(data[0].matches('z').count(), 2);
        assert_eq!(data[1].matches('M').count(), 1);
        // The paint is the group's alone.
        assert_eq!(svg.matches("fill-rule=\"evenodd\"").count(), 1);
        assert_eq!(svg.matches("fill=").count(), 1);
        assert!(!svg.contains("<!--"));
    }

    /// A page of shapes, enough segments for the path data to be written on the thread
    /// pool, gives each shape's path (its outer border, then its holes) in contour order,
    /// exactly as the shape's own contours are written one by one.
    #[test]
    fn a_page_of_shapes_is_written_in_order() {
        let mut contours = Vec::new();
        for k in 0..800 {
            let centre = Point::new(20.0 + (k % 40) as f64 * 40.0, 20.0 + (k / 40) as f64 * 40.0);
            let outer = contours.len();
            contours.push(circle(centre, 15.0 + (k % 7) as f64, false, None));
            if k % 3 == 0 {
                contours.push(circle(centre, 6.0, true, Some(outer)));
            }
        }
        let segments: usize = contours.iter().map(|c| c.segments.len()).sum();
        assert!(segments >= PARALLEL_SEGMENTS, "{segments}");
        let r = result(1600, 800, contours);
        let opts = ExportOptions::default();
        let data = path_data(&to_svg(&r, &opts));
        let (bound, precision) = (opts.effective_bound(), opts.effective_precision());
        let one = |k: usize| match contour_path_data(
            &r.contours[k],
            &[],
            bound,
            precision,
            PathUnits::Grid,
        ) {
            ContourPath::Data(d) => d,
            _ => unreachable!(),
        };
        let mut expected = Vec::new();
        for (i, c) in r.contours.iter().enumerate() {
            if c.is_hole {
                continue;
            }
            let mut d = one(i);
            if r.contours.get(i + 1).is_some_and(|h| h.parent == Some(i)) {
                d.push_str(&one(i + 1));
            }
            expected.push(d);
        }
        assert_eq!(data.len(), 800);
        assert_eq!(data, expected);
    }

    #[test]
    fn output_is_deterministic_and_respects_options() {
        let r = result(
            64,
            64,
            vec![circle(Point::new(32.123456, 31.987654), 20.0, false, None)],
        );
        let opts = ExportOptions {
            precision: 1,
            fill: crate::export::Rgb([0x12, 0xab, 0xff]),
            ..ExportOptions::default()
        };
        let a = to_svg(&r, &opts);
        assert_eq!(a, to_svg(&r, &opts));
        assert!(a.contains("fill=\"#12abff\""));
        assert_eq!(units_per_pixel(&a), 10.0);
        for d in path_data(&a) {
            assert!(!d.contains('.'), "{d}");
            for (_, numbers) in parse_path(&d, 10.0) {
                for x in numbers {
                    // One decimal at most.
                    assert!(((x * 10.0).round() - x * 10.0).abs() < 1e-9, "{x}");
                }
            }
        }
        assert!(!a.contains("-0 ") && !a.contains("-0C"));
    }

    #[test]
    fn bad_contours_are_reported_not_drawn() {
        let mut broken = circle(Point::new(10.0, 10.0), 5.0, false, None);
        broken.segments[1].curve.points[1].x = f64::NAN;
        let orphan = circle(Point::new(40.0, 40.0), 5.0, true, None);
        let mut empty = circle(Point::new(50.0, 10.0), 5.0, false, None);
        empty.segments.clear();
        let svg = to_svg(
            &result(64, 64, vec![broken, orphan, empty]),
            &ExportOptions::default(),
        );
        assert!(svg.contains("<!-- contour 0 skipped: non-finite coordinates -->"));
        assert!(svg.contains("<!-- contour 1 skipped: a hole without an outer border -->"));
        assert!(!svg.contains("<path"));
        assert!(!svg.contains("NaN"));
    }

    #[test]
    fn polynomial_segments_are_written_exactly() {
        let mut c = circle(Point::new(32.0, 32.0), 20.0, false, None);
        for s in &mut c.segments {
            s.curve.weights = [1.0, 1.0];
        }
        let svg = to_svg(&result(64, 64, vec![c.clone()]), &ExportOptions::default());
        let cmds = parse_path(&path_data(&svg)[0], units_per_pixel(&svg));
        assert_eq!(cmds.len(), 6);
        for (cmd, s) in cmds[1..5].iter().zip(&c.segments) {
            let p = &s.curve.points;
            let want = [p[1].x, p[1].y, p[2].x, p[2].y, p[3].x, p[3].y];
            for (got, want) in cmd.1.iter().zip(want) {
                assert!((got - want).abs() <= 0.005 + 1e-9);
            }
        }
    }

    #[test]
    fn for_tolerance_clamps_the_bound() {
        assert_eq!(ExportOptions::for_tolerance(0.4).bound, 0.02);
        assert_eq!(ExportOptions::for_tolerance(0.01).bound, 0.005);
        assert_eq!(ExportOptions::for_tolerance(5.0).bound, 0.05);
        assert_eq!(ExportOptions::for_tolerance(f64::NAN).bound, 0.02);
        assert_eq!(ExportOptions::for_tolerance(-1.0), ExportOptions::default());
    }

    #[test]
    fn rendered_ring_has_the_right_area() {
        use resvg::{tiny_skia, usvg};
        let outer = circle(Point::new(32.0, 32.0), 25.0, false, None);
        let hole = circle(Point::new(32.0, 32.0), 10.0, true, Some(0));
        let svg = to_svg(
            &result(64, 64, vec![outer, hole]),
            &ExportOptions::default(),
        );
        let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).unwrap();
        let mut pixmap = tiny_skia::Pixmap::new(64, 64).unwrap();
        resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
        let covered: f64 = pixmap
            .pixels()
            .iter()
            .map(|p| p.alpha() as f64 / 255.0)
            .sum();
        let area = std::f64::consts::PI * (25.0 * 25.0 - 10.0 * 10.0);
        assert!((covered - area).abs() < 1e-3 * area, "{covered} vs {area}");
        // The centre (in the hole) is empty, the ring is full.
        assert_eq!(pixmap.pixel(32, 32).unwrap().alpha(), 0);
        assert_eq!(pixmap.pixel(32, 14).unwrap().alpha(), 255);
    }

    #[test]
    fn quarter_arc_helper_is_exact() {
        let arc = quarter_arc(Point::new(1.0, 2.0), 5.0, FRAC_PI_4, FRAC_PI_4 + FRAC_PI_2);
        for j in 0..=16 {
            let d = arc.eval(j as f64 / 16.0).distance(Point::new(1.0, 2.0));
            assert!((d - 5.0).abs() < 1e-12);
        }
    }
    #[test]
    fn relative_path_lands_on_the_rounded_points_without_drift() {
        // A long contour of many small cubics with awkward coordinates: every written end
        // point, read back as absolute, is the original rounded to two decimals (a drift
        // of one unit over 400 relative steps would show).
        let mut c = circle(Point::new(500.123, 400.987), 300.0, false, None);
        let template = c.segments[0].clone();
        c.segments.clear();
        let n = 400;
        let at = |k: usize| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            Point::new(500.123 + 300.0 * t.cos(), 400.987 + 300.0 * t.sin())
        };
        for k in 0..n {
            let mut s = template.clone();
            let (a, b) = (at(k), at(k + 1));
            let bulge = (b - a).perp() * 0.08;
            s.curve.points = [
                a,
                a.lerp(b, 1.0 / 3.0) + bulge,
                a.lerp(b, 2.0 / 3.0) - bulge,
                b,
            ];
            s.curve.weights = [1.0, 1.0];
            c.segments.push(s);
        }
        let opts = ExportOptions::default();
        assert_eq!(opts.precision, 2);
        let svg = to_svg(&result(1000, 800, vec![c.clone()]), &opts);
        let cmds = parse_path(&path_data(&svg)[0], units_per_pixel(&svg));
        assert_eq!(cmds.len(), n + 2);
        for (k, cmd) in cmds[1..=n].iter().enumerate() {
            assert_eq!(cmd.0, 'C');
            let want = c.segments[k].curve.points[3];
            let round = |v: f64| (v * 100.0).round() / 100.0;
            assert!(
                (cmd.1[4] - round(want.x)).abs() < 1e-9,
                "{k}: {:?} {want:?}",
                cmd.1
            );
            assert!(
                (cmd.1[5] - round(want.y)).abs() < 1e-9,
                "{k}: {:?} {want:?}",
                cmd.1
            );
        }
    }

    #[test]
    fn straight_cubics_are_written_as_lines() {
        // A square whose sides are straight cubics (control points on the side, as a
        // least-squares fit of a line puts them) and one side bowed by 0.1 px.
        let corners = [
            Point::new(10.0, 10.0),
            Point::new(50.0, 10.0),
            Point::new(50.0, 40.0),
            Point::new(12.5, 43.25),
        ];
        let mut c = circle(Point::new(30.0, 30.0), 10.0, false, None);
        let template = c.segments[0].clone();
        c.segments.clear();
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let mut s = template.clone();
            let bow = if k == 1 {
                Point::new(0.1, 0.0)
            } else {
                Point::new(0.0, 0.0)
            };
            s.curve.points = [a, a.lerp(b, 0.3) + bow, a.lerp(b, 0.7) + bow, b];
            s.curve.weights = [1.0, 1.0];
            c.segments.push(s);
        }
        let svg = to_svg(&result(64, 64, vec![c]), &ExportOptions::default());
        let d = &path_data(&svg)[0];
        assert_eq!(
            d, "M1000 1000h4000c10 900 10 2100 0 3000l-3750 325-250-3325z",
            "{svg}"
        );
    }
}
