//! What every writer shares: the output format, its size and unit, the fill colour.

use crate::curve::approx::{drawing_bound, DEFAULT_DRAWING_BOUND};
use crate::svg_writer::{decimals_for, MAX_PRECISION};
use std::fmt;
use std::str::FromStr;

/// The file formats the outline can be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// SVG 1.1: one filled path per shape, rational segments as cubics within the bound.
    Svg,
    /// PDF 1.7: one page of the image's size, even-odd fill, rational segments as cubics.
    Pdf,
    /// Encapsulated PostScript (EPS 3.0), for placing in other documents.
    Eps,
    /// PostScript: a printable page of the image's size.
    Ps,
    /// DXF R2000 (AC1015): every rational segment as an exact NURBS `SPLINE`.
    Dxf,
    /// DXF R12 (AC1009), for older laser and CNC software: no splines, closed polylines
    /// within the bound.
    DxfR12,
    /// GeoJSON (RFC 7946): one polygon with its holes per shape, flattened within the
    /// bound.
    GeoJson,
}

impl Format {
    /// Every format, in the order `--help` lists them.
    pub const ALL: [Format; 7] = [
        Format::Svg,
        Format::Pdf,
        Format::Eps,
        Format::Ps,
        Format::Dxf,
        Format::DxfR12,
        Format::GeoJson,
    ];

    /// The format's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Pdf => "pdf",
            Format::Eps => "eps",
            Format::Ps => "ps",
            Format::Dxf => "dxf",
            Format::DxfR12 => "dxf-r12",
            Format::GeoJson => "geojson",
        }
    }

    /// The file ending written by default (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::DxfR12 => "dxf",
            other => other.name(),
        }
    }

    /// Whether a file ending (without the dot, any case) suits this format: its own, and
    /// `json` for GeoJSON.
    pub fn accepts_extension(self, ending: &str) -> bool {
        let ending = ending.to_ascii_lowercase();
        ending == self.extension() || (self == Format::GeoJson && ending == "json")
    }

    /// The format a file ending names on its own (`.json` does not: it is the report's).
    pub fn from_extension(ending: &str) -> Option<Format> {
        let ending = ending.to_ascii_lowercase();
        [
            Format::Svg,
            Format::Pdf,
            Format::Eps,
            Format::Ps,
            Format::Dxf,
            Format::GeoJson,
        ]
        .into_iter()
        .find(|f| f.extension() == ending)
    }

    /// The MIME type, for a caller that serves the bytes.
    pub fn mime_type(self) -> &'static str {
        match self {
            Format::Svg => "image/svg+xml",
            Format::Pdf => "application/pdf",
            Format::Eps | Format::Ps => "application/postscript",
            Format::Dxf | Format::DxfR12 => "image/vnd.dxf",
            Format::GeoJson => "application/geo+json",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Format {
    type Err = String;

    /// A format's name, or one of potrace's backend names for it (`postscript`, `dxf12`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim().to_ascii_lowercase();
        match s.as_str() {
            "postscript" => return Ok(Format::Ps),
            "dxf12" | "r12" => return Ok(Format::DxfR12),
            _ => {}
        }
        Format::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Format::ALL.iter().map(|f| f.name()).collect();
                format!(
                    "unknown format `{s}` (expected one of {})",
                    names.join(", ")
                )
            })
    }
}

/// A length unit of the written size.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Unit {
    /// Input pixels: the size is the image's, times the scale; no physical size.
    #[default]
    Px,
    /// PostScript points, 1/72 inch.
    Pt,
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Inches.
    In,
}

impl Unit {
    /// Every unit.
    pub const ALL: [Unit; 5] = [Unit::Px, Unit::Pt, Unit::Mm, Unit::Cm, Unit::In];

    /// The unit's name, as SVG and the command line write it.
    pub fn name(self) -> &'static str {
        match self {
            Unit::Px => "px",
            Unit::Pt => "pt",
            Unit::Mm => "mm",
            Unit::Cm => "cm",
            Unit::In => "in",
        }
    }

    /// How many of this unit make an inch; `None` for pixels, which have no physical size.
    pub fn per_inch(self) -> Option<f64> {
        match self {
            Unit::Px => None,
            Unit::Pt => Some(72.0),
            Unit::Mm => Some(25.4),
            Unit::Cm => Some(2.54),
            Unit::In => Some(1.0),
        }
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Unit {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim().to_ascii_lowercase();
        Unit::ALL
            .into_iter()
            .find(|u| u.name() == s)
            .ok_or_else(|| format!("unknown unit `{s}` (expected px, pt, mm, cm or in)"))
    }
}

/// How big the written outline is: `dpi` input pixels make an inch, the whole is
/// multiplied by `scale`, and lengths are given in `unit`.
///
/// PDF, EPS and PostScript always measure in points: a pixel is `72 / dpi × scale` pt
/// whatever the unit (at the default 72 dpi, one point per pixel, as potrace does). SVG
/// writes `width` and `height` in the unit (the `viewBox` stays in pixels); DXF and
/// GeoJSON write their coordinates in it. With [`Unit::Px`] the size is the pixel size
/// times the scale, and `dpi` has no effect on those three.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// Unit of the written lengths. Default: pixels.
    pub unit: Unit,
    /// Input pixels per inch. Default: 72.
    pub dpi: f64,
    /// Factor on the whole size. Default: 1.
    pub scale: f64,
}

impl Default for Size {
    fn default() -> Self {
        Size {
            unit: Unit::Px,
            dpi: DEFAULT_DPI,
            scale: 1.0,
        }
    }
}

/// Pixels per inch when none is given: potrace's, one point per pixel.
pub const DEFAULT_DPI: f64 = 72.0;

impl Size {
    /// Length in `unit` of one input pixel.
    pub fn per_pixel(&self, unit: Unit) -> f64 {
        match unit.per_inch() {
            None => self.scale,
            Some(per_inch) => per_inch / self.dpi * self.scale,
        }
    }

    /// Length in the size's own unit of one input pixel.
    pub fn unit_per_pixel(&self) -> f64 {
        self.per_pixel(self.unit)
    }

    /// Whether the size is usable: dpi and scale positive and finite; the message names
    /// the one that is not.
    pub fn check(&self) -> Result<(), String> {
        if !(self.dpi.is_finite() && self.dpi > 0.0) {
            return Err(format!("dpi must be a positive number, not {}", self.dpi));
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(format!(
                "scale must be a positive number, not {}",
                self.scale
            ));
        }
        Ok(())
    }
}

/// An sRGB colour, written `#rrggbb`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rgb(pub [u8; 3]);

impl Rgb {
    /// Black, the default fill.
    pub const BLACK: Rgb = Rgb([0, 0, 0]);

    /// The components in [0, 1], as PDF and PostScript take them.
    pub fn unit_components(self) -> [f64; 3] {
        self.0.map(|c| f64::from(c) / 255.0)
    }
}

impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [r, g, b] = self.0;
        write!(f, "#{r:02x}{g:02x}{b:02x}")
    }
}

impl FromStr for Rgb {
    type Err = String;

    /// `#rrggbb` or `#rgb` (the `#` may be left out, which saves quoting it in a shell).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let hex = s.trim().trim_start_matches('#');
        let bad = || format!("`{s}` is not a colour (expected #rrggbb or #rgb, hexadecimal)");
        if !hex.chars().all(|c| c.is_ascii_hexdigit()) {
            return Err(bad());
        }
        let digit = |k: usize| u8::from_str_radix(&hex[k..=k], 16).map_err(|_| bad());
        match hex.len() {
            6 => {
                let byte = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).map_err(|_| bad());
                Ok(Rgb([byte(0)?, byte(2)?, byte(4)?]))
            }
            3 => Ok(Rgb([digit(0)? * 17, digit(1)? * 17, digit(2)? * 17])),
            _ => Err(bad()),
        }
    }
}

/// How the outline is written, in every format.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportOptions {
    /// Largest distance, in pixels, between a rational segment and the polynomial cubics
    /// that draw it (SVG, PDF, EPS), or between the outline and its flattened polygon (DXF
    /// R12, GeoJSON: twice this at most, the cubics' bound plus the flattening's). DXF
    /// R2000 writes the rational segments exactly. Non-positive or non-finite values are
    /// replaced by the default. Default: 0.02.
    pub bound: f64,
    /// Decimals of every coordinate in pixels, at most [`MAX_PRECISION`]. Default: 2
    /// (0.01 px), the fewest whose rounding (half a unit) stays within half the default
    /// bound. Formats that write another unit keep the same resolution in it; SVG writes
    /// whole numbers of 10^-precision px, with its `viewBox` in the same unit.
    pub precision: usize,
    /// The fill colour. Default: black.
    pub fill: Rgb,
    /// Draw the outlines as thin lines without fill (cutting paths for lasers and
    /// plotters). DXF and GeoJSON have no fill and are the same either way.
    pub stroke_only: bool,
    /// Size and unit of the written outline.
    pub size: Size,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            bound: DEFAULT_DRAWING_BOUND,
            precision: precision_for(DEFAULT_DRAWING_BOUND),
            fill: Rgb::BLACK,
            stroke_only: false,
            size: Size::default(),
        }
    }
}

impl ExportOptions {
    /// Options matched to a fitting tolerance: the approximation bound of
    /// `drawing_bound` (a twentieth of the tolerance, clamped to [0.005, 0.05] px), and
    /// coordinates with the fewest decimals whose rounding stays within half the bound (2
    /// for tolerances from 0.2 px, 3 below). A non-positive or non-finite tolerance gives
    /// the defaults.
    pub fn for_tolerance(tolerance: f64) -> Self {
        let bound = drawing_bound(tolerance);
        ExportOptions {
            bound,
            precision: precision_for(bound),
            ..ExportOptions::default()
        }
    }

    /// The bound actually used: [`ExportOptions::bound`] if it is a positive number.
    pub(crate) fn effective_bound(&self) -> f64 {
        effective_bound(self.bound)
    }

    /// The precision actually used, at most [`MAX_PRECISION`].
    pub(crate) fn effective_precision(&self) -> usize {
        self.precision.min(MAX_PRECISION)
    }

    /// Half the unit of the last decimal written, in pixels: what rounding may move a
    /// point, and so how close to its chord a cubic must be to be written as a line.
    pub(crate) fn half_unit(&self) -> f64 {
        0.5 * 10f64.powi(-(self.effective_precision() as i32))
    }

    /// Decimals of a coordinate written in `unit`: the pixel precision's resolution, in
    /// that unit.
    pub(crate) fn precision_in(&self, unit: Unit) -> usize {
        let pixel = 10f64.powi(-(self.effective_precision() as i32));
        decimals_for(pixel * self.size.per_pixel(unit))
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
        DEFAULT_DRAWING_BOUND
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_parse_and_print() {
        assert_eq!("#1a2B3c".parse::<Rgb>(), Ok(Rgb([0x1a, 0x2b, 0x3c])));
        assert_eq!("f80".parse::<Rgb>(), Ok(Rgb([0xff, 0x88, 0x00])));
        assert_eq!(Rgb([0x1a, 0x2b, 0x3c]).to_string(), "#1a2b3c");
        for bad in ["", "#12345", "#ggg", "red", "#+12345", "#1234567"] {
            assert!(bad.parse::<Rgb>().is_err(), "{bad}");
        }
    }

    #[test]
    fn sizes_convert_between_units() {
        let size = Size {
            unit: Unit::Mm,
            dpi: 300.0,
            scale: 2.0,
        };
        assert!((size.per_pixel(Unit::In) - 2.0 / 300.0).abs() < 1e-15);
        assert!((size.unit_per_pixel() - 2.0 * 25.4 / 300.0).abs() < 1e-15);
        assert!((size.per_pixel(Unit::Pt) - 2.0 * 72.0 / 300.0).abs() < 1e-15);
        assert_eq!(size.per_pixel(Unit::Px), 2.0);
        assert_eq!(Size::default().per_pixel(Unit::Pt), 1.0);
        assert!(Size { dpi: 0.0, ..size }.check().is_err());
        assert!(Size {
            scale: f64::NAN,
            ..size
        }
        .check()
        .is_err());
    }

    #[test]
    fn formats_by_name_and_ending() {
        for f in Format::ALL {
            assert_eq!(f.name().parse::<Format>(), Ok(f));
            assert!(f.accepts_extension(&f.extension().to_uppercase()));
        }
        assert_eq!("postscript".parse::<Format>(), Ok(Format::Ps));
        assert_eq!(Format::from_extension("DXF"), Some(Format::Dxf));
        assert_eq!(Format::from_extension("json"), None);
        assert!(Format::GeoJson.accepts_extension("json"));
        assert!("png".parse::<Format>().is_err());
    }
}
