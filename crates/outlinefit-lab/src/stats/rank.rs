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
    // `+ 0.0`: an empty float sum is −0.0.
    let w_plus: f64 = r
        .iter()
        .zip(&d)
        .filter(|(_, d)| **d > 0.0)
        .map(|(r, _)| r)
        .sum::<f64>()
        + 0.0;
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

#[cfg(test)]
mod tests {
    //! Reference values from scipy 1.17.1: `scipy.stats.wilcoxon(x, y)` (and
    //! `method="approx"` for the tied case, where scipy's "auto" switches to a permutation
    //! test) and `scipy.stats.mannwhitneyu(x, y, method="asymptotic")`; the statistics are
    //! the sums of `scipy.stats.rankdata` over the positive differences and over x.
    use super::*;

    const SR_EXACT_X: &[f64] = &[
        0.304717, -1.039984, 0.750451, 0.940565, -1.951035, -1.30218, 0.12784, -0.316243,
        -0.016801, -0.853044, 0.879398, 0.777792, 0.066031, 1.127241, 0.467509, -0.859292,
        0.368751, -0.958883, 0.87845, -0.049926,
    ];
    const SR_EXACT_Y: &[f64] = &[
        0.215138, -0.28093, 1.622541, 0.245471, -0.028328, 0.047866, 0.932309, 0.765444, 0.812733,
        0.830821, 2.541648, -0.006415, -0.112243, -0.413773, 1.015979, 1.528972, 0.286053,
        -0.440156, -0.424481, 1.050593,
    ];
    const SR_APPROX_X: &[f64] = &[
        0.743254, 0.543154, -0.66551, 0.232161, 0.116686, 0.218689, 0.871429, 0.223596, 0.678914,
        0.067579, 0.289119, 0.631288, -1.457156, -0.319671, -0.470373, -0.638878, -0.275142,
        1.494941, -0.865831, 0.968278, -1.68287, -0.334885, 0.162753, 0.586222, 0.711227, 0.793347,
        -0.348725, -0.462352, 0.857976, -0.191304, -1.275686, -1.133287, -0.919452, 0.497161,
        0.142426, 0.690485, -0.427253, 0.15854, 0.62559, -0.309347, 0.456775, -0.661926, -0.363054,
        -0.381738, -1.19584, 0.486972, -0.469402, 0.012494, 0.480747, 0.446531, 0.665385,
        -0.098485, -0.423298, -0.079718, -1.687334, -1.447112, -1.3227, -0.997247, 0.399774,
        -0.905479,
    ];
    const SR_APPROX_Y: &[f64] = &[
        0.674173, 1.312768, -0.723642, 0.720919, -0.230123, 0.23597, 0.516418, 0.174079, 1.219068,
        -0.676081, 0.626331, 0.870156, -1.634231, -0.9227, -0.314308, -0.783624, -0.038804,
        1.625867, 0.055058, 0.9686, -2.074619, -0.125247, 0.392751, 1.385816, 1.248783, 1.091783,
        0.502926, -0.936734, 0.6581, -0.534592, -1.350591, -1.70163, -0.481877, 0.50605, -0.472977,
        0.302695, -0.150496, 0.697603, 1.743955, 1.267584, 0.78398, -1.036695, -1.309077,
        -0.127882, -1.482311, 0.399293, -0.65545, 0.062099, 1.133737, 0.645055, 0.706068,
        -0.496312, -1.140639, -0.202872, -1.594225, -0.443147, -1.137563, -0.385877, 0.270126,
        -1.377951,
    ];
    const SR_TIES_X: &[f64] = &[1.0, 2.0, 2.0, 3.0, 5.0, 5.0, 5.0, 7.0, 8.0, 9.0, 4.0, 4.0];
    const SR_TIES_Y: &[f64] = &[1.0, 1.0, 2.0, 4.0, 3.0, 3.0, 6.0, 6.0, 8.0, 8.0, 8.0, 2.0];
    const RS_TIES_X: &[f64] = &[
        2.0, 0.0, 1.0, 5.0, 5.0, 3.0, 3.0, 8.0, 4.0, 8.0, 9.0, 3.0, 2.0, 9.0, 6.0,
    ];
    const RS_TIES_Y: &[f64] = &[
        4.0, 8.0, 7.0, 11.0, 4.0, 11.0, 11.0, 3.0, 3.0, 7.0, 2.0, 4.0, 6.0, 11.0, 11.0, 3.0, 10.0,
        2.0,
    ];
    const RS_50_X: &[f64] = &[
        1.173501, 0.888129, 1.330861, 3.691385, 1.245308, 0.663035, 3.023118, 1.535347, 4.644836,
        1.201096, 0.293914, 0.254575, 5.211814, 5.605037, 0.835672, 0.681685, 4.312183, 0.330534,
        0.408719, 1.902801, 0.673946, 0.994891, 0.849215, 1.401544, 4.085654, 1.094814, 1.903965,
        0.128713, 0.952449, 0.430318, 0.295581, 0.41555, 0.715965, 2.49903, 0.265433, 1.031105,
        0.616209, 0.720599, 2.725789, 1.712776, 3.80912, 0.856839, 0.498604, 0.799428, 1.274427,
        1.193122, 0.338109, 1.09471, 1.256372, 12.397242,
    ];
    const RS_50_Y: &[f64] = &[
        8.492716, 0.55384, 0.975291, 0.30087, 0.720116, 1.782415, 4.341491, 0.627056, 0.675851,
        0.15184, 1.104838, 0.449306, 0.765616, 0.540913, 1.183057, 0.224167, 0.299788, 10.931094,
        0.358776, 0.434126, 8.160274, 23.746412, 0.402845, 0.899528, 1.829275, 7.323306, 0.48457,
        1.017233, 2.828374, 2.007982, 0.892444, 1.137168, 0.328726, 1.024485, 0.995985, 1.639734,
        0.74605, 2.083195, 3.578988, 1.518607, 1.848031, 1.370971, 1.30011, 0.631793, 1.784001,
        1.179485, 10.543743, 6.269641, 1.912117, 0.606111,
    ];

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs()
    }

    #[test]
    fn signed_rank_matches_scipy() {
        let t = wilcoxon_signed_rank(SR_EXACT_X, SR_EXACT_Y).unwrap();
        assert!(t.exact);
        assert_eq!((t.n, t.w_plus, t.w_minus), (20, 50.0, 160.0));
        assert!(close(t.p_value, 0.039989471435546875), "{}", t.p_value);
        let t = wilcoxon_signed_rank(SR_APPROX_X, SR_APPROX_Y).unwrap();
        assert!(!t.exact);
        assert_eq!(t.w_plus.min(t.w_minus), 792.0);
        assert!(close(t.p_value, 0.3652126497063902), "{}", t.p_value);
        let t = wilcoxon_signed_rank(SR_TIES_X, SR_TIES_Y).unwrap();
        assert!(!t.exact);
        assert_eq!((t.n, t.w_plus, t.w_minus), (9, 30.0, 15.0));
        assert!(close(t.p_value, 0.36396207510247747), "{}", t.p_value);
    }

    #[test]
    fn rank_sum_matches_scipy() {
        let t = wilcoxon_rank_sum(RS_TIES_X, RS_TIES_Y).unwrap();
        assert_eq!(t.rank_sum, 210.5);
        assert!(close(t.p_value, 0.10916178257750415), "{}", t.p_value);
        let t = wilcoxon_rank_sum(RS_50_X, RS_50_Y).unwrap();
        assert_eq!(t.rank_sum, 2468.0);
        assert!(close(t.p_value, 0.6969057019843775), "{}", t.p_value);
    }

    #[test]
    fn refuses_what_it_cannot_test() {
        assert!(matches!(
            wilcoxon_signed_rank(&[1.0, 2.0], &[1.0]),
            Err(StatsError::LengthMismatch { .. })
        ));
        assert!(matches!(
            wilcoxon_signed_rank(&[1.0, 2.0], &[1.0, 2.0]),
            Err(StatsError::ZeroVariance { .. })
        ));
        assert!(wilcoxon_rank_sum(&[1.0, f64::NAN], &[1.0]).is_err());
        // Every difference negative: W+ is 0 (not −0, which a report would print).
        let t = wilcoxon_signed_rank(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.0]).unwrap();
        assert!(t.w_plus == 0.0 && t.w_plus.is_sign_positive());
    }
}
