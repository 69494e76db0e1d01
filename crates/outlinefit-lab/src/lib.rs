//! # outlinefit-lab
//!
//! The research lab around the [`outlinefit`] tracer: the papers' experiments and the
//! systems they describe beside curve fitting.
//!
//! * [`compare`] refits one segmentation with every optimizer of [`outlinefit::optim`] over
//!   many seeded runs, with descriptive statistics, normality and hypothesis tests
//!   ([`stats`]) and charts (`plotters`).
//! * [`bspline`] converts a parametric curve given by expressions into a B-spline
//!   (the fireworks paper).
//! * [`reduce`] reduces the degree of (SG-)Bézier curves (the grey-wolf paper).
//! * [`surface`] fits Bézier surfaces to point clouds (the cuckoo-search paper).
//! * [`merge`] is the two-curve disk Wang–Ball merge as a command: its input file, its
//!   picture and the BEESO paper's examples (the merge itself is
//!   [`outlinefit::merge::MergeProblem`]).
//!
//! Every failure is an [`Error`]: the tracer's own errors pass through unchanged.

pub mod bspline;
pub mod compare;
mod error;
pub mod merge;
pub mod reduce;
pub mod stats;
pub mod surface;

pub use crate::error::{Error, Result};
