//! Least-squares B-spline through a set of curve samples, its errors, and the sampling
//! problem the optimizers solve.
//!
//! **Parameterisation.** The spline's parameter *is* the curve's parameter u: sample i at
//! uᵢ is compared with S(uᵢ), exactly as Eq. 1 of the paper writes N_{j,k}(uᵢ). This is
//! also what lets a cubic spline reproduce a cubic polynomial curve exactly (Examples 4
//! and 5): any re-parameterisation (chord length, centripetal) would make the target a
//! non-polynomial function of the spline parameter. The dense errors therefore compare
//! S(u) with r(u) at the same u, a parametric distance (an upper bound of the geometric
//! distance from r(u) to the spline).
//!
//! **Knots.** The paper does not state its knot rule. We use the averaging rule of Piegl &
//! Tiller for least-squares approximation (*The NURBS Book*, Eqs. 9.68–9.69): with m + 1
//! samples and n + 1 control points of degree p, d = (m + 1)/(n − p + 1) and the interior
//! knots are t_{p+j} = (1 − α) u_{i−1} + α u_i, i = ⌊j d⌋, α = j d − i, j = 1 … n − p; the
//! ends are clamped (p + 1 copies of the first and last sample parameter). Every knot span
//! then holds at least one sample (Schoenberg–Whitney), so the collocation matrix has full
//! rank whenever the sample parameters are distinct.
//!
//! **Control points.** Least squares, solved by a Householder QR of the collocation matrix
//! (not the normal equations, whose squared condition number would cost digits on the
//! round-off tests), against one of two targets ([`FitTarget`]):
//!
//! * [`FitTarget::Samples`], the paper's Eq. 1: the curve at the samples only;
//! * [`FitTarget::Curve`]: the true curve at the dense reference parameters (the 1000
//!   evenly spaced u of [`DenseReference`]). For a given knot vector these control points
//!   minimise the dense RMSE itself, so the only thing left for the optimizer is the knots,
//!   which still come from the samples by the averaging rule. (The same evenly spaced
//!   points rather than a Gauss–Legendre rule per knot span: the reported `rmse_dense` is
//!   measured on them, and with 1000 points the discrete and the continuous L2 optimum
//!   differ far below the figures reported.)
//!
//! **Objective.** Eq. 1 over the samples can be gamed: samples clustered where the spline
//! happens to fit give a tiny value while the spline strays between them. The optimizers
//! therefore minimise the *dense* RMSE, ‖S(u) − r(u)‖ over a fixed set of evenly spaced
//! parameters (1000 by default, the same set the report's `rmse_dense` uses) — a number
//! that depends on the samples only through the spline they produce.

use super::basis::{basis_functions, find_span, BSpline, MAX_ORDER};
use super::expr::ParametricCurve;
use nalgebra::DMatrix;
use outlinefit::optim::Problem;
use outlinefit::Point;
use serde::Serialize;

/// The clamped knot vector by the averaging rule (module docs) for sorted sample
/// parameters `params` (at least `n_ctrl` of them), `n_ctrl` ≥ `order` control points.
pub fn averaging_knots(params: &[f64], n_ctrl: usize, order: usize) -> Vec<f64> {
    let m1 = params.len(); // m + 1
    let p = order - 1;
    let n = n_ctrl - 1;
    let first = params[0];
    let last = params[m1 - 1];
    let mut knots = Vec::with_capacity(n_ctrl + order);
    knots.extend(std::iter::repeat_n(first, order));
    let d = m1 as f64 / (n - p + 1) as f64;
    for j in 1..=(n - p) {
        let jd = j as f64 * d;
        let i = (jd.floor() as usize).clamp(1, m1 - 1);
        let alpha = jd - i as f64;
        knots.push((1.0 - alpha) * params[i - 1] + alpha * params[i]);
    }
    knots.extend(std::iter::repeat_n(last, order));
    knots
}

/// Least-squares control points: minimises Σ ‖S(uᵢ) − Qᵢ‖² over the control points of
/// a spline with the given `order` and `knots`. `None` when the collocation matrix is
/// (numerically) rank deficient, e.g. when several samples coincide.
pub fn least_squares_control_points(
    params: &[f64],
    points: &[Point],
    order: usize,
    knots: &[f64],
) -> Option<Vec<Point>> {
    let rows = params.len();
    let n_ctrl = knots.len() - order;
    if rows < n_ctrl || order > MAX_ORDER {
        return None;
    }
    let mut a = DMatrix::<f64>::zeros(rows, n_ctrl);
    let mut b = DMatrix::<f64>::zeros(rows, 2);
    let mut basis = [0.0f64; MAX_ORDER];
    for (r, (&u, q)) in params.iter().zip(points).enumerate() {
        let span = find_span(knots, order, n_ctrl, u);
        basis_functions(knots, span, order, u, &mut basis);
        for j in 0..order {
            a[(r, span + 1 - order + j)] = basis[j];
        }
        b[(r, 0)] = q.x;
        b[(r, 1)] = q.y;
    }
    let qr = a.qr();
    let rmat = qr.r();
    let diag_max = (0..n_ctrl).fold(0.0f64, |m, i| m.max(rmat[(i, i)].abs()));
    if diag_max.is_nan()
        || diag_max <= 0.0
        || (0..n_ctrl).any(|i| rmat[(i, i)].abs() <= 1e-12 * diag_max)
    {
        return None;
    }
    let qtb = qr.q().transpose() * b;
    let x = rmat.solve_upper_triangular(&qtb)?;
    let cps: Vec<Point> = (0..n_ctrl)
        .map(|i| Point::new(x[(i, 0)], x[(i, 1)]))
        .collect();
    cps.iter().all(|p| p.is_finite()).then_some(cps)
}

/// What the control points are fitted to (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FitTarget {
    /// Least squares on the samples (the paper's Eq. 1).
    Samples,
    /// Least squares on the true curve at the dense reference parameters (default: it
    /// minimises the dense error the optimizers are scored on).
    #[default]
    Curve,
}

impl FitTarget {
    /// Every target, for the command line.
    pub const ALL: [FitTarget; 2] = [FitTarget::Samples, FitTarget::Curve];

    /// The command-line name (`samples` or `curve`).
    pub fn name(self) -> &'static str {
        match self {
            FitTarget::Samples => "samples",
            FitTarget::Curve => "curve",
        }
    }
}

/// The least-squares spline of `order` with `n_ctrl` control points through the samples
/// (sorted `params`, their curve `points`), knots by the averaging rule.
pub fn fit_samples(
    params: &[f64],
    points: &[Point],
    n_ctrl: usize,
    order: usize,
) -> Option<BSpline> {
    fit_with_sample_knots(params, params, points, n_ctrl, order)
}

/// The spline of `order` with `n_ctrl` control points whose knots come from the samples
/// (sorted `params`) by the averaging rule and whose control points are the least-squares
/// fit to the curve at the `reference` parameters ([`FitTarget::Curve`]).
pub fn fit_curve(
    params: &[f64],
    reference: &DenseReference,
    n_ctrl: usize,
    order: usize,
) -> Option<BSpline> {
    fit_with_sample_knots(params, &reference.params, &reference.points, n_ctrl, order)
}

/// Knots from the samples' `params` by the averaging rule, control points by least squares
/// through `fit_points` at `fit_params`.
fn fit_with_sample_knots(
    params: &[f64],
    fit_params: &[f64],
    fit_points: &[Point],
    n_ctrl: usize,
    order: usize,
) -> Option<BSpline> {
    if params.len() < n_ctrl || n_ctrl < order || order < 2 {
        return None;
    }
    let knots = averaging_knots(params, n_ctrl, order);
    let control_points = least_squares_control_points(fit_params, fit_points, order, &knots)?;
    Some(BSpline {
        order,
        knots,
        control_points,
    })
}

/// Eq. 1 of the paper: √(Σᵢ ‖Qᵢ − S(uᵢ)‖² / n) over the samples (the paper prints the
/// norm without its square; the RMSE it names needs it).
pub fn sample_rmse(spline: &BSpline, params: &[f64], points: &[Point]) -> f64 {
    let sum: f64 = params
        .iter()
        .zip(points)
        .map(|(&u, q)| (spline.point(u) - *q).length_squared())
        .sum();
    (sum / params.len() as f64).sqrt()
}

/// The true curve at a fixed set of evenly spaced parameters, for dense errors.
#[derive(Clone, Debug)]
pub struct DenseReference {
    /// The parameters, `count` evenly spaced values from a to b inclusive.
    pub params: Vec<f64>,
    /// r(u) at each.
    pub points: Vec<Point>,
}

/// Dense error figures of a spline against the true curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenseErrors {
    /// √(mean ‖S(u) − r(u)‖²) over the reference parameters.
    pub rmse: f64,
    /// max ‖S(u) − r(u)‖ over the reference parameters.
    pub max: f64,
}

/// Number of reference parameters of the dense errors.
pub const DENSE_COUNT: usize = 1000;

impl DenseReference {
    /// `count` ≥ 2 evenly spaced parameters of [a, b] (both ends included) and the curve
    /// there.
    pub fn new(curve: &ParametricCurve, a: f64, b: f64, count: usize) -> DenseReference {
        let count = count.max(2);
        let params: Vec<f64> = (0..count)
            .map(|i| {
                if i + 1 == count {
                    b
                } else {
                    a + (b - a) * i as f64 / (count - 1) as f64
                }
            })
            .collect();
        let points = params.iter().map(|&u| curve.point(u)).collect();
        DenseReference { params, points }
    }

    /// The spline's dense errors against the curve.
    pub fn errors(&self, spline: &BSpline) -> DenseErrors {
        let mut sum = 0.0;
        let mut max = 0.0f64;
        for (&u, q) in self.params.iter().zip(&self.points) {
            let d2 = (spline.point(u) - *q).length_squared();
            sum += d2;
            max = max.max(d2);
        }
        DenseErrors {
            rmse: (sum / self.params.len() as f64).sqrt(),
            max: max.sqrt(),
        }
    }
}

/// Samples from the auxiliary parameters an optimizer proposes: `fixed` (the ends and the
/// feature points, sorted) merged with a + xᵢ (b − a), sorted.
pub fn merge_samples(fixed: &[f64], aux01: &[f64], a: f64, b: f64) -> Vec<f64> {
    let mut all: Vec<f64> = fixed.to_vec();
    all.extend(aux01.iter().map(|&x| (a + x * (b - a)).clamp(a, b)));
    all.sort_by(f64::total_cmp);
    all
}

/// The search problem of the hybrid algorithm: the variables are the auxiliary sample
/// positions, each a fraction of the range in [0, 1]; an evaluation merges them with the
/// fixed samples, takes the knots from them, fits the control points to the `fit` target
/// and returns the spline's dense RMSE (+∞ when the fit is singular).
pub struct SamplingProblem<'a> {
    /// The curve being converted.
    pub curve: &'a ParametricCurve,
    /// The range [a, b].
    pub range: (f64, f64),
    /// Fixed sample parameters (ends and feature points), sorted.
    pub fixed: Vec<f64>,
    /// Number of auxiliary samples (the dimension).
    pub aux: usize,
    /// Control points of the spline.
    pub control_points: usize,
    /// Order of the spline.
    pub order: usize,
    /// The dense reference the objective measures against.
    pub reference: &'a DenseReference,
    /// What the control points are fitted to.
    pub fit: FitTarget,
}

impl SamplingProblem<'_> {
    /// The spline of a candidate, its samples and their curve points.
    pub fn spline_for(&self, x: &[f64]) -> (Vec<f64>, Vec<Point>, Option<BSpline>) {
        let (a, b) = self.range;
        let params = merge_samples(&self.fixed, x, a, b);
        let points: Vec<Point> = params.iter().map(|&u| self.curve.point(u)).collect();
        let spline = match self.fit {
            FitTarget::Samples => fit_samples(&params, &points, self.control_points, self.order),
            FitTarget::Curve => fit_curve(&params, self.reference, self.control_points, self.order),
        };
        (params, points, spline)
    }
}

impl Problem for SamplingProblem<'_> {
    fn dim(&self) -> usize {
        self.aux
    }

    fn bounds(&self, _i: usize) -> (f64, f64) {
        (0.0, 1.0)
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        match self.spline_for(x).2 {
            Some(s) => self.reference.errors(&s).rmse,
            None => f64::INFINITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averaging_knots_match_the_nurbs_book_rule_and_are_clamped() {
        let params: Vec<f64> = (0..20).map(|i| i as f64 / 19.0).collect();
        let k = averaging_knots(&params, 6, 4);
        assert_eq!(k.len(), 10);
        assert_eq!(&k[..4], &[0.0; 4]);
        assert_eq!(&k[6..], &[1.0; 4]);
        // d = 20/3: j = 1 → i = 6, α = 2/3 → t = (1/3)·5/19 + (2/3)·6/19.
        assert!((k[4] - (5.0 / 19.0 / 3.0 + 2.0 * 6.0 / 19.0 / 3.0)).abs() < 1e-15);
        assert!(k.windows(2).all(|w| w[0] <= w[1]));
    }

    #[test]
    fn least_squares_reproduces_a_cubic_and_detects_coincident_samples() {
        let params: Vec<f64> = (0..12).map(|i| (i as f64 / 11.0).powf(1.3)).collect();
        let f = |u: f64| Point::new(u * u * u - 2.0 * u, 3.0 * u * u + 1.0);
        let pts: Vec<Point> = params.iter().map(|&u| f(u)).collect();
        let s = fit_samples(&params, &pts, 6, 4).unwrap();
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            assert!((s.point(u) - f(u)).length() < 1e-13);
        }
        assert!(sample_rmse(&s, &params, &pts) < 1e-14);
        // Six control points from samples at only three distinct parameters: singular.
        let bad = [0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0];
        let bad_pts: Vec<Point> = bad.iter().map(|&u| f(u)).collect();
        assert!(fit_samples(&bad, &bad_pts, 6, 4).is_none());
    }

    #[test]
    fn merged_samples_are_sorted_and_in_range() {
        let s = merge_samples(&[0.0, 0.4, 1.0], &[0.9, 0.1, 1.0], 0.0, 2.0);
        assert_eq!(s, vec![0.0, 0.2, 0.4, 1.0, 1.8, 2.0]);
    }
}
