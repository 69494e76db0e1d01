//! The entry point of a metaheuristic refit: it picks the search space of the options and
//! hands the segmentation to the module that owns it ([`super::paper`] for
//! [`Search::Full`], [`super::meta`] for [`Search::Weights`]). Kept apart from both so that
//! neither of them imports the other's caller.

use super::meta::{fit_weights, MetaOptions, Search};
use super::{paper, FittedContour};

/// Refits every segment of `base` (segmentation and joint kinds kept) with the optimizer
/// and search space of `opts`. `contour_index` feeds the per-segment seeds.
pub fn fit_contour(
    base: &FittedContour,
    opts: &MetaOptions,
    contour_index: usize,
) -> FittedContour {
    let optimizer = opts.optimizer.build();
    match opts.search {
        Search::Full => paper::fit_contour(base, optimizer.as_ref(), opts, contour_index),
        Search::Weights => fit_weights(base, optimizer.as_ref(), opts, contour_index),
    }
}
