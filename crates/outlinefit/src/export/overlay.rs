//! A diagnostic picture of a fit, in the manner of Fig. 4 of the harmony-search paper.
//!
//! Layers, bottom to top, each in its own `<g id="…">` so that a viewer (or a test) can pick
//! them apart:
//!
//! 1. `background`: the input image, embedded as a base64 PNG `<image>` at the image's own
//!    size, drawn with nearest-neighbour scaling so that pixels stay square when zoomed, and
//!    opacity 0.6 so that the marks on top stay readable on black shapes. The scaling is
//!    asked for twice: `image-rendering="optimizeSpeed"` (the SVG 1.1 attribute value, which
//!    resvg honours; it ignores `pixelated` in an attribute, as the specification says) and
//!    `style="image-rendering:pixelated"` (CSS, which browsers prefer);
//! 2. `control-polygons`: C0–C1–C2–C3 of every segment as thin grey lines, and
//!    `control-points`: hollow grey circles on the inner control points C1, C2 (C0 and C3
//!    are joints and get joint markers);
//! 3. `merged-envelopes` (only with `--merge`): the disk envelope of every merged curve as
//!    a translucent purple band, the error band its radii carry;
//! 4. `data-points`: the fitted data points (`FittedContour::points`) as small orange dots,
//!    drawn compactly as zero-length round-capped strokes (`M x y h0`);
//! 5. `outline`: the fitted outline, a thin green stroke without fill, drawn from the same
//!    cubic approximation as the main SVG. It lies over the dots (thinner than they are), so
//!    that it stays visible where dense data merge into a band;
//! 6. `smooth-joints` (blue circles) and `corners` (red squares), one marker per joint;
//! 7. `legend`, in the top-left corner.
//!
//! The viewBox is the image in pixel units, as in the main SVG. Marker sizes and line widths
//! are fixed fractions of the image's longer side (a "screen pixel" is 1/800 of it), and the
//! `width`/`height` attributes enlarge small images by a whole factor to about 800 screen
//! pixels, so a 64-px glyph and a 1024-px logo are both readable. On large images with dense
//! data the dots merge into a band around the outline.

use super::options::effective_bound;
use super::svg::{contour_path_data, pixel_document, ContourPath};
use crate::curve::wang_ball::envelope::envelope_band;
use crate::fit::JointKind;
use crate::geom::Point;
use crate::svg_writer::{
    comment, number, push_number, Circle, Group, Image, PathData, PathUnits, Rectangle, Text,
    MAX_PRECISION,
};
use crate::trace::TraceResult;
use base64::Engine as _;
use image::ImageEncoder as _;

type SvgPath = crate::svg_writer::Path;

/// Nominal size, in screen pixels, of the longer side of the picture.
pub(crate) const VIEW_SIDE: f64 = 800.0;

/// Fewest decimals of marker sizes and line widths, which are small numbers on small images
/// (one nominal screen pixel of an 8-px image is 0.01 px).
const SIZE_PRECISION: usize = 4;

const OUTLINE_COLOUR: &str = "#00a651";
const POINT_COLOUR: &str = "#ff7f0e";
const SMOOTH_COLOUR: &str = "#1f5fff";
const CORNER_COLOUR: &str = "#e00000";
const CONTROL_COLOUR: &str = "#808080";
const MERGED_COLOUR: &str = "#9467bd";

/// Samples along a merged curve for its envelope band.
const ENVELOPE_SAMPLES: usize = 120;

/// What [`to_overlay_svg`] draws.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayOptions {
    /// Largest distance, in pixels, between a rational segment and the cubics that draw the
    /// outline (as [`super::ExportOptions::bound`]). Default: 0.02.
    pub bound: f64,
    /// Decimals of every coordinate, at most 12. Default: 3.
    pub precision: usize,
    /// Multiplies every marker size and line width; non-positive or non-finite values count
    /// as 1. Default: 1.
    pub marker_scale: f64,
    /// Draw the data points. Default: true.
    pub show_points: bool,
    /// Draw the control polygons and inner control points. Default: true.
    pub show_control_polygons: bool,
    /// Draw the legend. Default: true.
    pub show_legend: bool,
}

impl Default for OverlayOptions {
    fn default() -> Self {
        OverlayOptions {
            bound: 0.02,
            precision: 3,
            marker_scale: 1.0,
            show_points: true,
            show_control_polygons: true,
            show_legend: true,
        }
    }
}

/// Draws the fit over the input image (see the module docs for the layers). `background`
/// is the image to show underneath, normally the bitmap's grey-level preview; it is
/// stretched to the traced image's size if it differs. `None` draws no background.
/// Deterministic: the same inputs give the same bytes.
pub fn to_overlay_svg(
    result: &TraceResult,
    background: Option<&image::GrayImage>,
    opts: &OverlayOptions,
) -> String {
    let (width, height) = (result.image.width, result.image.height);
    let side = f64::from(width.max(height).max(1));
    let zoom = (VIEW_SIDE / side).ceil().max(1.0) as u64;
    let scale = if opts.marker_scale.is_finite() && opts.marker_scale > 0.0 {
        opts.marker_scale
    } else {
        1.0
    };
    // One nominal screen pixel, in user units (image pixels).
    let unit = side / VIEW_SIDE * scale;
    let precision = opts.precision.min(MAX_PRECISION);
    let bound = effective_bound(opts.bound);
    let size = |x: f64| number(x, precision.max(SIZE_PRECISION));

    let mut doc = pixel_document(width, height, zoom);
    if let Some(img) = background {
        add_background(&mut doc, img, width, height, 0.6);
    }

    if opts.show_control_polygons {
        let mut polygons = Group::new()
            .set("id", "control-polygons")
            .set("fill", "none")
            .set("stroke", CONTROL_COLOUR)
            .set("stroke-width", size(0.75 * unit));
        for c in &result.contours {
            let mut d = PathData::new(precision);
            for s in &c.segments {
                let p = &s.curve.points;
                if p.iter().all(|q| q.is_finite()) {
                    d.polyline(p.iter().copied());
                }
            }
            if !d.is_empty() {
                polygons = polygons.add(SvgPath::new().set("d", d.finish()));
            }
        }
        doc.add(polygons);
        let mut points = Group::new()
            .set("id", "control-points")
            .set("fill", "none")
            .set("stroke", CONTROL_COLOUR)
            .set("stroke-width", size(0.6 * unit));
        let r = size(2.0 * unit);
        for s in result.contours.iter().flat_map(|c| &c.segments) {
            for &p in &s.curve.points[1..3] {
                if p.is_finite() {
                    points = points.add(circle(p, &r, precision));
                }
            }
        }
        doc.add(points);
    }

    let has_merged = result.merged.iter().any(|m| !m.is_empty());
    if has_merged {
        let mut bands = Group::new()
            .set("id", "merged-envelopes")
            .set("fill", MERGED_COLOUR)
            .set("fill-opacity", 0.25)
            .set("stroke", MERGED_COLOUR)
            .set("stroke-width", size(0.5 * unit));
        for m in result.merged.iter().flatten() {
            let Some(band) = envelope_band(&m.curve(), ENVELOPE_SAMPLES) else {
                continue;
            };
            let mut d = PathData::new(precision);
            d.polyline(band);
            d.close();
            bands = bands.add(SvgPath::new().set("d", d.finish()));
        }
        doc.add(bands);
    }

    if opts.show_points {
        let mut dots = Group::new()
            .set("id", "data-points")
            .set("fill", "none")
            .set("stroke", POINT_COLOUR)
            .set("stroke-width", size(3.5 * unit))
            .set("stroke-linecap", "round");
        for c in &result.contours {
            let mut d = PathData::new(precision);
            for &p in c.points.iter().filter(|p| p.is_finite()) {
                d.dot(p);
            }
            if !d.is_empty() {
                dots = dots.add(SvgPath::new().set("d", d.finish()));
            }
        }
        doc.add(dots);
    }

    let mut outline = Group::new()
        .set("id", "outline")
        .set("fill", "none")
        .set("stroke", OUTLINE_COLOUR)
        .set("stroke-width", size(1.5 * unit))
        .set("stroke-linejoin", "round");
    for (i, c) in result.contours.iter().enumerate() {
        match contour_path_data(c, result.merged_of(i), bound, precision, PathUnits::Picture) {
            ContourPath::Data(d) => outline = outline.add(SvgPath::new().set("d", d)),
            ContourPath::Empty => {}
            ContourPath::NonFinite => {
                outline = outline.add(comment(&format!(
                    "contour {i} skipped: non-finite coordinates"
                )));
            }
        }
    }
    doc.add(outline);

    let joints = || {
        result
            .contours
            .iter()
            .flat_map(|c| &c.joints)
            .filter(|j| j.position.is_finite())
    };
    let mut smooth = Group::new()
        .set("id", "smooth-joints")
        .set("fill", SMOOTH_COLOUR);
    let r = size(3.0 * unit);
    for j in joints().filter(|j| j.kind == JointKind::Smooth) {
        smooth = smooth.add(circle(j.position, &r, precision));
    }
    doc.add(smooth);
    let mut corners = Group::new().set("id", "corners").set("fill", CORNER_COLOUR);
    let half = 3.0 * unit;
    for j in joints().filter(|j| j.kind == JointKind::Corner) {
        corners = corners.add(square(j.position, half, precision));
    }
    doc.add(corners);

    if opts.show_legend {
        doc.add(legend(unit, opts, has_merged, precision));
    }
    doc.finish()
}

/// `<circle cx cy r/>` with a preformatted radius.
fn circle(p: Point, r: &str, precision: usize) -> Circle {
    Circle::new()
        .set("cx", number(p.x, precision))
        .set("cy", number(p.y, precision))
        .set("r", r)
}

/// An axis-aligned square of half side `half` centred on `p`.
fn square(p: Point, half: f64, precision: usize) -> Rectangle {
    let side = number(2.0 * half, precision.max(SIZE_PRECISION));
    Rectangle::new()
        .set("x", number(p.x - half, precision))
        .set("y", number(p.y - half, precision))
        .set("width", side.clone())
        .set("height", side)
}

/// The legend box in the top-left corner; its sample markers are outside the counted
/// marker groups.
fn legend(unit: f64, opts: &OverlayOptions, has_merged: bool, precision: usize) -> Group {
    let p = precision.max(SIZE_PRECISION);
    let n = |x: f64| number(x, p);
    let line_path = |from: Point, to_x: f64| {
        let mut d = String::from("M");
        crate::svg_writer::push_point(&mut d, from, p);
        d.push('H');
        push_number(&mut d, to_x, p);
        d
    };
    let mut entries: Vec<(&str, &str)> = vec![("line", "fitted outline")];
    if opts.show_points {
        entries.push(("dot", "data points"));
    }
    entries.push(("smooth", "smooth joint (G1)"));
    entries.push(("corner", "corner"));
    if opts.show_control_polygons {
        entries.push(("polygon", "control polygon"));
    }
    if has_merged {
        entries.push(("band", "merged curve's error band"));
    }
    let line = 16.0 * unit;
    let (x0, y0) = (4.0 * unit, 4.0 * unit);
    let mut g = Group::new()
        .set("id", "legend")
        .set("font-family", "sans-serif")
        .set("font-size", n(11.0 * unit))
        .add(
            Rectangle::new()
                .set("x", n(x0))
                .set("y", n(y0))
                .set("width", n(132.0 * unit))
                .set("height", n(line * entries.len() as f64 + 8.0 * unit))
                .set("fill", "#ffffff")
                .set("fill-opacity", 0.85)
                .set("stroke", CONTROL_COLOUR)
                .set("stroke-width", n(0.5 * unit)),
        );
    for (k, (kind, label)) in entries.iter().enumerate() {
        let cy = y0 + 4.0 * unit + line * (k as f64 + 0.5);
        let (sx, sx2) = (x0 + 6.0 * unit, x0 + 26.0 * unit);
        let mid = 0.5 * (sx + sx2);
        g = match *kind {
            "line" => g.add(
                SvgPath::new()
                    .set("d", line_path(Point::new(sx, cy), sx2))
                    .set("stroke", OUTLINE_COLOUR)
                    .set("stroke-width", n(1.5 * unit)),
            ),
            "dot" => {
                let mut d = PathData::new(p);
                d.dot(Point::new(mid, cy));
                g.add(
                    SvgPath::new()
                        .set("d", d.finish())
                        .set("stroke", POINT_COLOUR)
                        .set("stroke-width", n(3.5 * unit))
                        .set("stroke-linecap", "round"),
                )
            }
            "smooth" => {
                g.add(circle(Point::new(mid, cy), &n(3.0 * unit), p).set("fill", SMOOTH_COLOUR))
            }
            "corner" => {
                g.add(square(Point::new(mid, cy), 3.0 * unit, p).set("fill", CORNER_COLOUR))
            }
            "band" => g.add(
                Rectangle::new()
                    .set("x", n(sx))
                    .set("y", n(cy - 3.0 * unit))
                    .set("width", n(sx2 - sx))
                    .set("height", n(6.0 * unit))
                    .set("fill", MERGED_COLOUR)
                    .set("fill-opacity", 0.25)
                    .set("stroke", MERGED_COLOUR)
                    .set("stroke-width", n(0.5 * unit)),
            ),
            _ => g
                .add(
                    SvgPath::new()
                        .set("d", line_path(Point::new(sx, cy), sx2))
                        .set("stroke", CONTROL_COLOUR)
                        .set("stroke-width", n(0.75 * unit)),
                )
                .add(
                    circle(Point::new(mid, cy), &n(2.0 * unit), p)
                        .set("fill", "none")
                        .set("stroke", CONTROL_COLOUR)
                        .set("stroke-width", n(0.6 * unit)),
                ),
        };
        g = g.add(
            Text::new(*label)
                .set("x", n(x0 + 32.0 * unit))
                .set("y", n(cy + 4.0 * unit))
                .set("fill", "#000000"),
        );
    }
    g
}

/// Adds `img` as the picture's `background` layer, stretched to `width` × `height` (the
/// traced image's size) with its pixels kept sharp, or a comment saying why it is left out.
pub(crate) fn add_background(
    doc: &mut crate::svg_writer::Document,
    img: &image::GrayImage,
    width: u32,
    height: u32,
    opacity: f64,
) {
    match png_base64(img) {
        Ok(data) => doc.add(
            Image::new()
                .set("id", "background")
                .set("x", 0)
                .set("y", 0)
                .set("width", width)
                .set("height", height)
                .set("preserveAspectRatio", "none")
                .set("image-rendering", "optimizeSpeed")
                .set("style", "image-rendering:pixelated")
                .set("opacity", opacity)
                .set("href", format!("data:image/png;base64,{data}")),
        ),
        Err(e) => doc.comment(&format!("background image left out: {e}")),
    }
}

/// The image as a PNG, base64-encoded.
fn png_base64(img: &image::GrayImage) -> Result<String, image::ImageError> {
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png).write_image(
        img.as_raw(),
        img.width(),
        img.height(),
        image::ExtendedColorType::L8,
    )?;
    Ok(base64::engine::general_purpose::STANDARD.encode(&png))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::svg::tests::{circle, result};
    use crate::fit::JointKind;

    fn element_count(svg: &str, group: &str, element: &str) -> usize {
        let doc = roxmltree::Document::parse(svg).unwrap();
        let g = doc
            .descendants()
            .find(|n| n.attribute("id") == Some(group))
            .unwrap_or_else(|| panic!("no group {group}"));
        g.children().filter(|n| n.has_tag_name(element)).count()
    }

    fn sample() -> TraceResult {
        let mut outer = circle(Point::new(32.0, 32.0), 25.0, false, None);
        outer.joints[2].kind = JointKind::Corner;
        let hole = circle(Point::new(32.0, 32.0), 10.0, true, Some(0));
        result(64, 64, vec![outer, hole])
    }

    #[test]
    fn one_marker_per_joint_of_each_kind() {
        let r = sample();
        let corners = r
            .contours
            .iter()
            .flat_map(|c| &c.joints)
            .filter(|j| j.kind == JointKind::Corner)
            .count();
        let smooth = r
            .contours
            .iter()
            .flat_map(|c| &c.joints)
            .filter(|j| j.kind == JointKind::Smooth)
            .count();
        assert_eq!((corners, smooth), (3, 5));
        let svg = to_overlay_svg(&r, None, &OverlayOptions::default());
        assert_eq!(element_count(&svg, "corners", "rect"), corners);
        assert_eq!(element_count(&svg, "smooth-joints", "circle"), smooth);
        // Two inner control points per segment, one outline path per contour.
        assert_eq!(element_count(&svg, "control-points", "circle"), 16);
        assert_eq!(element_count(&svg, "outline", "path"), 2);
        assert_eq!(element_count(&svg, "data-points", "path"), 2);
        // Every data point is one dot.
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let dots: usize = doc
            .descendants()
            .find(|n| n.attribute("id") == Some("data-points"))
            .unwrap()
            .children()
            .filter_map(|n| n.attribute("d"))
            .map(|d| d.matches("h0").count())
            .sum();
        assert_eq!(dots, 32);
        assert!(!svg.contains("<image"));
        let root = doc.root_element();
        assert_eq!(root.attribute("viewBox"), Some("0 0 64 64"));
        assert_eq!(root.attribute("width"), Some("832"));
    }

    #[test]
    fn background_is_embedded_png_of_the_image() {
        let mut img = image::GrayImage::new(64, 64);
        img.put_pixel(3, 5, image::Luma([200]));
        let svg = to_overlay_svg(&sample(), Some(&img), &OverlayOptions::default());
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let node = doc.descendants().find(|n| n.has_tag_name("image")).unwrap();
        assert_eq!(node.attribute("image-rendering"), Some("optimizeSpeed"));
        assert_eq!(node.attribute("style"), Some("image-rendering:pixelated"));
        assert_eq!(
            (node.attribute("width"), node.attribute("height")),
            (Some("64"), Some("64"))
        );
        let href = node.attribute("href").unwrap();
        let b64 = href.strip_prefix("data:image/png;base64,").unwrap();
        let png = base64::engine::general_purpose::STANDARD
            .decode(b64)
            .unwrap();
        let back = image::load_from_memory(&png).unwrap().to_luma8();
        assert_eq!(back, img);
        // Rendered at 13×, the bright pixel stays a crisp 13-px square (no interpolation).
        use resvg::{tiny_skia, usvg};
        let opts = OverlayOptions {
            show_legend: false,
            show_points: false,
            show_control_polygons: false,
            ..OverlayOptions::default()
        };
        let svg = to_overlay_svg(&result(64, 64, vec![]), Some(&img), &opts);
        let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).unwrap();
        let mut pixmap = tiny_skia::Pixmap::new(832, 832).unwrap();
        resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
        let centre = pixmap.pixel(3 * 13 + 6, 5 * 13 + 6).unwrap();
        assert_eq!(pixmap.pixel(3 * 13 + 1, 5 * 13 + 1).unwrap(), centre);
        assert_eq!(pixmap.pixel(3 * 13 + 11, 5 * 13 + 11).unwrap(), centre);
        assert_ne!(pixmap.pixel(3 * 13 - 1, 5 * 13 + 6).unwrap(), centre);
        // 200 at opacity 0.6 (premultiplied): about 0.6 × 200 = 120.
        assert!((i32::from(centre.red()) - 120).abs() <= 2, "{centre:?}");
    }

    #[test]
    fn marker_sizes_follow_the_image_size() {
        let small = to_overlay_svg(&result(64, 64, vec![]), None, &OverlayOptions::default());
        let large = to_overlay_svg(&result(1024, 512, vec![]), None, &OverlayOptions::default());
        let stroke = |svg: &str| -> f64 {
            let doc = roxmltree::Document::parse(svg).unwrap();
            let g = doc
                .descendants()
                .find(|n| n.attribute("id") == Some("outline"))
                .unwrap();
            g.attribute("stroke-width").unwrap().parse().unwrap()
        };
        // 1.5 nominal screen pixels of an 800-px view in both cases.
        assert!((stroke(&small) - 1.5 * 64.0 / 800.0).abs() < 1e-9);
        assert!((stroke(&large) - 1.5 * 1024.0 / 800.0).abs() < 1e-9);
        let doc = roxmltree::Document::parse(&large).unwrap();
        let root = doc.root_element();
        assert_eq!(root.attribute("width"), Some("1024"));
        assert_eq!(root.attribute("height"), Some("512"));
        assert_eq!(root.attribute("viewBox"), Some("0 0 1024 512"));
    }

    #[test]
    fn renders_and_marks_land_where_expected() {
        use resvg::{tiny_skia, usvg};
        let mut r = sample();
        // Move one data point 0.5 px off the outline, radially.
        let centre = Point::new(32.0, 32.0);
        let p = r.contours[0].points[1];
        r.contours[0].points[1] = p + (p - centre).normalized().unwrap() * 0.5;
        let opts = OverlayOptions {
            show_legend: false,
            ..OverlayOptions::default()
        };
        let svg = to_overlay_svg(&r, None, &opts);
        assert_eq!(svg, to_overlay_svg(&r, None, &opts));
        let tree = usvg::Tree::from_str(&svg, &usvg::Options::default()).unwrap();
        let mut pixmap = tiny_skia::Pixmap::new(832, 832).unwrap();
        // The document's own size is 13 × 64 = 832 px, so no extra transform.
        resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
        let at = |p: Point| {
            pixmap
                .pixel((p.x * 13.0) as u32, (p.y * 13.0) as u32)
                .unwrap()
        };
        // The corner at joint 0 of the outer circle is red, a smooth joint is blue.
        let corner = at(r.contours[0].joints[0].position);
        assert!(corner.red() > 200 && corner.green() < 50, "{corner:?}");
        let smooth = at(r.contours[0].joints[1].position);
        assert!(smooth.blue() > 200 && smooth.red() < 80, "{smooth:?}");
        // Outside every mark the picture is transparent; the centre of the hole is empty.
        assert_eq!(at(Point::new(32.0, 32.0)).alpha(), 0);
        // A data point off the outline is an orange dot.
        let dot = at(r.contours[0].points[1]);
        assert!(
            dot.red() > 200 && dot.green() > 90 && dot.green() < 160,
            "{dot:?}"
        );
        // The outline between data points is green.
        let a = 3.0 * std::f64::consts::FRAC_PI_8 / 2.0 + 0.05;
        let on = at(Point::new(32.0, 32.0) + Point::new(a.cos(), a.sin()) * 25.0);
        assert!(on.green() > 100 && on.red() < 60, "{on:?}");
    }

    #[test]
    fn non_finite_data_does_not_break_the_document() {
        let mut r = sample();
        r.contours[0].points[0].x = f64::NAN;
        r.contours[0].joints[1].position.y = f64::INFINITY;
        r.contours[1].segments[0].curve.points[1].x = f64::NAN;
        let svg = to_overlay_svg(&r, None, &OverlayOptions::default());
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        assert!(svg.contains("<!-- contour 1 skipped: non-finite coordinates -->"));
        assert_eq!(element_count(&svg, "smooth-joints", "circle"), 4);
    }
}
