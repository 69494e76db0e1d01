//! The linear part of a segment fit: for fixed weights and parameters the curve is linear
//! in its free control points (or tangent lengths), so they come from a normal system of
//! at most 4 × 4, solved on the stack.

use crate::curve::rational::bernstein;
use crate::curve::rational::RationalCubic;
use crate::geom::Point;
use crate::linalg::solve_rank_tolerant;
use crate::param::Parameterization;

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

/// Settings of [`fit_segment`](super::fit_segment).
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
    /// The parameter correction stops early once, after its round k (from 1), a point
    /// lies farther than this divided by k from the curve at its foot (px): a fit that far
    /// off will be split whatever the remaining rounds do, so they are not spent on it.
    /// The bound tightens because each round brings the curve closer to where it ends.
    /// `None` always runs every round.
    pub give_up: Option<f64>,
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
            give_up: None,
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
            give_up: None,
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
pub(super) struct LinearModel<'a> {
    pub(super) points: &'a [Point],
    bern: Vec<[f64; 4]>,
    pub(super) start: EndCondition,
    pub(super) end: EndCondition,
    /// Bounds of the tangent lengths.
    pub(super) len_bounds: (f64, f64),
}

/// The length scale of a run of points, which bounds its tangent lengths: the longer of
/// its polyline and its chord (at least 1e-9).
pub(super) fn run_scale(points: &[Point]) -> f64 {
    let chord = points[0].distance(points[points.len() - 1]);
    let poly: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    poly.max(chord).max(1e-9)
}

/// Unknowns of the linear model: up to 4 numbers.
#[derive(Clone, Copy, Debug)]
pub(super) struct Unknowns {
    pub(super) z: [f64; 4],
    pub(super) n: usize,
}

impl<'a> LinearModel<'a> {
    pub(super) fn new(
        points: &'a [Point],
        params: &[f64],
        start: EndCondition,
        end: EndCondition,
    ) -> Self {
        Self::with_scale(points, params, start, end, run_scale(points))
    }

    /// [`LinearModel::new`] with the run's [`run_scale`] already known.
    pub(super) fn with_scale(
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

    /// The same model at other parameters (one per point): the Bernstein values are
    /// computed again in place, so that the rounds of a fit reuse one buffer.
    pub(super) fn set_params(&mut self, params: impl Iterator<Item = f64>) {
        self.bern.clear();
        self.bern.extend(params.map(bernstein));
    }

    pub(super) fn c0(&self) -> Point {
        self.points[0]
    }

    pub(super) fn c3(&self) -> Point {
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
    pub(super) fn bounded(&self) -> [Option<usize>; 2] {
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
    pub(super) fn columns(&self, b: &[f64; 4], w: [f64; 2]) -> (Point, [Point; 4]) {
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
    pub(super) fn curve(&self, z: &Unknowns, w: [f64; 2]) -> RationalCubic {
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
    pub(super) fn unknowns_of(&self, c: &RationalCubic) -> Unknowns {
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
    pub(super) fn solve(&self, w: [f64; 2]) -> (Unknowns, f64) {
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
    pub(super) fn error(&self, z: &Unknowns, w: [f64; 2]) -> f64 {
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
    solve_rank_tolerant(&mut m, n)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::param::centripetal_parameters;

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
