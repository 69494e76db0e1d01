//! A colour trace as a printed page (PDF, EPS, PostScript) and the choice of format: the
//! layers in drawing order, each set in its colour and filled even-odd (stroked with
//! `--stroke-only`), from the same cubics the SVG writes and with the page geometry of
//! one-colour pages. These formats have no opacity here: a translucent colour is drawn
//! opaque, with a comment saying so.

use super::result::ColourTrace;
use super::svg::{colour_svg, loop_pieces};
use crate::error::{Error, Result};
use crate::export::options::{ExportOptions, Format};
use crate::export::page::{pdf_page, postscript_page, push_loop};
use crate::export::shapes::{is_straight, Cmd};
use crate::svg_writer::number;

/// The page's operators: per layer its colour (`fill_op` or `stroke_op` with `width_op`),
/// its loops, and the paint.
fn body(trace: &ColourTrace, opts: &ExportOptions, ops: [&str; 3]) -> String {
    let [fill_op, stroke_op, width_op] = ops;
    let precision = opts.effective_precision();
    let bound = opts.effective_bound();
    let straight = opts.half_unit();
    let n = |x: f64| number(x, 4);
    let mut out = String::new();
    if opts.stroke_only {
        out.push_str(&format!(
            "{} {width_op}\n",
            number(crate::export::svg::STROKE_WIDTH, 3)
        ));
    }
    for layer in &trace.layers {
        let swatch = &trace.palette[layer.colour];
        let mut path = String::new();
        for lp in &layer.loops {
            for (start, cubics) in loop_pieces(trace, lp, bound) {
                if !cubics
                    .iter()
                    .all(|c| c.points.iter().all(|p| p.is_finite()))
                {
                    out.push_str(&format!(
                        "% a loop of colour {} skipped: non-finite coordinates\n",
                        swatch.hex()
                    ));
                    continue;
                }
                let cmds: Vec<Cmd> = cubics
                    .iter()
                    .map(|c| {
                        if is_straight(c, straight) {
                            Cmd::Line(c.points[3])
                        } else {
                            Cmd::Cubic([c.points[1], c.points[2], c.points[3]])
                        }
                    })
                    .collect();
                push_loop(&mut path, start, &cmds, precision);
            }
        }
        if path.is_empty() {
            continue;
        }
        if swatch.alpha < 255 {
            out.push_str(&format!(
                "% colour {} has opacity {} in the input; drawn opaque\n",
                swatch.hex(),
                number(f64::from(swatch.alpha) / 255.0, 3)
            ));
        }
        let [r, g, b] = swatch.rgb.map(|c| f64::from(c) / 255.0);
        let op = if opts.stroke_only { stroke_op } else { fill_op };
        out.push_str(&format!("{} {} {} {op}\n", n(r), n(g), n(b)));
        out.push_str(&path);
        out.push_str(if opts.stroke_only { "S\n" } else { "f*\n" });
    }
    out
}

/// Writes a colour trace as a one-page PDF.
pub fn colour_pdf(trace: &ColourTrace, opts: &ExportOptions) -> Vec<u8> {
    pdf_page(
        trace.width,
        trace.height,
        &body(trace, opts, ["rg", "RG", "w"]),
        opts,
    )
}

/// Writes a colour trace as EPS (`page = false`) or a PostScript page (`page = true`).
pub fn colour_postscript(trace: &ColourTrace, opts: &ExportOptions, page: bool) -> String {
    let ops = ["setrgbcolor", "setrgbcolor", "setlinewidth"];
    postscript_page(
        trace.width,
        trace.height,
        &body(trace, opts, ops),
        opts,
        page,
    )
}

/// Writes a colour trace in `format`: SVG, PDF, EPS or PostScript. The other formats hold
/// one colour and are refused with [`Error::InvalidOption`].
pub fn export_colour(trace: &ColourTrace, format: Format, opts: &ExportOptions) -> Result<Vec<u8>> {
    opts.size.check().map_err(|message| Error::InvalidOption {
        name: "size",
        message,
    })?;
    match format {
        Format::Svg => Ok(colour_svg(trace, opts).into_bytes()),
        Format::Pdf => Ok(colour_pdf(trace, opts)),
        Format::Eps => Ok(colour_postscript(trace, opts, false).into_bytes()),
        Format::Ps => Ok(colour_postscript(trace, opts, true).into_bytes()),
        other => Err(Error::InvalidOption {
            name: "format",
            message: format!(
                "colour tracing writes SVG, PDF, EPS or PostScript, not {}",
                other.name()
            ),
        }),
    }
}
