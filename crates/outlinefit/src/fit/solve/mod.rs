//! Fitting one rational cubic segment to a run of data points: the segment-fitting seam
//! every strategy uses.
//!
//! The end points C0 and C3 are the first and last data points. Each end is either free
//! (C1 or C2 is an unknown point) or tangent-constrained (C1 = C0 + a·t0, C2 = C3 − b·t3
//! with given unit tangents and unknown lengths a, b > 0), which is how G1 joints are made
//! exact: both neighbours of a smooth joint use the same unit tangent.
//!
//! **Separable least squares.** For fixed weights (w1, w2) and parameters u_i the curve
//! is linear in the unknowns, P(u) = Σ φ_k(u) C_k with φ_k = B_k w_k / D known numbers, so
//! the unknowns come from a normal system of at most 4 × 4 ([`solve_control_points`]).
//! The weights are then searched in [0.01, 2.5] by a deterministic compass search in
//! log-space ([`fit_segment`]), the parameters are refined by projecting the points onto
//! the curve, and a Levenberg–Marquardt polish minimises the true (orthogonal) distances
//! over control points and weights together, so that data lying exactly on a rational
//! cubic is recovered to round-off.
//!
//! Files: `model` (the linear model and its small solvers), `weights` (the weight search),
//! `polish` (Levenberg–Marquardt), `segment` (one segment from start to error measures).

mod model;
mod polish;
mod segment;
mod weights;

pub use model::{solve_control_points, EndCondition, FitSettings, SegmentSolution, WEIGHT_RANGE};
pub(crate) use segment::spread_params;
pub use segment::{
    fit_polynomial_until, fit_segment, fit_segment_from, optimum_at_fixed_params,
    resume_polynomial, segment_error, Stopped,
};
pub(crate) use weights::every;
pub use weights::WeightsProblem;
// For the no-allocation test and the objective benchmark: the full search space's
// segment problem and the parameters both search spaces fit at.
pub use crate::fit::refit::full::SegmentProblem;
pub use crate::param::centripetal_parameters;

#[cfg(test)]
mod tests;
