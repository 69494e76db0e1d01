//! Normality tests: Shapiro–Wilk (Royston's AS R94, as scipy) and the Kolmogorov–Smirnov
//! test with Lilliefors' correction (as statsmodels).

use super::{check_overflow, check_sample, mean_var, StatsError};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

/// The result of a normality test (one row of the paper's Table 3).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Normality {
    /// The test: `"Shapiro-Wilk"` or `"Kolmogorov-Smirnov (Lilliefors)"`.
    pub test: &'static str,
    /// The statistic: W for Shapiro–Wilk, D = sup |F_n − Φ| for Lilliefors.
    pub statistic: f64,
    /// Degrees of freedom as SPSS reports them: the sample size.
    pub df: usize,
    /// The p-value ("Sig."); small values reject normality.
    pub p_value: f64,
}

impl Normality {
    /// The p-value as SPSS prints it. SPSS reports the Lilliefors significance as ".200*",
    /// a lower bound, whenever it is at least 0.2, so this gives min(p, 0.2) for Lilliefors
    /// (the paper's Table 3 shows 0.200 for every normal-looking sample) and the p-value
    /// itself for Shapiro–Wilk.
    pub fn spss_p_value(&self) -> f64 {
        if self.test == LILLIEFORS {
            self.p_value.min(0.2)
        } else {
            self.p_value
        }
    }
}

const SHAPIRO_WILK: &str = "Shapiro-Wilk";
const LILLIEFORS: &str = "Kolmogorov-Smirnov (Lilliefors)";

/// The Shapiro–Wilk W test of normality with Royston's (1995) approximation of the
/// coefficients and of the p-value (Algorithm AS R94, as `scipy.stats.shapiro`; the p-value
/// is exact for n = 3).
///
/// Needs 3 ≤ n ≤ 5000 finite values that are not all equal.
pub fn shapiro_wilk(x: &[f64]) -> Result<Normality, StatsError> {
    const MAX_N: usize = 5000;
    check_sample(SHAPIRO_WILK, x, 3)?;
    let n = x.len();
    if n > MAX_N {
        return Err(StatsError::TooManyValues {
            what: SHAPIRO_WILK,
            max: MAX_N,
            got: n,
        });
    }
    // Shift by a central value before sorting (scipy subtracts x[n/2] of the input, which
    // keeps the sums below well conditioned for data far from zero).
    let shift = x[n / 2];
    let mut y: Vec<f64> = x.iter().map(|v| v - shift).collect();
    y.sort_by(f64::total_cmp);
    let range = y[n - 1] - y[0];
    if range <= 0.0 {
        return Err(StatsError::ZeroVariance { what: SHAPIRO_WILK });
    }
    let (w, p_value) = swilk(&y, range);
    Ok(Normality {
        test: SHAPIRO_WILK,
        statistic: w,
        df: n,
        p_value,
    })
}

/// AS R94 on sorted data with positive range: returns (W, p).
fn swilk(y: &[f64], range: f64) -> (f64, f64) {
    // Polynomial coefficients (ascending powers) of Royston (1995).
    const C1: [f64; 6] = [0.0, 0.221157, -0.147981, -2.07119, 4.434685, -2.706056];
    const C2: [f64; 6] = [0.0, 0.042981, -0.293762, -1.752461, 5.682633, -3.582633];
    const C3: [f64; 4] = [0.544, -0.39978, 0.025054, -6.714e-4];
    const C4: [f64; 4] = [1.3822, -0.77857, 0.062767, -0.0020322];
    const C5: [f64; 4] = [-1.5861, -0.31082, -0.083751, 0.0038915];
    const C6: [f64; 3] = [-0.4803, -0.082676, 0.0030302];
    const G: [f64; 2] = [-2.273, 0.459];
    // The p-value AS R94 returns when W is beyond the small-sample approximation's range.
    const SMALL: f64 = 1e-19;

    let n = y.len();
    let half = n / 2;
    let an = n as f64;

    // Coefficients a_i for the lower half, positive, largest first.
    let mut a = vec![0.0; half];
    if n == 3 {
        a[0] = std::f64::consts::FRAC_1_SQRT_2;
    } else {
        let an25 = an + 0.25;
        let m: Vec<f64> = (0..half)
            .map(|i| ppnd((i as f64 + 1.0 - 0.375) / an25))
            .collect();
        let summ2 = 2.0 * m.iter().map(|v| v * v).sum::<f64>();
        let ssumm2 = summ2.sqrt();
        let rsn = 1.0 / an.sqrt();
        let a1 = poly(&C1, rsn) - m[0] / ssumm2;
        let (first, fac) = if n > 5 {
            let a2 = -m[1] / ssumm2 + poly(&C2, rsn);
            let fac = ((summ2 - 2.0 * m[0] * m[0] - 2.0 * m[1] * m[1])
                / (1.0 - 2.0 * a1 * a1 - 2.0 * a2 * a2))
                .sqrt();
            a[1] = a2;
            (2, fac)
        } else {
            let fac = ((summ2 - 2.0 * m[0] * m[0]) / (1.0 - 2.0 * a1 * a1)).sqrt();
            (1, fac)
        };
        a[0] = a1;
        for i in first..half {
            a[i] = -m[i] / fac;
        }
    }

    // The coefficient of the i-th order statistic: −a_i in the lower half, +a in the upper,
    // 0 for the middle value of an odd sample.
    let coef = |i: usize| -> f64 {
        let j = n - 1 - i;
        if i < j {
            -a[i]
        } else if i > j {
            a[j]
        } else {
            0.0
        }
    };
    // W is the squared correlation of the coefficients and the data (scaled by the range),
    // computed as 1 − w1 to keep precision near W = 1.
    let sa = (0..n).map(coef).sum::<f64>() / an;
    let sx = y.iter().map(|v| v / range).sum::<f64>() / an;
    let (mut ssa, mut ssx, mut sax) = (0.0, 0.0, 0.0);
    for (i, v) in y.iter().enumerate() {
        let asa = coef(i) - sa;
        let xsx = v / range - sx;
        ssa += asa * asa;
        ssx += xsx * xsx;
        sax += asa * xsx;
    }
    let ssassx = (ssa * ssx).sqrt();
    let w1 = (ssassx - sax) * (ssassx + sax) / (ssa * ssx);
    let w = 1.0 - w1;

    if n == 3 {
        // Exact distribution; W ≥ 0.75 in theory, clamp rounding below it.
        if w < 0.75 {
            return (0.75, 0.0);
        }
        let p = 1.0 - 6.0 / std::f64::consts::PI * w.sqrt().acos();
        return (w, p);
    }

    let mut yv = w1.ln();
    let (m, s) = if n <= 11 {
        let gamma = poly(&G, an);
        if yv >= gamma {
            return (w, SMALL);
        }
        yv = -(gamma - yv).ln();
        (poly(&C3, an), poly(&C4, an).exp())
    } else {
        let ln_n = an.ln();
        (poly(&C5, ln_n), poly(&C6, ln_n).exp())
    };
    (w, alnorm_upper((yv - m) / s))
}

/// c[0] + c[1] x + c[2] x² + … by Horner's rule.
fn poly(c: &[f64], x: f64) -> f64 {
    match c.split_first() {
        None => 0.0,
        Some((c0, rest)) => c0 + rest.iter().rev().fold(0.0, |acc, ci| (acc + ci) * x),
    }
}

/// The upper tail of the standard normal, P(Z > z), by Hill's Algorithm AS 66 (the tail
/// function of AS R94; kept so W's p-value matches the reference implementation bit for
/// bit rather than to AS 66's ~1e-9 accuracy).
fn alnorm_upper(z: f64) -> f64 {
    const LTONE: f64 = 7.0;
    const UTZERO: f64 = 38.0;
    const CON: f64 = 1.28;
    let (mut upper, mut z) = (true, z);
    if z.is_nan() || z <= 0.0 {
        upper = false;
        z = -z;
    }
    if !(z <= LTONE || (upper && z <= UTZERO)) {
        return if upper { 0.0 } else { 1.0 };
    }
    let y = 0.5 * z * z;
    let tail = if z <= CON {
        0.5 - z
            * (0.398942280444
                - 0.399903438504 * y
                    / (y + 5.75885480458
                        - 29.8213557808
                            / (y + 2.62433121679 + 48.6959930692 / (y + 5.92885724438))))
    } else {
        0.398942280385 * (-y).exp()
            / (z - 3.8052e-8
                + 1.00000615302
                    / (z + 3.98064794e-4
                        + 1.98615381364
                            / (z - 0.151679116635
                                + 5.29330324926
                                    / (z + 4.8385912808
                                        - 15.1508972451
                                            / (z + 0.742380924027
                                                + 30.789933034 / (z + 3.99019417011))))))
    };
    if upper {
        tail
    } else {
        1.0 - tail
    }
}

/// The standard normal quantile by Beasley and Springer's Algorithm AS 111 (about 7
/// digits), which AS R94 uses for the expected normal order statistics.
fn ppnd(p: f64) -> f64 {
    const SPLIT: f64 = 0.42;
    let q = p - 0.5;
    if q.abs() <= SPLIT {
        let r = q * q;
        let num =
            q * (((-25.44106049637 * r + 41.39119773534) * r - 18.61500062529) * r + 2.50662823884);
        let den = (((3.13082909833 * r - 21.06224101826) * r + 23.08336743743) * r - 8.47351093090)
            * r
            + 1.0;
        return num / den;
    }
    let r = if q > 0.0 { 1.0 - p } else { p };
    if r <= 0.0 {
        return 0.0;
    }
    let r = (-r.ln()).sqrt();
    let v = (((2.32121276858 * r + 4.85014127135) * r - 2.29796479134) * r - 2.78718931138)
        / ((1.63706781897 * r + 3.54388924762) * r + 1.0);
    if q < 0.0 {
        -v
    } else {
        v
    }
}

/// The Kolmogorov–Smirnov test of normality with Lilliefors' correction: D is the largest
/// distance between the empirical distribution of `x` and the normal distribution with the
/// sample mean and standard deviation (n − 1). This is the "Kolmogorov-Smirnov^a
/// (Lilliefors Significance Correction)" column of SPSS and the paper's Table 3.
///
/// The p-value follows `statsmodels.stats.diagnostic.lilliefors(x, dist='norm',
/// pvalmethod='approx')`: Dallal and Wilkinson's (1986) approximation, valid for p < 0.1
/// (for n > 100, D is scaled by (n/100)^0.49 and n set to 100); when it gives p > 0.1,
/// statsmodels (and so this function) interpolates instead in its table of critical values
/// from 10⁷ simulations, linearly in n and then in D, with an asymptotic fit in n beyond
/// n = 1600. Table p-values are clamped to [0.001, 0.99]. SPSS instead caps its printout at
/// 0.200, see [`Normality::spss_p_value`].
///
/// Needs at least 4 finite values that are not all equal.
pub fn lilliefors(x: &[f64]) -> Result<Normality, StatsError> {
    check_sample(LILLIEFORS, x, 4)?;
    let n = x.len();
    let (mean, var) = mean_var(x);
    let sd = var.sqrt();
    check_overflow(LILLIEFORS, &[mean, sd])?;
    if sd == 0.0 {
        return Err(StatsError::ZeroVariance { what: LILLIEFORS });
    }
    let std_normal = Normal::standard();
    let mut cdf: Vec<f64> = x.iter().map(|v| std_normal.cdf((v - mean) / sd)).collect();
    cdf.sort_by(f64::total_cmp);
    let nf = n as f64;
    let (mut d_plus, mut d_minus) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (i, c) in cdf.iter().enumerate() {
        d_plus = d_plus.max((i + 1) as f64 / nf - c);
        d_minus = d_minus.max(c - i as f64 / nf);
    }
    let d = d_plus.max(d_minus);
    let mut p_value = dallal_wilkinson(d, nf);
    if p_value > 0.1 {
        p_value = lilliefors_table_p(d, nf);
    }
    Ok(Normality {
        test: LILLIEFORS,
        statistic: d,
        df: n,
        p_value,
    })
}

/// Dallal and Wilkinson's (1986) approximation of the Lilliefors p-value (for p < 0.1).
fn dallal_wilkinson(d: f64, n: f64) -> f64 {
    let (d, n) = if n > 100.0 {
        (d * (n / 100.0).powf(0.49), 100.0)
    } else {
        (d, n)
    };
    (-7.01256 * d * d * (n + 2.78019) + 2.99587 * d * (n + 2.78019).sqrt() - 0.122119
        + 0.974598 / n.sqrt()
        + 1.67997 / n)
        .exp()
}

/// The Lilliefors p-value interpolated in statsmodels' table of simulated critical values.
fn lilliefors_table_p(d: f64, n: f64) -> f64 {
    use lilliefors_table::{ASYMP_INTERCEPT, ASYMP_LN_N, ASYMP_LN_N2, CRIT, PERCENTILES, SIZES};
    // Critical values for this n, increasing with the percentile.
    let crit: [f64; 14] = if n > SIZES[SIZES.len() - 1] {
        let l = n.ln();
        std::array::from_fn(|k| (ASYMP_INTERCEPT[k] + ASYMP_LN_N * l + ASYMP_LN_N2 * l * l).exp())
    } else {
        let hi = SIZES.partition_point(|&s| s < n).clamp(1, SIZES.len() - 1);
        let lo = hi - 1;
        std::array::from_fn(|k| lerp(SIZES[lo], SIZES[hi], CRIT[lo][k], CRIT[hi][k], n))
    };
    let alpha = |k: usize| 1.0 - PERCENTILES[k] / 100.0;
    if d < crit[0] {
        return alpha(0);
    }
    if d > crit[13] {
        return alpha(13);
    }
    let hi = crit.partition_point(|&c| c < d).clamp(1, 13);
    lerp(crit[hi - 1], crit[hi], alpha(hi - 1), alpha(hi), d)
}

/// Linear interpolation through (x0, y0) and (x1, y1) at x, in scipy's `interp1d` form.
fn lerp(x0: f64, x1: f64, y0: f64, y1: f64, x: f64) -> f64 {
    (y1 - y0) / (x1 - x0) * (x - x0) + y0
}

/// statsmodels' simulated critical values of the Lilliefors statistic for the normal
/// distribution (statsmodels/stats/_lilliefors_critical_values.py, BSD-3-Clause, 10⁷
/// simulations per size).
#[allow(clippy::excessive_precision)]
mod lilliefors_table {
    /// Percentiles of the null distribution of D, one per column.
    pub(super) const PERCENTILES: [f64; 14] = [
        1.0, 5.0, 10.0, 25.0, 50.0, 75.0, 90.0, 92.5, 95.0, 97.5, 99.0, 99.5, 99.7, 99.9,
    ];
    /// Sample sizes, one per row of `CRIT`.
    pub(super) const SIZES: [f64; 26] = [
        4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0, 17.0, 18.0, 19.0,
        20.0, 25.0, 30.0, 40.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0,
    ];
    /// Critical values of D by sample size (rows) and percentile (columns).
    pub(super) const CRIT: [[f64; 14]; 26] = [
        [
            0.14467854, 0.16876575, 0.18664724, 0.22120362, 0.25828924, 0.29341032, 0.34532673,
            0.35917374, 0.37521968, 0.39563998, 0.41307904, 0.42157653, 0.4261507, 0.43265213,
        ],
        [
            0.13587046, 0.16098893, 0.17638354, 0.20235666, 0.2333944, 0.27766941, 0.31900772,
            0.32936832, 0.34309223, 0.36727643, 0.39671728, 0.41322814, 0.42293504, 0.4386304,
        ],
        [
            0.12919635, 0.15139467, 0.16384021, 0.18597849, 0.2186713, 0.2585473, 0.29713753,
            0.30829444, 0.32338252, 0.3456671, 0.37038945, 0.38760943, 0.40001813, 0.42304439,
        ],
        [
            0.12263812, 0.14163065, 0.15238656, 0.17435948, 0.20617949, 0.24243592, 0.28031415,
            0.29068512, 0.3042307, 0.32532967, 0.35070348, 0.3678189, 0.37908881, 0.40078798,
        ],
        [
            0.11633728, 0.13297288, 0.14353311, 0.16537078, 0.19477376, 0.22936164, 0.2652001,
            0.27501697, 0.28804474, 0.30862157, 0.33279908, 0.34911188, 0.3603517, 0.38252055,
        ],
        [
            0.11029593, 0.126086, 0.1365291, 0.15748048, 0.18510669, 0.21822055, 0.25223085,
            0.26161129, 0.27415243, 0.29383667, 0.31708299, 0.33312043, 0.34406772, 0.36524182,
        ],
        [
            0.10487398, 0.12044377, 0.13065174, 0.15042835, 0.17679904, 0.20848607, 0.24098605,
            0.25001629, 0.26202351, 0.2809226, 0.30341763, 0.31888089, 0.32960742, 0.35061378,
        ],
        [
            0.10036835, 0.11563925, 0.12540948, 0.14421024, 0.1695621, 0.19993088, 0.23119563,
            0.23987246, 0.25142048, 0.26961902, 0.29148756, 0.30646087, 0.31678589, 0.33743951,
        ],
        [
            0.09649147, 0.11137479, 0.12069511, 0.13877133, 0.16313672, 0.19233706, 0.22244871,
            0.23082937, 0.24194831, 0.25959488, 0.28077229, 0.29526801, 0.30538827, 0.32558601,
        ],
        [
            0.09318309, 0.10753337, 0.11647389, 0.13389325, 0.15739248, 0.18555597, 0.21463087,
            0.22267463, 0.23346007, 0.25054975, 0.27100552, 0.28519234, 0.29504428, 0.31445229,
        ],
        [
            0.09024138, 0.1040431, 0.11266368, 0.12948657, 0.15221479, 0.17944478, 0.2075745,
            0.21536969, 0.22585144, 0.2423819, 0.26231339, 0.2760657, 0.28555592, 0.30466148,
        ],
        [
            0.08750578, 0.10085666, 0.1092263, 0.12552356, 0.14751778, 0.17390304, 0.2011939,
            0.20879449, 0.21891697, 0.23499116, 0.25427802, 0.26772298, 0.27706522, 0.29551017,
        ],
        [
            0.08501529, 0.09795236, 0.10607182, 0.1219047, 0.14327014, 0.16885124, 0.19537444,
            0.20274039, 0.21257643, 0.22822187, 0.24703504, 0.26003621, 0.26913735, 0.28745211,
        ],
        [
            0.0827393, 0.09529635, 0.10320903, 0.11859867, 0.13936135, 0.16422592, 0.1900207,
            0.19722541, 0.20683438, 0.22204864, 0.2402864, 0.25306469, 0.26200104, 0.2798316,
        ],
        [
            0.08063198, 0.09285546, 0.10055901, 0.11554003, 0.13575222, 0.15996707, 0.18509495,
            0.1921063, 0.20145911, 0.2163409, 0.23420221, 0.24665892, 0.25527246, 0.27285099,
        ],
        [
            0.0786934, 0.09059543, 0.09810264, 0.11271608, 0.1324079, 0.15602767, 0.18052002,
            0.18736281, 0.19652196, 0.21105313, 0.22854301, 0.24068403, 0.24912401, 0.26624557,
        ],
        [
            0.07686372, 0.08852309, 0.09582876, 0.11008398, 0.12930804, 0.15236687, 0.1762829,
            0.18297149, 0.19190794, 0.20610189, 0.22327259, 0.23513834, 0.24349604, 0.2602868,
        ],
        [
            0.06933943, 0.07985746, 0.08645091, 0.09927555, 0.11656692, 0.1373056, 0.15889286,
            0.16493761, 0.17300926, 0.18582499, 0.2013265, 0.21221932, 0.21979198, 0.2350391,
        ],
        [
            0.06380332, 0.07339662, 0.07942847, 0.09118039, 0.10701841, 0.12603791, 0.14586121,
            0.15138566, 0.15878307, 0.17058849, 0.18492078, 0.19492393, 0.20198353, 0.21612086,
        ],
        [
            0.055784, 0.06414642, 0.06940064, 0.07961554, 0.09339439, 0.10994266, 0.12719016,
            0.13202416, 0.13850018, 0.14877502, 0.16131916, 0.17009968, 0.17633078, 0.18870328,
        ],
        [
            0.05022994, 0.05773701, 0.06243507, 0.07160481, 0.08395875, 0.09882109, 0.11431303,
            0.11863768, 0.12444044, 0.1337458, 0.14504504, 0.15299605, 0.15854061, 0.16985345,
        ],
        [
            0.0361047, 0.04146075, 0.0448043, 0.05131964, 0.06011456, 0.07068396, 0.08173283,
            0.08483991, 0.08900091, 0.09564506, 0.10373761, 0.10937278, 0.11338394, 0.12161442,
        ],
        [
            0.02584151, 0.02963511, 0.03200533, 0.0366259, 0.04286406, 0.05036816, 0.05820564,
            0.06041126, 0.06336215, 0.06809025, 0.0738379, 0.07788879, 0.08074047, 0.08663425,
        ],
        [
            0.01844162, 0.02112065, 0.02280475, 0.02607295, 0.03049198, 0.03580284, 0.04135097,
            0.04290933, 0.04500619, 0.04834792, 0.0524239, 0.05530289, 0.05733374, 0.06145404,
        ],
        [
            0.0131231, 0.01501723, 0.01620598, 0.01852257, 0.02164634, 0.02540595, 0.02933599,
            0.03043873, 0.03192094, 0.03429131, 0.03718247, 0.03922491, 0.0406419, 0.04361741,
        ],
        [
            0.00932049, 0.01066126, 0.01150366, 0.01314135, 0.0153528, 0.0180115, 0.02079512,
            0.02157469, 0.02262168, 0.02429563, 0.02634302, 0.02777611, 0.02879721, 0.03088286,
        ],
    ];
    /// Beyond n = 1600: ln(critical value) = intercept + b1 ln n + b2 (ln n)², intercept by percentile.
    pub(super) const ASYMP_INTERCEPT: [f64; 14] = [
        -1.17114969,
        -1.03298277,
        -0.95518114,
        -0.81912169,
        -0.6607348,
        -0.49861004,
        -0.35446139,
        -0.31737193,
        -0.26969888,
        -0.1979977,
        -0.11709649,
        -0.06398777,
        -0.0281863,
        0.04129756,
    ];
    /// Coefficient of ln n, shared by every percentile.
    pub(super) const ASYMP_LN_N: f64 = -0.45068579;
    /// Coefficient of (ln n)², shared by every percentile.
    pub(super) const ASYMP_LN_N2: f64 = -0.00356741;
}
