//! Break points (placeholder).
use crate::contour::Contour;
use crate::fit::JointKind;
use crate::geom::Point;
use serde::Serialize;

/// Options of break detection.
#[derive(Clone, Debug)]
pub struct BreakOptions {
    /// Corner angle in degrees.
    pub corner_angle: f64,
    /// Curvature window in px.
    pub window: f64,
}
impl BreakOptions {
    /// Options scaled to an image.
    pub fn for_image(corner_angle: f64, _w: u32, _h: u32) -> Self {
        BreakOptions { corner_angle, window: 2.0 }
    }
}
/// A break.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Break {
    /// Index into points.
    pub index: usize,
    /// Kind.
    pub kind: JointKind,
}
/// A contour with breaks.
#[derive(Clone, Debug)]
pub struct SegmentedContour {
    /// Points.
    pub points: Vec<Point>,
    /// Hole.
    pub is_hole: bool,
    /// Parent.
    pub parent: Option<usize>,
    /// Breaks.
    pub breaks: Vec<Break>,
}
/// Finds breaks.
pub fn find_breaks(c: &Contour, _o: &BreakOptions) -> SegmentedContour {
    SegmentedContour { points: c.points.clone(), is_hole: c.is_hole, parent: c.parent, breaks: vec![] }
}
