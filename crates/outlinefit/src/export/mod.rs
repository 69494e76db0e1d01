//! Writers for the traced outline.
//!
//! * [`svg`]: the outline itself as an SVG document, one filled path per shape (outer border
//!   plus its holes). SVG has no rational curves, so every rational segment is drawn as
//!   polynomial cubics within a small, configurable distance
//!   ([`crate::curve::approximate_with_cubics`]); joints that are G1 in the fit stay G1.
//! * [`page`]: the same drawing as a PDF page, Encapsulated PostScript or a PostScript
//!   page, sized in points from the options' dpi and scale.
//! * [`dxf`]: a DXF drawing for CAD, laser and CNC software, every rational segment as an
//!   exact NURBS spline (R2000), or closed polylines for R12.
//! * [`geojson`]: polygons with holes, flattened within the bound.
//! * [`overlay`]: a diagnostic picture in the manner of Fig. 4 of the harmony-search paper:
//!   the input image underneath, the fitted outline, the data points, the joints (corners
//!   and smooth joints told apart) and every control polygon.
//!
//! [`export`] picks the writer of a [`Format`]; every writer takes the same
//! [`ExportOptions`] (bound, precision, fill colour, stroke-only, [`Size`]). SVG and the
//! overlay use input pixel units (`viewBox="0 0 W H"`, x right, y down); the other formats
//! have y up with the origin at the image's bottom-left corner. Each returns the document;
//! writing it to disk is [`crate::io::write_atomic`]'s job. The JSON and CSV reports,
//! which keep the exact rational data, live elsewhere.

pub(crate) mod dxf;
pub(crate) mod geojson;
pub(crate) mod options;
pub(crate) mod overlay;
pub(crate) mod page;
pub(crate) mod shapes;
pub(crate) mod svg;

pub use dxf::LAYER as DXF_LAYER;
pub use geojson::to_geojson;
pub use options::{ExportOptions, Format, Rgb, Size, Unit, DEFAULT_DPI};
pub use overlay::{to_overlay_svg, OverlayOptions};
pub use page::{to_pdf, to_postscript};
pub use svg::to_svg;

use crate::error::{Error, Result};
use crate::trace::TraceResult;

/// Writes the outline in `format` with `opts`.
///
/// Errors: [`Error::InvalidOption`] when the size's dpi or scale is not a positive number,
/// or when DXF is asked for in points (DXF has no such unit); [`Error::InvalidInput`] when
/// the DXF writer cannot start a drawing (it needs a source of random bytes).
pub fn export(result: &TraceResult, format: Format, opts: &ExportOptions) -> Result<Vec<u8>> {
    opts.size.check().map_err(|message| Error::InvalidOption {
        name: "size",
        message,
    })?;
    Ok(match format {
        Format::Svg => to_svg(result, opts).into_bytes(),
        Format::Pdf => to_pdf(result, opts),
        Format::Eps => to_postscript(result, opts, false).into_bytes(),
        Format::Ps => to_postscript(result, opts, true).into_bytes(),
        Format::Dxf | Format::DxfR12 => dxf::to_dxf(result, opts, format == Format::DxfR12)
            .map_err(|e| match e {
                dxf::DxfError::Unit(unit) => Error::InvalidOption {
                    name: "unit",
                    message: format!("DXF has no unit `{unit}`; use px, mm, cm or in"),
                },
                dxf::DxfError::Write(message) => Error::InvalidInput {
                    what: "DXF output".to_string(),
                    message,
                },
            })?,
        Format::GeoJson => to_geojson(result, opts).into_bytes(),
    })
}
