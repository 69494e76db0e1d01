//! The outline as a printed page: PDF, EPS and PostScript.
//!
//! The three share one drawing, written in the operators PDF defines (`m`, `l`, `c`, `h`,
//! `f*` for the even-odd fill, `S` for a stroke); the PostScript prolog defines the same
//! names, so the path text is identical in all three. Coordinates are input pixels, y
//! down, as in the SVG (same rounding, same cubics within the same bound); one transform
//! at the start of the page (`cm` in PDF, `concat` in PostScript) turns them into points
//! with y up: a pixel is `72 / dpi × scale` pt ([`super::Size`]), and the page is the
//! image's size. Each shape (an outer border with its holes) is one path, filled with the
//! even-odd rule, or stroked with a one-pixel line with `stroke_only`.
//!
//! PDF goes through `pdf-writer` (document structure, cross-reference table), its content
//! stream compressed with `miniz_oxide`'s deflate (both crates the `image` stack already
//! builds). PostScript is plain text, written here: DSC comments, a prolog, one page.

use super::options::{ExportOptions, Unit};
use super::shapes::{drawn_loop, holes_of, Cmd, Drawn};
use super::svg::STROKE_WIDTH;
use crate::geom::Point;
use crate::svg_writer::{number, push_point};
use crate::trace::TraceResult;
use pdf_writer::{Filter, Pdf, Rect, Ref};

/// The page: path operators in pixel coordinates, `% …` comments for what was left out.
fn drawing(result: &TraceResult, opts: &ExportOptions) -> String {
    let precision = opts.effective_precision();
    let bound = opts.effective_bound();
    let straight = opts.half_unit();
    let (holes, orphans) = holes_of(result);
    let mut out = String::new();
    for i in orphans {
        out.push_str(&format!(
            "% contour {i} skipped: a hole without an outer border\n"
        ));
    }
    let paint = if opts.stroke_only { "S" } else { "f*" };
    for (i, c) in result.contours.iter().enumerate() {
        if c.is_hole {
            continue;
        }
        let mut path = String::new();
        for k in std::iter::once(i).chain(holes[i].iter().copied()) {
            let l = match drawn_loop(&result.contours[k], result.merged_of(k), bound, straight) {
                Drawn::Loop(l) => l,
                Drawn::Empty => continue,
                Drawn::NonFinite => {
                    out.push_str(&format!("% contour {k} skipped: non-finite coordinates\n"));
                    continue;
                }
            };
            push_loop(&mut path, l.start, &l.cmds, precision);
        }
        if !path.is_empty() {
            out.push_str(&path);
            out.push_str(paint);
            out.push('\n');
        }
    }
    out
}

/// Appends one closed loop's path operators (`m`, `l`, `c`, `h`).
pub(crate) fn push_loop(path: &mut String, start: Point, cmds: &[Cmd], precision: usize) {
    push_point(path, start, precision);
    path.push_str(" m\n");
    for cmd in cmds {
        match cmd {
            Cmd::Line(p) => {
                push_point(path, *p, precision);
                path.push_str(" l\n");
            }
            Cmd::Cubic(points) => {
                for (j, p) in points.iter().enumerate() {
                    if j > 0 {
                        path.push(' ');
                    }
                    push_point(path, *p, precision);
                }
                path.push_str(" c\n");
            }
        }
    }
    path.push_str("h\n");
}

/// The page's size in points and the transform from pixels (y down) to points (y up):
/// `[k 0 0 -k 0 height]`.
fn geometry(width: u32, height: u32, opts: &ExportOptions) -> (f64, f64, [f64; 6]) {
    let k = opts.size.per_pixel(Unit::Pt);
    let (w, h) = (f64::from(width) * k, f64::from(height) * k);
    (w, h, [k, 0.0, 0.0, -k, 0.0, h])
}

/// The painting state before the paths: the colour, and the line width of a stroke.
fn state(opts: &ExportOptions, fill_op: &str, stroke_op: &str, width_op: &str) -> String {
    let [r, g, b] = opts.fill.unit_components();
    let n = |x: f64| number(x, 4);
    if opts.stroke_only {
        format!(
            "{} {} {} {stroke_op}\n{} {width_op}\n",
            n(r),
            n(g),
            n(b),
            number(STROKE_WIDTH, 3)
        )
    } else {
        format!("{} {} {} {fill_op}\n", n(r), n(g), n(b))
    }
}

/// Numbers of a transform or a size: points to a thousandth of a point would do for a
/// page, but a scale must keep enough digits for the far corner of a large image.
fn matrix_text(m: &[f64; 6]) -> String {
    m.iter()
        .map(|&x| number(x, 9))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes the outline as a one-page PDF (see the module docs).
pub fn to_pdf(result: &TraceResult, opts: &ExportOptions) -> Vec<u8> {
    let body = state(opts, "rg", "RG", "w") + &drawing(result, opts);
    pdf_page(result.image.width, result.image.height, &body, opts)
}

/// Writes the outline as Encapsulated PostScript (`page = false`: a bounding box to place
/// in another document) or as a PostScript page of the image's size (`page = true`).
pub fn to_postscript(result: &TraceResult, opts: &ExportOptions, page: bool) -> String {
    let body = state(opts, "setrgbcolor", "setrgbcolor", "setlinewidth") + &drawing(result, opts);
    postscript_page(result.image.width, result.image.height, &body, opts, page)
}

/// A one-page PDF of a `width` × `height` px image whose page content (in pixel
/// coordinates, y down) is `body`.
pub(crate) fn pdf_page(width: u32, height: u32, body: &str, opts: &ExportOptions) -> Vec<u8> {
    let (w, h, m) = geometry(width, height, opts);
    let mut content = format!("q\n{} cm\n", matrix_text(&m));
    content.push_str(body);
    content.push_str("Q\n");
    let compressed = miniz_oxide::deflate::compress_to_vec_zlib(content.as_bytes(), 6);

    let (catalog, tree, page, stream, info) = (
        Ref::new(1),
        Ref::new(2),
        Ref::new(3),
        Ref::new(4),
        Ref::new(5),
    );
    let mut pdf = Pdf::new();
    pdf.catalog(catalog).pages(tree);
    pdf.pages(tree).kids([page]).count(1);
    pdf.page(page)
        .parent(tree)
        .media_box(Rect::new(0.0, 0.0, w as f32, h as f32))
        .contents(stream);
    pdf.stream(stream, &compressed).filter(Filter::FlateDecode);
    pdf.document_info(info)
        .producer(pdf_writer::TextStr(concat!(
            "outlinefit ",
            env!("CARGO_PKG_VERSION")
        )));
    pdf.finish()
}

/// An EPS file or PostScript page (see [`to_postscript`]) of a `width` × `height` px image
/// whose page content is `body`.
pub(crate) fn postscript_page(
    width: u32,
    height: u32,
    body: &str,
    opts: &ExportOptions,
    page: bool,
) -> String {
    let (w, h, m) = geometry(width, height, opts);
    let mut out = String::new();
    out.push_str(if page {
        "%!PS-Adobe-3.0\n"
    } else {
        "%!PS-Adobe-3.0 EPSF-3.0\n"
    });
    out.push_str(concat!(
        "%%Creator: outlinefit ",
        env!("CARGO_PKG_VERSION"),
        "\n"
    ));
    let (ws, hs) = (number(w, 3), number(h, 3));
    out.push_str(&format!(
        "%%BoundingBox: 0 0 {} {}\n%%HiResBoundingBox: 0 0 {ws} {hs}\n",
        w.ceil(),
        h.ceil(),
    ));
    out.push_str("%%LanguageLevel: 2\n%%Pages: 1\n");
    if page {
        out.push_str(&format!("%%DocumentMedia: image {ws} {hs} 0 () ()\n"));
    }
    out.push_str("%%EndComments\n%%BeginProlog\n");
    out.push_str(
        "/m {moveto} bind def /l {lineto} bind def /c {curveto} bind def\n\
         /h {closepath} bind def /f* {eofill} bind def /S {stroke} bind def\n",
    );
    out.push_str("%%EndProlog\n");
    if page {
        out.push_str(&format!(
            "%%BeginSetup\n<< /PageSize [{ws} {hs}] >> setpagedevice\n%%EndSetup\n"
        ));
    }
    out.push_str("%%Page: 1 1\ngsave\n");
    out.push_str(&format!("[{}] concat\n", matrix_text(&m)));
    out.push_str(body);
    out.push_str("grestore\nshowpage\n%%Trailer\n%%EOF\n");
    out
}
