//! Rank tests for two samples of runs (the surface paper's Table 5): the Wilcoxon
//! signed-rank test for paired samples and the Wilcoxon rank-sum test (Mann–Whitney U) for
//! independent ones, both two-sided.
//!
//! They follow scipy's definitions, so their p-values can be checked against it:
//! [`wilcoxon_signed_rank`] is `scipy.stats.wilcoxon(x, y)` (zero differences dropped,
//! the exact null distribution when at most 50 differences remain and none tie, otherwise
//! the normal approximation with the tie correction and no continuity correction);
//! [`wilcoxon_rank_sum`] is `scipy.stats.mannwhitneyu(x, y, method="asymptotic")` (normal
//! approximation with tie and continuity corrections). The normal tail is `libm`'s erfc,
//! accurate to the last bits.

use super::{check_sample, StatsError};
use serde::Serialize;

/// A Wilcoxon signed-rank test of x against y.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SignedRank {
    /// Pairs with a non-zero difference.
    pub n: usize,
    /// Sum of the ranks of |x − y| over the pairs with x > y.
    pub w_plus: f64,
    /// Sum of the ranks over the pairs with x < y.
    pub w_minus: f64,
    /// Two-sided p-value.
    pub p_value: f64,
    /// Whether the p-value comes from the exact null distribution.
    pub exact: bool,
}

/// A Wilcoxon rank-sum (Mann–Whitney) test of x against y.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RankSum {
    /// Sum of the ranks of x in the pooled sample (ties get their average rank).
    pub rank_sum: f64,
    /// Mann–Whitney U of x: `rank_sum − n_x (n_x + 1) / 2`.
    pub u: f64,
    /// Two-sided p-value.
    pub p_value: f64,
}

/// Ranks 1..=n of `v` (average ranks for ties) and Σ (t³ − t) over the tie groups.
fn ranks(v: &[f64]) -> (Vec<f64>, f64) {
    let mut order: Vec<usize> = (0..v.len()).collect();
    order.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut ties = 0.0;
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && v[order[j + 1]] == v[order[i]] {
            j += 1;
        }
        let avg = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            r[k] = avg;
        }
        let t = (j - i + 1) as f64;
        ties += t * t * t - t;
        i = j + 1;
    }
    (r, ties)
}

/// Two-sided normal p-value of z.
fn normal_two_sided(z: f64) -> f64 {
    libm::erfc(z.abs() / std::f64::consts::SQRT_2).min(1.0)
}

/// The Wilcoxon signed-rank test of paired samples `x` and `y` (same length, at least one
/// non-zero difference).
pub fn wilcoxon_signed_rank(x: &[f64], y: &[f64]) -> Result<SignedRank, StatsError> {
    const WHAT: &str = "Wilcoxon signed-rank test";
    check_sample(WHAT, x, 1)?;
    check_sample(WHAT, y, 1)?;
    if x.len() != y.len() {
        return Err(StatsError::LengthMismatch {
            what: WHAT,
            left: x.len(),
            right: y.len(),
        });
    }
    let d: Vec<f64> = x
        .iter()
        .zip(y)
        .map(|(a, b)| a - b)
        .filter(|d| *d != 0.0)
        .collect();
    if d.is_empty() {
        return Err(StatsError::ZeroVariance { what: WHAT });
    }
    let n = d.len();
    let abs: Vec<f64> = d.iter().map(|v| v.abs()).collect();
    let (r, ties) = ranks(&abs);
    let w_plus: f64 = r
        .iter()
        .zip(&d)
        .filter(|(_, d)| **d > 0.0)
        .map(|(r, _)| r)
        .sum();
    let total = (n * (n + 1)) as f64 / 2.0;
    let w_minus = total - w_plus;
    let nf = n as f64;
    let exact = n <= 50 && ties == 0.0;
    let p_value = if exact {
        // Number of subsets of {1..n} with each rank sum: the null distribution of W+.
        let max = n * (n + 1) / 2;
        let mut count = vec![0u64; max + 1];
        count[0] = 1;
        for k in 1..=n {
            for s in (k..=max).rev() {
                count[s] += count[s - k];
            }
        }
        let t = w_plus.min(w_minus).round() as usize;
        let below: u64 = count[..=t].iter().sum();
        (2.0 * below as f64 / 2f64.powi(n as i32)).min(1.0)
    } else {
        let mean = nf * (nf + 1.0) / 4.0;
        let var = (nf * (nf + 1.0) * (2.0 * nf + 1.0) - 0.5 * ties) / 24.0;
        if var <= 0.0 {
            return Err(StatsError::ZeroVariance { what: WHAT });
        }
        normal_two_sided((w_plus.min(w_minus) - mean) / var.sqrt())
    };
    Ok(SignedRank {
        n,
        w_plus,
        w_minus,
        p_value,
        exact,
    })
}

/// The Wilcoxon rank-sum (Mann–Whitney U) test of independent samples `x` and `y`.
pub fn wilcoxon_rank_sum(x: &[f64], y: &[f64]) -> Result<RankSum, StatsError> {
    const WHAT: &str = "Wilcoxon rank-sum test";
    check_sample(WHAT, x, 1)?;
    check_sample(WHAT, y, 1)?;
    let pooled: Vec<f64> = x.iter().chain(y).copied().collect();
    let (r, ties) = ranks(&pooled);
    let (n1, n2) = (x.len() as f64, y.len() as f64);
    let n = n1 + n2;
    let rank_sum: f64 = r[..x.len()].iter().sum();
    let u1 = rank_sum - n1 * (n1 + 1.0) / 2.0;
    let u = u1.max(n1 * n2 - u1);
    let mean = n1 * n2 / 2.0;
    let var = n1 * n2 / 12.0 * ((n + 1.0) - ties / (n * (n - 1.0)));
    if var <= 0.0 {
        return Err(StatsError::ZeroVariance { what: WHAT });
    }
    let z = (u - mean - 0.5) / var.sqrt();
    Ok(RankSum {
        rank_sum,
        u: u1,
        p_value: normal_two_sided(z),
    })
}
