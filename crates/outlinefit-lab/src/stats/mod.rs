//! Statistics for comparing optimizers over independent runs (the HS paper's Tables 2–6):
//! descriptive statistics, normality tests, the F-test for two variances, Welch's t-test and
//! one-way ANOVA.
//!
//! Every function checks its input and returns a [`StatsError`] instead of a NaN or a panic:
//! too few (or too many) values, a non-finite value, or zero variance where the test divides
//! by it (a deterministic method that gives 30 identical errors). A report prints such an
//! error as "n/a".
//!
//! The tests are written out here; only the reference distributions (Student's t,
//! Fisher–Snedecor, the normal) come from `statrs`. They agree with scipy / statsmodels (see
//! `tools/stats_vectors.py` and the tests for the tolerances).
//!
//! | paper | function |
//! |---|---|
//! | Table 2, descriptive data | [`describe`] |
//! | Table 3, tests of normality | [`lilliefors`], [`shapiro_wilk`] |
//! | Table 4, independent-group ANOVA | [`anova_oneway`] |
//! | Table 5, F-test two-sample for variances | [`f_test`] |
//! | Table 6, t-test two-sample assuming unequal variances | [`welch_t`] |
//! | surface paper, Table 5, Wilcoxon signed-rank and rank-sum | [`wilcoxon_signed_rank`], [`wilcoxon_rank_sum`] |

mod hypothesis;
mod normality;
mod rank;

pub use hypothesis::{anova_oneway, f_test, welch_t, Anova, FTest, TTest};
pub use normality::{lilliefors, shapiro_wilk, Normality};
pub use rank::{wilcoxon_rank_sum, wilcoxon_signed_rank, RankSum, SignedRank};

use serde::Serialize;

/// Significance level of the critical values reported by [`f_test`], [`welch_t`] and
/// [`anova_oneway`] (the paper's tables use 0.05).
pub const ALPHA: f64 = 0.05;

/// Why a statistic could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StatsError {
    /// A sample (or the data of a test) has fewer values than the statistic needs.
    #[error("{what} needs at least {needed} values, got {got}")]
    TooFewValues {
        /// The statistic or test.
        what: &'static str,
        /// The smallest accepted number of values.
        needed: usize,
        /// The number given.
        got: usize,
    },
    /// A sample has more values than the method supports (Shapiro–Wilk: 5000).
    #[error("{what} accepts at most {max} values, got {got}")]
    TooManyValues {
        /// The statistic or test.
        what: &'static str,
        /// The largest accepted number of values.
        max: usize,
        /// The number given.
        got: usize,
    },
    /// Paired samples of different lengths.
    #[error("{what} needs paired samples of equal length, got {left} and {right} values")]
    LengthMismatch {
        /// The statistic or test.
        what: &'static str,
        /// Length of the first sample.
        left: usize,
        /// Length of the second sample.
        right: usize,
    },
    /// A one-way ANOVA needs at least two groups.
    #[error("one-way ANOVA needs at least 2 groups, got {got}")]
    TooFewGroups {
        /// The number of groups given.
        got: usize,
    },
    /// The data have zero variance where the test divides by it (for instance a
    /// deterministic method that gave the same value in every run).
    #[error("{what}: the data have zero variance")]
    ZeroVariance {
        /// The statistic or test.
        what: &'static str,
    },
    /// An intermediate result overflowed (finite values too close to `f64::MAX`).
    #[error("{what}: the computation overflowed")]
    Overflow {
        /// The statistic or test.
        what: &'static str,
    },
    /// A value is NaN or infinite.
    #[error("{what}: value #{index} is not finite ({value})")]
    NonFinite {
        /// The statistic or test.
        what: &'static str,
        /// Its position in the sample (0-based).
        index: usize,
        /// The value.
        value: f64,
    },
}

/// Descriptive statistics of one sample (the paper's Table 2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Describe {
    /// Number of values.
    pub n: usize,
    /// The smallest value (the best error of a minimizer).
    pub best: f64,
    /// The largest value (the worst error).
    pub worst: f64,
    /// Arithmetic mean.
    pub mean: f64,
    /// Median (the 50 % quantile).
    pub median: f64,
    /// Sample variance, with the n − 1 denominator.
    pub variance: f64,
    /// Sample standard deviation, the square root of `variance`.
    pub std_dev: f64,
    /// First quartile (25 % quantile, linear interpolation as numpy's default).
    pub q1: f64,
    /// Third quartile (75 % quantile, linear interpolation as numpy's default).
    pub q3: f64,
}

/// Descriptive statistics of `x`: n, best (min), worst (max), mean, median, sample variance
/// and standard deviation (n − 1), and the quartiles by linear interpolation between order
/// statistics (numpy's default `percentile` rule: position (n − 1)·q).
///
/// Needs at least 2 finite values. Zero variance is not an error here.
pub fn describe(x: &[f64]) -> Result<Describe, StatsError> {
    const WHAT: &str = "descriptive statistics";
    check_sample(WHAT, x, 2)?;
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    let (mean, variance) = mean_var(x);
    check_overflow(WHAT, &[mean, variance])?;
    Ok(Describe {
        n: x.len(),
        best: sorted[0],
        worst: sorted[sorted.len() - 1],
        mean,
        median: median_sorted(&sorted),
        variance,
        std_dev: variance.sqrt(),
        q1: quantile_sorted(&sorted, 0.25),
        q3: quantile_sorted(&sorted, 0.75),
    })
}

/// The `q` quantile of sorted, non-empty data by linear interpolation (numpy's "linear",
/// including its choice of interpolating from the nearer end). The one quantile of the
/// crate: the statistics and the box plots use it.
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    let pos = (sorted.len() - 1) as f64 * q;
    let lo = pos.floor() as usize;
    let t = pos - lo as f64;
    if lo + 1 >= sorted.len() || t == 0.0 {
        return sorted[lo];
    }
    let (a, b) = (sorted[lo], sorted[lo + 1]);
    if t < 0.5 {
        a + (b - a) * t
    } else {
        b - (b - a) * (1.0 - t)
    }
}

/// The median of sorted, non-empty data (the mean of the two middle values for even n).
fn median_sorted(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    }
}

/// Checks that `x` has at least `needed` values, all finite.
fn check_sample(what: &'static str, x: &[f64], needed: usize) -> Result<(), StatsError> {
    if x.len() < needed {
        return Err(StatsError::TooFewValues {
            what,
            needed,
            got: x.len(),
        });
    }
    check_finite(what, x)
}

/// Checks that every value of `x` is finite.
fn check_finite(what: &'static str, x: &[f64]) -> Result<(), StatsError> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(StatsError::NonFinite {
            what,
            index,
            value: x[index],
        }),
        None => Ok(()),
    }
}

/// Errors out when an intermediate result overflowed (finite data near `f64::MAX`).
fn check_overflow(what: &'static str, values: &[f64]) -> Result<(), StatsError> {
    check_finite(what, values).map_err(|_| StatsError::Overflow { what })
}

/// Mean and sample variance (n − 1) of at least two values, by two passes.
fn mean_var(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let ss: f64 = x.iter().map(|v| (v - mean) * (v - mean)).sum();
    (mean, ss / (n - 1.0))
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod vectors;
