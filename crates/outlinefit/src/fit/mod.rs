//! Fitting: one G1-continuous chain of rational cubic segments per contour.
//!
//! Two strategies share the data types here: `lsq` (the default; separable least
//! squares with exact G1 at every smooth joint and error-driven splitting) and `refit`
//! (an `lsq` segmentation refitted by a metaheuristic, in the HS paper's search space
//! of §6 or the separable one). `placement` moves the smooth
//! joints of an `lsq` chain to lower its total error (`--breaks optimize`).

pub(crate) mod lsq;
pub(crate) mod placement;
pub(crate) mod refit;
// Internal: public (and hidden from the docs) only so that the no-allocation test and the
// objective benchmark can drive the solver directly.
#[doc(hidden)]
pub mod solve;

pub(crate) use crate::breaks::JointKind;
pub use refit::{reference_errors, refit_contour, segment_seed, RefitOptions, Search};

use crate::curve::RationalCubic;
use crate::error::{Error, Result};
use crate::geom::{cyclic_run, Point};
use crate::optim::{Algorithm, NAMES};
use serde::Serialize;
use std::str::FromStr;

/// How segments are fitted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Separable least squares with error-driven splitting (`lsq`; the default).
    #[default]
    Lsq,
    /// The `lsq` segmentation refitted by a metaheuristic at fixed centripetal parameters
    /// ([`refit_contour`]).
    Metaheuristic(Algorithm),
}

impl Method {
    /// The command-line and report name: `lsq` or the algorithm's name.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Lsq => "lsq",
            Method::Metaheuristic(a) => a.name(),
        }
    }

    /// The metaheuristic, unless the method is `lsq`.
    pub fn algorithm(self) -> Option<Algorithm> {
        match self {
            Method::Lsq => None,
            Method::Metaheuristic(a) => Some(a),
        }
    }
}

impl FromStr for Method {
    type Err = Error;

    /// `lsq` or a name of [`NAMES`]; an error names the field `optimizer`.
    fn from_str(s: &str) -> Result<Method> {
        if s == Method::Lsq.name() {
            return Ok(Method::Lsq);
        }
        Algorithm::from_name(s)
            .map(Method::Metaheuristic)
            .ok_or_else(|| Error::InvalidOption {
                name: "optimizer",
                message: format!(
                    "unknown optimizer `{s}` (expected lsq or one of {})",
                    NAMES.join(", ")
                ),
            })
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Method {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// The meeting point of segment `i − 1` and segment `i` of a contour.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Joint {
    /// Corner or smooth.
    pub kind: JointKind,
    /// Position (the shared end point).
    pub position: Point,
    /// Index of the joint in the contour's point list.
    pub index: usize,
    /// Angle in radians between the end tangent of the previous segment and the start
    /// tangent of the next one (0 for a perfect G1 joint).
    pub angle: f64,
    /// β of Eq. 8 of the HS paper: |P'(u⁺)| / |P'(u⁻)|.
    pub beta: f64,
}

/// Error measures of one fitted segment against its data points.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct SegmentError {
    /// Eq. 4 of the HS paper: Σ |P(u_i) − Q_i|² at the segment's final parameters.
    pub sum_sq: f64,
    /// sqrt(sum_sq / n).
    pub rmse: f64,
    /// Largest distance from a data point to the curve, by projection onto the curve.
    pub max_distance: f64,
    /// Mean distance from the data points to the curve, by projection.
    pub mean_distance: f64,
}

/// One fitted segment.
#[derive(Clone, Debug, Serialize)]
pub struct FittedSegment {
    /// The curve.
    pub curve: RationalCubic,
    /// Index of the first data point (the start joint) in the contour's point list.
    pub start: usize,
    /// Index of the last data point (the end joint); smaller than `start` when the segment
    /// wraps past the end of the list.
    pub end: usize,
    /// Number of data points fitted, both end points included.
    pub point_count: usize,
    /// Parameter of each data point on the curve, in [0, 1] (centripetal, Eq. 2–3, then
    /// refined by projection when the strategy does so).
    pub params: Vec<f64>,
    /// Arc-length position of the start and end along the contour polygon, in pixels.
    pub arc_range: [f64; 2],
    /// Error measures.
    pub error: SegmentError,
    /// Objective evaluations spent on this segment.
    pub evaluations: u64,
    /// Wall time spent fitting this segment, in seconds (0 when timing is off).
    pub seconds: f64,
    /// Metaheuristic fits only: true when the best point found lies on the boundary of the
    /// search box (Eq. 9 of the HS paper for `full` search, the weight range for `weights`),
    /// a sign that the box may exclude the optimum.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub on_search_boundary: Option<bool>,
    /// Metaheuristic fits with history on: the best objective value after each evaluation.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub history: Vec<f64>,
    /// The polynomial cubics the SVG draws for `curve`, when the fit already made them
    /// (see [`FittedSegment::drawn_cubics`]).
    #[serde(skip)]
    pub(crate) drawn: DrawnCubics,
}

/// Polynomial cubics approximating a rational segment within a bound, kept from the fit
/// (which needs them to count SVG pieces) so that the fidelity check and the SVG writer do
/// not compute them again. They stay tied to the curve and bound they were made for.
#[derive(Clone, Debug, Default)]
pub(crate) struct DrawnCubics {
    /// A 64-bit fingerprint of the curve and bound they were made for ([`fingerprint`]):
    /// eight bytes per segment instead of a copy of the curve (a page has 35 000).
    made_for: Option<u64>,
    cubics: Vec<crate::curve::CubicBez>,
}

/// The fingerprint of a curve and a bound: a hash of their bits, with fixed keys (the same
/// in every run).
fn fingerprint(curve: &RationalCubic, bound: f64) -> u64 {
    use std::hash::Hasher;
    // The eleven numbers' bits in one write: a write per number cost the scan of
    // `make_scan.py` a million hasher calls.
    let p = &curve.points;
    let values = [
        p[0].x,
        p[0].y,
        p[1].x,
        p[1].y,
        p[2].x,
        p[2].y,
        p[3].x,
        p[3].y,
        curve.weights[0],
        curve.weights[1],
        bound,
    ];
    let mut bytes = [0u8; 88];
    for (chunk, v) in bytes.chunks_exact_mut(8).zip(values) {
        chunk.copy_from_slice(&v.to_bits().to_le_bytes());
    }
    let mut h = std::collections::hash_map::DefaultHasher::new();
    h.write(&bytes);
    h.finish()
}

impl DrawnCubics {
    /// `cubics`, the approximation of `curve` within `bound`.
    pub(crate) fn new(
        curve: RationalCubic,
        bound: f64,
        cubics: Vec<crate::curve::CubicBez>,
    ) -> Self {
        DrawnCubics {
            made_for: Some(fingerprint(&curve, bound)),
            cubics,
        }
    }
}

impl FittedSegment {
    /// The polynomial cubics that draw this segment within `bound` px
    /// ([`crate::curve::approximate_with_cubics`]): the ones kept from the fit when they
    /// were made for this very curve and bound (same 64-bit fingerprint), otherwise
    /// computed now.
    pub fn drawn_cubics(&self, bound: f64) -> std::borrow::Cow<'_, [crate::curve::CubicBez]> {
        match self.drawn.made_for {
            Some(print) if print == fingerprint(&self.curve, bound) => {
                std::borrow::Cow::Borrowed(&self.drawn.cubics)
            }
            _ => std::borrow::Cow::Owned(crate::curve::approximate_with_cubics(&self.curve, bound)),
        }
    }
}

/// A closed contour fitted by a closed chain of segments.
#[derive(Clone, Debug, Serialize)]
pub struct FittedContour {
    /// The data points that were fitted (sub-pixel boundary points, with break points
    /// inserted where they fall between samples).
    pub points: Vec<Point>,
    /// True for the border of a hole.
    pub is_hole: bool,
    /// Index of the enclosing contour, as in `crate::contour::Contour::parent`.
    pub parent: Option<usize>,
    /// Segments in order; segment i runs from joint i to joint i + 1 (cyclically).
    pub segments: Vec<FittedSegment>,
    /// `joints[i]` is where `segments[i − 1]` ends and `segments[i]` starts.
    pub joints: Vec<Joint>,
    /// The tolerance (px) the contour was fitted to: the trace's `--tolerance`, widened
    /// on a blurred edge (see `Config::edge_tolerance`) and tightened by a repair.
    pub tolerance: f64,
}

impl FittedContour {
    /// Largest point-to-curve distance over all segments.
    pub fn max_distance(&self) -> f64 {
        self.segments
            .iter()
            .map(|s| s.error.max_distance)
            .fold(0.0, f64::max)
    }

    /// The data points of segment `k`, from its start joint to its end joint, into `out`.
    pub fn segment_points_into(&self, k: usize, out: &mut Vec<Point>) {
        let s = &self.segments[k];
        cyclic_run(&self.points, s.start, s.end, out);
    }

    /// The data points of segment `k`, from its start joint to its end joint.
    pub fn segment_points(&self, k: usize) -> Vec<Point> {
        let mut out = Vec::new();
        self.segment_points_into(k, &mut out);
        out
    }

    /// Sum of Eq. 4 errors over all segments.
    pub fn sum_sq(&self) -> f64 {
        self.segments.iter().map(|s| s.error.sum_sq).sum()
    }
}
