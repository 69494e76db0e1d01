//! The reusable buffers one thread traces its borders with.

use crate::geom::Point;

/// Reusable buffers, so that tracing allocates per contour, not per point.
#[derive(Default)]
pub(super) struct Workspace {
    /// The outline being built.
    pub(super) points: Vec<Point>,
    /// Unit walking direction (foreground on the right) at each point.
    pub(super) tangents: Vec<Point>,
    /// Points that must survive clean-up and resampling exactly (corners, sharp turns).
    pub(super) anchors: Vec<bool>,
    /// Bilevel: the raw crack midpoints.
    pub(super) raw: Vec<Point>,
    /// Bilevel: the crack normals.
    pub(super) normals: Vec<Point>,
    pub(super) scratch: Vec<Point>,
    pub(super) scratch_tangents: Vec<Point>,
    pub(super) values: Vec<f64>,
    /// Grey-level corner detector: chord angle at each point.
    pub(super) angles: Vec<f64>,
    /// Grey-level corner detector: unrolled chord end indices at each point.
    pub(super) chord_ends: Vec<(i64, i64)>,
    /// Bilevel: the regression bandwidth at each point.
    pub(super) sigma: Vec<f64>,
    /// Bilevel: which points the current regression round fits.
    pub(super) near: Vec<bool>,
    /// Bilevel: the run weight of each crack.
    pub(super) run_weight: Vec<f64>,
    pub(super) corners: Vec<usize>,
}
