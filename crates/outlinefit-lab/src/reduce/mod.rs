//! Degree reduction of (SG-)Bézier curves: the n-th degree curve P is replaced by an
//! m-th degree SG-Bézier curve Q (m < n), unconstrained, with C0 end points or with C1 end
//! tangents, after the grey-wolf paper (`shared/papers/sg-bezier-degree-reduction-gwo.txt`,
//! §4–§5).
//!
//! # The error
//!
//! The error is the paper's ε of §5, the L2 distance ε = sqrt(∫₀¹ ‖P(t) − Q(t)‖² dt)
//! (`papers/NOTES.md`: the printed formula lost its square root and square). Both curves are
//! polynomials of degree at most n + 1 (an SG-Bézier curve of degree n is a polynomial of
//! degree n + 1), so the integrand has degree at most 2(n + 1) and a Gauss–Legendre rule
//! with n + 2 nodes integrates it exactly (`quad::GaussLegendre::exact_for_degree`).
//!
//! # The method: separable least squares
//!
//! For fixed shape parameters (ω, λ, μ) of the reduced curve, Q is *linear* in its control
//! points, so ε² is a quadratic in them and its minimum is a linear least-squares problem:
//! the Gram matrix G_ij = ∫ l_i l_j of the reduced basis and the right-hand sides
//! b_i = ∫ l_i P, both by the exact quadrature, solved by Cholesky (nalgebra). With ω = 0
//! this is the classical L2-optimal degree reduction of Bézier curves. This is method
//! `exact` ([`reduce_exact`]).
//!
//! An optimizer method (`gwo`, the paper's, with 20 wolves and 20 × 300 = 6,000
//! evaluations, or any name of [`outlinefit::optim::NAMES`]) searches only the reduced curve's
//! shape parameters — ω ∈ [0, 1], λ_j, μ_j ∈ [0, C(m+1, j)], the paper's box (the values
//! Remark 1 derives then lie in the box too) — and takes the control points of every
//! candidate from the least squares above. **The paper does otherwise:** its wolves are the
//! control points themselves (§4.2, §4.4) with the shape parameters fixed per table row, and
//! its fitness is a sampled distance (Eq. 19). Searching the shape and solving the points is
//! never worse at equal shape parameters (the least squares is the exact minimum over the
//! points, which a search can only approach), and it searches the shape, which the paper
//! leaves to the user (its conclusion names this as future work). ω = 0 (the plain Bézier
//! reduction) lies in the box, so the optimizer result is compared with the `exact` ω = 0
//! solution and the better one is returned: an optimizer run is never worse than `exact`.
//! That comparison costs one evaluation of the budget.
//!
//! # Constraints
//!
//! * C0: Q_0 = P(0) = P_0 and Q_m = P(1) = P_n.
//! * C1: also Q'(0) = P'(0) and Q'(1) = P'(1). Derived from the basis, not assumed
//!   Bernstein: only l_{0,m} and l_{1,m} have a nonzero derivative at 0 (l_{i,m} has the
//!   factor t^i), and they sum to zero there, so Q'(0) = l'_{1,m}(0) (Q_1 − Q_0) with
//!   l'_{1,m}(0) = m + ω − ωλ_1; likewise Q'(1) = l'_{m−1,m}(1) (Q_{m−1} − Q_m) with
//!   l'_{m−1,m}(1) = −(m + ω − ωμ_1). Hence Q_1 = P_0 + P'(0) / (m + ω − ωλ_1) and
//!   Q_{m−1} = P_n − P'(1) / (m + ω − ωμ_1), where P' is the original curve's own
//!   derivative (n(P_1 − P_0) for a plain Bézier original). The paper's §4.2 formula,
//!   Q_1 = P_0 + (n + ω − ωλ_1) / (m + ω − ωλ_1) (P_1 − P_0), is the same thing only when
//!   the original curve has the same ω and λ_1 as the reduced one; for its examples (an
//!   original with ω* = 0) it agrees with ours at ω = 0 only. At ω = 1, λ_1 = m + 1 (a
//!   corner of the box) the end derivative of every such Q vanishes, so C1 is impossible
//!   there; `exact` reports it, an optimizer scores it +∞. C1 needs m ≥ 3 (four distinct
//!   fixed points); for m = 3 nothing is left free.
//!
//! # On the paper's Example 1 (degree 6 → 4, tests in `tests.rs`)
//!
//! `exact` at the shapes of Table 2 gives its C1 row to 5 digits (9.1096e-3, 9.1890e-3,
//! 9.1935e-3, 9.1096e-3 for ω = 0, 0.2, 0.3, 0.5), which also confirms the C1 condition
//! above. Its unconstrained and C0 values all lie at or above our exact optimum for the
//! same shape (at ω = 0: 1.8305e-3 and 2.6469e-3; the paper's range 4.0e-3–1.0e-2 and
//! 2.66e-3–1.1e-2): its control-point search did not converge there. `gwo` over the shape
//! reaches 3.6020e-4, 4.9212e-4 and 1.3477e-3 (unconstrained, C0, C1) on every seed tried,
//! what DE also reaches with ten times the budget.
//!
//! Limits: the Gram matrix of a degree-m basis grows ill-conditioned with m (about 10× per
//! degree for Bernstein), so a solve whose Cholesky pivots fall below 1e-14 of the
//! matrix's scale is reported as singular rather than returned inaccurate; some boundary
//! shapes (e.g. ω = 1, λ_1 = m + 1, λ_2 = 0 makes l_{1,m} ≡ 0) are singular by nature.

mod file;
pub mod sg_bezier;

pub use file::{parse_curve_json, read_curve_json, reduction_svg};

use crate::reduce::sg_bezier::{sg_basis, sg_to_bernstein, SgBezier, SgShape};
use crate::{Error, Result};
use nalgebra::DMatrix;
use outlinefit::curve::basis::binomial;
use outlinefit::optim::{self, Problem, SeededRng};
use outlinefit::quad::GaussLegendre;
use outlinefit::Point;
use rand::SeedableRng;
use serde::Serialize;

/// End conditions of the reduced curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Constraint {
    /// No end conditions: the L2-closest curve.
    #[default]
    None,
    /// The end points are kept: Q_0 = P(0), Q_m = P(1).
    C0,
    /// The end points and end derivatives are kept: also Q'(0) = P'(0), Q'(1) = P'(1).
    C1,
}

impl Constraint {
    /// The command-line name: `none`, `c0` or `c1`.
    pub fn name(self) -> &'static str {
        match self {
            Constraint::None => "none",
            Constraint::C0 => "c0",
            Constraint::C1 => "c1",
        }
    }

    /// The smallest reduced degree the constraint allows: 1 for `none` and `c0`, 3 for
    /// `c1` (two fixed points at each end).
    pub fn min_degree(self) -> usize {
        match self {
            Constraint::None | Constraint::C0 => 1,
            Constraint::C1 => 3,
        }
    }
}

impl std::fmt::Display for Constraint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How a reduction is computed. `ReduceOptions::new(m)` gives the documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct ReduceOptions {
    /// The reduced degree m, 1 ≤ m < n (m ≥ 3 with C1).
    pub degree: usize,
    /// End conditions. Default: [`Constraint::None`].
    pub constraint: Constraint,
    /// `exact` (least squares at fixed shape parameters) or the name of an optimizer of
    /// [`outlinefit::optim::NAMES`] that searches the shape parameters. Default: `exact`.
    pub method: String,
    /// The reduced curve's fixed shape for `exact` (lengths for degree m). Default: `None`,
    /// the Bernstein basis (ω = 0, [`SgShape::bezier`]). Must be `None` for an optimizer.
    pub shape: Option<SgShape>,
    /// Objective evaluations for an optimizer, including the one spent on the ω = 0
    /// comparison. Default: 6000 (the paper's 20 wolves × 300 iterations).
    pub budget: u64,
    /// Seed of the optimizer's generator. Default: 1.
    pub seed: u64,
}

impl ReduceOptions {
    /// The defaults for reduced degree `degree`: unconstrained, `exact`, ω = 0, budget
    /// 6000, seed 1.
    pub fn new(degree: usize) -> Self {
        ReduceOptions {
            degree,
            constraint: Constraint::None,
            method: "exact".to_string(),
            shape: None,
            budget: DEFAULT_BUDGET,
            seed: outlinefit::optim::DEFAULT_SEED,
        }
    }
}

/// Default objective evaluations of a metaheuristic: the paper's 20 wolves × 300
/// iterations.
pub const DEFAULT_BUDGET: u64 = 6000;

/// A reduced curve and how good it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Reduction {
    /// The reduced curve: m + 1 control points and its shape (ω = 0 for a plain Bézier).
    pub curve: SgBezier,
    /// The paper's ε = sqrt(∫₀¹ ‖P(t) − Q(t)‖² dt), integrated exactly.
    pub error: f64,
    /// The end conditions that hold.
    pub constraint: Constraint,
    /// `exact` or the optimizer's name.
    pub method: String,
    /// Objective evaluations (least-squares solves) spent: 1 for `exact`.
    pub evaluations: u64,
}

/// Reduces `original` (degree n) to degree `options.degree` as `options` says.
///
/// Errors: [`Error::InvalidOption`] for a degree outside 1 ≤ m < n (m ≥ 3 with C1), an
/// unknown method, a zero budget, a shape of the wrong lengths or given with an optimizer;
/// [`Error::InvalidInput`] for a curve with non-finite data, or when the least squares is
/// singular or C1 is impossible for the given shape (`exact` only; an optimizer skips such
/// shapes).
pub fn reduce(original: &SgBezier, options: &ReduceOptions) -> Result<Reduction> {
    let reducer = Reducer::new(original, options.degree, options.constraint)?;
    let m = options.degree;
    if options.method == "exact" {
        let shape = match &options.shape {
            Some(s) => {
                s.validate(m).map_err(|e| Error::InvalidOption {
                    name: "shape",
                    message: format!("the reduced curve's shape: {e}"),
                })?;
                s.clone()
            }
            None => SgShape::bezier(m),
        };
        let (points, error) = reducer.solve(&shape)?;
        return Ok(Reduction {
            curve: SgBezier {
                points,
                shape: shape.clone(),
            },
            error,
            constraint: options.constraint,
            method: "exact".to_string(),
            evaluations: 1,
        });
    }
    let Some(optimizer) = optim::by_name(&options.method) else {
        return Err(Error::InvalidOption {
            name: "method",
            message: format!(
                "unknown method {:?}; expected exact or one of {}",
                options.method,
                optim::NAMES.join(", ")
            ),
        });
    };
    if options.shape.is_some() {
        return Err(Error::InvalidOption {
            name: "shape",
            message: "a fixed shape applies to method exact only (an optimizer searches it)"
                .to_string(),
        });
    }
    if options.budget == 0 {
        return Err(Error::InvalidOption {
            name: "budget",
            message: "must be at least 1".to_string(),
        });
    }
    // The plain Bézier reduction first: one evaluation, and the result to beat.
    let baseline_shape = SgShape::bezier(m);
    let baseline = reducer.solve(&baseline_shape).ok();
    let problem = ShapeProblem { reducer: &reducer };
    let mut rng = SeededRng::seed_from_u64(options.seed);
    let outcome = optimizer.minimize(&problem, options.budget - 1, &mut rng, false);
    let found = (!outcome.best.is_empty())
        .then(|| {
            let shape = problem.shape(&outcome.best);
            reducer.solve(&shape).ok().map(|(p, e)| (shape, p, e))
        })
        .flatten();
    let best = match (found, baseline) {
        (Some(f), Some((bp, be))) if be <= f.2 => (baseline_shape, bp, be),
        (Some(f), _) => f,
        (None, Some((bp, be))) => (baseline_shape, bp, be),
        (None, None) => {
            // Every candidate failed; the ω = 0 solve's own error says why.
            reducer.solve(&baseline_shape)?;
            return Err(Error::InvalidInput {
                what: "degree reduction".to_string(),
                message: "no shape in the search box gave a solvable least-squares problem"
                    .to_string(),
            });
        }
    };
    Ok(Reduction {
        curve: SgBezier {
            points: best.1,
            shape: best.0,
        },
        error: best.2,
        constraint: options.constraint,
        method: optimizer.name().to_string(),
        evaluations: outcome.evaluations + 1,
    })
}

/// The least-squares reduction of `original` to degree `m` for the reduced curve's fixed
/// `shape` (method `exact`). See [`reduce`] for the errors.
pub fn reduce_exact(
    original: &SgBezier,
    m: usize,
    constraint: Constraint,
    shape: &SgShape,
) -> Result<Reduction> {
    let options = ReduceOptions {
        constraint,
        shape: Some(shape.clone()),
        ..ReduceOptions::new(m)
    };
    reduce(original, &options)
}

/// The L2-optimal reduction of the plain Bézier curve on `points` (degree n =
/// `points.len() − 1`) to a plain Bézier curve of degree `m`: its m + 1 control points and
/// the error ε = sqrt(∫₀¹ ‖P − Q‖² dt). For instance degree 5 → 3 with [`Constraint::C1`]
/// keeps the end points and end tangents (with their lengths).
///
/// Errors as [`reduce`]; also [`Error::InvalidInput`] for no points.
pub fn reduce_bezier(
    points: &[Point],
    m: usize,
    constraint: Constraint,
) -> Result<(Vec<Point>, f64)> {
    let original = SgBezier::from_bezier(points.to_vec()).map_err(|e| Error::InvalidInput {
        what: "Bézier curve".to_string(),
        message: e.to_string(),
    })?;
    let r = reduce_exact(&original, m, constraint, &SgShape::bezier(m))?;
    Ok((r.curve.points, r.error))
}

/// The L2 distance sqrt(∫₀¹ ‖a(t) − b(t)‖² dt) of two SG-Bézier curves of any degrees, by a
/// Gauss–Legendre rule exact for the integrand.
///
/// Errors: [`Error::InvalidInput`] when either curve's fields are inconsistent.
pub fn l2_distance(a: &SgBezier, b: &SgBezier) -> Result<f64> {
    let bad = |e: crate::reduce::sg_bezier::SgError| Error::InvalidInput {
        what: "SG-Bézier curve".to_string(),
        message: e.to_string(),
    };
    a.validate().map_err(bad)?;
    b.validate().map_err(bad)?;
    let rule = GaussLegendre::exact_for_degree(2 * (a.degree().max(b.degree()) + 1));
    let mut sum = 0.0;
    for (&t, &w) in rule.nodes.iter().zip(&rule.weights) {
        let d = a.try_eval(t).map_err(bad)? - b.try_eval(t).map_err(bad)?;
        sum += w * d.length_squared();
    }
    Ok(sum.sqrt())
}

/// Derivatives of the degree-m SG-Bernstein functions at the ends: (l'_{i,m}(0),
/// l'_{i,m}(1)) for every i, from their exact Bernstein form of degree m + 1.
fn end_derivatives(m: usize, shape: &SgShape) -> Result<Vec<(f64, f64)>> {
    let rows = sg_to_bernstein(m, shape).map_err(|e| Error::InvalidInput {
        what: "reduced curve's shape".to_string(),
        message: e.to_string(),
    })?;
    let d = (m + 1) as f64;
    Ok(rows
        .iter()
        .map(|r| (d * (r[1] - r[0]), d * (r[m + 1] - r[m])))
        .collect())
}

/// Everything about the original curve that every least-squares solve reuses.
struct Reducer {
    m: usize,
    constraint: Constraint,
    /// Quadrature nodes and weights, exact for degree 2(n + 1).
    rule: GaussLegendre,
    /// The original curve at the nodes.
    values: Vec<Point>,
    /// P(0), P(1), P'(0), P'(1).
    start: Point,
    end: Point,
    start_derivative: Point,
    end_derivative: Point,
}

impl Reducer {
    /// Checks the curve and the degree, and samples the original at the quadrature nodes.
    fn new(original: &SgBezier, m: usize, constraint: Constraint) -> Result<Self> {
        let bad_curve = |message: String| Error::InvalidInput {
            what: "the original curve".to_string(),
            message,
        };
        original.validate().map_err(|e| bad_curve(e.to_string()))?;
        if let Some(i) = original.points.iter().position(|p| !p.is_finite()) {
            return Err(bad_curve(format!("control point {i} is not finite")));
        }
        let n = original.degree();
        let lowest = constraint.min_degree();
        if m < lowest || m >= n {
            let message = if n <= lowest {
                format!(
                    "the input has degree {n}; reducing it with constraint {constraint} needs \
                     degree at least {}",
                    lowest + 1
                )
            } else {
                format!(
                    "must be between {lowest} and {} (below the input's degree {n}{}), got {m}",
                    n - 1,
                    if constraint == Constraint::C1 {
                        "; C1 needs at least 3"
                    } else {
                        ""
                    }
                )
            };
            return Err(Error::InvalidOption {
                name: "degree",
                message,
            });
        }
        let bernstein = original
            .to_bernstein()
            .map_err(|e| bad_curve(e.to_string()))?;
        let k = bernstein.len() - 1; // n + 1
        let rule = GaussLegendre::exact_for_degree(2 * k);
        let values = rule
            .nodes
            .iter()
            .map(|&t| original.try_eval(t))
            .collect::<std::result::Result<Vec<_>, _>>()
            .map_err(|e| bad_curve(e.to_string()))?;
        let r = Reducer {
            m,
            constraint,
            rule,
            values,
            start: original.points[0],
            end: original.points[n],
            start_derivative: (bernstein[1] - bernstein[0]) * k as f64,
            end_derivative: (bernstein[k] - bernstein[k - 1]) * k as f64,
        };
        let all_finite = r.values.iter().all(|p| p.is_finite())
            && r.start_derivative.is_finite()
            && r.end_derivative.is_finite();
        if !all_finite {
            return Err(bad_curve(
                "the coordinates are too large to evaluate the curve".to_string(),
            ));
        }
        Ok(r)
    }

    /// The least-squares control points for the reduced shape `shape` and the error ε.
    fn solve(&self, shape: &SgShape) -> Result<(Vec<Point>, f64)> {
        let m = self.m;
        let fail = |message: String| Error::InvalidInput {
            what: "degree reduction".to_string(),
            message,
        };
        // Basis values at the nodes, row-major by node.
        let nodes = self.rule.nodes.len();
        let mut phi = vec![0.0; nodes * (m + 1)];
        for (row, &t) in phi.chunks_exact_mut(m + 1).zip(&self.rule.nodes) {
            sg_basis(m, shape, t, row).map_err(|e| fail(e.to_string()))?;
        }
        // Fixed control points.
        let mut fixed: Vec<Option<Point>> = vec![None; m + 1];
        if self.constraint != Constraint::None {
            fixed[0] = Some(self.start);
            fixed[m] = Some(self.end);
        }
        if self.constraint == Constraint::C1 {
            let d = end_derivatives(m, shape)?;
            // Q'(0) = l'_0(0) Q_0 + l'_1(0) Q_1 (l_i has the factor t^i, so the rest vanish
            // at 0 for m ≥ 3); mirrored at 1 with Q_{m−1}, Q_m.
            let (d0, d1) = (d[1].0, d[m - 1].1);
            let scale0 = d[0].0.abs().max(1.0);
            let scale1 = d[m].1.abs().max(1.0);
            if d0.abs() <= 1e-12 * scale0 || d1.abs() <= 1e-12 * scale1 {
                return Err(fail(format!(
                    "C1 is impossible for this shape: the reduced curve's end derivative \
                     vanishes (l'_1(0) = {d0:e}, l'_{{m-1}}(1) = {d1:e})"
                )));
            }
            fixed[1] = Some((self.start_derivative - self.start * d[0].0) / d0);
            fixed[m - 1] = Some((self.end_derivative - self.end * d[m].1) / d1);
        }
        let free: Vec<usize> = (0..=m).filter(|&i| fixed[i].is_none()).collect();
        let mut points: Vec<Point> = fixed.iter().map(|f| f.unwrap_or(Point::ZERO)).collect();
        if !free.is_empty() {
            let f = free.len();
            let mut gram = DMatrix::<f64>::zeros(f, f);
            let mut rhs = DMatrix::<f64>::zeros(f, 2);
            for ((row, &w), &p) in phi
                .chunks_exact(m + 1)
                .zip(&self.rule.weights)
                .zip(&self.values)
            {
                // What the free points must approximate at this node.
                let target = fixed
                    .iter()
                    .zip(row)
                    .fold(p, |acc, (q, &l)| acc - q.unwrap_or(Point::ZERO) * l);
                for (a, &i) in free.iter().enumerate() {
                    let wi = w * row[i];
                    rhs[(a, 0)] += wi * target.x;
                    rhs[(a, 1)] += wi * target.y;
                    for (b, &j) in free.iter().enumerate().take(a + 1) {
                        gram[(a, b)] += wi * row[j];
                    }
                }
            }
            for a in 0..f {
                for b in 0..a {
                    gram[(b, a)] = gram[(a, b)];
                }
            }
            let singular = || {
                fail(format!(
                    "the least-squares system of the reduced degree-{m} basis is singular for \
                     this shape (ω = {}, λ = {:?}, μ = {:?})",
                    shape.omega, shape.lambda, shape.mu
                ))
            };
            let scale = (0..f).map(|a| gram[(a, a)]).fold(0.0, f64::max);
            let chol = gram.cholesky().ok_or_else(singular)?;
            let smallest_pivot = chol
                .l_dirty()
                .diagonal()
                .iter()
                .fold(f64::INFINITY, |a, &v| a.min(v * v));
            if !(scale > 0.0 && smallest_pivot > 1e-14 * scale) {
                return Err(singular());
            }
            let x = chol.solve(&rhs);
            for (a, &i) in free.iter().enumerate() {
                points[i] = Point::new(x[(a, 0)], x[(a, 1)]);
            }
        }
        let error = self.error(&phi, &points);
        if !error.is_finite() || points.iter().any(|p| !p.is_finite()) {
            return Err(fail(
                "the reduced curve is not finite (coordinates too large?)".to_string(),
            ));
        }
        Ok((points, error))
    }

    /// ε for reduced control points `points` whose basis values at the nodes are `phi`.
    fn error(&self, phi: &[f64], points: &[Point]) -> f64 {
        let sum: f64 = phi
            .chunks_exact(self.m + 1)
            .zip(&self.rule.weights)
            .zip(&self.values)
            .map(|((row, &w), &p)| {
                let q = points
                    .iter()
                    .zip(row)
                    .fold(Point::ZERO, |acc, (&c, &l)| acc + c * l);
                w * (p - q).length_squared()
            })
            .sum();
        sum.sqrt()
    }
}

/// The optimizer's problem: the reduced curve's free shape parameters (ω, λ_1.., μ_1..) in
/// the paper's box; the objective is ε of the least-squares control points (+∞ where the
/// solve fails).
struct ShapeProblem<'a> {
    reducer: &'a Reducer,
}

impl ShapeProblem<'_> {
    /// The shape at the search point `x` = (ω, λ…, μ…).
    fn shape(&self, x: &[f64]) -> SgShape {
        let m = self.reducer.m;
        let nl = SgShape::lambda_len(m);
        SgShape {
            omega: x[0],
            lambda: x[1..1 + nl].to_vec(),
            mu: x[1 + nl..].to_vec(),
        }
    }
}

impl Problem for ShapeProblem<'_> {
    fn dim(&self) -> usize {
        1 + self.reducer.m
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        let m = self.reducer.m;
        let nl = SgShape::lambda_len(m);
        match i {
            0 => (0.0, 1.0),
            i if i <= nl => (0.0, binomial(m + 1, i)),
            i => (0.0, binomial(m + 1, i - nl)),
        }
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        self.reducer
            .solve(&self.shape(x))
            .map_or(f64::INFINITY, |(_, e)| e)
    }
}

#[cfg(test)]
mod tests;
