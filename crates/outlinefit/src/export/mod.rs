//! Writers for the traced outline.
//!
//! * [`svg`]: the outline itself as an SVG document, one filled path per shape (outer border
//!   plus its holes). SVG has no rational curves, so every rational segment is drawn as
//!   polynomial cubics within a small, configurable distance
//!   ([`crate::curve::approximate_with_cubics`]); joints that are G1 in the fit stay G1.
//! * [`overlay`]: a diagnostic picture in the manner of Fig. 4 of the harmony-search paper:
//!   the input image underneath, the fitted outline, the data points, the joints (corners
//!   and smooth joints told apart) and every control polygon.
//!
//! Both use input pixel units (`viewBox="0 0 W H"`, x right, y down) and return the
//! document as a `String`, written by `svg_writer`, the one SVG writer every picture of the
//! crate goes through (the `svg` crate for elements and escaping, numbers and path data
//! formatted here); writing it to disk is [`crate::io::write_atomic`]'s job. The
//! JSON and CSV reports, which keep the exact rational data, live elsewhere.

pub(crate) mod overlay;
pub(crate) mod svg;

pub use overlay::{to_overlay_svg, OverlayOptions};
pub use svg::{to_svg, SvgOptions};
