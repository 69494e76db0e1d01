//! The separable search space (`--search weights`, variable projection): the optimizer
//! searches only the weights (w1, w2) of each segment (in the coordinates of
//! [`WeightsProblem`]); the control points are solved by least squares for each
//! candidate. Each smooth joint keeps the unit tangent of the `lsq` fit, which both
//! neighbours share, so G1 is exact and segments are independent.

use super::common::{finish_segment, rebuild, run_optimizer, RefitOptions};
use crate::fit::solve::{optimum_at_fixed_params, EndCondition, WeightsProblem};
use crate::fit::{FittedContour, JointKind};
use crate::optim::Optimizer;
use crate::param::centripetal_parameters;
use std::time::Instant;

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
pub(crate) fn fit_weights(
    base: &FittedContour,
    optimizer: &dyn Optimizer,
    opts: &RefitOptions,
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
