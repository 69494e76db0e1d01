//! Loading images into a foreground *coverage field*: the first stage of the pipeline.
//!
//! This module owns everything between an image file and a [`Bitmap`]: decoding (the
//! `decode` file: any format the `image` crate reads, recognised by content rather than by
//! file name, within the size and memory limits; a large 8-bit grey PNG is inflated on
//! one core while a second undoes its rows' filters and its histogram is counted,
//! `grey_png`), the choice between the alpha channel and
//! the luminance as the shape, polarity (`invert`), the threshold (fixed or Otsu's) and
//! two facts the later stages need: whether the image is *bilevel* (no grey levels at its
//! edges, so sub-pixel refinement cannot work) and whether its border is mostly foreground
//! (the polarity is probably wrong).
//!
//! Coverage is a number per pixel in [0, 1]: 1 is foreground (ink), 0 background (paper).
//!
//! * When at least a tenth of the pixels are mostly transparent (alpha below one half:
//!   a logo or silhouette on a transparent background), the shape **is** the alpha:
//!   coverage = alpha ([`AlphaRule`]; an opaque picture with a few transparent pixels or
//!   rounded transparent corners traces its luminance). Colour is ignored, so a white
//!   logo on a transparent background traces the same as a black one (the tempting
//!   alpha × (1 − luma) would make white logos vanish). `invert` then traces the
//!   transparent part.
//! * Otherwise coverage = 1 − luma (Rec. 601 for colour images; dark shapes on a light background), and `invert` makes it
//!   luma (light shapes on dark).
//!
//! Conversion goes through 32-bit floats, so 16-bit images keep their precision. The
//! bitmap stores a level per pixel, not the float (`levels`): 8-bit grey images keep their
//! bytes, 16-bit grey images their 16-bit values, and everything else is quantised to 16
//! bits (within 7.7 × 10⁻⁶ of the float), so a large image costs one or two bytes per
//! pixel.
//!
//! The threshold (foreground ⇔ coverage ≥ threshold) only decides the *topology* of the
//! outlines; where the image has grey levels, `contour` places the edges by integrating the
//! coverage, which does not depend on the threshold. Otsu's level is computed on a
//! 256-bin histogram and clamped to [0.2, 0.8]: for an anti-aliased (area-coverage) image the
//! true edge is at 0.5 and Otsu's level can wander far from it when the histogram is almost
//! all 0s and 1s, and a nearly empty image gives a meaningless level. When several levels are
//! equally good (a bilevel image has a whole empty range between its two levels) the middle
//! of that range is taken, so a 0/255 image gets exactly 0.5.

use crate::error::{Error, Result};
use crate::geom::Point;
use image::{DynamicImage, GenericImageView, GrayImage};
pub(crate) use levels::Classes;
use levels::Levels;
use std::borrow::Cow;
use std::path::Path;

pub(crate) mod bits;
mod decode;
pub(crate) mod frames;
mod grey_png;
mod levels;
mod lighting;

use decode::{check_dimensions, decode_counted_png, open_image, Opened};
pub(crate) use decode::{decode_bytes, decode_file};
pub use lighting::ThresholdMode;

/// Rec. 601 luma weights of red, green and blue.
const REC601: [f32; 3] = [0.299, 0.587, 0.114];
/// Lowest threshold Otsu's method may choose, on the [0, 1] coverage scale.
const OTSU_MIN: f64 = 0.2;
/// Highest threshold Otsu's method may choose, on the [0, 1] coverage scale.
const OTSU_MAX: f64 = 0.8;
/// Coverage strictly between `GREY_LO` and `GREY_HI` counts as a grey level.
const GREY_LO: f32 = 0.05;
/// See [`GREY_LO`].
const GREY_HI: f32 = 0.95;
/// An image is bilevel when fewer than this fraction of its edge pixels are grey.
const BILEVEL_GREY_FRACTION: f64 = 0.05;

/// Options for turning an image into foreground coverage.
#[derive(Clone, Debug)]
pub struct RasterOptions {
    /// Fixed threshold on the 0–255 scale of what is traced ([`ThresholdScale`]): with
    /// luminance, pixels darker than it are the shape; with `invert`, lighter ones; with
    /// alpha, more opaque ones. Default: `None`, Otsu's level (clamped to [0.2, 0.8] of
    /// the coverage).
    pub threshold: Option<u8>,
    /// Whether the alpha channel or the luminance is the shape. Default:
    /// [`AlphaRule::Auto`].
    pub alpha: AlphaRule,
    /// Trace light shapes on a dark background (or, with alpha, the transparent part).
    /// Default: false.
    pub invert: bool,
    /// Largest accepted width × height, checked from the file header before any pixel is
    /// decoded. Default (in [`crate::Config`]): 50 000 000.
    pub max_pixels: u64,
    /// Which frame of an animation (GIF, APNG, WebP) or page of a TIFF file to trace,
    /// from 0. Default: 0.
    pub frame: u32,
    /// One threshold for the whole image, or uneven lighting divided out first (see
    /// [`ThresholdMode`]); images traced from their alpha channel always use one.
    /// Default: [`ThresholdMode::Auto`].
    pub threshold_mode: ThresholdMode,
}

impl RasterOptions {
    /// What decoding needs of these options.
    pub(crate) fn decoding(&self) -> decode::Request {
        decode::Request {
            max_pixels: self.max_pixels,
            frame: self.frame,
        }
    }
}

/// What the threshold is compared with, as a user sees the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ThresholdScale {
    /// Luminance 0–255 (Rec. 601): pixels darker than the threshold are the shape.
    Luminance,
    /// Luminance with `invert`: pixels lighter than the threshold are the shape.
    InvertedLuminance,
    /// Alpha 0–255: pixels more opaque than the threshold are the shape.
    Alpha,
    /// Alpha with `invert`: pixels more transparent than the threshold are the shape.
    InvertedAlpha,
    /// The coverage itself, scaled to 0–255 ([`Bitmap::from_coverage`]): coverage at or
    /// above the threshold is the shape.
    Coverage,
}

impl ThresholdScale {
    /// True when values below the threshold are the shape.
    fn below_is_shape(self) -> bool {
        matches!(
            self,
            ThresholdScale::Luminance | ThresholdScale::InvertedAlpha
        )
    }

    /// The coverage threshold (foreground ⇔ coverage ≥ it) of a threshold `t` on this
    /// scale. Half a level separates the two sides, so that on 8-bit values "darker than
    /// t" is exact.
    pub fn coverage_threshold(self, t: f64) -> f64 {
        let c = match self {
            ThresholdScale::Coverage => t / 255.0,
            _ if self.below_is_shape() => 1.0 - (t - 0.5) / 255.0,
            _ => (t + 0.5) / 255.0,
        };
        c.clamp(0.0, 1.0)
    }

    /// The threshold on this scale of a coverage threshold `c`: the exact boundary, so
    /// that the shape is what lies beyond it (`--threshold 100` on luminance gives 99.5:
    /// luminance 99 and darker is the shape, 100 is not).
    pub fn value_of(self, c: f64) -> f64 {
        match self {
            ThresholdScale::Coverage => 255.0 * c,
            _ if self.below_is_shape() => 255.0 * (1.0 - c),
            _ => 255.0 * c,
        }
    }

    /// A short description for messages, e.g. "luminance below 136.0".
    pub fn describe(self, value: f64) -> String {
        match self {
            ThresholdScale::Luminance => format!("luminance below {value:.1}"),
            ThresholdScale::InvertedLuminance => format!("luminance above {value:.1}"),
            ThresholdScale::Alpha => format!("alpha above {value:.1}"),
            ThresholdScale::InvertedAlpha => format!("alpha below {value:.1}"),
            ThresholdScale::Coverage => format!("coverage at least {value:.1}/255"),
        }
    }
}

/// Foreground coverage of an image, with the threshold and the facts detected about it.
///
/// Construct it with `load`, `from_image` or [`Bitmap::from_coverage`].
#[derive(Clone, Debug)]
pub struct Bitmap {
    /// Width in pixels.
    width: u32,
    /// Height in pixels.
    height: u32,
    /// Row-major coverage, 1.0 = foreground, 0.0 = background.
    coverage: Levels,
    /// Foreground ⇔ coverage ≥ threshold; in [0, 1].
    threshold: f64,
    /// True when (almost) no edge pixel has a grey level.
    bilevel: bool,
    /// True when the coverage is the alpha channel.
    from_alpha: bool,
    /// What the threshold is compared with, as the user sees the image.
    scale: ThresholdScale,
    /// Share of the outermost ring of pixels that is foreground.
    border_foreground: f64,
    /// Fraction of the pixels that are mostly transparent (alpha below one half).
    transparent: f64,
    /// The frame or page traced, from 0.
    frame: u32,
    /// How many frames or pages the file has (1 for a still image or a coverage field).
    frames: u32,
    /// True when the paper's level was divided out before thresholding.
    local_threshold: bool,
    /// The thresholded pixels, made with the bitmap, until the border scan takes them.
    padded: PaddedBits,
}

/// The foreground bits of a [`Bitmap`] (see [`bits::padded_foreground`]), taken once: a
/// copy of the bitmap starts without them, and whoever needs them then makes them.
#[derive(Default)]
struct PaddedBits(std::sync::Mutex<Option<bits::Bits>>);

impl Clone for PaddedBits {
    fn clone(&self) -> Self {
        PaddedBits::default()
    }
}

impl std::fmt::Debug for PaddedBits {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PaddedBits")
    }
}

/// The pixel cell (its top-left pixel) of the last sample of [`Bitmap::sample_in`] and
/// the coverages of its four pixels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cell {
    at: (i64, i64),
    values: [f32; 4],
}

impl Cell {
    /// No cell read yet (no sample lands in cell (i64::MIN, i64::MIN)).
    pub(crate) const NONE: Cell = Cell {
        at: (i64::MIN, i64::MIN),
        values: [0.0; 4],
    };
}

impl Bitmap {
    /// Turns a decoded image into a [`Bitmap`] (see the module docs for the coverage rules).
    ///
    /// Errors: [`Error::ZeroSize`], [`Error::TooLarge`] (against `opts.max_pixels`),
    /// [`Error::InvalidOption`] for [`AlphaRule::Alpha`] on an image without alpha.
    pub fn from_image(img: &DynamicImage, opts: &RasterOptions) -> Result<Bitmap> {
        from_image(img, opts)
    }

    /// Loads an image file into a [`Bitmap`]; see [`Bitmap::load_bytes`].
    ///
    /// Errors: [`Error::Read`] when the file cannot be opened or read, and those of
    /// [`Bitmap::load_bytes`].
    pub fn load(path: &Path, opts: &RasterOptions) -> Result<Bitmap> {
        load(path, opts)
    }

    /// Decodes an encoded image (`name` names it in errors) into a [`Bitmap`].
    ///
    /// The format is recognised from the content, not the name. The dimensions are read from
    /// the header and checked before any pixel is decoded, and the decoder's memory is capped
    /// in proportion to `opts.max_pixels`, so a hostile header cannot make it allocate much
    /// more than an accepted image would need. The EXIF orientation (JPEG, PNG, TIFF, WebP) is
    /// applied as image viewers do, so a phone photo is traced upright. Animated GIF, PNG and
    /// WebP files and multi-page TIFF files give frame `opts.frame`. A JPEG without its end-of-image marker is
    /// refused as truncated: its decoder fills the missing rows silently.
    ///
    /// Errors: [`Error::Decode`] when the bytes are not a supported image or are truncated or
    /// corrupt; [`Error::Unsupported`] for a TIFF pixel layout that is not read;
    /// [`Error::InvalidOption`] for a frame past the last; [`Error::ZeroSize`];
    /// [`Error::TooLarge`].
    pub fn load_bytes(bytes: &[u8], name: &Path, opts: &RasterOptions) -> Result<Bitmap> {
        load_bytes(bytes, name, opts)
    }

    /// Builds a bitmap from a row-major coverage field (1 = foreground, 0 = background).
    ///
    /// Values are clamped to [0, 1], NaN counts as background, and each is stored to 16
    /// bits (within 7.7 × 10⁻⁶; 0 and 1 exactly). `threshold` is on the
    /// [0, 1] scale; `None` chooses Otsu's level (see the module docs). Detects
    /// [`is_bilevel`](Self::is_bilevel) and [`dark_border`](Self::dark_border).
    ///
    /// Errors: [`Error::ZeroSize`] when a dimension is 0; [`Error::InvalidOption`] when the
    /// length of `coverage` is not `width × height` or the threshold is outside [0, 1].
    pub fn from_coverage(
        width: u32,
        height: u32,
        coverage: Vec<f32>,
        threshold: Option<f64>,
    ) -> Result<Bitmap> {
        Bitmap::build(
            width,
            height,
            Levels::quantised(coverage.into_iter().map(levels::quantise).collect()),
            threshold,
            false,
        )
    }

    fn build(
        width: u32,
        height: u32,
        coverage: Levels,
        threshold: Option<f64>,
        from_alpha: bool,
    ) -> Result<Bitmap> {
        if width == 0 || height == 0 {
            return Err(Error::ZeroSize { width, height });
        }
        let expected = u64::from(width) * u64::from(height);
        if coverage.len() as u64 != expected {
            return Err(Error::InvalidOption {
                name: "coverage",
                message: format!(
                    "{} values given for a {width}×{height} image ({expected} expected)",
                    coverage.len()
                ),
            });
        }
        if let Some(t) = threshold {
            if !(0.0..=1.0).contains(&t) {
                return Err(Error::InvalidOption {
                    name: "threshold",
                    message: format!("{t} is outside [0, 1]"),
                });
            }
        }
        let threshold = threshold.unwrap_or_else(|| otsu_threshold(&coverage, None));
        let mut bitmap = Bitmap {
            width,
            height,
            coverage,
            threshold,
            bilevel: false,
            from_alpha,
            scale: ThresholdScale::Coverage,
            border_foreground: 0.0,
            transparent: 0.0,
            frame: 0,
            frames: 1,
            local_threshold: false,
            padded: PaddedBits::default(),
        };
        let foreground = bitmap.padded_foreground();
        bitmap.bilevel = bitmap.detect_bilevel(&foreground);
        bitmap.padded = PaddedBits(std::sync::Mutex::new(Some(foreground)));
        bitmap.border_foreground = bitmap.measure_border();
        Ok(bitmap)
    }

    /// The thresholded pixels in the border scan's padded layout, made with the bitmap;
    /// `None` once taken (or in a copy of the bitmap).
    pub(crate) fn take_padded_foreground(&self) -> Option<bits::Bits> {
        self.padded.0.lock().ok()?.take()
    }

    /// The thresholded pixels in the border scan's padded layout, made anew.
    pub(crate) fn padded_foreground(&self) -> bits::Bits {
        let t = self.threshold;
        let classes = self.level_classes(|v| u8::from(f64::from(v) >= t));
        let read_row = |r: usize, out: &mut [u8]| self.read_row_classes(r, 0, &classes, out);
        bits::padded_foreground(self.width as usize, self.height as usize, &read_row)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// A copy of the row-major coverage values, `width × height` of them (4 bytes per
    /// pixel; the bitmap itself stores one or two).
    pub fn to_coverage(&self) -> Vec<f32> {
        let mut out = vec![0.0; self.coverage.len()];
        self.coverage.read(0, &mut out);
        out
    }

    /// A class (a byte) for every coverage level of the image: `class` of that level's
    /// coverage (see [`Bitmap::read_row_classes`]).
    pub(crate) fn level_classes(&self, class: impl Fn(f32) -> u8) -> Classes {
        self.coverage.classes(class)
    }

    /// The classes of row `row`'s pixels from column `col` on, from a table made by
    /// [`Bitmap::level_classes`], written to `out` (at most `width − col` values; zeros
    /// past the image's end). A pixel's class is exactly `class` of its coverage.
    pub(crate) fn read_row_classes(
        &self,
        row: usize,
        col: usize,
        classes: &Classes,
        out: &mut [u8],
    ) {
        debug_assert!(col + out.len() <= self.width as usize);
        self.coverage
            .read_classes(row * self.width as usize + col, classes, out);
    }

    /// Coverage of pixel (col, row); 0 outside the image.
    #[inline]
    pub fn coverage_at(&self, col: i64, row: i64) -> f32 {
        if col < 0 || row < 0 || col >= i64::from(self.width) || row >= i64::from(self.height) {
            return 0.0;
        }
        let index = row as usize * self.width as usize + col as usize;
        self.coverage.get(index).unwrap_or(0.0)
    }

    /// Bilinear interpolation of the coverage at `p`, with pixel (c, r) sampled at its centre
    /// (c + 0.5, r + 0.5) and every pixel outside the image counted as 0 (so the value falls
    /// to 0 over the half pixel beyond the border, and is 0 further out).
    #[inline(always)]
    pub fn sample(&self, p: Point) -> f64 {
        let mut cell = Cell::NONE;
        self.sample_in(p, &mut cell)
    }

    /// [`Bitmap::sample`] that keeps the four coverages of the last cell it read in
    /// `cell`: a walk in quarter-pixel steps stays in a cell for several samples, and
    /// reads its pixels once. The same values as [`Bitmap::sample`].
    #[inline(always)]
    pub(crate) fn sample_in(&self, p: Point, cell: &mut Cell) -> f64 {
        let x = p.x - 0.5;
        let y = p.y - 0.5;
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        // Also rejects NaN.
        if !(x > -1.0 && y > -1.0 && x < w && y < h) {
            return 0.0;
        }
        // floor() for x, y > −1 without the libm call `f64::floor` becomes on baseline
        // x86-64: truncation, minus one for negative non-integers.
        let c = x as i64 - i64::from(x < 0.0);
        let r = y as i64 - i64::from(y < 0.0);
        let fx = (x - c as f64) as f32;
        let fy = (y - r as f64) as f32;
        if cell.at != (c, r) {
            cell.at = (c, r);
            cell.values = if c >= 0
                && r >= 0
                && c + 1 < i64::from(self.width)
                && r + 1 < i64::from(self.height)
            {
                let stride = self.width as usize;
                let i = r as usize * stride + c as usize;
                let at = |k: usize| self.coverage.get(k).unwrap_or(0.0);
                [at(i), at(i + 1), at(i + stride), at(i + stride + 1)]
            } else {
                [
                    self.coverage_at(c, r),
                    self.coverage_at(c + 1, r),
                    self.coverage_at(c, r + 1),
                    self.coverage_at(c + 1, r + 1),
                ]
            };
        }
        let [v00, v10, v01, v11] = cell.values;
        let top = v00 + (v10 - v00) * fx;
        let bottom = v01 + (v11 - v01) * fx;
        f64::from(top + (bottom - top) * fy)
    }

    /// The threshold in [0, 1]: a pixel is foreground when its coverage is at least this.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// True when the image carries (almost) no grey levels at its edges: fewer than 5 % of
    /// the pixels next to a threshold crossing have a coverage strictly between 0.05 and
    /// 0.95. Also true when there is no crossing at all. Contour extraction then smooths the
    /// pixel staircase instead of refining edges to sub-pixel positions.
    pub fn is_bilevel(&self) -> bool {
        self.bilevel
    }

    /// True when the coverage came from the alpha channel.
    pub fn from_alpha(&self) -> bool {
        self.from_alpha
    }

    /// The frame or page traced (from 0) and how many the file has.
    pub fn frame(&self) -> (u32, u32) {
        (self.frame, self.frames)
    }

    /// Fraction of the pixels that are mostly transparent (alpha below one half); 0 for an
    /// image without alpha.
    pub fn transparent_fraction(&self) -> f64 {
        self.transparent
    }

    /// What the threshold is compared with, as the user sees the image.
    pub fn threshold_scale(&self) -> ThresholdScale {
        self.scale
    }

    /// [`ThresholdMode::Local`] when uneven lighting was divided out before the
    /// threshold, [`ThresholdMode::Global`] otherwise (never `Auto`: what was used).
    pub fn threshold_mode(&self) -> ThresholdMode {
        if self.local_threshold {
            ThresholdMode::Local
        } else {
            ThresholdMode::Global
        }
    }

    /// The threshold on [`Bitmap::threshold_scale`] (0–255), as `--threshold` takes it.
    pub fn threshold_value(&self) -> f64 {
        self.scale.value_of(self.threshold)
    }

    /// True when more than half of the outermost ring of pixels is foreground: the polarity
    /// is probably wrong (try `invert`). Only reported, never acted on.
    pub fn dark_border(&self) -> bool {
        self.border_foreground > 0.5
    }

    /// Share (0–1) of the outermost ring of pixels that is foreground.
    pub fn border_foreground(&self) -> f64 {
        self.border_foreground
    }

    /// True when a coverage value counts as foreground.
    #[inline]
    fn is_foreground(&self, v: f32) -> bool {
        f64::from(v) >= self.threshold
    }

    /// The thresholded image: 255 where coverage ≥ threshold, 0 elsewhere.
    pub fn mask(&self) -> GrayImage {
        let pixels = (0..self.coverage.len())
            .map(|i| {
                let v = self.coverage.get(i).unwrap_or(0.0);
                if self.is_foreground(v) {
                    255
                } else {
                    0
                }
            })
            .collect();
        GrayImage::from_raw(self.width, self.height, pixels)
            .unwrap_or_else(|| GrayImage::new(self.width, self.height))
    }

    /// The coverage as a picture: foreground black (0), background white (255), grey levels
    /// in between. Used as the backdrop of overlays.
    pub fn preview(&self) -> GrayImage {
        let pixels = (0..self.coverage.len())
            .map(|i| ((1.0 - self.coverage.get(i).unwrap_or(0.0)) * 255.0 + 0.5) as u8)
            .collect();
        GrayImage::from_raw(self.width, self.height, pixels)
            .unwrap_or_else(|| GrayImage::new(self.width, self.height))
    }

    /// The smallest `f32` that counts as foreground: `v >= self.foreground_level()` exactly
    /// when `f64::from(v) >= self.threshold`, for comparisons in `f32`.
    #[cfg(test)]
    fn foreground_level(&self) -> f32 {
        let t = self.threshold as f32;
        if f64::from(t) < self.threshold {
            // The next f32 up (the threshold is in [0, 1], so positive and finite).
            f32::from_bits(t.to_bits() + 1)
        } else {
            t
        }
    }

    /// Whether (almost) no pixel beside a threshold crossing is grey, from the crossings
    /// of `foreground` (the thresholded pixels, padded), whose grey pixels alone are read.
    fn detect_bilevel(&self, foreground: &bits::Bits) -> bool {
        let w = self.width as usize;
        let rows = self.coverage.len() / w;
        let grey = |c: usize, r: usize| {
            let v = self.coverage_at(c as i64, r as i64);
            v > GREY_LO && v < GREY_HI
        };
        // A large image is counted in bands of rows on the thread pool; the counts are
        // whole numbers, so their sum is the same on any number of threads.
        let band = (BILEVEL_BAND_PIXELS / w).max(1);
        let (edge, grey_edge) = if rows * w >= 2 * BILEVEL_BAND_PIXELS {
            use rayon::prelude::*;
            (0..rows.div_ceil(band))
                .into_par_iter()
                .map(|k| {
                    let part = k * band..((k + 1) * band).min(rows);
                    bits::crossings(foreground, w, rows, part, grey)
                })
                .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
        } else {
            bits::crossings(foreground, w, rows, 0..rows, grey)
        };
        (grey_edge as f64) < BILEVEL_GREY_FRACTION * edge as f64 || edge == 0
    }

    /// The threshold crossings between neighbouring pixels within the rows of `band` and
    /// between each of them and the next row, and how many of their pixels are grey (see
    /// [`crossing_counts`]), from the classes of [`Bitmap::crossing_classes`]: every
    /// pixel read, what [`bits::crossings`] counts from the bits' changes.
    #[cfg(test)]
    fn crossings(&self, band: std::ops::Range<usize>, classes: &Classes) -> (u64, u64) {
        let w = self.width as usize;
        let rows = self.coverage.len() / w;
        let (mut edge, mut grey_edge) = (0u64, 0u64);
        let (mut row, mut next) = (vec![0; w], vec![0; w]);
        self.read_row_classes(band.start, 0, classes, &mut row);
        for r in band {
            let (e, g) = crossing_counts(&row[..w - 1], &row[1..]);
            edge += e;
            grey_edge += g;
            if r + 1 < rows {
                self.read_row_classes(r + 1, 0, classes, &mut next);
                let (e, g) = crossing_counts(&row, &next);
                edge += e;
                grey_edge += g;
                std::mem::swap(&mut row, &mut next);
            }
        }
        (edge, grey_edge)
    }

    /// The classes the bilevel count reads: [`FOREGROUND`] and [`GREY`] bits.
    #[cfg(test)]
    fn crossing_classes(&self) -> Classes {
        let level = self.foreground_level();
        self.level_classes(|v| {
            (u8::from(v >= level) * FOREGROUND) | (u8::from(v > GREY_LO && v < GREY_HI) * GREY)
        })
    }

    fn measure_border(&self) -> f64 {
        let (w, h) = (i64::from(self.width), i64::from(self.height));
        let mut ring = 0u64;
        let mut dark = 0u64;
        let mut visit = |c: i64, r: i64| {
            ring += 1;
            dark += u64::from(self.is_foreground(self.coverage_at(c, r)));
        };
        for c in 0..w {
            visit(c, 0);
            if h > 1 {
                visit(c, h - 1);
            }
        }
        for r in 1..h - 1 {
            visit(0, r);
            if w > 1 {
                visit(w - 1, r);
            }
        }
        dark as f64 / ring as f64
    }
}

/// Pixels per band of rows in which [`Bitmap::detect_bilevel`] counts a large image's
/// crossings in parallel.
const BILEVEL_BAND_PIXELS: usize = 1 << 20;

/// Class bit of a pixel at or above the foreground level (see [`crossing_counts`]).
#[cfg(test)]
const FOREGROUND: u8 = 1;
/// Class bit of a grey pixel: coverage strictly between [`GREY_LO`] and [`GREY_HI`].
#[cfg(test)]
const GREY: u8 = 2;

/// Over pixel pairs (a[i], b[i]) of classes ([`FOREGROUND`], [`GREY`] bits): twice the
/// number of pairs that cross the threshold (one on each side), and how many of those
/// pixels are grey. Written as plain sums of bytes so that it vectorises.
#[cfg(test)]
fn crossing_counts(a: &[u8], b: &[u8]) -> (u64, u64) {
    let grey = |c: u8| u16::from(c >> 1);
    let (mut edge, mut grey_edge) = (0u64, 0u64);
    // 16-bit partial sums (twice as many to a vector register as 32-bit ones) cannot
    // overflow within a chunk: at most 2 × 2¹⁴ each.
    for (ca, cb) in a.chunks(1 << 14).zip(b.chunks(1 << 14)) {
        let (mut e, mut g) = (0u16, 0u16);
        for (&x, &y) in ca.iter().zip(cb) {
            let crossing = u16::from((x ^ y) & FOREGROUND);
            e += crossing;
            g += crossing * (grey(x) + grey(y));
        }
        edge += 2 * u64::from(e);
        grey_edge += u64::from(g);
    }
    (edge, grey_edge)
}

/// Otsu's threshold of a coverage field on a 256-bin histogram, on the [0, 1] scale, clamped
/// to [`OTSU_MIN`, `OTSU_MAX`]. Ties (an empty range of levels between the classes) resolve
/// to the middle of the range. A uniform field gives 0.5. `counts`: the 8-bit levels'
/// counts when they are known already ([`Levels::binned`]).
fn otsu_threshold(coverage: &Levels, counts: Option<&[u64; 256]>) -> f64 {
    // Coverage is already clamped to [0, 1].
    // (Through i32: float to u64 conversion is much slower on x86-64.)
    let bin = |v: f32| ((v * 255.0 + 0.5) as i32).clamp(0, 255) as usize;
    let hist = coverage.binned(bin, counts);
    let total = coverage.len() as f64;
    let sum_all: f64 = hist
        .iter()
        .enumerate()
        .map(|(i, &n)| i as f64 * n as f64)
        .sum();
    let (mut w_b, mut sum_b) = (0.0, 0.0);
    let mut best = -1.0;
    let (mut lo, mut hi) = (0usize, 0usize);
    for (t, &n) in hist.iter().enumerate().take(255) {
        w_b += n as f64;
        sum_b += t as f64 * n as f64;
        let w_f = total - w_b;
        if w_b == 0.0 {
            continue;
        }
        if w_f == 0.0 {
            break;
        }
        let diff = sum_b / w_b - (sum_all - sum_b) / w_f;
        let between = w_b * w_f * diff * diff;
        if between > best * (1.0 + 1e-12) {
            best = between;
            lo = t;
            hi = t;
        } else if between >= best * (1.0 - 1e-12) {
            hi = t;
        }
    }
    if best < 0.0 {
        return 0.5;
    }
    // Background = levels ≤ t, so the cut lies half a level above t.
    let t = (lo + hi) as f64 / 2.0;
    ((t + 0.5) / 255.0).clamp(OTSU_MIN, OTSU_MAX)
}

/// Calls `f(luma, alpha)` for every pixel in row-major order, both in [0, 1] (floats as
/// stored). Colour goes through Rec. 601 luma, the weights of JPEG's Y channel and of most
/// image tools' greyscale (the `image` crate's own conversion uses Rec. 709, which puts an
/// orange or red shape on the other side of a threshold than the same picture in
/// greyscale does in those tools). The common layouts are read in place; others are
/// converted to 32-bit float RGBA first.
fn for_each_luma_alpha(img: &DynamicImage, mut f: impl FnMut(f32, f32)) {
    // Divisions, not multiplications by reciprocals: the same values as `image`'s own
    // conversion to floats.
    let (u8f, u16f) = (u8_value, u16_value);
    let rgb = |r: f32, g: f32, b: f32| REC601[0] * r + REC601[1] * g + REC601[2] * b;
    match img {
        DynamicImage::ImageLuma8(b) => b.pixels().for_each(|p| f(u8f(p[0]), 1.0)),
        DynamicImage::ImageLumaA8(b) => b.pixels().for_each(|p| f(u8f(p[0]), u8f(p[1]))),
        DynamicImage::ImageLuma16(b) => b.pixels().for_each(|p| f(u16f(p[0]), 1.0)),
        DynamicImage::ImageLumaA16(b) => b.pixels().for_each(|p| f(u16f(p[0]), u16f(p[1]))),
        DynamicImage::ImageRgb8(b) => b.pixels().for_each(|p| {
            let [r, g, bl] = p.0.map(u8f);
            f(rgb(r, g, bl), 1.0)
        }),
        DynamicImage::ImageRgba8(b) => b.pixels().for_each(|p| {
            let [r, g, bl, a] = p.0.map(u8f);
            f(rgb(r, g, bl), a)
        }),
        other => other
            .to_rgba32f()
            .pixels()
            .for_each(|p| f(rgb(p[0], p[1], p[2]), p[3])),
    }
}

/// The first `pixels` samples of a one-channel image buffer (which may be longer than its
/// image).
fn first_pixels<T>(mut raw: Vec<T>, pixels: u64) -> Vec<T> {
    raw.truncate(usize::try_from(pixels).unwrap_or(usize::MAX));
    raw
}

/// An 8-bit channel value on the [0, 1] scale. A division, not a multiplication by the
/// reciprocal: the same value as `image`'s own conversion to floats.
fn u8_value(v: u8) -> f32 {
    f32::from(v) / 255.0
}

/// A 16-bit channel value on the [0, 1] scale (see [`u8_value`]).
fn u16_value(v: u16) -> f32 {
    f32::from(v) / 65535.0
}

/// Fraction of an image's pixels that must be mostly transparent (alpha below one half)
/// for its alpha channel to be traced as the shape ([`AlphaRule::Auto`]).
pub(crate) const ALPHA_SHAPE_FRACTION: f64 = 0.10;

/// Whether the shape is the alpha channel or the luminance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AlphaRule {
    /// The alpha channel when at least `ALPHA_SHAPE_FRACTION` of the pixels are mostly
    /// transparent (a logo or silhouette on a transparent background), otherwise the
    /// luminance composited over white (an opaque picture with a few transparent pixels,
    /// an icon with rounded transparent corners).
    #[default]
    Auto,
    /// Always the alpha channel; an image without one is an error.
    Alpha,
    /// Always the luminance, transparent pixels counting as white paper.
    Luminance,
}

/// [`Bitmap::from_image`].
pub(crate) fn from_image(img: &DynamicImage, opts: &RasterOptions) -> Result<Bitmap> {
    convert(Cow::Borrowed(img), opts)
}

/// [`from_image`], keeping an owned 8- or 16-bit grey image's pixel buffer as the bitmap's
/// levels instead of copying it.
fn convert(img: Cow<'_, DynamicImage>, opts: &RasterOptions) -> Result<Bitmap> {
    convert_counted(img, None, opts)
}

/// [`convert`] of an owned 8-bit grey image whose levels were counted as it was decoded
/// (`counts`, see `grey_png`): Otsu's threshold takes the counts instead of counting the
/// pixels again. The counts of any other image are ignored.
fn convert_counted(
    img: Cow<'_, DynamicImage>,
    counts: Option<grey_png::ByteCounts>,
    opts: &RasterOptions,
) -> Result<Bitmap> {
    let counts = counts.filter(|_| matches!(img, Cow::Owned(DynamicImage::ImageLuma8(_))));
    let (width, height) = img.dimensions();
    check_dimensions(width, height, opts.max_pixels)?;
    let pixels = u64::from(width) * u64::from(height);
    let has_alpha = img.color().has_alpha();
    let mut transparent = 0u64;
    if has_alpha {
        for_each_luma_alpha(&img, |_, a| transparent += u64::from(a < 0.5));
    }
    let transparent = transparent as f64 / pixels as f64;
    let from_alpha = match opts.alpha {
        AlphaRule::Auto => has_alpha && transparent >= ALPHA_SHAPE_FRACTION,
        AlphaRule::Luminance => false,
        AlphaRule::Alpha if has_alpha => true,
        AlphaRule::Alpha => {
            return Err(Error::InvalidOption {
                name: "alpha",
                message: "the image has no alpha channel".into(),
            })
        }
    };
    // With luminance, transparent pixels show the white paper under them.
    let value = |l: f32, a: f32| {
        let c = if from_alpha {
            a
        } else {
            1.0 - (l * a + (1.0 - a))
        };
        if opts.invert {
            1.0 - c
        } else {
            c
        }
    };
    // A grey image's own buffer becomes the levels: taken over when the image is owned,
    // copied when it is borrowed (as any conversion would copy it).
    let img = match img {
        Cow::Borrowed(grey @ (DynamicImage::ImageLuma8(_) | DynamicImage::ImageLuma16(_))) => {
            Cow::Owned(grey.clone())
        }
        other => other,
    };
    // A colour image is kept for the lighting rule, which asks whether dark "paper" is
    // grey (the grey images' buffers become the levels and are not needed).
    let mut colour = None;
    let coverage = match img {
        Cow::Owned(DynamicImage::ImageLuma8(b)) => {
            Levels::bytes(first_pixels(b.into_raw(), pixels), |v| {
                value(u8_value(v), 1.0)
            })
        }
        Cow::Owned(DynamicImage::ImageLuma16(b)) => {
            Levels::words(first_pixels(b.into_raw(), pixels), |v| {
                value(u16_value(v), 1.0)
            })
        }
        other => {
            let mut levels = Vec::with_capacity(pixels as usize);
            for_each_luma_alpha(&other, |l, a| levels.push(levels::quantise(value(l, a))));
            if other.color().has_color() {
                colour = Some(other);
            }
            Levels::quantised(levels)
        }
    };
    let scale = match (from_alpha, opts.invert) {
        (false, false) => ThresholdScale::Luminance,
        (false, true) => ThresholdScale::InvertedLuminance,
        (true, false) => ThresholdScale::Alpha,
        (true, true) => ThresholdScale::InvertedAlpha,
    };
    let threshold = opts
        .threshold
        .map(|t| scale.coverage_threshold(f64::from(t)));
    let (w, h) = (width as usize, height as usize);
    // Otsu's level of the coverage, once the lighting rule has needed it.
    let mut otsu = None;
    let map = match opts.threshold_mode {
        _ if from_alpha => None,
        ThresholdMode::Global => None,
        ThresholdMode::Local => Some(lighting::PaperMap::new(&coverage, w, h)),
        ThresholdMode::Auto => {
            let global = threshold
                .unwrap_or_else(|| *otsu.insert(otsu_threshold(&coverage, counts.as_deref())));
            // A page whose paper is light everywhere needs no map (the common case).
            (!lighting::paper_is_light(&coverage, w, h, global))
                .then(|| lighting::PaperMap::new(&coverage, w, h))
                .filter(|map| {
                    let chroma = colour.as_deref().map(|img| map.block_chroma(img));
                    map.is_uneven(global, chroma.as_deref())
                })
        }
    };
    // Without a paper map the coverage is as it was: Otsu's level is the one just found,
    // or the one of the counts made while decoding (otherwise `Bitmap::build` counts).
    let threshold = if map.is_none() {
        threshold.or(otsu).or_else(|| {
            counts
                .as_deref()
                .map(|c| otsu_threshold(&coverage, Some(c)))
        })
    } else {
        threshold
    };
    drop(colour);
    let local = map.is_some();
    let coverage = match map {
        Some(map) => map.flatten(&coverage, w, h),
        None => coverage,
    };
    let mut bitmap = Bitmap::build(width, height, coverage, threshold, from_alpha)?;
    bitmap.local_threshold = local;
    bitmap.scale = scale;
    bitmap.transparent = transparent;
    Ok(bitmap)
}

/// [`Bitmap::load`].
pub(crate) fn load(path: &Path, opts: &RasterOptions) -> Result<Bitmap> {
    match open_image(path, opts.decoding())? {
        Opened::Decoded(img, counts) => {
            let mut bitmap = convert_counted(Cow::Owned(img), counts, opts)?;
            bitmap.frame = opts.frame;
            bitmap.frames = 1;
            Ok(bitmap)
        }
        Opened::Bytes(bytes) => load_bytes(&bytes, path, opts),
    }
}

/// [`Bitmap::load_bytes`].
pub(crate) fn load_bytes(bytes: &[u8], name: &Path, opts: &RasterOptions) -> Result<Bitmap> {
    let counted = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        decode_counted_png(std::io::Cursor::new(bytes), opts.decoding())?
    } else {
        None
    };
    let ((img, frames), counts) = match counted {
        Some(grey) => ((DynamicImage::ImageLuma8(grey.image), 1), Some(grey.counts)),
        None => (decode_bytes(bytes, name, opts.decoding())?, None),
    };
    let mut bitmap = convert_counted(Cow::Owned(img), counts, opts)?;
    bitmap.frame = opts.frame;
    bitmap.frames = frames;
    Ok(bitmap)
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Luma, LumaA, Rgba, RgbaImage};
    use std::path::PathBuf;

    fn opts() -> RasterOptions {
        RasterOptions {
            threshold: None,
            alpha: AlphaRule::Auto,
            invert: false,
            max_pixels: 1 << 30,
            frame: 0,
            threshold_mode: ThresholdMode::Auto,
        }
    }

    /// A unique path in the system temp directory.
    fn temp_path(name: &str) -> PathBuf {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        std::env::temp_dir().join(format!(
            "outlinefit-raster-{}-{nanos}-{name}",
            std::process::id()
        ))
    }

    /// A 6×4 grey image: a dark 2×2 block (luma 0) on white (255) with one mid-grey pixel.
    fn block_image() -> GrayImage {
        let mut img = GrayImage::from_pixel(6, 4, Luma([255]));
        for (c, r) in [(2, 1), (3, 1), (2, 2), (3, 2)] {
            img.put_pixel(c, r, Luma([0]));
        }
        img.put_pixel(4, 1, Luma([128]));
        img
    }

    #[test]
    fn dark_on_light_coverage_and_invert() {
        let img = DynamicImage::ImageLuma8(block_image());
        let b = from_image(&img, &opts()).unwrap();
        assert_eq!((b.width, b.height), (6, 4));
        assert_eq!(b.coverage_at(2, 1), 1.0);
        assert_eq!(b.coverage_at(0, 0), 0.0);
        assert!((b.coverage_at(4, 1) - (1.0 - 128.0 / 255.0)).abs() < 1e-6);
        assert_eq!(b.coverage_at(-1, 0), 0.0);
        assert_eq!(b.coverage_at(6, 0), 0.0);
        assert!(!b.from_alpha());
        assert!(!b.dark_border());

        let inv = from_image(
            &img,
            &RasterOptions {
                invert: true,
                ..opts()
            },
        )
        .unwrap();
        assert_eq!(inv.coverage_at(2, 1), 0.0);
        assert_eq!(inv.coverage_at(0, 0), 1.0);
        assert!(inv.dark_border());
    }

    #[test]
    fn sixteen_bit_precision_is_kept() {
        let mut img = image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_pixel(2, 1, Luma([0]));
        img.put_pixel(1, 0, Luma([32768]));
        let b = from_image(&DynamicImage::ImageLuma16(img), &opts()).unwrap();
        // 8-bit quantisation would give 127/255 or 128/255, 0.0020 away from 0.5.
        assert!((b.coverage_at(1, 0) - (1.0 - 32768.0 / 65535.0)).abs() < 1e-6);
    }

    #[test]
    fn otsu_of_bilevel_is_half_and_fixed_threshold_is_used() {
        let img = DynamicImage::ImageLuma8(block_image());
        let b = from_image(&img, &opts()).unwrap();
        // Levels {0, 127, 255}: Otsu separates 0 from the rest, the cut is in the empty
        // range between 0 and 127: its middle is 63, 63.5/255 = 0.249.
        assert!(
            (b.threshold() - 63.5 / 255.0).abs() < 1e-12,
            "{}",
            b.threshold()
        );

        let mut pure = block_image();
        pure.put_pixel(4, 1, Luma([255]));
        let b = from_image(&DynamicImage::ImageLuma8(pure), &opts()).unwrap();
        assert!((b.threshold() - 0.5).abs() < 1e-12);
        assert!(b.is_bilevel());

        let fixed = from_image(
            &img,
            &RasterOptions {
                threshold: Some(100),
                ..opts()
            },
        )
        .unwrap();
        // Darker than 100 is the shape: coverage above 1 − 99.5/255.
        assert!((fixed.threshold() - (1.0 - 99.5 / 255.0)).abs() < 1e-12);
        assert!((fixed.threshold_value() - 99.5).abs() < 1e-9);
        // The grey pixel (luminance 128) is foreground at Otsu's level, not darker than 100.
        let otsu_mask = from_image(&img, &opts()).unwrap().mask();
        assert_eq!(otsu_mask.get_pixel(4, 1).0[0], 255);
        assert_eq!(fixed.mask().get_pixel(4, 1).0[0], 0);
        assert_eq!(fixed.mask().get_pixel(2, 1).0[0], 255);
    }

    #[test]
    fn otsu_is_clamped() {
        // 1 foreground pixel among 10 000 at coverage 0.1 levels: Otsu alone would cut near
        // 0.05; the clamp keeps it at 0.2.
        let mut cov = vec![0.0f32; 10_000];
        cov[5] = 0.1;
        cov[6] = 0.1;
        let b = Bitmap::from_coverage(100, 100, cov, None).unwrap();
        assert_eq!(b.threshold(), OTSU_MIN);
        let b = Bitmap::from_coverage(2, 2, vec![0.9, 1.0, 1.0, 1.0], None).unwrap();
        assert_eq!(b.threshold(), OTSU_MAX);
        // A uniform field has no cut at all.
        let b = Bitmap::from_coverage(2, 2, vec![0.3; 4], None).unwrap();
        assert_eq!(b.threshold(), 0.5);
    }

    #[test]
    fn otsu_separates_two_grey_populations() {
        // Half the pixels around 0.3, half around 0.7: the cut must fall between them.
        let cov: Vec<f32> = (0..400)
            .map(|i| {
                if i % 2 == 0 {
                    0.28 + (i % 7) as f32 * 0.01
                } else {
                    0.68 + (i % 5) as f32 * 0.01
                }
            })
            .collect();
        let b = Bitmap::from_coverage(20, 20, cov, None).unwrap();
        assert!(
            b.threshold() > 0.34 && b.threshold() < 0.68,
            "{}",
            b.threshold()
        );
    }

    #[test]
    fn alpha_is_the_shape_even_for_white_logos() {
        // A white, fully opaque 2×2 block on a transparent (black, alpha 0) background.
        let mut img = RgbaImage::from_pixel(5, 5, Rgba([0, 0, 0, 0]));
        for (c, r) in [(1, 1), (2, 1), (1, 2), (2, 2)] {
            img.put_pixel(c, r, Rgba([255, 255, 255, 255]));
        }
        img.put_pixel(3, 1, Rgba([255, 255, 255, 64]));
        let dynimg = DynamicImage::ImageRgba8(img);
        let b = from_image(&dynimg, &opts()).unwrap();
        assert!(b.from_alpha());
        assert_eq!(b.coverage_at(1, 1), 1.0);
        assert_eq!(b.coverage_at(0, 0), 0.0);
        assert!((b.coverage_at(3, 1) - 64.0 / 255.0).abs() < 1e-6);
        let inv = from_image(
            &dynimg,
            &RasterOptions {
                invert: true,
                ..opts()
            },
        )
        .unwrap();
        assert_eq!(inv.coverage_at(1, 1), 0.0);
        assert_eq!(inv.coverage_at(0, 0), 1.0);

        // An alpha channel that is opaque everywhere is ignored: luminance decides.
        let mut opaque = image::GrayAlphaImage::from_pixel(3, 1, LumaA([255, 255]));
        opaque.put_pixel(1, 0, LumaA([0, 255]));
        let b = from_image(&DynamicImage::ImageLumaA8(opaque), &opts()).unwrap();
        assert!(!b.from_alpha());
        assert_eq!(b.to_coverage(), &[0.0, 1.0, 0.0]);
    }

    #[test]
    fn alpha_is_traced_only_where_a_tenth_of_the_image_is_transparent() {
        // 100 opaque pixels, a dark bar in the middle; `clear` of them transparent.
        let picture = |clear: u32| {
            let img = RgbaImage::from_fn(10, 10, |x, y| {
                let dark = (3..7).contains(&x) && (3..7).contains(&y);
                let a = if y * 10 + x < clear { 0 } else { 255 };
                let v = if dark { 0 } else { 255 };
                Rgba([v, v, v, a])
            });
            DynamicImage::ImageRgba8(img)
        };
        // One transparent pixel: the luminance is the shape, not the whole rectangle.
        let b = from_image(&picture(1), &opts()).unwrap();
        assert!(!b.from_alpha());
        assert_eq!(b.to_coverage().iter().filter(|&&c| c > 0.5).count(), 16);
        assert!((b.transparent_fraction() - 0.01).abs() < 1e-12);
        // Nine transparent pixels (just under a tenth): still luminance; ten: alpha.
        assert!(!from_image(&picture(9), &opts()).unwrap().from_alpha());
        let b = from_image(&picture(10), &opts()).unwrap();
        assert!(b.from_alpha());
        assert_eq!(b.to_coverage().iter().filter(|&&c| c > 0.5).count(), 90);
        // Either choice can be forced.
        let forced = |alpha| RasterOptions { alpha, ..opts() };
        assert!(from_image(&picture(1), &forced(AlphaRule::Alpha))
            .unwrap()
            .from_alpha());
        assert!(!from_image(&picture(10), &forced(AlphaRule::Luminance))
            .unwrap()
            .from_alpha());
        let grey = DynamicImage::ImageLuma8(GrayImage::new(4, 4));
        assert!(matches!(
            from_image(&grey, &forced(AlphaRule::Alpha)),
            Err(Error::InvalidOption { name: "alpha", .. })
        ));
    }

    #[test]
    fn crossing_counts_of_long_rows_are_the_direct_counts() {
        // Rows longer than one chunk of 16-bit partial sums, every pair crossing in the
        // worst case, and random classes.
        let n = 3 * (1 << 14) + 77;
        let all_fg = vec![FOREGROUND | GREY; n];
        let all_bg = vec![GREY; n];
        assert_eq!(
            crossing_counts(&all_fg, &all_bg),
            (2 * n as u64, 2 * n as u64)
        );
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as u8 & (FOREGROUND | GREY)
        };
        let a: Vec<u8> = (0..n).map(|_| next()).collect();
        let b: Vec<u8> = (0..n).map(|_| next()).collect();
        let (mut edge, mut grey) = (0u64, 0u64);
        for (&x, &y) in a.iter().zip(&b) {
            if (x & FOREGROUND) != (y & FOREGROUND) {
                edge += 2;
                grey += u64::from(x & GREY != 0) + u64::from(y & GREY != 0);
            }
        }
        assert_eq!(crossing_counts(&a, &b), (edge, grey));
    }

    #[test]
    fn crossings_of_bands_add_up_to_those_of_the_whole_image() {
        // Anti-aliased disks on a 300 × 200 image, counted whole and in bands of 7 rows
        // (the parallel split of a large image), band boundaries included.
        let (w, h) = (300usize, 200usize);
        let coverage: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                let d =
                    ((x - 150.0).hypot(y - 100.0) - 60.0).min((x - 40.0).hypot(y - 30.0) - 12.0);
                (0.5 - d).clamp(0.0, 1.0) as f32
            })
            .collect();
        let b = Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap();
        let classes = b.crossing_classes();
        let whole = b.crossings(0..h, &classes);
        let banded = (0..h.div_ceil(7))
            .map(|k| b.crossings(k * 7..((k + 1) * 7).min(h), &classes))
            .fold((0, 0), |a, c| (a.0 + c.0, a.1 + c.1));
        assert_eq!(whole, banded);
        assert!(whole.0 > 0 && whole.1 > 0, "{whole:?}");
    }

    /// The bilevel count read from the foreground bits' changes gives the counts of the
    /// pass that reads every pixel's class, on random grey and black-and-white images of
    /// widths below, at and across 64-bit words, in bands and whole.
    #[test]
    fn crossings_from_the_bits_are_those_of_every_pixel() {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h) in [
            (1usize, 1usize),
            (5, 7),
            (63, 9),
            (64, 4),
            (65, 11),
            (130, 40),
            (300, 17),
        ] {
            for grey_levels in [false, true] {
                let coverage: Vec<f32> = (0..w * h)
                    .map(|_| {
                        let v = next();
                        if grey_levels && v % 3 == 0 {
                            (v >> 40) as f32 / (1u64 << 24) as f32
                        } else {
                            f32::from(u8::from(v % 2 == 0))
                        }
                    })
                    .collect();
                let b = Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap();
                let foreground = b.padded_foreground();
                let grey = |c: usize, r: usize| {
                    let v = b.coverage_at(c as i64, r as i64);
                    v > GREY_LO && v < GREY_HI
                };
                let classes = b.crossing_classes();
                for band in [0..h, 0..h / 2, h / 2..h] {
                    let ours = bits::crossings(&foreground, w, h, band.clone(), grey);
                    assert_eq!(ours, b.crossings(band, &classes), "{w} × {h}");
                }
                let whole = bits::crossings(&foreground, w, h, 0..h, grey);
                assert!(w * h < 4 || whole.0 > 0, "{w} × {h}");
                assert_eq!(grey_levels && w * h > 20, whole.1 > 0, "{w} × {h}");
            }
        }
    }

    #[test]
    fn sample_is_bilinear_between_pixel_centres() {
        let b = Bitmap::from_coverage(2, 2, vec![0.0, 1.0, 0.5, 0.25], Some(0.5)).unwrap();
        assert_eq!(b.sample(Point::new(0.5, 0.5)), 0.0);
        assert_eq!(b.sample(Point::new(1.5, 0.5)), 1.0);
        assert_eq!(b.sample(Point::new(1.0, 0.5)), 0.5);
        // Centre of the four: mean 0.4375 (to the 16-bit steps the values are stored in).
        assert!((b.sample(Point::new(1.0, 1.0)) - 0.4375).abs() < 1e-5);
        // Half a pixel past the right border: halfway to the outside zero.
        assert!((b.sample(Point::new(2.0, 0.5)) - 0.5).abs() < 1e-7);
        assert_eq!(b.sample(Point::new(2.5, 0.5)), 0.0);
        assert_eq!(b.sample(Point::new(-3.0, 0.5)), 0.0);
        assert_eq!(b.sample(Point::new(f64::NAN, 0.5)), 0.0);
    }

    #[test]
    fn samples_along_a_walk_reuse_cells_and_equal_single_samples() {
        // Walks in quarter-pixel steps through the image, along its borders and out of
        // it, in every direction: each sample with the walk's cell equals one without.
        use rand::{RngExt, SeedableRng};
        let mut rng = crate::optim::SeededRng::seed_from_u64(23);
        let (w, h) = (9u32, 7u32);
        let cov: Vec<f32> = (0..w * h).map(|_| rng.random::<f32>()).collect();
        let b = Bitmap::from_coverage(w, h, cov, Some(0.5)).unwrap();
        let mut reused = 0;
        for _ in 0..300 {
            let start = Point::new(rng.random_range(-2.0..11.0), rng.random_range(-2.0..9.0));
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let step = Point::new(angle.cos(), angle.sin()) * 0.25;
            let mut cell = Cell::NONE;
            for j in 0..40 {
                let p = start + step * f64::from(j);
                let before = cell.at;
                assert_eq!(b.sample_in(p, &mut cell).to_bits(), b.sample(p).to_bits());
                reused += usize::from(cell.at == before);
            }
        }
        assert!(reused > 3000, "{reused} samples reused their cell");
    }

    #[test]
    fn bilevel_detection() {
        // A 0/1 square: bilevel.
        let mut cov = vec![0.0f32; 100];
        for r in 3..7 {
            for c in 3..7 {
                cov[r * 10 + c] = 1.0;
            }
        }
        let b = Bitmap::from_coverage(10, 10, cov.clone(), None).unwrap();
        assert!(b.is_bilevel());
        // The same square with half-covered pixels around it: anti-aliased.
        for r in 3..7 {
            cov[r * 10 + 7] = 0.5;
            cov[r * 10 + 2] = 0.5;
        }
        let b = Bitmap::from_coverage(10, 10, cov, None).unwrap();
        assert!(!b.is_bilevel());
    }

    #[test]
    fn dark_border_detection() {
        let mut cov = vec![1.0f32; 16];
        cov[5] = 0.0;
        let b = Bitmap::from_coverage(4, 4, cov, Some(0.5)).unwrap();
        assert!(b.dark_border());
        let b = Bitmap::from_coverage(1, 3, vec![1.0, 0.0, 0.0], Some(0.5)).unwrap();
        assert!(!b.dark_border());
    }

    #[test]
    fn grey_levels_are_stored_exactly() {
        // Every 8-bit and a spread of 16-bit levels, plain and inverted: the stored
        // coverage is bit for bit the float conversion's (1 − v/255, v/255).
        let img = GrayImage::from_raw(256, 1, (0..=255u8).collect()).unwrap();
        let wide = image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_raw(
            1024,
            1,
            (0..1024u32).map(|v| (v * 64 + v / 16) as u16).collect(),
        )
        .unwrap();
        for invert in [false, true] {
            let o = RasterOptions { invert, ..opts() };
            let b = from_image(&DynamicImage::ImageLuma8(img.clone()), &o).unwrap();
            for (v, c) in (0..=255u8).zip(b.to_coverage()) {
                let l = f32::from(v) / 255.0;
                let want = if invert { 1.0 - (1.0 - l) } else { 1.0 - l };
                assert_eq!(c.to_bits(), want.to_bits(), "{v} {invert}");
            }
            let b = from_image(&DynamicImage::ImageLuma16(wide.clone()), &o).unwrap();
            for (&v, c) in wide.as_raw().iter().zip(b.to_coverage()) {
                let l = f32::from(v) / 65535.0;
                let want = if invert { 1.0 - (1.0 - l) } else { 1.0 - l };
                assert_eq!(c.to_bits(), want.to_bits(), "{v} {invert}");
            }
        }
        // A buffer longer than its pixels keeps only the pixels.
        let long = GrayImage::from_raw(2, 2, vec![0, 255, 255, 0, 7, 7]).unwrap();
        let b = from_image(&DynamicImage::ImageLuma8(long), &opts()).unwrap();
        assert_eq!(b.to_coverage(), vec![1.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn mask_and_preview() {
        let b = Bitmap::from_coverage(3, 1, vec![0.0, 0.5, 1.0], Some(0.5)).unwrap();
        assert_eq!(b.mask().into_raw(), vec![0, 255, 255]);
        // 0.5 is stored as 32768/65535, a hair above one half.
        assert_eq!(b.preview().into_raw(), vec![255, 127, 0]);
    }

    #[test]
    fn from_coverage_validates() {
        assert!(matches!(
            Bitmap::from_coverage(0, 3, vec![], None),
            Err(Error::ZeroSize {
                width: 0,
                height: 3
            })
        ));
        assert!(matches!(
            Bitmap::from_coverage(2, 2, vec![0.0; 3], None),
            Err(Error::InvalidOption { .. })
        ));
        assert!(matches!(
            Bitmap::from_coverage(1, 1, vec![0.0], Some(1.5)),
            Err(Error::InvalidOption { .. })
        ));
        let b = Bitmap::from_coverage(3, 1, vec![f32::NAN, -2.0, 7.0], Some(0.5)).unwrap();
        assert_eq!(b.to_coverage(), &[0.0, 0.0, 1.0]);
    }

    #[test]
    fn size_limits() {
        let img = DynamicImage::ImageLuma8(GrayImage::new(0, 5));
        assert!(matches!(
            from_image(&img, &opts()),
            Err(Error::ZeroSize {
                width: 0,
                height: 5
            })
        ));
        let img = DynamicImage::ImageLuma8(GrayImage::new(10, 10));
        let small = RasterOptions {
            max_pixels: 99,
            ..opts()
        };
        assert!(matches!(
            from_image(&img, &small),
            Err(Error::TooLarge {
                pixels: 100,
                limit: 99,
                ..
            })
        ));

        // From a file: the header alone decides.
        let path = temp_path("big.png");
        img.save(&path).unwrap();
        let res = load(&path, &small);
        let ok = load(&path, &opts());
        let _ = std::fs::remove_file(&path);
        assert!(
            matches!(res, Err(Error::TooLarge { pixels: 100, .. })),
            "{res:?}"
        );
        assert_eq!(ok.unwrap().width, 10);
    }

    #[test]
    fn zero_size_file_is_rejected() {
        // A PGM header may declare 0×4 pixels.
        let path = temp_path("empty.pgm");
        std::fs::write(&path, b"P5\n0 4\n255\n").unwrap();
        let res = load(&path, &opts());
        let _ = std::fs::remove_file(&path);
        assert!(matches!(res, Err(Error::ZeroSize { .. })), "{res:?}");
    }

    #[test]
    fn read_and_decode_errors() {
        let missing = temp_path("missing.png");
        assert!(matches!(load(&missing, &opts()), Err(Error::Read { .. })));

        // Not an image, whatever its name says.
        let fake = temp_path("fake.png");
        std::fs::write(&fake, b"this is plain text, not a PNG").unwrap();
        let res = load(&fake, &opts());
        let _ = std::fs::remove_file(&fake);
        assert!(matches!(res, Err(Error::Decode { .. })), "{res:?}");

        // A truncated PNG.
        let mut img = GrayImage::new(64, 64);
        for (i, p) in img.pixels_mut().enumerate() {
            p.0[0] = (i * 37 % 251) as u8;
        }
        let full = temp_path("full.png");
        DynamicImage::ImageLuma8(img).save(&full).unwrap();
        let bytes = std::fs::read(&full).unwrap();
        let _ = std::fs::remove_file(&full);
        let cut = temp_path("cut.png");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        let res = load(&cut, &opts());
        let _ = std::fs::remove_file(&cut);
        assert!(matches!(res, Err(Error::Decode { .. })), "{res:?}");
    }

    /// A PNG file large enough to be decoded from the file gives the bitmap its bytes give,
    /// and its errors are those of its bytes: truncated, a frame past the first, too large.
    /// A large file that is not a PNG is read whole as before.
    #[test]
    fn large_png_files_are_decoded_as_their_bytes_are() {
        // Noise does not compress: 1200 × 1000 grey pixels make a file over 1 MiB.
        let (w, h) = (1200u32, 1000u32);
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let img = GrayImage::from_fn(w, h, |c, r| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let disc = (f64::from(c) - 600.0).hypot(f64::from(r) - 500.0) < 300.0;
            let noise = (state >> 58) as u8;
            Luma([if disc { 20 + noise } else { 230 - noise }])
        });
        let dynamic = DynamicImage::ImageLuma8(img);
        let png = temp_path("large.png");
        dynamic.save(&png).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        assert!(
            bytes.len() as u64 >= decode::STREAM_PNG_BYTES,
            "{}",
            bytes.len()
        );
        let from_file = load(&png, &opts()).unwrap();
        let from_bytes = load_bytes(&bytes, &png, &opts()).unwrap();
        assert_eq!((from_file.width, from_file.height), (w, h));
        assert_eq!(from_file.threshold(), from_bytes.threshold());
        assert_eq!(from_file.is_bilevel(), from_bytes.is_bilevel());
        assert_eq!((from_file.frame, from_file.frames), (0, 1));
        for r in 0..h as i64 {
            for c in 0..w as i64 {
                assert_eq!(from_file.coverage_at(c, r), from_bytes.coverage_at(c, r));
            }
        }
        let (ink, paper) = (from_file.coverage_at(600, 500), from_file.coverage_at(5, 5));
        assert!(ink > 0.5 && paper < 0.5, "{ink} {paper}");
        let second = RasterOptions { frame: 1, ..opts() };
        assert!(matches!(
            load(&png, &second),
            Err(Error::InvalidOption { .. })
        ));
        let small = RasterOptions {
            max_pixels: 1000,
            ..opts()
        };
        let res = load(&png, &small);
        assert!(matches!(res, Err(Error::TooLarge { .. })), "{res:?}");
        let cut = temp_path("large-cut.png");
        std::fs::write(&cut, &bytes[..bytes.len() * 3 / 4]).unwrap();
        let res = load(&cut, &opts());
        let _ = std::fs::remove_file(&cut);
        let _ = std::fs::remove_file(&png);
        assert!(matches!(res, Err(Error::Decode { .. })), "{res:?}");

        // A large BMP named .png: read whole and decoded by its content.
        let res = load_misnamed(&dynamic, "large.bmp", "large-bmp.png");
        assert_eq!(
            res.unwrap().coverage_at(600, 500),
            from_bytes.coverage_at(600, 500)
        );
    }

    /// Saves `img` in the format its name `saved` says, renames the file to `misnamed`,
    /// loads it and removes it.
    fn load_misnamed(img: &DynamicImage, saved: &str, misnamed: &str) -> Result<Bitmap> {
        let path = temp_path(saved);
        img.save(&path).unwrap();
        let renamed = temp_path(misnamed);
        std::fs::rename(&path, &renamed).unwrap();
        let res = load(&renamed, &opts());
        let _ = std::fs::remove_file(&renamed);
        res
    }

    #[test]
    fn content_decides_the_format() {
        // A PNG named .jpg, and a BMP named .png.
        let img = DynamicImage::ImageLuma8(block_image());
        let res = load_misnamed(&img, "really-png.png", "misnamed.jpg");
        assert_eq!(res.unwrap().coverage_at(2, 1), 1.0);

        let rgb = DynamicImage::ImageRgb8(img.to_rgb8());
        let res = load_misnamed(&rgb, "really-bmp.bmp", "misnamed-bmp.png");
        assert_eq!(res.unwrap().coverage_at(3, 2), 1.0);
    }
}
