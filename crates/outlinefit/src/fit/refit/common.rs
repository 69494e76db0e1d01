//! What both search spaces of a refit share: the options, running the optimizer on one
//! segment with that segment's seed, and turning its outcome back into a fitted segment
//! and contour.

use crate::curve::RationalCubic;
use crate::fit::lsq::joint_report;
use crate::fit::solve::segment_error;
use crate::fit::{FittedContour, FittedSegment};
use crate::geom::Point;
use crate::optim::{Algorithm, Optimizer, Outcome, Problem, SeededRng};
use rand::SeedableRng;
use serde::Serialize;
use std::time::Instant;

/// What a metaheuristic searches for each segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Search {
    /// The HS paper's formulation: control points C1, C2 and weights w1, w2.
    Full,
    /// The separable formulation: weights only, control points by least squares.
    #[default]
    Weights,
}

impl Search {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Search::Full => "full",
            Search::Weights => "weights",
        }
    }
}

/// Options of a metaheuristic refit.
#[derive(Clone, Debug)]
pub struct RefitOptions {
    /// The metaheuristic.
    pub optimizer: Algorithm,
    /// The search space.
    pub search: Search,
    /// Objective evaluations per segment.
    pub budget: u64,
    /// Base seed of the per-segment generators.
    pub seed: u64,
    /// Record wall times.
    pub timings: bool,
    /// `full` only: scale of the control-point search box (1 = the paper's Eq. 9 box).
    pub box_scale: f64,
    /// Keep each segment's best-so-far history.
    pub history: bool,
}

/// Runs the optimizer on one segment's problem with that segment's seed.
pub(crate) fn run_optimizer(
    optimizer: &dyn Optimizer,
    problem: &dyn Problem,
    opts: &RefitOptions,
    contour_index: usize,
    segment: usize,
) -> Outcome {
    let mut rng = SeededRng::seed_from_u64(segment_seed(opts.seed, contour_index, segment));
    optimizer.minimize(problem, opts.budget, &mut rng, opts.history)
}

/// The fitted segment `k` for a curve found by an optimizer.
#[allow(clippy::too_many_arguments)]
pub(crate) fn finish_segment(
    base: &FittedContour,
    k: usize,
    curve: RationalCubic,
    run: &[Point],
    params: Vec<f64>,
    outcome: Outcome,
    on_search_boundary: bool,
    started: Instant,
    opts: &RefitOptions,
) -> FittedSegment {
    let seg = &base.segments[k];
    FittedSegment {
        error: segment_error(&curve, run, &params),
        curve,
        start: seg.start,
        end: seg.end,
        point_count: run.len(),
        params,
        arc_range: seg.arc_range,
        evaluations: outcome.evaluations,
        seconds: if opts.timings {
            started.elapsed().as_secs_f64()
        } else {
            0.0
        },
        on_search_boundary: Some(on_search_boundary),
        history: outcome.history,
        drawn: Default::default(),
    }
}

/// The contour with new segments and its joints re-measured.
pub(crate) fn rebuild(base: &FittedContour, segments: Vec<FittedSegment>) -> FittedContour {
    let joints = joint_report(
        &segments,
        base.joints.iter().map(|j| (j.index, j.kind)),
        &base.points,
    );
    FittedContour {
        points: base.points.clone(),
        is_hole: base.is_hole,
        parent: base.parent,
        segments,
        joints,
        tolerance: base.tolerance,
    }
}

/// True when some variable of `x` sits on a bound of the problem's box.
pub(crate) fn on_boundary(problem: &dyn Problem, x: &[f64]) -> bool {
    x.iter().enumerate().any(|(i, v)| {
        let (lo, hi) = problem.bounds(i);
        let eps = 1e-9 * (hi - lo).abs().max(1e-12);
        (v - lo).abs() <= eps || (hi - v).abs() <= eps
    })
}

/// Per-segment seed: a SplitMix64 mix of the base seed, contour and segment index.
pub fn segment_seed(seed: u64, contour: usize, segment: usize) -> u64 {
    let mut z =
        seed ^ ((contour as u64) << 32 | segment as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
