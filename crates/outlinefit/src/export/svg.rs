//! The traced outline as an SVG document.
//!
//! One `<path>` per shape: an outer border together with every hole whose `parent` is that
//! border, filled with `fill-rule="evenodd"` (outer borders and holes run in opposite
//! directions, so `nonzero` would work too; `evenodd` does not depend on it). Each closed
//! contour becomes `M x0 y0`, a relative `c` per polynomial cubic (`l`, `h` or `v` where
//! the cubic is a straight line), then `z`, in the compact syntax SVG allows (see
//! `contour_path_data`). Islands inside holes are outer borders of their own and get
//! their own path.
//!
//! SVG cannot draw rational curves, so each rational segment goes through
//! [`approximate_with_cubics`](crate::curve::approx::approximate_with_cubics) with [`SvgOptions::bound`]: polynomial segments are written
//! exactly, rational ones as one or more cubics whose measured distance to the rational
//! curve is within the bound, and G1 joints stay G1. The exact rational data belongs in the
//! JSON report.
//!
//! The document uses input pixel units (`viewBox="0 0 W H"`, x right, y down) and is
//! written by `svg_writer`, the writer all pictures share: numbers get fixed
//! decimals, trailing zeros trimmed, never `-0`, so identical results give byte-identical
//! files. Points are rounded to `precision` decimals, which moves them by at most half a
//! unit of the last decimal (0.005 px by default), on top of the approximation bound;
//! [`SvgOptions::for_tolerance`] picks the fewest decimals that keep this within half the
//! bound.
//!
//! Nothing is dropped silently: a contour with non-finite coordinates, or a hole without an
//! outer border to cut into, is left out with an XML comment saying so (drawn alone, a hole
//! would be filled). Contours without segments have nothing to draw and are skipped.

use crate::curve::approx::{drawing_bound, DEFAULT_DRAWING_BOUND};
use crate::curve::CubicBez;
use crate::fit::FittedContour;
use crate::merge::outline::{drawing_pieces, MergedCurve};
use crate::trace::TraceResult;

pub(crate) use crate::svg_writer::MAX_PRECISION;
use crate::svg_writer::{decimals_for, CompactPath, Document, Path};

/// How [`to_svg`] writes the outline.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    /// Largest distance, in pixels, between a rational segment and the polynomial cubics
    /// that draw it. Non-positive or non-finite values are replaced by the default.
    /// Default: 0.02.
    pub bound: f64,
    /// Decimals of every coordinate, at most [`MAX_PRECISION`]. Default: 2 (0.01 px),
    /// the fewest whose rounding (half a unit) stays within half the default bound.
    pub precision: usize,
    /// The fill colour, any SVG paint (escaped when written). Default: `#000000`.
    pub fill: String,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            bound: DEFAULT_BOUND,
            precision: precision_for(DEFAULT_BOUND),
            fill: "#000000".to_string(),
        }
    }
}

/// The default approximation bound, in pixels.
const DEFAULT_BOUND: f64 = DEFAULT_DRAWING_BOUND;

impl SvgOptions {
    /// Options matched to a fitting tolerance: the approximation bound of
    /// `drawing_bound` (a twentieth of the tolerance, clamped to [0.005, 0.05] px), and
    /// coordinates with the fewest decimals whose rounding stays within half the bound (2
    /// for tolerances from 0.2 px, 3 below). A non-positive or non-finite tolerance gives
    /// the defaults.
    pub fn for_tolerance(tolerance: f64) -> Self {
        let bound = drawing_bound(tolerance);
        SvgOptions {
            bound,
            precision: precision_for(bound),
            ..SvgOptions::default()
        }
    }

    /// The bound actually used: [`SvgOptions::bound`] if it is a positive number.
    pub(crate) fn effective_bound(&self) -> f64 {
        effective_bound(self.bound)
    }
}

/// The fewest decimals (at most [`MAX_PRECISION`]) whose unit is at most `bound`, so that
/// rounding (half a unit) moves a point by at most half the bound.
fn precision_for(bound: f64) -> usize {
    decimals_for(effective_bound(bound))
}

/// `bound` if it is a positive finite number, else the default.
pub(crate) fn effective_bound(bound: f64) -> f64 {
    if bound.is_finite() && bound > 0.0 {
        bound
    } else {
        DEFAULT_BOUND
    }
}

/// Writes the traced outline as an SVG document (see the module docs for the layout).
/// Deterministic: the same result and options give the same bytes.
pub fn to_svg(result: &TraceResult, opts: &SvgOptions) -> String {
    let precision = opts.precision.min(MAX_PRECISION);
    let bound = opts.effective_bound();
    let mut doc = pixel_document(result.image.width, result.image.height, 1);
    let contours = &result.contours;
    let mut holes_of: Vec<Vec<usize>> = vec![Vec::new(); contours.len()];
    for (i, c) in contours.iter().enumerate() {
        if !c.is_hole {
            continue;
        }
        match c.parent {
            Some(p) if p < contours.len() && !contours[p].is_hole => holes_of[p].push(i),
            _ => {
                if !c.segments.is_empty() {
                    doc.comment(&format!(
                        "contour {i} skipped: a hole without an outer border"
                    ));
                }
            }
        }
    }
    for (i, c) in contours.iter().enumerate() {
        if c.is_hole {
            continue;
        }
        let mut data = String::new();
        for k in std::iter::once(i).chain(holes_of[i].iter().copied()) {
            match contour_path_data(&contours[k], result.merged_of(k), bound, precision) {
                ContourPath::Data(d) => data.push_str(&d),
                ContourPath::Empty => {}
                ContourPath::NonFinite => {
                    doc.comment(&format!("contour {k} skipped: non-finite coordinates"));
                }
            }
        }
        if !data.is_empty() {
            doc.add(
                Path::new()
                    .set("fill", opts.fill.as_str())
                    .set("fill-rule", "evenodd")
                    .set("d", data),
            );
        }
    }
    doc.finish()
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
) -> ContourPath {
    if contour.segments.is_empty() {
        return ContourPath::Empty;
    }
    let pieces = drawing_pieces(contour, merged, bound);
    let finite = contour
        .segments
        .iter()
        .all(|s| s.curve.points.iter().all(|p| p.is_finite()))
        && pieces.iter().all(|(start, cubics)| {
            start.is_finite()
                && cubics
                    .iter()
                    .all(|c| c.points.iter().all(|p| p.is_finite()))
        });
    if !finite {
        return ContourPath::NonFinite;
    }
    let mut w = CompactPath::new(precision);
    let mut pen = w.grid(pieces[0].0);
    w.command('M');
    w.number(pen.0);
    w.number(pen.1);
    for (start, cubics) in &pieces {
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
    ContourPath::Data(w.finish())
}

/// True when a cubic draws a straight line from its start to its end: both inner control
/// points lie within `tolerance` of the chord and between its ends, so the curve (inside
/// the hull of its control points) stays within `tolerance` of the line drawn instead.
fn is_straight(c: &CubicBez, tolerance: f64) -> bool {
    let [p0, p1, p2, p3] = c.points;
    let chord = p3 - p0;
    let length = chord.length();
    if length <= tolerance {
        return false;
    }
    let u = chord * (1.0 / length);
    [p1, p2].iter().all(|&p| {
        let d = p - p0;
        let along = d.dot(u);
        d.cross(u).abs() <= tolerance && along >= -tolerance && along <= length + tolerance
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::curve::{approximate_with_cubics, RationalCubic};
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

    /// Path data as absolute (command, numbers) pairs: `M`, `L`, `C` and `Z`, read by
    /// the parser resvg uses.
    fn parse_path(d: &str) -> Vec<(char, Vec<f64>)> {
        use svgtypes::SimplePathSegment as S;
        svgtypes::SimplifyingPathParser::from(d)
            .map(|s| match s.unwrap() {
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
            .collect()
    }

    #[test]
    fn circle_path_has_every_coordinate_right() {
        let c = circle(Point::new(30.0, 20.0), 12.0, false, None);
        let svg = to_svg(&result(64, 48, vec![c.clone()]), &SvgOptions::default());
        let data = path_data(&svg);
        assert_eq!(data.len(), 1);
        let cmds = parse_path(&data[0]);
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
            &SvgOptions::default(),
        );
        assert!(svg.starts_with(
            "<svg height=\"64\" viewBox=\"0 0 64 64\" width=\"64\" xmlns=\"http://www.w3.org/2000/svg\">"
        ));
        assert!(svg.ends_with("</svg>\n"));
        let data = path_data(&svg);
        assert_eq!(data.len(), 2, "{svg}");
        assert_eq!(data[0].matches('M').count(), 2);
        assert_eq!(data[0].matches('z').count(), 2);
        assert_eq!(data[1].matches('M').count(), 1);
        assert_eq!(svg.matches("fill-rule=\"evenodd\"").count(), 2);
        assert!(!svg.contains("<!--"));
    }

    #[test]
    fn output_is_deterministic_and_respects_options() {
        let r = result(
            64,
            64,
            vec![circle(Point::new(32.123456, 31.987654), 20.0, false, None)],
        );
        let opts = SvgOptions {
            precision: 1,
            fill: "url(#a)\"<x>".to_string(),
            ..SvgOptions::default()
        };
        let a = to_svg(&r, &opts);
        assert_eq!(a, to_svg(&r, &opts));
        assert!(a.contains("fill=\"url(#a)&quot;&lt;x&gt;\""));
        for d in path_data(&a) {
            for (_, numbers) in parse_path(&d) {
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
            &SvgOptions::default(),
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
        let svg = to_svg(&result(64, 64, vec![c.clone()]), &SvgOptions::default());
        let cmds = parse_path(&path_data(&svg)[0]);
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
        assert_eq!(SvgOptions::for_tolerance(0.4).bound, 0.02);
        assert_eq!(SvgOptions::for_tolerance(0.01).bound, 0.005);
        assert_eq!(SvgOptions::for_tolerance(5.0).bound, 0.05);
        assert_eq!(SvgOptions::for_tolerance(f64::NAN).bound, 0.02);
        assert_eq!(SvgOptions::for_tolerance(-1.0), SvgOptions::default());
    }

    #[test]
    fn rendered_ring_has_the_right_area() {
        use resvg::{tiny_skia, usvg};
        let outer = circle(Point::new(32.0, 32.0), 25.0, false, None);
        let hole = circle(Point::new(32.0, 32.0), 10.0, true, Some(0));
        let svg = to_svg(&result(64, 64, vec![outer, hole]), &SvgOptions::default());
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
        let opts = SvgOptions::default();
        assert_eq!(opts.precision, 2);
        let svg = to_svg(&result(1000, 800, vec![c.clone()]), &opts);
        let cmds = parse_path(&path_data(&svg)[0]);
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
        let svg = to_svg(&result(64, 64, vec![c]), &SvgOptions::default());
        let d = &path_data(&svg)[0];
        assert_eq!(
            d, "M10 10h40c.1 9 .1 21 0 30l-37.5 3.25-2.5-33.25z",
            "{svg}"
        );
    }
}
