//! Boundary extraction (placeholder: being written by a helper).

use crate::error::Result;
use crate::geom::Point;
use crate::raster::Bitmap;
use serde::Serialize;

/// Options of boundary extraction.
#[derive(Clone, Debug)]
pub struct ContourOptions {
    /// Shapes and holes with a smaller area (px²) are dropped.
    pub min_area: f64,
}

/// One closed boundary of a shape, as sub-pixel points in image pixel units.
#[derive(Clone, Debug, Serialize)]
pub struct Contour {
    /// Boundary points in order, closed implicitly (the last connects to the first; the
    /// first point is not repeated). Outer borders run so that `geom::signed_area` is
    /// positive (clockwise on screen), holes so that it is negative.
    pub points: Vec<Point>,
    /// True for the border of a hole.
    pub is_hole: bool,
    /// Index (in the same list) of the enclosing contour: a hole's outer border, or the hole
    /// an island sits in. `None` for top-level outer borders.
    pub parent: Option<usize>,
}

/// Extracts the contours of the foreground.
pub fn extract_contours(_bitmap: &Bitmap, _opts: &ContourOptions) -> Result<Vec<Contour>> {
    Ok(vec![])
}
