//! Fitting one rational cubic segment to a run of data points: the segment-fitting seam
//! every strategy uses.
//!
//! The end points C0 and C3 are the first and last data points. Each end is either free
//! (C1 or C2 is an unknown point) or tangent-constrained (C1 = C0 + a·t0, C2 = C3 − b·t3
//! with given unit tangents and unknown lengths a, b > 0), which is how G1 joints are made
//! exact: both neighbours of a smooth joint use the same unit tangent.
//!
//! **Separable least squares.** For fixed weights (w1, w2) and parameters u_i the curve
//! is linear in the unknowns, P(u) = Σ φ_k(u) C_k with φ_k = B_k w_k / D known numbers, so
//! the unknowns come from a normal system of at most 4 × 4 ([`solve_control_points`]).
//! The weights are then searched in [0.01, 2.5] by a deterministic compass search in
//! log-space ([`fit_segment`]), the parameters are refined by projecting the points onto
//! the curve, and a Levenberg–Marquardt polish minimises the true (orthogonal) distances
//! over control points and weights together, so that data lying exactly on a rational
//! cubic is recovered to round-off.

use crate::curve::power::EXACT_STEP;
use crate::curve::rational::{bernstein, nearest_sample, RationalCubic};
use crate::fit::SegmentError;
use crate::geom::Point;
use crate::param::{centripetal_parameters, parameters_into, Parameterization};

/// What is known about one end of a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EndCondition {
    /// The inner control point next to this end is unconstrained (corner joints).
    Free,
    /// The curve leaves (start) or arrives (end) along this unit tangent, the direction of
    /// travel; only the distance of the inner control point is unknown (smooth joints).
    Tangent(Point),
}

/// The inner-weight interval searched by the fitting strategies: [0.01, 2.5].
pub const WEIGHT_RANGE: (f64, f64) = (0.01, 2.5);

/// Settings of [`fit_segment`].
#[derive(Clone, Copy, Debug)]
pub struct FitSettings {
    /// Weights are searched in this closed interval.
    pub weight_range: (f64, f64),
    /// Rounds of parameter correction by projection, alternating with re-solving.
    pub reparam_rounds: usize,
    /// Levenberg–Marquardt iterations on the orthogonal distances (0 = no polish).
    pub polish_iterations: usize,
    /// The polish stops once an iteration improves the objective by less than this
    /// fraction.
    pub polish_tolerance: f64,
    /// Independent starts (distinct local minima of the weight grid) that are each refined;
    /// the best result wins. The weight landscape has local minima whose curves differ by
    /// a few thousandths of a pixel, so 1 start is enough for noisy outlines while exact
    /// recovery of a rational cubic needs several.
    pub starts: usize,
    /// Initial parameterisations tried; the first is the HS paper's centripetal rule.
    /// Exact recovery needs more than one: data spaced far from centripetally can lead
    /// every start of one rule into the same wrong basin.
    pub initial: &'static [Parameterization],
    /// The weight search of a run of at least twice this many data points evaluates its
    /// objective on every k-th point (and the last), k the largest step that keeps this
    /// many, so between this many and twice as many; the control points are then solved on
    /// every point at the weights found. `None` searches on every point.
    /// The objective is smooth in the weights and the data dense (about a point per pixel),
    /// so a few dozen points place its minimum close to where all of them do, at a
    /// fraction of the cost on long runs.
    pub search_points: Option<usize>,
}

impl FitSettings {
    /// Settings for a polynomial cubic: both weights fixed at 1, so that the segment is
    /// exactly what SVG can draw.
    pub fn polynomial() -> Self {
        FitSettings {
            weight_range: (1.0, 1.0),
            ..FitSettings::default()
        }
    }

    /// True when the weights are fixed (the weight range is a single value).
    pub fn fixed_weights(&self) -> bool {
        self.weight_range.0 == self.weight_range.1
    }

    /// Settings for exact data: several starts and a polish run to round-off. Slower than
    /// the default by roughly the number of starts.
    pub fn thorough() -> Self {
        FitSettings {
            weight_range: WEIGHT_RANGE,
            reparam_rounds: 2,
            polish_iterations: 400,
            polish_tolerance: 0.0,
            starts: 4,
            initial: &[
                Parameterization::Centripetal,
                Parameterization::Chordal,
                Parameterization::Uniform,
            ],
            search_points: None,
        }
    }
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            weight_range: WEIGHT_RANGE,
            reparam_rounds: 2,
            polish_iterations: 25,
            polish_tolerance: 1e-7,
            starts: 1,
            initial: &[Parameterization::Centripetal],
            search_points: None,
        }
    }
}

/// The result of fitting one segment.
#[derive(Clone, Debug)]
pub struct SegmentSolution {
    /// The fitted curve.
    pub curve: RationalCubic,
    /// Final parameter of every data point.
    pub params: Vec<f64>,
    /// Objective evaluations used (one per solve of the linear system or per evaluation of
    /// the distance objective).
    pub evaluations: u64,
}

/// The linear model of a segment at fixed parameters: Bernstein values are computed once.
struct LinearModel<'a> {
    points: &'a [Point],
    bern: Vec<[f64; 4]>,
    start: EndCondition,
    end: EndCondition,
    /// Bounds of the tangent lengths.
    len_bounds: (f64, f64),
}

/// The length scale of a run of points, which bounds its tangent lengths: the longer of
/// its polyline and its chord (at least 1e-9).
fn run_scale(points: &[Point]) -> f64 {
    let chord = points[0].distance(points[points.len() - 1]);
    let poly: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    poly.max(chord).max(1e-9)
}

/// Unknowns of the linear model: up to 4 numbers.
#[derive(Clone, Copy, Debug)]
struct Unknowns {
    z: [f64; 4],
    n: usize,
}

impl<'a> LinearModel<'a> {
    fn new(points: &'a [Point], params: &[f64], start: EndCondition, end: EndCondition) -> Self {
        Self::with_scale(points, params, start, end, run_scale(points))
    }

    /// [`LinearModel::new`] with the run's [`run_scale`] already known.
    fn with_scale(
        points: &'a [Point],
        params: &[f64],
        start: EndCondition,
        end: EndCondition,
        scale: f64,
    ) -> Self {
        let bern = params.iter().map(|&u| bernstein(u)).collect();
        LinearModel {
            points,
            bern,
            start,
            end,
            len_bounds: (1e-4 * scale, 2.0 * scale),
        }
    }

    fn c0(&self) -> Point {
        self.points[0]
    }

    fn c3(&self) -> Point {
        self.points[self.points.len() - 1]
    }

    fn n_unknowns(&self) -> usize {
        let k = |e: EndCondition| {
            if matches!(e, EndCondition::Free) {
                2
            } else {
                1
            }
        };
        k(self.start) + k(self.end)
    }

    /// Indices of unknowns that are bounded tangent lengths.
    fn bounded(&self) -> [Option<usize>; 2] {
        let a = matches!(self.start, EndCondition::Tangent(_)).then_some(0);
        let first_end = if matches!(self.start, EndCondition::Free) {
            2
        } else {
            1
        };
        let b = matches!(self.end, EndCondition::Tangent(_)).then_some(first_end);
        [a, b]
    }

    /// Base point and unknown columns at one data point for weights `w` (the Jacobian of
    /// the polish; [`LinearModel::normal_system`] condenses their products).
    #[inline]
    fn columns(&self, b: &[f64; 4], w: [f64; 2]) -> (Point, [Point; 4]) {
        let nb = [b[0], b[1] * w[0], b[2] * w[1], b[3]];
        let d = nb[0] + nb[1] + nb[2] + nb[3];
        let phi = [nb[0] / d, nb[1] / d, nb[2] / d, nb[3] / d];
        let (c0, c3) = (self.c0(), self.c3());
        let mut base = c0 * phi[0] + c3 * phi[3];
        let mut cols = [Point::ZERO; 4];
        let mut j = 0;
        match self.start {
            EndCondition::Free => {
                cols[0] = Point::new(phi[1], 0.0);
                cols[1] = Point::new(0.0, phi[1]);
                j = 2;
            }
            EndCondition::Tangent(t) => {
                base += c0 * phi[1];
                cols[0] = t * phi[1];
                j += 1;
            }
        }
        match self.end {
            EndCondition::Free => {
                cols[j] = Point::new(phi[2], 0.0);
                cols[j + 1] = Point::new(0.0, phi[2]);
            }
            EndCondition::Tangent(t) => {
                base += c3 * phi[2];
                cols[j] = t * (-phi[2]);
            }
        }
        (base, cols)
    }

    /// Control points from unknowns.
    fn curve(&self, z: &Unknowns, w: [f64; 2]) -> RationalCubic {
        let (c0, c3) = (self.c0(), self.c3());
        let mut j = 0;
        let c1 = match self.start {
            EndCondition::Free => {
                j = 2;
                Point::new(z.z[0], z.z[1])
            }
            EndCondition::Tangent(t) => {
                j += 1;
                c0 + t * z.z[0]
            }
        };
        let c2 = match self.end {
            EndCondition::Free => Point::new(z.z[j], z.z[j + 1]),
            EndCondition::Tangent(t) => c3 - t * z.z[j],
        };
        RationalCubic::new([c0, c1, c2, c3], w)
    }

    /// Unknowns of a given curve (inverse of `curve`).
    fn unknowns_of(&self, c: &RationalCubic) -> Unknowns {
        let mut z = [0.0; 4];
        let mut j = match self.start {
            EndCondition::Free => {
                z[0] = c.points[1].x;
                z[1] = c.points[1].y;
                2
            }
            EndCondition::Tangent(t) => {
                z[0] = (c.points[1] - c.points[0]).dot(t);
                1
            }
        };
        match self.end {
            EndCondition::Free => {
                z[j] = c.points[2].x;
                z[j + 1] = c.points[2].y;
                j += 2;
            }
            EndCondition::Tangent(t) => {
                z[j] = (c.points[3] - c.points[2]).dot(t);
                j += 1;
            }
        }
        Unknowns { z, n: j }
    }

    /// The normal system (A, r) of the unknowns and Σ|q − base|² for weights `w`, in one
    /// pass over the data. Every column of the least-squares problem is φ1 or φ2 times a
    /// fixed vector (a unit axis, or ±a tangent), so A and r follow from five scalar and
    /// two vector sums (Σφ1², Σφ1φ2, Σφ2², Σφ1·res, Σφ2·res); this is the objective of the
    /// `weights` search, and about three times cheaper than forming every column.
    #[inline]
    fn normal_system(&self, w: [f64; 2]) -> ([[f64; 4]; 4], [f64; 4], f64) {
        let (c0, c3) = (self.c0(), self.c3());
        // The base point takes C0's share of φ1 (tangent start) and C3's of φ2 (tangent
        // end), since the unknown only moves the inner control point along the tangent.
        let start_free = matches!(self.start, EndCondition::Free);
        let end_free = matches!(self.end, EndCondition::Free);
        let (mut s11, mut s12, mut s22, mut c) = (0.0, 0.0, 0.0, 0.0);
        let (mut r1, mut r2) = (Point::ZERO, Point::ZERO);
        for (q, b) in self.points.iter().zip(&self.bern) {
            let nb1 = b[1] * w[0];
            let nb2 = b[2] * w[1];
            let inv = 1.0 / (b[0] + nb1 + nb2 + b[3]);
            let (p0, p1, p2, p3) = (b[0] * inv, nb1 * inv, nb2 * inv, b[3] * inv);
            let k0 = if start_free { p0 } else { p0 + p1 };
            let k3 = if end_free { p3 } else { p3 + p2 };
            let res = *q - (c0 * k0 + c3 * k3);
            c += res.length_squared();
            s11 += p1 * p1;
            s12 += p1 * p2;
            s22 += p2 * p2;
            r1 += res * p1;
            r2 += res * p2;
        }
        // Column j is φ_s(j) · v_j with s(j) ∈ {1, 2} and a fixed vector v_j.
        let mut side = [0usize; 4];
        let mut dir = [Point::ZERO; 4];
        let mut n = 0;
        match self.start {
            EndCondition::Free => {
                dir[0] = Point::new(1.0, 0.0);
                dir[1] = Point::new(0.0, 1.0);
                n = 2;
            }
            EndCondition::Tangent(t) => {
                dir[0] = t;
                n += 1;
            }
        }
        match self.end {
            EndCondition::Free => {
                side[n] = 1;
                side[n + 1] = 1;
                dir[n] = Point::new(1.0, 0.0);
                dir[n + 1] = Point::new(0.0, 1.0);
                n += 2;
            }
            EndCondition::Tangent(t) => {
                side[n] = 1;
                dir[n] = t * -1.0;
                n += 1;
            }
        }
        let s = [[s11, s12], [s12, s22]];
        let rs = [r1, r2];
        let mut a = [[0.0; 4]; 4];
        let mut r = [0.0; 4];
        for j in 0..n {
            r[j] = dir[j].dot(rs[side[j]]);
            for k in 0..n {
                a[j][k] = s[side[j]][side[k]] * dir[j].dot(dir[k]);
            }
        }
        (a, r, c)
    }

    /// Least-squares unknowns for weights `w` at the model's parameters (tangent lengths
    /// kept inside their bounds), with the Eq. 4 error they give.
    fn solve(&self, w: [f64; 2]) -> (Unknowns, f64) {
        let n = self.n_unknowns();
        let (a, r, c) = self.normal_system(w);
        let mut fixed: [Option<f64>; 4] = [None; 4];
        let mut z = solve_with_fixed(&a, &r, n, &fixed);
        for _ in 0..2 {
            let mut changed = false;
            for idx in self.bounded().into_iter().flatten() {
                if fixed[idx].is_none() {
                    let v = z[idx];
                    let clamped = v.clamp(self.len_bounds.0, self.len_bounds.1);
                    if v != clamped {
                        fixed[idx] = Some(clamped);
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
            z = solve_with_fixed(&a, &r, n, &fixed);
        }
        // E(z) = Σ|res|² − 2 zᵀr + zᵀAz, exact for any z: one pass over the data. It
        // loses digits only when E is ~1e-12 of Σ|res|², far below what the weight
        // search needs; the polish measures distances directly.
        let mut e = c;
        for j in 0..n {
            e -= 2.0 * z[j] * r[j];
            for k in 0..n {
                e += z[j] * a[j][k] * z[k];
            }
        }
        (Unknowns { z, n }, e.max(0.0))
    }

    /// Eq. 4 error of given unknowns and weights at the model's parameters.
    #[cfg(test)]
    fn error(&self, z: &Unknowns, w: [f64; 2]) -> f64 {
        let mut e = 0.0;
        for (q, b) in self.points.iter().zip(&self.bern) {
            let (base, cols) = self.columns(b, w);
            let mut p = base;
            for j in 0..z.n {
                p += cols[j] * z.z[j];
            }
            e += (p - *q).length_squared();
        }
        e
    }
}

/// Solves the symmetric system `a z = r` of size `n` with some unknowns held fixed, by
/// Gaussian elimination with partial pivoting and a tiny ridge for rank-deficient cases.
fn solve_with_fixed(
    a: &[[f64; 4]; 4],
    r: &[f64; 4],
    n: usize,
    fixed: &[Option<f64>; 4],
) -> [f64; 4] {
    let mut m = [[0.0; 5]; 4];
    let trace: f64 = (0..n).map(|j| a[j][j]).sum();
    let ridge = 1e-13 * trace.max(1e-300);
    for j in 0..n {
        if let Some(v) = fixed[j] {
            m[j][j] = 1.0;
            m[j][4] = v;
            continue;
        }
        let mut rhs = r[j];
        for k in 0..n {
            if let Some(v) = fixed[k] {
                rhs -= a[j][k] * v;
            } else {
                m[j][k] = a[j][k];
            }
        }
        m[j][j] += ridge;
        m[j][4] = rhs;
    }
    solve_dense(&mut m, n)
}

/// Gaussian elimination with partial pivoting on an augmented n × (n+1) matrix.
fn solve_dense(m: &mut [[f64; 5]; 4], n: usize) -> [f64; 4] {
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if m[row][col].abs() > m[piv][col].abs() {
                piv = row;
            }
        }
        m.swap(col, piv);
        let p = m[col][col];
        if p.abs() < 1e-300 {
            continue;
        }
        for row in col + 1..n {
            let f = m[row][col] / p;
            if f != 0.0 {
                for k in col..5 {
                    m[row][k] -= f * m[col][k];
                }
            }
        }
    }
    let mut z = [0.0; 4];
    for row in (0..n).rev() {
        let mut s = m[row][4];
        for k in row + 1..n {
            s -= m[row][k] * z[k];
        }
        let p = m[row][row];
        z[row] = if p.abs() < 1e-300 { 0.0 } else { s / p };
    }
    z
}

/// Control points C1, C2 for fixed weights and fixed parameters, by linear least squares
/// under the end conditions. Returns the curve and its Eq. 4 error.
pub fn solve_control_points(
    points: &[Point],
    params: &[f64],
    start: EndCondition,
    end: EndCondition,
    weights: [f64; 2],
) -> (RationalCubic, f64) {
    let model = LinearModel::new(points, params, start, end);
    let (z, e) = model.solve(weights);
    (model.curve(&z, weights), e)
}

/// The separable formulation as an optimisation problem: the variables stand for the two
/// inner weights (w1, w2) in [`WEIGHT_RANGE`]; for each candidate the control points are
/// solved by least squares under the end conditions, at fixed parameters, and the
/// objective is the resulting Eq. 4 error. Evaluation is allocation-free: one pass over
/// the data and a solve of at most 4 × 4.
///
/// The optimizer does not see w1, w2 themselves but x = (w1 + w2, w1 − w2): scaling both
/// weights together (how strongly the curve is pulled towards its control polygon) and
/// skewing them (how the parameter speed shifts along the curve) are the natural
/// directions of this problem. In (w1, w2) the error has a long, narrow valley along
/// w1 ≈ w2 (on one sample segment it rises 25-fold 0.4 across the valley and changes by
/// 10 % over 1.0 along it), which coordinate-wise searches such as harmony search cross
/// but cannot follow; in these coordinates it lies along the first axis. On the bundled
/// samples harmony search at 5 000 evaluations misses the optimum by more than 0.1 % on
/// 16 of 106 segments in (w1, w2), 29 in (ln w1, ln w2), and on none in these coordinates
/// (apart from two straight runs whose optimum is ~1e-6 px²). Points of the
/// diamond-shaped box outside the weight range are clamped into it
/// ([`WeightsProblem::weights`]).
pub struct WeightsProblem<'a> {
    model: LinearModel<'a>,
}

impl<'a> WeightsProblem<'a> {
    /// The problem for a run of at least 3 `points` at fixed `params`.
    pub fn new(
        points: &'a [Point],
        params: &[f64],
        start: EndCondition,
        end: EndCondition,
    ) -> Self {
        WeightsProblem {
            model: LinearModel::new(points, params, start, end),
        }
    }

    /// The weights a point of the search space stands for, clamped into [`WEIGHT_RANGE`].
    pub fn weights(x: &[f64]) -> [f64; 2] {
        let (lo, hi) = WEIGHT_RANGE;
        [
            (0.5 * (x[0] + x[1])).clamp(lo, hi),
            (0.5 * (x[0] - x[1])).clamp(lo, hi),
        ]
    }

    /// The point of the search space standing for weights `w` (inverse of
    /// [`WeightsProblem::weights`] inside the range).
    pub fn point_of(w: [f64; 2]) -> [f64; 2] {
        [w[0] + w[1], w[0] - w[1]]
    }

    /// The curve (least-squares control points) for the point `x`, with its Eq. 4 error.
    pub fn curve(&self, x: &[f64]) -> (RationalCubic, f64) {
        let w = Self::weights(x);
        let (z, e) = self.model.solve(w);
        (self.model.curve(&z, w), e)
    }

    /// True when a weight of the point `x` sits on a bound of [`WEIGHT_RANGE`].
    pub fn on_weight_bound(x: &[f64]) -> bool {
        let (lo, hi) = WEIGHT_RANGE;
        Self::weights(x)
            .iter()
            .any(|&w| w <= lo * (1.0 + 1e-9) || w >= hi * (1.0 - 1e-9))
    }
}

impl crate::optim::Problem for WeightsProblem<'_> {
    fn dim(&self) -> usize {
        2
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        let (lo, hi) = WEIGHT_RANGE;
        if i == 0 {
            (2.0 * lo, 2.0 * hi)
        } else {
            (lo - hi, hi - lo)
        }
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        self.model.solve(Self::weights(x)).1
    }
}

/// Compass search in (ln w1, ln w2) for the weights minimising the Eq. 4 error with control
/// points solved by least squares. Deterministic. Returns (weights, error, evaluations).
fn search_weights(
    model: &LinearModel<'_>,
    range: (f64, f64),
    start: [f64; 2],
    step0: f64,
    min_step: f64,
) -> ([f64; 2], f64, u64) {
    let (lo, hi) = (range.0.ln(), range.1.ln());
    let mut x = [start[0].ln().clamp(lo, hi), start[1].ln().clamp(lo, hi)];
    let to_w = |x: [f64; 2]| [x[0].exp(), x[1].exp()];
    let mut best = model.solve(to_w(x)).1;
    let mut evals = 1;
    let mut step = step0;
    while step >= min_step && evals < 400 {
        let mut moved = false;
        for dim in 0..2 {
            for dir in [1.0, -1.0] {
                let mut y = x;
                y[dim] = (y[dim] + dir * step).clamp(lo, hi);
                if y[dim] == x[dim] {
                    continue;
                }
                let e = model.solve(to_w(y)).1;
                evals += 1;
                if e < best {
                    best = e;
                    x = y;
                    moved = true;
                    break;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    (to_w(x), best, evals)
}

/// Every `stride`-th item of `items`, and the last one.
fn strided<T: Copy>(items: &[T], stride: usize) -> Vec<T> {
    let last = items.len() - 1;
    let mut out: Vec<T> = items[..last].iter().step_by(stride).copied().collect();
    out.push(items[last]);
    out
}

/// Starting weights from a 4 × 4 grid of typical weights (0.1, 0.4, 1, 2, clamped into
/// `range`): the grid's local minima (4-neighbourhood), best first, at most `count` of them.
/// Returns the starts and the evaluations spent.
fn grid_starts(model: &LinearModel<'_>, range: (f64, f64), count: usize) -> (Vec<[f64; 2]>, u64) {
    const N: usize = 4;
    const GRID: [f64; N] = [0.1, 0.4, 1.0, 2.0];
    let at = |i: usize| GRID[i].clamp(range.0, range.1);
    let mut e = [[0.0; N]; N];
    for (i, row) in e.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = model.solve([at(i), at(j)]).1;
        }
    }
    let mut minima: Vec<(f64, [f64; 2])> = Vec::new();
    for i in 0..N {
        for j in 0..N {
            let v = e[i][j];
            let lower = |a: usize, b: usize| e[a][b] < v;
            let is_min = !((i > 0 && lower(i - 1, j))
                || (i + 1 < N && lower(i + 1, j))
                || (j > 0 && lower(i, j - 1))
                || (j + 1 < N && lower(i, j + 1)));
            if is_min {
                minima.push((v, [at(i), at(j)]));
            }
        }
    }
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut starts: Vec<[f64; 2]> = minima.into_iter().take(count).map(|m| m.1).collect();
    if starts.len() < count && !starts.contains(&[1.0, 1.0]) {
        starts.push([1.0, 1.0]);
    }
    (starts, (N * N) as u64)
}

/// Fits one segment: centripetal parameters, weight search with least-squares control
/// points, parameter correction, then a Levenberg–Marquardt polish of the orthogonal
/// distances. `points` holds the data in order; its first and last points are the end
/// points C0 and C3. Needs at least 2 points; with 2 the result is the straight segment.
pub fn fit_segment(
    points: &[Point],
    start: EndCondition,
    end: EndCondition,
    settings: &FitSettings,
) -> SegmentSolution {
    fit_segment_from(points, start, end, settings, None)
}

/// [`fit_segment`] started from given data parameters (one per point, increasing from 0
/// to 1, e.g. the feet of the points on an earlier fit of the same run) instead of the
/// rules of `settings.initial`: close parameters need fewer correction rounds.
pub fn fit_segment_from(
    points: &[Point],
    start: EndCondition,
    end: EndCondition,
    settings: &FitSettings,
    warm: Option<&[f64]>,
) -> SegmentSolution {
    let mut params = centripetal_parameters(points);
    if points.len() < 3 {
        let (c0, c3) = (points[0], points[points.len() - 1]);
        let curve = straight_segment(c0, c3, start, end);
        return SegmentSolution {
            curve,
            params,
            evaluations: 0,
        };
    }
    let any_free = matches!(start, EndCondition::Free) || matches!(end, EndCondition::Free);
    if points.len() == 3 && any_free {
        // One interior point cannot determine a free handle (two unknowns each): the
        // normal equations are singular and their solution arbitrary (a loop far from
        // the points). Take the nearest curve to the straight one through the point.
        let curve = bent_straight_segment(points, params[1], start, end);
        return SegmentSolution {
            curve,
            params,
            evaluations: 1,
        };
    }
    let centripetal = params.clone();
    let scale = run_scale(points);
    let mut evaluations = 0;
    let mut runs: Vec<(Vec<f64>, [f64; 2])> = Vec::new();
    let inits: Vec<Vec<f64>> = match warm.filter(|w| w.len() == points.len()) {
        Some(w) => vec![w.to_vec()],
        None => settings
            .initial
            .iter()
            .map(|&rule| {
                let mut p = Vec::with_capacity(points.len());
                parameters_into(points, rule, &mut p);
                p
            })
            .collect(),
    };
    // The weight search evaluates every `stride`-th point (and the last) of a long run.
    let stride = match settings.search_points {
        Some(m) if !settings.fixed_weights() => (points.len() / m.max(2)).max(1),
        _ => 1,
    };
    let search_points = (stride > 1).then(|| strided(points, stride));
    let search_model = |params: &[f64]| {
        search_points.as_deref().map(|subset| {
            LinearModel::with_scale(subset, &strided(params, stride), start, end, scale)
        })
    };
    for initial in inits {
        if settings.fixed_weights() {
            runs.push((initial.clone(), [settings.weight_range.0; 2]));
            continue;
        }
        let model = search_model(&initial)
            .unwrap_or_else(|| LinearModel::with_scale(points, &initial, start, end, scale));
        let (starts, ev) = grid_starts(&model, settings.weight_range, settings.starts.max(1));
        evaluations += ev;
        runs.extend(starts.into_iter().map(|w| (initial.clone(), w)));
    }
    let mut best: Option<(RationalCubic, Vec<f64>, f64)> = None;
    // With one run there is nothing to choose between: its objective (one more projection
    // of every point) is not needed.
    let single = runs.len() == 1;
    for (initial_params, w0) in runs {
        params.copy_from_slice(&initial_params);
        let mut weights = w0;
        let mut curve;
        let mut round = 0;
        loop {
            let model = LinearModel::with_scale(points, &params, start, end, scale);
            if !settings.fixed_weights() {
                // Later rounds only adjust: the parameters moved a little.
                let step = if round == 0 { 0.5 } else { 0.1 };
                let coarse = search_model(&params);
                let searched = coarse.as_ref().unwrap_or(&model);
                let (w, _, ev) =
                    search_weights(searched, settings.weight_range, weights, step, 0.02);
                evaluations += ev;
                weights = w;
            }
            let (z, _) = model.solve(weights);
            evaluations += 1;
            curve = model.curve(&z, weights);
            if round >= settings.reparam_rounds {
                break;
            }
            reproject(&curve, points, &mut params);
            round += 1;
        }
        // Leave the parameters at the feet of the points, so that residuals are distances.
        reproject(&curve, points, &mut params);
        if settings.polish_iterations > 0 {
            let model = LinearModel::with_scale(points, &params, start, end, scale);
            let (polished, ev) = polish(&model, curve, &mut params, settings);
            curve = polished;
            evaluations += ev;
        }
        if single {
            best = Some((curve, params, 0.0));
            break;
        }
        let obj = orthogonal_objective(&curve, points, &mut params);
        if best.as_ref().is_none_or(|b| obj < b.2) {
            best = Some((curve, params.clone(), obj));
        }
    }
    let (curve, params, _) = best.unwrap_or_else(|| {
        (
            straight_segment(points[0], points[points.len() - 1], start, end),
            centripetal,
            0.0,
        )
    });
    SegmentSolution {
        curve,
        params,
        evaluations,
    }
}

/// The least-squares optimum at fixed parameters: weights by a grid and a fine compass
/// search (to a step of 1e-4 in log-space), control points solved exactly for each. This is
/// the reference a metaheuristic searching the same space is compared with. Returns the
/// curve and its Eq. 4 error.
pub fn optimum_at_fixed_params(
    points: &[Point],
    params: &[f64],
    start: EndCondition,
    end: EndCondition,
) -> (RationalCubic, f64) {
    if points.len() < 3 {
        return (
            straight_segment(points[0], points[points.len() - 1], start, end),
            0.0,
        );
    }
    let model = LinearModel::new(points, params, start, end);
    let (starts, _) = grid_starts(&model, WEIGHT_RANGE, 3);
    let mut best = ([1.0, 1.0], f64::INFINITY);
    for w0 in starts {
        let (w, e, _) = search_weights(&model, WEIGHT_RANGE, w0, 0.5, 1e-4);
        let (w, e) = follow_valley(&model, w, e);
        if e < best.1 {
            best = (w, e);
        }
    }
    let (z, e) = model.solve(best.0);
    (model.curve(&z, best.0), e)
}

/// Pattern search in (ln w1, ln w2) along the axes and both diagonals, from weights `w`
/// with error `e`, down to steps of 1e-7: it follows the narrow valley along w1 ≈ w2 that
/// an axis-only search leaves early (see [`WeightsProblem`]). Used for the reference
/// optimum, where a precise value matters more than time.
fn follow_valley(model: &LinearModel<'_>, w: [f64; 2], e: f64) -> ([f64; 2], f64) {
    const DIRS: [[f64; 2]; 8] = [
        [1.0, 0.0],
        [-1.0, 0.0],
        [0.0, 1.0],
        [0.0, -1.0],
        [1.0, 1.0],
        [-1.0, -1.0],
        [1.0, -1.0],
        [-1.0, 1.0],
    ];
    let (lo, hi) = (WEIGHT_RANGE.0.ln(), WEIGHT_RANGE.1.ln());
    let mut x = [w[0].ln(), w[1].ln()];
    let mut best = e;
    let mut step = 0.05;
    let mut evals = 0;
    while step >= 1e-7 && evals < 20_000 {
        let mut moved = false;
        for d in DIRS {
            let y = [
                (x[0] + d[0] * step).clamp(lo, hi),
                (x[1] + d[1] * step).clamp(lo, hi),
            ];
            if y == x {
                continue;
            }
            let v = model.solve([y[0].exp(), y[1].exp()]).1;
            evals += 1;
            if v < best {
                best = v;
                x = y;
                moved = true;
                break;
            }
        }
        if moved {
            step *= 1.5;
        } else {
            step *= 0.5;
        }
    }
    ([x[0].exp(), x[1].exp()], best)
}

/// A straight segment honouring the end conditions as well as it can.
fn straight_segment(c0: Point, c3: Point, start: EndCondition, end: EndCondition) -> RationalCubic {
    let third = c0.distance(c3) / 3.0;
    let c1 = match start {
        EndCondition::Free => c0.lerp(c3, 1.0 / 3.0),
        EndCondition::Tangent(t) => c0 + t * third.max(1e-9),
    };
    let c2 = match end {
        EndCondition::Free => c0.lerp(c3, 2.0 / 3.0),
        EndCondition::Tangent(t) => c3 - t * third.max(1e-9),
    };
    RationalCubic::new([c0, c1, c2, c3], [1.0, 1.0])
}

/// The cubic through three points (the middle one at parameter `u`) whose inner control
/// points are nearest to those of the straight segment (chord thirds, or along the given
/// tangents): the least-norm change of the handles that moves the curve at `u` onto the
/// middle point. A free handle moves in any direction, a tangent handle only along its
/// tangent.
fn bent_straight_segment(
    points: &[Point],
    u: f64,
    start: EndCondition,
    end: EndCondition,
) -> RationalCubic {
    let (c0, c3) = (points[0], points[points.len() - 1]);
    let straight = straight_segment(c0, c3, start, end);
    let [_, c1, c2, _] = straight.points;
    let v = 1.0 - u;
    let basis = [3.0 * u * v * v, 3.0 * u * u * v];
    let conditions = [start, end];
    let miss = points[1] - straight.eval(u);
    // M = Σ b² P over the handles, P the identity (free) or t tᵀ (tangent).
    let mut m = [[0.0; 2]; 2];
    for (b, c) in basis.iter().zip(conditions) {
        let p = match c {
            EndCondition::Free => [[1.0, 0.0], [0.0, 1.0]],
            EndCondition::Tangent(t) => [[t.x * t.x, t.x * t.y], [t.x * t.y, t.y * t.y]],
        };
        for (row, prow) in m.iter_mut().zip(p) {
            for (e, pe) in row.iter_mut().zip(prow) {
                *e += b * b * pe;
            }
        }
    }
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if det.abs() < 1e-18 {
        return straight;
    }
    let lambda = Point::new(
        (m[1][1] * miss.x - m[0][1] * miss.y) / det,
        (m[0][0] * miss.y - m[1][0] * miss.x) / det,
    );
    let shift = |b: f64, c: EndCondition| match c {
        EndCondition::Free => lambda * b,
        EndCondition::Tangent(t) => t * (b * t.dot(lambda)),
    };
    RationalCubic::new(
        [
            c0,
            c1 + shift(basis[0], start),
            c2 + shift(basis[1], end),
            c3,
        ],
        [1.0, 1.0],
    )
}

/// Moves every interior parameter to the foot of its point on the curve (local Newton).
fn reproject(curve: &RationalCubic, points: &[Point], params: &mut [f64]) {
    let n = points.len();
    let power = curve.power_form();
    for i in 1..n.saturating_sub(1) {
        params[i] = power.project_quick(points[i], params[i], 3);
    }
}

/// Sum of squared point-to-curve distances, re-projecting parameters from their current
/// values.
fn orthogonal_objective(curve: &RationalCubic, points: &[Point], params: &mut [f64]) -> f64 {
    let n = points.len();
    let mut e = 0.0;
    let power = curve.power_form();
    for i in 1..n - 1 {
        let u = power.project_quick(points[i], params[i], 4);
        params[i] = u;
        e += (power.eval(u) - points[i]).length_squared();
    }
    e
}

/// Levenberg–Marquardt on the orthogonal distances: a Gauss–Newton method over the linear
/// unknowns, the log weights and every data parameter together (orthogonal distance
/// regression). The parameters are eliminated by a Schur complement, so each iteration
/// solves one system of at most 6 × 6; steps are accepted only if the sum of squared
/// point-to-curve distances (after re-projection) decreases.
fn polish(
    model: &LinearModel<'_>,
    start_curve: RationalCubic,
    params: &mut [f64],
    settings: &FitSettings,
) -> (RationalCubic, u64) {
    let points = model.points;
    let n_pts = points.len();
    let mut z = model.unknowns_of(&start_curve);
    let nz = z.n;
    let nv = nz + 2;
    let (wlo, whi) = (settings.weight_range.0.ln(), settings.weight_range.1.ln());
    let mut lw = [start_curve.weights[0].ln(), start_curve.weights[1].ln()];
    let mut curve = start_curve;
    let mut trial_params = params.to_vec();
    let mut obj = orthogonal_objective(&curve, points, params);
    let mut evals = 1u64;
    let mut mu = 1e-4;
    let bounded = model.bounded();
    for _ in 0..settings.polish_iterations {
        if obj <= 1e-26 {
            break;
        }
        // Per point: residual r_i, Jacobian in θ (2 × nv) and P'(u_i).
        let mut jtj = [[0.0; 6]; 6];
        let mut jtr = [0.0; 6];
        // Cross terms b_i = P'ᵀ J_i and tangential residuals, needed after the θ solve.
        let mut cross_sum = [[0.0; 6]; 6];
        let mut cross_rhs = [0.0; 6];
        let w = curve.weights;
        for i in 1..n_pts - 1 {
            let u = params[i];
            let jet = curve.jet(u);
            let r = jet.point - points[i];
            let b = bernstein(u);
            let (_, cols) = model.columns(&b, w);
            let mut jac = [Point::ZERO; 6];
            jac[..nz].copy_from_slice(&cols[..nz]);
            let d = b[0] + b[1] * w[0] + b[2] * w[1] + b[3];
            for k in 0..2 {
                // ∂P/∂ln w_k = w_k B_k (C_k − P) / D.
                jac[nz + k] = (curve.points[k + 1] - jet.point) * (w[k] * b[k + 1] / d);
            }
            // A parameter held at an end of [0, 1] is treated as fixed: its point then pulls
            // with its full residual, not only the normal part.
            let pinned = u <= 0.0 || u >= 1.0;
            let a_i = jet.d1.length_squared() * (1.0 + mu) + 1e-300;
            let mut bi = [0.0; 6];
            if !pinned {
                for c in 0..nv {
                    bi[c] = jet.d1.dot(jac[c]);
                }
            }
            let tr = jet.d1.dot(r);
            for c in 0..nv {
                jtr[c] += jac[c].dot(r);
                cross_rhs[c] += bi[c] * tr / a_i;
                for e in c..nv {
                    jtj[c][e] += jac[c].dot(jac[e]);
                    cross_sum[c][e] += bi[c] * bi[e] / a_i;
                }
            }
        }
        for c in 0..nv {
            for e in 0..c {
                jtj[c][e] = jtj[e][c];
                cross_sum[c][e] = cross_sum[e][c];
            }
        }
        let mut improved = false;
        for _ in 0..8 {
            let mut m = [[0.0; 6]; 6];
            let mut g = [0.0; 6];
            for c in 0..nv {
                for e in 0..nv {
                    m[c][e] = jtj[c][e] - cross_sum[c][e];
                }
                g[c] = jtr[c] - cross_rhs[c];
            }
            // Damp with the reduced diagonal: the parameters absorb most of the tangential
            // motion, so the reduced system can be far smaller than JᵀJ.
            for c in 0..nv {
                m[c][c] += mu * m[c][c].abs().max(1e-18);
            }
            let Some(delta) = solve6(&m, &g, nv) else {
                break;
            };
            let mut z_new = z;
            for j in 0..nz {
                z_new.z[j] -= delta[j];
            }
            for idx in bounded.into_iter().flatten() {
                z_new.z[idx] = z_new.z[idx].clamp(model.len_bounds.0, model.len_bounds.1);
            }
            let lw_new = [
                (lw[0] - delta[nz]).clamp(wlo, whi),
                (lw[1] - delta[nz + 1]).clamp(wlo, whi),
            ];
            let cand = model.curve(&z_new, [lw_new[0].exp(), lw_new[1].exp()]);
            // Parameter update from the eliminated block, then re-projection.
            for i in 1..n_pts - 1 {
                let u = params[i];
                if u <= 0.0 || u >= 1.0 {
                    trial_params[i] = u;
                    continue;
                }
                let jet = curve.jet(u);
                let r = jet.point - points[i];
                let b = bernstein(u);
                let (_, cols) = model.columns(&b, w);
                let dd = b[0] + b[1] * w[0] + b[2] * w[1] + b[3];
                let mut bd = 0.0;
                for j in 0..nz {
                    bd += jet.d1.dot(cols[j]) * delta[j];
                }
                for k in 0..2 {
                    let dp = (curve.points[k + 1] - jet.point) * (w[k] * b[k + 1] / dd);
                    bd += jet.d1.dot(dp) * delta[nz + k];
                }
                let a_i = jet.d1.length_squared() * (1.0 + mu) + 1e-300;
                trial_params[i] = (u - (jet.d1.dot(r) - bd) / a_i).clamp(0.0, 1.0);
            }
            let o = orthogonal_objective(&cand, points, &mut trial_params);
            evals += 1;
            if o < obj {
                let rel = (obj - o) / obj.max(1e-300);
                obj = o;
                z = z_new;
                lw = lw_new;
                curve = cand;
                params.copy_from_slice(&trial_params);
                mu = (mu * 0.2).max(1e-15);
                improved = rel > settings.polish_tolerance;
                break;
            }
            mu *= 10.0;
        }
        if !improved {
            break;
        }
    }
    (curve, evals)
}

/// Gaussian elimination for the (≤ 6) × (≤ 6) LM system; `None` if singular.
fn solve6(a: &[[f64; 6]; 6], b: &[f64; 6], n: usize) -> Option<[f64; 6]> {
    let mut m = [[0.0; 7]; 6];
    for i in 0..n {
        m[i][..n].copy_from_slice(&a[i][..n]);
        m[i][6] = b[i];
    }
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if m[row][col].abs() > m[piv][col].abs() {
                piv = row;
            }
        }
        m.swap(col, piv);
        let p = m[col][col];
        if p.is_nan() || p.abs() <= 1e-300 {
            return None;
        }
        for row in col + 1..n {
            let f = m[row][col] / p;
            for k in col..7 {
                m[row][k] -= f * m[col][k];
            }
        }
    }
    let mut x = [0.0; 6];
    for row in (0..n).rev() {
        let mut s = m[row][6];
        for k in row + 1..n {
            s -= m[row][k] * x[k];
        }
        x[row] = s / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Error measures of `curve` against `points` with parameters `params`: Eq. 4 at the given
/// parameters, and point-to-curve distances by global projection (a scan of the curve
/// followed by Newton), so a poor parameter cannot hide or inflate a distance.
pub fn segment_error(curve: &RationalCubic, points: &[Point], params: &[f64]) -> SegmentError {
    let n = points.len().max(1);
    let mut sum_sq = 0.0;
    let mut max_d: f64 = 0.0;
    let mut sum_d = 0.0;
    const SAMPLES: usize = 24;
    let scan = curve.scan(SAMPLES);
    let power = curve.power_form();
    for (q, &u) in points.iter().zip(params) {
        sum_sq += (curve.eval(u) - *q).length_squared();
        let (foot, local) = power.refine_projection(*q, u, EXACT_STEP);
        // The global search refines from the scan's nearest sample; when that sample is
        // next to the local foot, it lies in the same basin and would find the same foot.
        let start = nearest_sample(scan.iter().copied(), *q);
        let d = if start.abs_diff((foot * SAMPLES as f64).round() as usize) <= 1 {
            local
        } else {
            let global = power.refine_projection(*q, start as f64 / SAMPLES as f64, EXACT_STEP);
            local.min(global.1)
        };
        max_d = max_d.max(d);
        sum_d += d;
    }
    SegmentError {
        sum_sq,
        rmse: (sum_sq / n as f64).sqrt(),
        max_distance: max_d,
        mean_distance: sum_d / n as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn sample_curve(c: &RationalCubic, n: usize) -> Vec<Point> {
        (0..n).map(|i| c.eval(i as f64 / (n - 1) as f64)).collect()
    }

    fn max_dist_to(c: &RationalCubic, pts: &[Point]) -> f64 {
        pts.iter().map(|q| c.nearest(*q, 64).1).fold(0.0, f64::max)
    }

    #[test]
    fn random_rational_cubics_are_recovered_with_free_ends() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for trial in 0..50 {
            let pts = [
                Point::new(0.0, 0.0),
                Point::new(rng.random_range(5.0..25.0), rng.random_range(10.0..40.0)),
                Point::new(rng.random_range(35.0..55.0), rng.random_range(10.0..40.0)),
                Point::new(60.0, rng.random_range(-5.0..5.0)),
            ];
            let w = [rng.random_range(0.2..2.5), rng.random_range(0.2..2.5)];
            let truth = RationalCubic::new(pts, w);
            let data = sample_curve(&truth, 200);
            let sol = fit_segment(
                &data,
                EndCondition::Free,
                EndCondition::Free,
                &FitSettings::thorough(),
            );
            let err = max_dist_to(&sol.curve, &data);
            assert!(
                err < 1e-6,
                "trial {trial}: weights {w:?} → {:?}, max distance {err}",
                sol.curve.weights
            );
        }
    }

    #[test]
    fn tangent_constraints_are_exact_and_recover_the_curve() {
        let truth = RationalCubic::new(
            [
                Point::new(0.0, 0.0),
                Point::new(10.0, 20.0),
                Point::new(40.0, 25.0),
                Point::new(50.0, 0.0),
            ],
            [1.7, 0.45],
        );
        let t0 = truth.start_tangent().unwrap();
        let t3 = truth.end_tangent().unwrap();
        let data = sample_curve(&truth, 120);
        let sol = fit_segment(
            &data,
            EndCondition::Tangent(t0),
            EndCondition::Tangent(t3),
            &FitSettings::thorough(),
        );
        let got0 = sol.curve.start_tangent().unwrap();
        let got3 = sol.curve.end_tangent().unwrap();
        assert!(crate::geom::angle_between(got0, t0) < 1e-12);
        assert!(crate::geom::angle_between(got3, t3) < 1e-12);
        assert!(max_dist_to(&sol.curve, &data) < 1e-6);
        assert!(
            (sol.curve.weights[0] - 1.7).abs() < 1e-5,
            "{:?}",
            sol.curve.weights
        );
    }

    #[test]
    fn linear_solve_is_exact_at_true_parameters_and_weights() {
        let truth = RationalCubic::new(
            [
                Point::new(1.0, 2.0),
                Point::new(3.0, 9.0),
                Point::new(8.0, 7.5),
                Point::new(11.0, 1.0),
            ],
            [0.3, 2.1],
        );
        let params: Vec<f64> = (0..30).map(|i| (i as f64 / 29.0).powf(1.3)).collect();
        let data: Vec<Point> = params.iter().map(|&u| truth.eval(u)).collect();
        let (c, e) = solve_control_points(
            &data,
            &params,
            EndCondition::Free,
            EndCondition::Free,
            [0.3, 2.1],
        );
        assert!(e < 1e-20);
        assert!(c.points[1].distance(truth.points[1]) < 1e-9);
        assert!(c.points[2].distance(truth.points[2]) < 1e-9);
    }

    /// Three points between two corners (a serif's short flat end) used to give an
    /// arbitrary solution of a singular system: a loop 2.4 px out from the points.
    #[test]
    fn three_points_with_a_free_end_give_a_curve_through_them_without_a_loop() {
        let points = [
            Point::new(32.986_531, 38.173_453),
            Point::new(33.011_039, 37.447_736),
            Point::new(33.113_380, 35.928_570),
        ];
        let tangent = Point::new(1.0, 0.0);
        for (start, end) in [
            (EndCondition::Free, EndCondition::Free),
            (EndCondition::Free, EndCondition::Tangent(tangent)),
            (
                EndCondition::Tangent(Point::new(0.0, -1.0)),
                EndCondition::Free,
            ),
        ] {
            let sol = fit_segment(&points, start, end, &FitSettings::polynomial());
            let c = sol.curve;
            assert!(
                c.eval(sol.params[1]).distance(points[1]) < 1e-9,
                "{start:?} {end:?}"
            );
            assert_eq!((c.eval(0.0), c.eval(1.0)), (points[0], points[2]));
            if let EndCondition::Tangent(t) = end {
                let arrival = (c.points[3] - c.points[2]).normalized().unwrap();
                assert!(arrival.cross(t).abs() < 1e-12, "{start:?} {end:?}");
            }
            if let EndCondition::Tangent(t) = start {
                let leaving = (c.points[1] - c.points[0]).normalized().unwrap();
                assert!(leaving.cross(t).abs() < 1e-12, "{start:?} {end:?}");
            }
            // Nothing of the curve strays from the points by more than the chord's length.
            let chord = points[0].distance(points[2]);
            let far = (0..=100)
                .map(|i| {
                    let p = c.eval(i as f64 / 100.0);
                    crate::geom::segment_distance(p, points[0], points[1])
                        .min(crate::geom::segment_distance(p, points[1], points[2]))
                })
                .fold(0.0, f64::max);
            assert!(far < 0.5 * chord, "{start:?} {end:?}: {far}");
        }
    }
}

#[cfg(test)]
mod quadratic_form_tests {
    use super::*;

    /// The condensed normal system equals the one formed column by column.
    #[test]
    fn normal_system_matches_the_columns() {
        let pts: Vec<Point> = (0..30)
            .map(|i| Point::new(i as f64 * 1.3, (i as f64 * 0.3).cos() * 5.0))
            .collect();
        let params = centripetal_parameters(&pts);
        let t0 = EndCondition::Tangent(Point::new(0.8, 0.6));
        let t3 = EndCondition::Tangent(Point::new(0.0, -1.0));
        for (start, end) in [
            (EndCondition::Free, EndCondition::Free),
            (t0, EndCondition::Free),
            (EndCondition::Free, t3),
            (t0, t3),
        ] {
            let model = LinearModel::new(&pts, &params, start, end);
            let n = model.n_unknowns();
            for w in [[1.0, 1.0], [0.05, 2.4], [1.7, 0.3]] {
                let (a, r, c) = model.normal_system(w);
                let (mut a2, mut r2, mut c2) = ([[0.0; 4]; 4], [0.0; 4], 0.0);
                for (q, b) in pts.iter().zip(&model.bern) {
                    let (base, cols) = model.columns(b, w);
                    let res = *q - base;
                    c2 += res.length_squared();
                    for j in 0..n {
                        r2[j] += cols[j].dot(res);
                        for k in 0..n {
                            a2[j][k] += cols[j].dot(cols[k]);
                        }
                    }
                }
                let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1.0);
                assert!(close(c, c2), "{c} vs {c2}");
                for j in 0..4 {
                    assert!(close(r[j], r2[j]), "r[{j}] {} vs {}", r[j], r2[j]);
                    for k in 0..4 {
                        assert!(close(a[j][k], a2[j][k]), "a[{j}][{k}]");
                    }
                }
            }
        }
    }

    #[test]
    fn one_pass_error_matches_direct_sum() {
        let pts: Vec<Point> = (0..40)
            .map(|i| {
                Point::new(
                    i as f64,
                    (i as f64 * 0.2).sin() * 6.0 + 0.01 * (i * i) as f64,
                )
            })
            .collect();
        let params = centripetal_parameters(&pts);
        for (start, end) in [
            (EndCondition::Free, EndCondition::Free),
            (
                EndCondition::Tangent(Point::new(1.0, 0.0)),
                EndCondition::Tangent(Point::new(0.6, 0.8)),
            ),
            // A tangent pointing backwards forces the length bound to be active.
            (
                EndCondition::Tangent(Point::new(-1.0, 0.0)),
                EndCondition::Free,
            ),
        ] {
            let model = LinearModel::new(&pts, &params, start, end);
            for w in [[1.0, 1.0], [0.3, 2.2], [2.5, 0.01]] {
                let (z, e) = model.solve(w);
                let direct = model.error(&z, w);
                assert!(
                    (e - direct).abs() <= 1e-9 * direct.max(1.0),
                    "{e} vs {direct}"
                );
            }
        }
    }
}
