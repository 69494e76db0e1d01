//! The data a surface is fitted to: the point cloud and its parameters.

use super::bezier::P3;
use serde::Serialize;

/// A cloud of 3-D points to fit.
#[derive(Clone, Debug, PartialEq)]
pub struct PointCloud {
    /// The points; for a grid, row by row (`points[p * n + q]` is row p, column q).
    pub points: Vec<P3>,
    /// `Some((m, n))` when the points form an organized grid of m rows and n columns.
    pub grid: Option<(usize, usize)>,
}

/// Data parameters: for a grid one τ per row and one ζ per column; for unorganized points
/// one (τ_k, ζ_k) per point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Params {
    /// τ: per row (grid) or per point.
    pub tau: Vec<f64>,
    /// ζ: per column (grid) or per point.
    pub zeta: Vec<f64>,
}
