//! Refitting a given segmentation with a metaheuristic optimizer (any of [`crate::optim`]):
//! the options, the per-segment machinery both search spaces share, and the separable one.
//! [`super::refit::fit_contour`] is the entry point that picks the search space.
//!
//! The segmentation, the joint kinds and the fixed centripetal parameters (Eq. 2–3 of the
//! HS paper) come from the `lsq` fit, so every optimizer is compared on the same pieces
//! with the same Eq. 4 objective. Two search spaces:
//!
//! * [`Search::Full`], the HS paper's formulation (§6.1–6.3): the optimizer searches C1,
//!   C2, w1, w2 with odd segments free and even segments collinear-constrained at their
//!   joints ([`super::paper`]).
//! * [`Search::Weights`], the separable formulation (variable projection): the optimizer searches
//!   only the weights (w1, w2) (in the coordinates of [`WeightsProblem`]); the control
//!   points are solved by least squares for each candidate. Each smooth joint keeps the unit tangent of the `lsq` fit, which both
//!   neighbours share, so G1 is exact and segments are independent.
//!
//! Each segment's generator is seeded from the base seed, the contour and the segment
//! index, so results do not depend on thread count or order.

use super::lsq::joint_report;
use super::solve::{optimum_at_fixed_params, segment_error, EndCondition, WeightsProblem};
use super::{FittedContour, FittedSegment, JointKind};
use crate::curve::RationalCubic;
use crate::geom::Point;
use crate::optim::{Algorithm, Optimizer, Outcome, Problem, SeededRng};
use crate::param::centripetal_parameters;
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
pub struct MetaOptions {
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

/// The end conditions of segment `k` in the separable formulation: at a smooth joint the
/// unit tangent the `lsq` fit gave both neighbours, at a corner none.
pub(crate) fn end_conditions(base: &FittedContour, k: usize) -> (EndCondition, EndCondition) {
    let m = base.segments.len();
    let tangent_at = |j: usize| {
        if base.joints.get(j).map(|j| j.kind) != Some(JointKind::Smooth) {
            return EndCondition::Free;
        }
        // Segment j starts at joint j: C1 − C0 lies along the shared tangent.
        let c = &base.segments[j].curve.points;
        (c[1] - c[0])
            .normalized()
            .map_or(EndCondition::Free, EndCondition::Tangent)
    };
    (tangent_at(k), tangent_at((k + 1) % m))
}

/// The separable least-squares optimum of every segment of `base` under the `weights`
/// formulation (same end conditions, same fixed centripetal parameters): the reference a
/// metaheuristic's Eq. 4 error is measured against.
pub fn reference_errors(base: &FittedContour) -> Vec<f64> {
    let mut run = Vec::new();
    (0..base.segments.len())
        .map(|k| {
            base.segment_points_into(k, &mut run);
            if run.len() < 3 {
                return 0.0;
            }
            let params = centripetal_parameters(&run);
            let (start, end) = end_conditions(base, k);
            optimum_at_fixed_params(&run, &params, start, end).1
        })
        .collect()
}

/// `weights` search: every segment independently, control points by least squares.
pub(super) fn fit_weights(
    base: &FittedContour,
    optimizer: &dyn Optimizer,
    opts: &MetaOptions,
    contour_index: usize,
) -> FittedContour {
    let mut run = Vec::new();
    let segments = (0..base.segments.len())
        .map(|k| {
            base.segment_points_into(k, &mut run);
            if run.len() < 3 {
                return base.segments[k].clone();
            }
            let started = Instant::now();
            let params = centripetal_parameters(&run);
            let (start, end) = end_conditions(base, k);
            let problem = WeightsProblem::new(&run, &params, start, end);
            let outcome = run_optimizer(optimizer, &problem, opts, contour_index, k);
            let (curve, _) = problem.curve(&outcome.best);
            let on_boundary = WeightsProblem::on_weight_bound(&outcome.best);
            finish_segment(
                base,
                k,
                curve,
                &run,
                params,
                outcome,
                on_boundary,
                started,
                opts,
            )
        })
        .collect();
    rebuild(base, segments)
}

/// Runs the optimizer on one segment's problem with that segment's seed.
pub(super) fn run_optimizer(
    optimizer: &dyn Optimizer,
    problem: &dyn Problem,
    opts: &MetaOptions,
    contour_index: usize,
    segment: usize,
) -> Outcome {
    let mut rng = SeededRng::seed_from_u64(segment_seed(opts.seed, contour_index, segment));
    optimizer.minimize(problem, opts.budget, &mut rng, opts.history)
}

/// The fitted segment `k` for a curve found by an optimizer.
#[allow(clippy::too_many_arguments)]
pub(super) fn finish_segment(
    base: &FittedContour,
    k: usize,
    curve: RationalCubic,
    run: &[Point],
    params: Vec<f64>,
    outcome: Outcome,
    on_search_boundary: bool,
    started: Instant,
    opts: &MetaOptions,
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
pub(super) fn rebuild(base: &FittedContour, segments: Vec<FittedSegment>) -> FittedContour {
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
    }
}

/// True when some variable of `x` sits on a bound of the problem's box.
pub(super) fn on_boundary(problem: &dyn Problem, x: &[f64]) -> bool {
    x.iter().enumerate().any(|(i, v)| {
        let (lo, hi) = problem.bounds(i);
        let eps = 1e-9 * (hi - lo).abs().max(1e-12);
        (v - lo).abs() <= eps || (hi - v).abs() <= eps
    })
}

/// Per-segment seed: a SplitMix64 mix of the base seed, contour and segment index.
pub(crate) fn segment_seed(seed: u64, contour: usize, segment: usize) -> u64 {
    let mut z =
        seed ^ ((contour as u64) << 32 | segment as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
