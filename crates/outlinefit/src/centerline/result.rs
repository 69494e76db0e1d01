//! What a centre-line trace gives: the strokes with their pieces, the junctions, the
//! check's verdict.

use super::fit::StrokeSegment;
use crate::geom::Point;
use crate::trace::ImageInfo;
use serde::Serialize;

/// Largest turn (degrees) at which a junction's two branches continue each other as one
/// stroke.
pub const PAIR_TURN_DEGREES: f64 = 50.0;

/// A stroke is wider than a stroke-like shape when its centre line is shorter than this
/// many widths.
pub const STROKE_LIKE_LENGTH: f64 = 2.0;

/// How the width of a stroke is fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum StrokeWidth {
    /// A radius function along the stroke (disk Wang–Ball curves), drawn as its filled
    /// envelope.
    Variable,
    /// One width per stroke, drawn as a stroked centre line.
    Constant,
}

impl StrokeWidth {
    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            StrokeWidth::Variable => "variable",
            StrokeWidth::Constant => "constant",
        }
    }
}

/// How a stroke ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum StrokeEnd {
    /// A free end (a pen lift).
    Free,
    /// At a junction (an index into [`CenterlineResult::junctions`]).
    Junction(usize),
}

/// One fitted stroke.
#[derive(Clone, Debug, Serialize)]
pub struct Stroke {
    /// True for a closed loop (an "o").
    pub closed: bool,
    /// How it starts and ends (both `Free` for a closed stroke).
    pub ends: [StrokeEnd; 2],
    /// Length of the fitted centre line, px.
    pub length: f64,
    /// Smallest and largest width (2 × radius) of the fitted curves, px.
    pub width_range: [f64; 2],
    /// Largest distance from a measured centre to the fitted centre line, px.
    pub centre_max: f64,
    /// Root mean square of those distances, px.
    pub centre_rms: f64,
    /// Largest difference between a measured radius and the fitted one, px.
    pub radius_max: f64,
    /// Root mean square of those differences, px.
    pub radius_rms: f64,
    /// The pieces, in order along the stroke.
    pub segments: Vec<StrokeSegment>,
    /// The measured centres and radii that were fitted.
    #[serde(skip)]
    pub(crate) data: Vec<(Point, f64)>,
}

impl Stroke {
    /// True when the centre line is shorter than [`STROKE_LIKE_LENGTH`] widths: a dot or a
    /// filled blob, not a stroke.
    pub fn is_stroke_like(&self) -> bool {
        self.length >= STROKE_LIKE_LENGTH * self.width_range[1]
    }

    /// The area its disks cover, roughly (mean width × length + the end caps).
    pub(crate) fn ink(&self) -> f64 {
        let r = (self.width_range[0] + self.width_range[1]) / 4.0;
        2.0 * r * self.length + std::f64::consts::PI * r * r
    }
}

/// A junction of strokes.
#[derive(Clone, Debug, Serialize)]
pub struct Junction {
    /// Its centre, px.
    pub centre: Point,
    /// Distance from the centre to the boundary, px.
    pub radius: f64,
    /// How many branches meet there.
    pub branches: usize,
}

/// The outcome of a centre-line trace.
#[derive(Clone, Debug, Serialize)]
pub struct CenterlineResult {
    /// What was detected about the input.
    pub image: ImageInfo,
    /// How widths were fitted.
    pub stroke_width: StrokeWidth,
    /// The strokes.
    pub strokes: Vec<Stroke>,
    /// The junctions.
    pub junctions: Vec<Junction>,
    /// Skeleton branches removed as spurs.
    pub spurs_removed: usize,
    /// The drawn strokes checked against the input.
    pub check: StrokeCheck,
    /// True when the strokes that are wider than long hold at least a quarter of the ink:
    /// the image is filled shapes rather than line art.
    pub not_stroke_like: bool,
    /// Wall time, seconds (0 when timing is off).
    pub seconds: f64,
    /// The thinned skeleton's pixel centres (for the overlay).
    #[serde(skip)]
    pub(crate) skeleton: Vec<Point>,
}

impl CenterlineResult {
    /// Number of fitted pieces over all strokes.
    pub fn segment_count(&self) -> usize {
        self.strokes.iter().map(|s| s.segments.len()).sum()
    }

    /// Strokes whose centre or radius misses the tolerance somewhere.
    pub fn strokes_over(&self, tolerance: f64) -> usize {
        self.strokes
            .iter()
            .filter(|s| s.centre_max > tolerance || s.radius_max > tolerance)
            .count()
    }
}

/// The verdict of the check.
#[derive(Clone, Debug, Default, Serialize)]
pub struct StrokeCheck {
    /// True when no lost or invented region reaches the region limit.
    pub held: bool,
    /// Intersection over union of the drawn strokes and the mask (pixel centres).
    pub iou: f64,
    /// Pixels lost (ink outside the strokes by more than the margin).
    pub lost_pixels: usize,
    /// Pixels invented (paper inside the strokes by more than the margin).
    pub invented_pixels: usize,
    /// Lost regions at or above the region limit.
    pub lost_regions: usize,
    /// Invented regions at or above the region limit.
    pub invented_regions: usize,
    /// The largest lost or invented region, pixels.
    pub largest_region: usize,
}
