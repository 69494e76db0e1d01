//! What the outline is written as: the format (by option or by the output's ending), its
//! size and unit, its colour; shared by `trace` and `batch`.

use anyhow::bail;
use clap::Args;
use outlinefit::{ExportOptions, Format, Rgb, Size, Unit, DEFAULT_DPI};
use std::path::Path;

/// Options of the written outline.
#[derive(Args, Debug, Clone)]
pub(crate) struct FormatArgs {
    /// Output format: svg, pdf, eps, ps, dxf, dxf-r12, geojson [default: from -o's ending, else svg].
    ///
    /// svg, pdf, eps, ps (a PostScript page), dxf (R2000, every curve an exact spline),
    /// dxf-r12 (closed polylines, for older laser and CNC software) or geojson (polygons
    /// with holes). Default: the one -o's file ending names, else svg. [potrace:
    /// -b/--backend]
    #[arg(
        long,
        short = 'b',
        visible_alias = "backend",
        value_name = "FORMAT",
        value_parser = parse_format,
        help_heading = "Output"
    )]
    pub(crate) format: Option<Format>,
    /// Pixels per inch of the input, for sizes in physical units: a PDF, EPS or PostScript
    /// page is W × 72/DPI points wide (72: a point per pixel), and --unit mm, cm, in or pt
    /// converts pixels with it. [potrace: -r/--resolution]
    #[arg(
        long,
        short = 'r',
        visible_alias = "resolution",
        value_name = "DPI",
        allow_negative_numbers = true,
        help_heading = "Output",
        hide_short_help = true
    )]
    pub(crate) dpi: Option<f64>,
    /// Unit of the written size: px (the image's pixels), pt, mm, cm or in. SVG writes its
    /// width and height in it (the viewBox stays in pixels), DXF and GeoJSON their
    /// coordinates; PDF and PostScript always measure in points.
    #[arg(
        long,
        value_name = "UNIT",
        default_value = "px",
        value_parser = parse_unit,
        help_heading = "Output",
        hide_short_help = true
    )]
    pub(crate) unit: Unit,
    /// Multiply the written size by this factor (every format). [potrace: -x/--scale]
    #[arg(
        long,
        short = 'x',
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true,
        help_heading = "Output",
        hide_short_help = true
    )]
    pub(crate) scale: f64,
    /// Fill colour, #rrggbb or #rgb.
    ///
    /// Fill colour of the outline, #rrggbb or #rgb (the line colour with --stroke-only;
    /// the `#` may be left out). [potrace: -C/--color]
    #[arg(
        long = "color",
        short = 'C',
        visible_alias = "colour",
        value_name = "#RRGGBB",
        default_value = "#000000",
        value_parser = parse_colour,
        help_heading = "Output"
    )]
    pub(crate) color: Rgb,
    /// Draw the outlines as thin lines without fill: cutting paths for lasers, vinyl
    /// cutters and plotters (SVG, PDF, EPS; DXF and GeoJSON have no fill anyway).
    #[arg(long, help_heading = "Output", hide_short_help = true)]
    pub(crate) stroke_only: bool,
}

fn parse_format(s: &str) -> Result<Format, String> {
    s.parse()
}

fn parse_unit(s: &str) -> Result<Unit, String> {
    s.parse()
}

fn parse_colour(s: &str) -> Result<Rgb, String> {
    s.parse()
}

impl FormatArgs {
    /// The writing options for a fit at `tolerance`; fails on a size that is not a
    /// positive number, or a unit the format has none of.
    pub(crate) fn options(&self, tolerance: f64, format: Format) -> anyhow::Result<ExportOptions> {
        let size = Size {
            unit: self.unit,
            dpi: self.dpi.unwrap_or(DEFAULT_DPI),
            scale: self.scale,
        };
        size.check()
            .map_err(|message| anyhow::anyhow!("--{message}"))?;
        if matches!(format, Format::Dxf | Format::DxfR12) && self.unit == Unit::Pt {
            bail!("--unit pt: DXF has no point unit; use px, mm, cm or in");
        }
        Ok(ExportOptions {
            fill: self.color,
            stroke_only: self.stroke_only,
            size,
            ..ExportOptions::for_tolerance(tolerance)
        })
    }

    /// A note for what has no effect: --dpi with sizes in pixels for a format measured in
    /// them.
    pub(crate) fn note(&self, format: Format) -> Option<String> {
        let pages = matches!(format, Format::Pdf | Format::Eps | Format::Ps);
        (self.dpi.is_some() && self.unit == Unit::Px && !pages).then(|| {
            format!(
                "note: --dpi has no effect on {} with --unit px (give --unit mm, cm, in or pt for a physical size)",
                format.name().to_uppercase()
            )
        })
    }

    /// The format of the outline written to `output` (`None`: the default name):
    /// --format, or the format its ending names, else SVG. Refuses an ending that names
    /// another format than --format, or a format not written.
    pub(crate) fn format_for(&self, output: Option<&Path>) -> anyhow::Result<Format> {
        let ending = output
            .filter(|p| !super::output::is_dash(p))
            .and_then(|p| p.extension())
            .map(|e| e.to_string_lossy().to_lowercase());
        let shown = || output.map_or(String::new(), |p| p.display().to_string());
        match (self.format, ending) {
            (Some(f), Some(e)) if !f.accepts_extension(&e) && is_known_ending(&e) => bail!(
                "-o {}: --format {f} writes {}, not {}; name the file .{} or change --format",
                shown(),
                f.name().to_uppercase(),
                e.to_uppercase(),
                f.extension()
            ),
            (Some(f), _) => Ok(f),
            (None, Some(e)) => match Format::from_extension(&e) {
                Some(f) => Ok(f),
                None if is_known_ending(&e) => bail!(
                    "-o {}: {} is not an output format (formats: {}; choose one with --format)",
                    shown(),
                    e.to_uppercase(),
                    format_names()
                ),
                None => Ok(Format::Svg),
            },
            (None, None) => Ok(Format::Svg),
        }
    }
}

/// Every format's name, for messages.
pub(crate) fn format_names() -> String {
    Format::ALL
        .iter()
        .map(|f| f.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// File endings of formats people may ask for by name; an output named with one of them
/// must be the format its option writes.
const KNOWN_ENDINGS: &[&str] = &[
    "svg", "svgz", "pdf", "eps", "ps", "ai", "dxf", "emf", "wmf", "json", "geojson", "csv", "tsv",
    "txt", "html", "png", "jpg", "jpeg", "gif", "bmp", "tif", "tiff", "webp", "pbm", "pgm", "ppm",
    "pnm", "ico", "avif", "qoi", "tga", "exr", "hdr",
];

/// Whether an ending (lower case) names a format people may ask for.
pub(crate) fn is_known_ending(ending: &str) -> bool {
    KNOWN_ENDINGS.contains(&ending)
}
