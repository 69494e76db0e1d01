//! Two-sample and k-sample tests: the F-test for two variances, Welch's t-test and one-way
//! ANOVA, with the layout of Excel's Analysis ToolPak tables that the paper reproduces.

use super::{check_overflow, check_sample, mean_var, StatsError, ALPHA};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, FisherSnedecor, StudentsT};
use statrs::function::beta::beta_reg;

/// An F-test for the equality of two variances (the paper's Table 5, Excel's "F-Test
/// Two-Sample for Variances").
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FTest {
    /// Number of values in the first sample.
    pub n_a: usize,
    /// Number of values in the second sample.
    pub n_b: usize,
    /// Mean of the first sample.
    pub mean_a: f64,
    /// Mean of the second sample.
    pub mean_b: f64,
    /// Sample variance (n − 1) of the first sample.
    pub variance_a: f64,
    /// Sample variance (n − 1) of the second sample.
    pub variance_b: f64,
    /// F = variance_a / variance_b.
    pub f: f64,
    /// Numerator degrees of freedom, n_a − 1.
    pub df1: f64,
    /// Denominator degrees of freedom, n_b − 1.
    pub df2: f64,
    /// P(F ≤ f) under equal variances: small when var(a) is significantly smaller.
    pub p_lower: f64,
    /// P(F ≥ f) under equal variances: small when var(a) is significantly larger.
    pub p_upper: f64,
    /// Excel's "P(F<=f) one-tail": the tail in the direction of the observed ratio,
    /// `p_lower` when f < 1 and `p_upper` otherwise.
    pub p_one_tail: f64,
    /// Two-tailed p-value, min(1, 2·min(p_lower, p_upper)) (Excel's `F.TEST`).
    pub p_two_tail: f64,
    /// Excel's "F critical one-tail" at [`ALPHA`], in the direction of the observed ratio:
    /// the α quantile when f < 1, the 1 − α quantile otherwise.
    pub f_crit_one_tail: f64,
}

/// The F-test of var(a) = var(b): F = var(a)/var(b) with (n_a − 1, n_b − 1) degrees of
/// freedom, one-tailed p-values both ways, the one-tailed p-value and critical value in
/// the direction of the observed ratio (as Excel's table), and the two-tailed p-value.
///
/// Needs at least 2 finite values per sample and nonzero variance in both.
pub fn f_test(a: &[f64], b: &[f64]) -> Result<FTest, StatsError> {
    const WHAT: &str = "F-test for variances";
    check_sample(WHAT, a, 2)?;
    check_sample(WHAT, b, 2)?;
    let (mean_a, variance_a) = mean_var(a);
    let (mean_b, variance_b) = mean_var(b);
    check_overflow(WHAT, &[mean_a, mean_b, variance_a, variance_b])?;
    if variance_a == 0.0 || variance_b == 0.0 {
        return Err(StatsError::ZeroVariance { what: WHAT });
    }
    let f = variance_a / variance_b;
    check_overflow(WHAT, &[f])?;
    let (df1, df2) = ((a.len() - 1) as f64, (b.len() - 1) as f64);
    let p_lower = f_cdf(f, df1, df2);
    let p_upper = f_sf(f, df1, df2);
    let below = f < 1.0;
    Ok(FTest {
        n_a: a.len(),
        n_b: b.len(),
        mean_a,
        mean_b,
        variance_a,
        variance_b,
        f,
        df1,
        df2,
        p_lower,
        p_upper,
        p_one_tail: if below { p_lower } else { p_upper },
        p_two_tail: (2.0 * p_lower.min(p_upper)).min(1.0),
        f_crit_one_tail: f_ppf(if below { ALPHA } else { 1.0 - ALPHA }, df1, df2),
    })
}

/// Welch's two-sample t-test assuming unequal variances (the paper's Table 6, Excel's
/// "t-Test: Two-Sample Assuming Unequal Variances" with hypothesized difference 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TTest {
    /// Number of values in the first sample.
    pub n_a: usize,
    /// Number of values in the second sample.
    pub n_b: usize,
    /// Mean of the first sample.
    pub mean_a: f64,
    /// Mean of the second sample.
    pub mean_b: f64,
    /// Sample variance (n − 1) of the first sample.
    pub variance_a: f64,
    /// Sample variance (n − 1) of the second sample.
    pub variance_b: f64,
    /// t = (mean_a − mean_b) / sqrt(variance_a/n_a + variance_b/n_b).
    pub t: f64,
    /// Welch–Satterthwaite degrees of freedom, unrounded (as scipy and R; every p-value and
    /// critical value here uses it).
    pub df: f64,
    /// `df` rounded to the nearest integer, the "df" row of Excel's table. (Excel also
    /// computes its p-values and critical values with this rounded df, so its figures
    /// differ slightly from these.)
    pub df_rounded: f64,
    /// P-value for the alternative mean_a < mean_b (P(T ≤ t)).
    pub p_less: f64,
    /// P-value for the alternative mean_a > mean_b (P(T ≥ t)).
    pub p_greater: f64,
    /// Excel's "P(T<=t) one-tail": P(T ≥ |t|), the one-tailed p-value in the direction of
    /// the observed difference, min(p_less, p_greater).
    pub p_one_tail: f64,
    /// Two-sided p-value, 2·P(T ≥ |t|).
    pub p_two_sided: f64,
    /// "t critical one-tail": the 1 − α quantile of t(df), α = [`ALPHA`].
    pub t_crit_one_tail: f64,
    /// "t critical two-tail": the 1 − α/2 quantile of t(df).
    pub t_crit_two_tail: f64,
}

/// Welch's t-test of mean(a) = mean(b) without assuming equal variances, with the
/// Welch–Satterthwaite degrees of freedom, p-values for both one-sided alternatives and the
/// two-sided one, and the critical values at α = 0.05.
///
/// Needs at least 2 finite values per sample, and not both variances zero. (One zero
/// variance is fine: a deterministic method against a stochastic one.)
pub fn welch_t(a: &[f64], b: &[f64]) -> Result<TTest, StatsError> {
    const WHAT: &str = "Welch t-test";
    check_sample(WHAT, a, 2)?;
    check_sample(WHAT, b, 2)?;
    let (mean_a, variance_a) = mean_var(a);
    let (mean_b, variance_b) = mean_var(b);
    let (na, nb) = (a.len() as f64, b.len() as f64);
    let (vna, vnb) = (variance_a / na, variance_b / nb);
    let se2 = vna + vnb;
    check_overflow(WHAT, &[mean_a, mean_b, se2])?;
    if se2 == 0.0 {
        return Err(StatsError::ZeroVariance { what: WHAT });
    }
    let df = se2 * se2 / (vna * vna / (na - 1.0) + vnb * vnb / (nb - 1.0));
    let t = (mean_a - mean_b) / se2.sqrt();
    check_overflow(WHAT, &[df, t])?;
    // df is positive and finite here; a failure would be an overflow of the inputs.
    let Ok(dist) = StudentsT::new(0.0, 1.0, df) else {
        return Err(StatsError::Overflow { what: WHAT });
    };
    let p_less = dist.cdf(t);
    let p_greater = dist.sf(t);
    let p_one_tail = dist.sf(t.abs());
    Ok(TTest {
        n_a: a.len(),
        n_b: b.len(),
        mean_a,
        mean_b,
        variance_a,
        variance_b,
        t,
        df,
        df_rounded: df.round(),
        p_less,
        p_greater,
        p_one_tail,
        p_two_sided: (2.0 * p_one_tail).min(1.0),
        t_crit_one_tail: t_ppf(1.0 - ALPHA, df),
        t_crit_two_tail: t_ppf(1.0 - ALPHA / 2.0, df),
    })
}

/// A one-way (independent groups) analysis of variance (the paper's Table 4).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Anova {
    /// Sum of squares between groups, Σ n_i (mean_i − grand mean)².
    pub ss_between: f64,
    /// Sum of squares within groups, Σ_i Σ_j (x_ij − mean_i)².
    pub ss_within: f64,
    /// Total sum of squares about the grand mean (= between + within).
    pub ss_total: f64,
    /// Degrees of freedom between groups, k − 1.
    pub df_between: f64,
    /// Degrees of freedom within groups, N − k.
    pub df_within: f64,
    /// Total degrees of freedom, N − 1.
    pub df_total: f64,
    /// Mean square between groups, ss_between / df_between.
    pub ms_between: f64,
    /// Mean square within groups, ss_within / df_within.
    pub ms_within: f64,
    /// F = ms_between / ms_within.
    pub f: f64,
    /// P(F(df_between, df_within) ≥ f).
    pub p_value: f64,
    /// "F crit": the 1 − α quantile of F(df_between, df_within), α = [`ALPHA`].
    pub f_crit: f64,
}

/// One-way ANOVA of `groups` (as `scipy.stats.f_oneway`, plus the sums of squares and the
/// critical value of Excel's "ANOVA: Single Factor" table).
///
/// Needs at least 2 groups, at least 1 finite value per group, more values than groups,
/// and some variation within the groups.
pub fn anova_oneway(groups: &[&[f64]]) -> Result<Anova, StatsError> {
    const WHAT: &str = "one-way ANOVA";
    if groups.len() < 2 {
        return Err(StatsError::TooFewGroups { got: groups.len() });
    }
    for g in groups {
        check_sample(WHAT, g, 1)?;
    }
    let k = groups.len();
    let total: usize = groups.iter().map(|g| g.len()).sum();
    if total <= k {
        return Err(StatsError::TooFewValues {
            what: WHAT,
            needed: k + 1,
            got: total,
        });
    }
    let grand = groups.iter().flat_map(|g| g.iter()).sum::<f64>() / total as f64;
    let (mut ss_between, mut ss_within, mut ss_total) = (0.0, 0.0, 0.0);
    for g in groups {
        let mean = g.iter().sum::<f64>() / g.len() as f64;
        ss_between += g.len() as f64 * (mean - grand) * (mean - grand);
        ss_within += g.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>();
        ss_total += g.iter().map(|v| (v - grand) * (v - grand)).sum::<f64>();
    }
    check_overflow(WHAT, &[grand, ss_between, ss_within, ss_total])?;
    if ss_within == 0.0 {
        return Err(StatsError::ZeroVariance { what: WHAT });
    }
    let df_between = (k - 1) as f64;
    let df_within = (total - k) as f64;
    let ms_between = ss_between / df_between;
    let ms_within = ss_within / df_within;
    let f = ms_between / ms_within;
    check_overflow(WHAT, &[f])?;
    Ok(Anova {
        ss_between,
        ss_within,
        ss_total,
        df_between,
        df_within,
        df_total: (total - 1) as f64,
        ms_between,
        ms_within,
        f,
        p_value: f_sf(f, df_between, df_within),
        f_crit: f_ppf(1.0 - ALPHA, df_between, df_within),
    })
}

/// P(F ≤ f) for F(d1, d2).
fn f_cdf(f: f64, d1: f64, d2: f64) -> f64 {
    beta_reg(d1 / 2.0, d2 / 2.0, d1 * f / (d1 * f + d2))
}

/// P(F ≥ f) for F(d1, d2), through the complementary incomplete beta so that tiny upper
/// tails keep their relative precision.
fn f_sf(f: f64, d1: f64, d2: f64) -> f64 {
    beta_reg(d2 / 2.0, d1 / 2.0, d2 / (d1 * f + d2))
}

/// The p quantile of F(d1, d2) (NaN if the degrees of freedom are not positive, which the
/// callers rule out).
fn f_ppf(p: f64, d1: f64, d2: f64) -> f64 {
    FisherSnedecor::new(d1, d2).map_or(f64::NAN, |d| d.inverse_cdf(p))
}

/// The p quantile of Student's t with df degrees of freedom (NaN if df is not positive,
/// which the callers rule out).
fn t_ppf(p: f64, df: f64) -> f64 {
    StudentsT::new(0.0, 1.0, df).map_or(f64::NAN, |d| d.inverse_cdf(p))
}
