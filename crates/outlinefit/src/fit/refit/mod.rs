//! Refitting a given segmentation with a metaheuristic optimizer (any of [`crate::optim`]).
//! [`refit_contour`] is the entry point: it picks the search space of the options and hands
//! the segmentation to the module that owns it.
//!
//! The segmentation, the joint kinds and the fixed centripetal parameters (Eq. 2–3 of the
//! HS paper) come from the `lsq` fit, so every optimizer is compared on the same pieces
//! with the same Eq. 4 objective. Two search spaces:
//!
//! * [`Search::Full`], the HS paper's formulation (§6.1–6.3): the optimizer searches C1,
//!   C2, w1, w2 with odd segments free and even segments collinear-constrained at their
//!   joints ([`full`]).
//! * [`Search::Weights`] ([`weights`]), the separable formulation (variable projection): the optimizer searches
//!   only the weights (w1, w2) (in the coordinates of `WeightsProblem`); the control
//!   points are solved by least squares for each candidate. Each smooth joint keeps the unit tangent of the `lsq` fit, which both
//!   neighbours share, so G1 is exact and segments are independent.
//!
//! Each segment's generator is seeded from the base seed, the contour and the segment
//! index, so results do not depend on thread count or order.

mod common;
pub(crate) mod full;
mod weights;

pub use common::{segment_seed, RefitOptions, Search};
pub use weights::reference_errors;

use crate::fit::FittedContour;

/// Refits every segment of `base` (segmentation and joint kinds kept) with the optimizer
/// and search space of `opts`. `contour_index` feeds the per-segment seeds.
pub fn refit_contour(
    base: &FittedContour,
    opts: &RefitOptions,
    contour_index: usize,
) -> FittedContour {
    let optimizer = opts.optimizer.build();
    match opts.search {
        Search::Full => full::fit_contour(base, optimizer.as_ref(), opts, contour_index),
        Search::Weights => weights::fit_weights(base, optimizer.as_ref(), opts, contour_index),
    }
}
