//! paper (placeholder).
use super::FittedContour;
/// Options.
pub struct PaperOptions;
impl PaperOptions {
    /// From config.
    pub fn new(_c: &crate::Config) -> Self { PaperOptions }
}
/// Fit.
pub fn fit_contour(s: &FittedContour, _o: &PaperOptions) -> FittedContour { s.clone() }
