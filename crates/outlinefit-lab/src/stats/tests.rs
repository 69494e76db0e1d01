//! Tests of the statistics against reference values computed by scipy and statsmodels.
//!
//! `vectors.rs` is the output of `tools/stats_vectors.py`, reference values from scipy
//! 1.17.1 / statsmodels 0.15.0 / numpy 2.4.6 (its header names the versions). Tolerances
//! reflect the algorithm: the closed-form statistics and Shapiro–Wilk (replicated operation
//! by operation, with the same AS 66 and AS 111 helpers as scipy) match to rounding; the t
//! and F p-values and critical values to the accuracy of statrs's incomplete beta function
//! and its inverse; Lilliefors to that of statrs's erfc (see `TOL_LF_D`).

use super::vectors::*;
use super::*;

// Tolerances, by what is compared (relative unless marked absolute). The observed maxima
// are printed by `cargo test --release --lib stats -- --nocapture`.

/// Means, variances, quantiles, t, F, sums of squares, Shapiro–Wilk W: rounding only.
const TOL_EXACT: f64 = 1e-12;
/// p-values from the t and F distributions (statrs's incomplete beta vs scipy's).
const TOL_P: f64 = 1e-10;
/// Shapiro–Wilk p (the same AS R94 / AS 66 / AS 111 arithmetic as scipy).
const TOL_SW_P: f64 = 1e-10;
/// Critical values (statrs's inverse incomplete beta vs scipy's).
const TOL_CRIT: f64 = 1e-10;
/// Lilliefors D, absolute. Lilliefors evaluates the normal CDF with statrs, whose erfc is
/// only good to ~1e-10 relative in 0.19 (truncated interval constants, fixed upstream by
/// statrs PR #412), while scipy's ndtr is exact to rounding; D, a difference of
/// probabilities, inherits that error as an absolute one.
const TOL_LF_D: f64 = 1e-10;
/// Lilliefors p: the Dallal–Wilkinson formula amplifies D's error by |d ln p / dD|
/// (≈ 800 for the n = 2000 skewed set, p ≈ 4e-89).
const TOL_LF_P: f64 = 1e-7;

/// The same LCG as `lcg_data` in tools/stats_vectors.py (exact in IEEE doubles).
fn lcg_data(n: usize, seed: u64, kind: &str) -> Vec<f64> {
    let mut state = seed;
    let mut next_u = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / 9007199254740992.0
    };
    (0..n)
        .map(|_| match kind {
            "sum3" => {
                let (a, b, c) = (next_u(), next_u(), next_u());
                (a + b) + c
            }
            "sum12" => (0..12).fold(0.0, |acc, _| acc + next_u()),
            "prod" => {
                let (a, b) = (next_u(), next_u());
                a * b
            }
            _ => panic!("unknown kind {kind}"),
        })
        .collect()
}

fn data(name: &str) -> Vec<f64> {
    let literal: &[f64] = match name {
        "HS30" => &HS30,
        "GA30" => &GA30,
        "PSO30" => &PSO30,
        "EXP30" => &EXP30,
        "OUTLIER30" => &OUTLIER30,
        "SMALL3" => &SMALL3,
        "SMALL4" => &SMALL4,
        "SMALL5" => &SMALL5,
        "SMALL7" => &SMALL7,
        "N11" => &N11,
        "N12" => &N12,
        "N35" => &N35,
        "QUANT20" => &QUANT20,
        _ => {
            let &(_, n, seed, kind) = LCG
                .iter()
                .find(|(k, ..)| *k == name)
                .unwrap_or_else(|| panic!("unknown data set {name}"));
            return lcg_data(n, seed, kind);
        }
    };
    literal.to_vec()
}

/// Tracks the largest error of one kind of value, and asserts the tolerance. The error is
/// |actual − expected| / max(|expected|, floor): floor 1e-300 makes it relative, floor 1
/// absolute for values below 1.
struct Errors {
    what: &'static str,
    tol: f64,
    floor: f64,
    max: f64,
}

impl Errors {
    fn new(what: &'static str, tol: f64) -> Self {
        Errors {
            what,
            tol,
            floor: 1e-300,
            max: 0.0,
        }
    }

    fn absolute(what: &'static str, tol: f64) -> Self {
        Errors {
            what,
            tol,
            floor: 1.0,
            max: 0.0,
        }
    }

    fn check(&mut self, case: &str, actual: f64, expected: f64) {
        let err = if actual == expected {
            0.0
        } else {
            (actual - expected).abs() / expected.abs().max(self.floor)
        };
        self.max = self.max.max(err);
        assert!(
            err <= self.tol,
            "{} {case}: got {actual:e}, expected {expected:e} (error {err:e} > {:e})",
            self.what,
            self.tol
        );
    }
}

impl Drop for Errors {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            eprintln!(
                "{:<28} max {} error {:.1e} (tolerance {:.0e})",
                self.what,
                if self.floor < 1.0 {
                    "relative"
                } else {
                    "absolute"
                },
                self.max,
                self.tol
            );
        }
    }
}

#[test]
fn lcg_matches_the_generator_script() {
    // First values of LCG150 as printed by the script's DESCRIBE row (min/max are data).
    let x = data("LCG150");
    assert_eq!(x.len(), 150);
    let d = DESCRIBE.iter().find(|r| r.0 == "LCG150").unwrap();
    let min = x.iter().copied().fold(f64::INFINITY, f64::min);
    let max = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert_eq!((min, max), (d.2[0], d.2[1]));
}

#[test]
fn describe_matches_numpy() {
    let mut exact = Errors::new("describe (min/max/median/q)", 0.0);
    let mut moments = Errors::new("describe (mean/var/sd)", TOL_EXACT);
    for &(name, n, [best, worst, mean, median, var, sd, q1, q3]) in DESCRIBE {
        let d = describe(&data(name)).unwrap();
        assert_eq!(d.n, n, "{name}");
        exact.check(name, d.best, best);
        exact.check(name, d.worst, worst);
        exact.check(name, d.median, median);
        // numpy's quartiles are the same interpolation, so they agree to rounding.
        moments.check(name, d.q1, q1);
        moments.check(name, d.q3, q3);
        moments.check(name, d.mean, mean);
        moments.check(name, d.variance, var);
        moments.check(name, d.std_dev, sd);
    }
}

#[test]
fn describe_quartiles_by_hand() {
    let d = describe(&[4.0, 1.0, 3.0, 2.0]).unwrap();
    assert_eq!((d.q1, d.median, d.q3), (1.75, 2.5, 3.25));
    assert_eq!((d.best, d.worst, d.mean), (1.0, 4.0, 2.5));
    assert!((d.variance - 5.0 / 3.0).abs() < 1e-15);
    let d = describe(&[7.0, 7.0]).unwrap();
    assert_eq!((d.variance, d.std_dev), (0.0, 0.0));
}

#[test]
fn shapiro_wilk_matches_scipy() {
    let mut w_err = Errors::new("Shapiro-Wilk W", TOL_EXACT);
    let mut p_err = Errors::new("Shapiro-Wilk p", TOL_SW_P);
    for &(name, w, p) in SHAPIRO {
        let x = data(name);
        let r = shapiro_wilk(&x).unwrap();
        assert_eq!(r.df, x.len());
        assert_eq!(r.test, "Shapiro-Wilk");
        w_err.check(name, r.statistic, w);
        p_err.check(name, r.p_value, p);
        assert_eq!(r.spss_p_value(), r.p_value);
    }
}

#[test]
fn lilliefors_matches_statsmodels() {
    let mut d_err = Errors::absolute("Lilliefors D", TOL_LF_D);
    let mut p_err = Errors::new("Lilliefors p", TOL_LF_P);
    for &(name, d, p) in LILLIEFORS {
        let x = data(name);
        let r = lilliefors(&x).unwrap();
        assert_eq!(r.df, x.len());
        d_err.check(name, r.statistic, d);
        p_err.check(name, r.p_value, p);
        assert_eq!(r.spss_p_value(), r.p_value.min(0.2));
    }
}

#[test]
fn lilliefors_covers_every_p_value_path() {
    // Dallal–Wilkinson (p < 0.1) for n ≤ 100 and n > 100, table rows, between rows, beyond
    // the last row, and the table's upper clamp: the vectors exercise each of them.
    let p = |name: &str| LILLIEFORS.iter().find(|r| r.0 == name).unwrap().2;
    assert!(p("EXP30") < 0.1 && p("LCG150P") < 0.1); // DW, n ≤ 100 and n > 100
    assert!(p("HS30") > 0.1 && p("N35") > 0.1); // table row 30, between 30 and 40
    assert!(p("LCG150") > 0.1 && p("LCG3000N") > 0.1); // between 100 and 200, beyond 1600
    assert_eq!(p("QUANT20"), 0.99); // clamp
}

fn pair(a: &str, b: &str) -> (Vec<f64>, Vec<f64>) {
    (data(a), data(b))
}

#[test]
fn f_test_matches_scipy() {
    let mut stat = Errors::new("F-test F", TOL_EXACT);
    let mut p_err = Errors::new("F-test p", TOL_P);
    let mut crit = Errors::new("F-test critical value", TOL_CRIT);
    for &(a, b, [f, df1, df2, lo, hi, two, crit_lo, crit_hi]) in F_TEST {
        let case = format!("{a} vs {b}");
        let (x, y) = pair(a, b);
        let r = f_test(&x, &y).unwrap();
        stat.check(&case, r.f, f);
        assert_eq!((r.df1, r.df2), (df1, df2));
        p_err.check(&case, r.p_lower, lo);
        p_err.check(&case, r.p_upper, hi);
        p_err.check(&case, r.p_two_tail, two);
        let (p_one, c) = if f < 1.0 {
            (lo, crit_lo)
        } else {
            (hi, crit_hi)
        };
        p_err.check(&case, r.p_one_tail, p_one);
        crit.check(&case, r.f_crit_one_tail, c);
    }
}

#[test]
fn welch_t_matches_scipy() {
    let mut stat = Errors::new("Welch t and df", TOL_EXACT);
    let mut p_err = Errors::new("Welch p", TOL_P);
    let mut crit = Errors::new("Welch critical value", TOL_CRIT);
    for &(a, b, [t, df, less, greater, two, crit_one, crit_two]) in WELCH {
        let case = format!("{a} vs {b}");
        let (x, y) = pair(a, b);
        let r = welch_t(&x, &y).unwrap();
        stat.check(&case, r.t, t);
        stat.check(&case, r.df, df);
        assert_eq!(r.df_rounded, df.round());
        p_err.check(&case, r.p_less, less);
        p_err.check(&case, r.p_greater, greater);
        p_err.check(&case, r.p_two_sided, two);
        p_err.check(&case, r.p_one_tail, less.min(greater));
        crit.check(&case, r.t_crit_one_tail, crit_one);
        crit.check(&case, r.t_crit_two_tail, crit_two);
    }
}

#[test]
fn anova_matches_scipy() {
    let mut stat = Errors::new("ANOVA SS/MS/F", TOL_EXACT);
    let mut p_err = Errors::new("ANOVA p", TOL_P);
    let mut crit = Errors::new("ANOVA critical value", TOL_CRIT);
    for &(names, [ssb, ssw, sst, dfb, dfw, msb, msw, f, p, f_crit]) in ANOVA {
        let case = names.join("+");
        let groups: Vec<Vec<f64>> = names.iter().map(|n| data(n)).collect();
        let refs: Vec<&[f64]> = groups.iter().map(Vec::as_slice).collect();
        let r = anova_oneway(&refs).unwrap();
        stat.check(&case, r.ss_between, ssb);
        stat.check(&case, r.ss_within, ssw);
        stat.check(&case, r.ss_total, sst);
        assert_eq!((r.df_between, r.df_within), (dfb, dfw));
        assert_eq!(r.df_total, dfb + dfw);
        stat.check(&case, r.ms_between, msb);
        stat.check(&case, r.ms_within, msw);
        stat.check(&case, r.f, f);
        p_err.check(&case, r.p_value, p);
        crit.check(&case, r.f_crit, f_crit);
    }
}

#[test]
fn critical_values_of_the_papers_excel_tables() {
    // Table 4 (df 2, 87) and Table 5 (df 29, 29), as Excel printed them.
    let x: Vec<f64> = (0..30).map(|i| (i * i % 17) as f64).collect();
    let groups: [&[f64]; 3] = [&x, &x[..], &x.iter().map(|v| v + 1.0).collect::<Vec<_>>()];
    let r = anova_oneway(&groups).unwrap();
    assert!((r.f_crit - 3.101295757).abs() < 1e-9, "{}", r.f_crit);
    let y: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
    let up = f_test(&y, &x).unwrap();
    assert!((up.f_crit_one_tail - 1.860811435).abs() < 1e-9);
    let down = f_test(&x, &y).unwrap();
    assert!((down.f_crit_one_tail - 0.537399965).abs() < 1e-9);
    assert_eq!(down.p_one_tail, down.p_lower);
    assert_eq!(up.p_one_tail, up.p_upper);
}

fn zero<T>(r: Result<T, StatsError>) -> bool {
    matches!(r, Err(StatsError::ZeroVariance { .. }))
}

fn few<T>(r: Result<T, StatsError>, need: usize) -> bool {
    matches!(r, Err(StatsError::TooFewValues { needed, .. }) if needed == need)
}

fn nonfinite<T>(r: Result<T, StatsError>) -> bool {
    matches!(r, Err(StatsError::NonFinite { index: 7, .. }))
}

#[test]
fn errors_instead_of_nan() {
    let same = [0.125; 30];
    let varied = &HS30[..];
    assert!(zero(shapiro_wilk(&same)));
    assert!(zero(lilliefors(&same)));
    assert!(zero(f_test(&same, varied)));
    assert!(zero(f_test(varied, &same)));
    assert!(zero(welch_t(&same, &[0.5; 10])));
    assert!(zero(anova_oneway(&[&same, &[0.5; 10]])));
    // One deterministic method against a stochastic one is still a valid Welch test.
    let r = welch_t(&same, varied).unwrap();
    assert!(r.t.is_finite() && r.p_two_sided.is_finite() && r.df == 29.0);
    // Zero variance is a fine description.
    assert_eq!(describe(&same).unwrap().std_dev, 0.0);

    assert!(few(describe(&[1.0]), 2));
    assert!(few(describe(&[]), 2));
    assert!(few(shapiro_wilk(&[1.0, 2.0]), 3));
    assert!(few(lilliefors(&[1.0, 2.0, 3.0]), 4));
    assert!(few(f_test(&[1.0], varied), 2));
    assert!(few(welch_t(varied, &[1.0]), 2));
    assert!(few(anova_oneway(&[varied, &[]]), 1));
    assert!(few(anova_oneway(&[&[1.0], &[2.0]]), 3));
    assert_eq!(
        anova_oneway(&[varied]).unwrap_err(),
        StatsError::TooFewGroups { got: 1 }
    );
    assert!(matches!(
        shapiro_wilk(&data("LCG5000").repeat(2)),
        Err(StatsError::TooManyValues {
            max: 5000,
            got: 10000,
            ..
        })
    ));

    let mut bad = HS30.to_vec();
    bad[7] = f64::NAN;
    assert!(nonfinite(describe(&bad)));
    assert!(nonfinite(shapiro_wilk(&bad)));
    assert!(nonfinite(lilliefors(&bad)));
    assert!(nonfinite(f_test(varied, &bad)));
    assert!(nonfinite(welch_t(&bad, varied)));
    assert!(nonfinite(anova_oneway(&[varied, &bad])));
    bad[7] = f64::INFINITY;
    assert!(nonfinite(describe(&bad)));

    // Finite data whose variance overflows.
    let huge = [f64::MAX, -f64::MAX, 0.0];
    assert!(matches!(describe(&huge), Err(StatsError::Overflow { .. })));
    assert!(matches!(
        welch_t(&huge, &huge),
        Err(StatsError::Overflow { .. })
    ));

    // Messages are one printable line.
    let msg = f_test(&same, varied).unwrap_err().to_string();
    assert_eq!(msg, "F-test for variances: the data have zero variance");
}

#[test]
fn results_serialize() {
    let r = welch_t(&HS30, &GA30).unwrap();
    let v = serde_json::to_value(&r).unwrap();
    assert_eq!(v["n_a"], 30);
    let v = serde_json::to_value(shapiro_wilk(&HS30).unwrap()).unwrap();
    assert_eq!(v["test"], "Shapiro-Wilk");
    serde_json::to_value(describe(&HS30).unwrap()).unwrap();
    serde_json::to_value(f_test(&HS30, &GA30).unwrap()).unwrap();
    serde_json::to_value(anova_oneway(&[&HS30, &GA30]).unwrap()).unwrap();
}

#[test]
fn quantiles_interpolate_linearly_between_order_statistics() {
    let s = [1.0, 2.0, 3.0, 4.0, 5.0];
    assert_eq!(quantile_sorted(&s, 0.5), 3.0);
    assert_eq!(quantile_sorted(&s, 0.25), 2.0);
    assert_eq!(quantile_sorted(&s, 0.6), 3.4);
    assert_eq!(quantile_sorted(&[1.0, 2.0], 0.5), 1.5);
    assert_eq!(quantile_sorted(&[7.0], 0.75), 7.0);
    assert_eq!(quantile_sorted(&s, 1.0), 5.0);
    assert_eq!(quantile_sorted(&s, 0.0), 1.0);
}
