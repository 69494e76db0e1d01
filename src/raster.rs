//! Loading images into a coverage field (placeholder: being written by a helper).

use crate::error::Result;
use crate::geom::Point;
use std::path::Path;

/// Options for turning an image into foreground coverage.
#[derive(Clone, Debug)]
pub struct RasterOptions {
    /// Fixed threshold on coverage (0–255 scale); `None` = Otsu.
    pub threshold: Option<u8>,
    /// Treat light-on-dark as foreground.
    pub invert: bool,
    /// Largest accepted width × height.
    pub max_pixels: u64,
}

/// Foreground coverage of an image.
#[derive(Clone, Debug)]
pub struct Bitmap {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    coverage: Vec<f32>,
    threshold: f64,
}

impl Bitmap {
    /// Builds a bitmap from a row-major coverage field (1 = foreground).
    pub fn from_coverage(width: u32, height: u32, coverage: Vec<f32>, threshold: Option<f64>) -> Result<Bitmap> {
        Ok(Bitmap { width, height, coverage, threshold: threshold.unwrap_or(0.5) })
    }
    /// Coverage of pixel (col, row), 0 outside the image.
    pub fn coverage_at(&self, col: i64, row: i64) -> f32 {
        if col < 0 || row < 0 || col >= self.width as i64 || row >= self.height as i64 {
            return 0.0;
        }
        self.coverage[row as usize * self.width as usize + col as usize]
    }
    /// Bilinear coverage at a point (pixel centres at half-integers).
    pub fn sample(&self, _p: Point) -> f64 {
        0.0
    }
    /// Threshold in [0, 1].
    pub fn threshold(&self) -> f64 {
        self.threshold
    }
    /// Bilevel input.
    pub fn is_bilevel(&self) -> bool {
        false
    }
    /// Shape from alpha.
    pub fn from_alpha(&self) -> bool {
        false
    }
    /// Border mostly foreground.
    pub fn dark_border(&self) -> bool {
        false
    }
}

/// Loads an image file.
pub fn load(_path: &Path, _opts: &RasterOptions) -> Result<Bitmap> {
    Bitmap::from_coverage(0, 0, vec![], None)
}
