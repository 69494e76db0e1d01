//! lsq (placeholder).
use super::FittedContour;
use crate::breaks::SegmentedContour;
/// Options.
pub struct LsqOptions;
impl LsqOptions {
    /// From config.
    pub fn new(_c: &crate::Config) -> Self { LsqOptions }
}
/// Fit.
pub fn fit_contour(s: &SegmentedContour, _o: &LsqOptions) -> FittedContour {
    FittedContour { points: s.points.clone(), is_hole: s.is_hole, parent: s.parent, segments: vec![], joints: vec![] }
}
