//! Polynomial cubic Bézier segments (placeholder: being written).

use super::RationalCubic;
use crate::geom::Point;

/// A polynomial cubic Bézier segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicBez {
    /// Control points.
    pub points: [Point; 4],
}

/// Approximates a rational cubic by polynomial cubics within `bound` pixels.
pub fn approximate_with_cubics(curve: &RationalCubic, _bound: f64) -> Vec<CubicBez> {
    vec![CubicBez { points: curve.points }]
}
