//! Rational cubic Bézier segments in the standard form of Eq. 1 of the harmony-search
//! paper: end weights w0 = w3 = 1, inner weights w1, w2 > 0.
//!
//! P(u) = Σ B_k(u) w_k C_k / Σ B_k(u) w_k, u ∈ [0, 1], with B_k the cubic Bernstein
//! polynomials. The module evaluates the curve and its first two derivatives, projects
//! points onto it (nearest point by a global scan followed by Newton's method), and
//! subdivides it. Written by hand: no maintained crate offers rational cubics.

pub(crate) use super::power::CurveJet;
use super::power::{PowerCubic, EXACT_STEP};
use crate::geom::Point;
use serde::{Deserialize, Serialize};

/// Cubic Bernstein basis values at `u`.
#[inline]
pub(crate) fn bernstein(u: f64) -> [f64; 4] {
    let v = 1.0 - u;
    [v * v * v, 3.0 * u * v * v, 3.0 * u * u * v, u * u * u]
}

/// First derivatives of the cubic Bernstein basis at `u`.
#[inline]
fn bernstein_d1(u: f64) -> [f64; 4] {
    let v = 1.0 - u;
    [
        -3.0 * v * v,
        3.0 * v * (1.0 - 3.0 * u),
        3.0 * u * (2.0 - 3.0 * u),
        3.0 * u * u,
    ]
}

/// Second derivatives of the cubic Bernstein basis at `u`.
#[inline]
fn bernstein_d2(u: f64) -> [f64; 4] {
    [6.0 * (1.0 - u), 18.0 * u - 12.0, 6.0 - 18.0 * u, 6.0 * u]
}

/// A rational cubic Bézier segment with end weights 1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RationalCubic {
    /// Control points C0, C1, C2, C3.
    pub points: [Point; 4],
    /// Inner weights w1, w2 (the end weights are 1).
    pub weights: [f64; 2],
}

impl RationalCubic {
    /// A segment from control points and inner weights.
    pub fn new(points: [Point; 4], weights: [f64; 2]) -> Self {
        RationalCubic { points, weights }
    }

    /// The conic arc with control points `p0`, `p1`, `p2` and middle weight `w` > 0 (end
    /// weights 1), exactly, as a rational cubic: degree elevation gives
    /// C1 = (P0 + 2w P1)/(1 + 2w), C2 = (2w P1 + P2)/(1 + 2w) and w1 = w2 = (1 + 2w)/3.
    /// A circular arc of angle θ is the conic with `p1` where the end tangents cross and
    /// w = cos(θ/2).
    pub fn from_conic(p0: Point, p1: Point, p2: Point, w: f64) -> Self {
        let s = 1.0 + 2.0 * w;
        let inner = (1.0 + 2.0 * w) / 3.0;
        RationalCubic::new(
            [p0, (p0 + p1 * (2.0 * w)) / s, (p1 * (2.0 * w) + p2) / s, p2],
            [inner, inner],
        )
    }

    /// All four weights (1, w1, w2, 1).
    #[inline]
    pub fn all_weights(&self) -> [f64; 4] {
        [1.0, self.weights[0], self.weights[1], 1.0]
    }

    /// The rational basis φ_k(u) = B_k(u) w_k / D(u); P(u) = Σ φ_k(u) C_k. The basis sums to 1.
    #[inline]
    pub fn rational_basis(&self, u: f64) -> [f64; 4] {
        rational_basis(self.weights, u)
    }

    /// P(u).
    #[inline]
    pub fn eval(&self, u: f64) -> Point {
        let phi = self.rational_basis(u);
        let c = &self.points;
        c[0] * phi[0] + c[1] * phi[1] + c[2] * phi[2] + c[3] * phi[3]
    }

    /// P(u), P'(u) and P''(u).
    pub fn jet(&self, u: f64) -> CurveJet {
        if self.is_polynomial() {
            // The denominator is 1 and its derivatives 0: skip them (most fitted segments
            // are polynomial, and projections evaluate jets more than anything else).
            let (b0, b1, b2) = (bernstein(u), bernstein_d1(u), bernstein_d2(u));
            let c = &self.points;
            let sum = |b: [f64; 4]| c[0] * b[0] + c[1] * b[1] + c[2] * b[2] + c[3] * b[3];
            return CurveJet {
                point: sum(b0),
                d1: sum(b1),
                d2: sum(b2),
            };
        }
        let w = self.all_weights();
        let (b0, b1, b2) = (bernstein(u), bernstein_d1(u), bernstein_d2(u));
        let mut n = [Point::ZERO; 3];
        let mut d = [0.0; 3];
        for k in 0..4 {
            let wc = self.points[k] * w[k];
            n[0] += wc * b0[k];
            n[1] += wc * b1[k];
            n[2] += wc * b2[k];
            d[0] += w[k] * b0[k];
            d[1] += w[k] * b1[k];
            d[2] += w[k] * b2[k];
        }
        let p = n[0] / d[0];
        let p1 = (n[1] - p * d[1]) / d[0];
        let p2 = (n[2] - p1 * (2.0 * d[1]) - p * d[2]) / d[0];
        CurveJet {
            point: p,
            d1: p1,
            d2: p2,
        }
    }

    /// P'(0) = 3 w1 (C1 − C0).
    pub fn start_derivative(&self) -> Point {
        (self.points[1] - self.points[0]) * (3.0 * self.weights[0])
    }

    /// P'(1) = 3 w2 (C3 − C2).
    pub fn end_derivative(&self) -> Point {
        (self.points[3] - self.points[2]) * (3.0 * self.weights[1])
    }

    /// Unit tangent at the start, or `None` for a degenerate start (C1 = C0).
    pub fn start_tangent(&self) -> Option<Point> {
        self.start_derivative().normalized()
    }

    /// Unit tangent at the end, or `None` for a degenerate end (C2 = C3).
    pub fn end_tangent(&self) -> Option<Point> {
        self.end_derivative().normalized()
    }

    /// True when the segment is a polynomial cubic (w1 = w2 = 1 exactly).
    pub fn is_polynomial(&self) -> bool {
        self.weights == [1.0, 1.0]
    }

    /// Refines a parameter guess `u0` so that P(u) is the point of the curve nearest to `q`
    /// (Newton's method on (P(u) − q)·P'(u) = 0, clamped to [0, 1], accepting only steps that
    /// do not increase the distance). Returns `(u, |P(u) − q|)`. Converges to the nearest
    /// point in the basin of `u0`; use [`RationalCubic::nearest`] for the global nearest point.
    pub fn refine_projection(&self, q: Point, u0: f64) -> (f64, f64) {
        self.power_form().refine_projection(q, u0, EXACT_STEP)
    }

    /// The curve in power form, for evaluating it at many parameters
    /// (projections of many points).
    pub fn power_form(&self) -> PowerCubic {
        if self.is_polynomial() {
            PowerCubic::polynomial(&self.points)
        } else {
            PowerCubic::rational(&self.points, self.all_weights())
        }
    }

    /// A cheap projection step for parameter correction: `iterations` plain Newton steps
    /// on (P(u) − q)·P'(u) = 0 from `u0`, clamped to [0, 1], keeping a step only when it
    /// brings the point closer. Returns the new parameter.
    pub fn project_quick(&self, q: Point, u0: f64, iterations: usize) -> f64 {
        self.power_form().project_quick(q, u0, iterations)
    }

    /// The global nearest point of the curve to `q`: a scan of `samples + 1` evenly spaced
    /// parameters picks the start, Newton refines it, and both ends are checked.
    /// Returns `(u, distance)`.
    pub fn nearest(&self, q: Point, samples: usize) -> (f64, f64) {
        let samples = samples.max(2);
        // (A half-open range: it knows its length.)
        let scan = (0..samples + 1).map(|j| self.eval(j as f64 / samples as f64));
        self.nearest_among(scan, q)
    }

    /// The curve at `samples + 1` evenly spaced parameters (at least 3), for
    /// `nearest_sample`: many points projected onto one curve share it.
    pub fn scan(&self, samples: usize) -> Vec<Point> {
        let samples = samples.max(2);
        (0..=samples)
            .map(|j| self.eval(j as f64 / samples as f64))
            .collect()
    }

    /// Newton from the nearest of `scan`, the curve at evenly spaced parameters from 0 to 1.
    fn nearest_among(&self, scan: impl ExactSizeIterator<Item = Point>, q: Point) -> (f64, f64) {
        let samples = scan.len() - 1;
        let j = nearest_sample(scan, q);
        self.refine_projection(q, j as f64 / samples as f64)
    }

    /// Splits the segment at parameter `t` into two segments in standard form
    /// (end weights 1) that together trace the same curve.
    pub fn split(&self, t: f64) -> (RationalCubic, RationalCubic) {
        // de Casteljau in homogeneous coordinates (w·x, w·y, w).
        let w = self.all_weights();
        let mut h: [(Point, f64); 4] = [(Point::ZERO, 0.0); 4];
        for k in 0..4 {
            h[k] = (self.points[k] * w[k], w[k]);
        }
        let lerp = |a: (Point, f64), b: (Point, f64)| (a.0.lerp(b.0, t), a.1 + (b.1 - a.1) * t);
        let a1 = lerp(h[0], h[1]);
        let a2 = lerp(h[1], h[2]);
        let a3 = lerp(h[2], h[3]);
        let b1 = lerp(a1, a2);
        let b2 = lerp(a2, a3);
        let c1 = lerp(b1, b2);
        (
            from_homogeneous([h[0], a1, b1, c1]),
            from_homogeneous([c1, b2, a3, h[3]]),
        )
    }
}

/// Index of the first point of `scan` nearest to `q` (0 when no distance compares, as with
/// non-finite points): where [`RationalCubic::nearest`] starts Newton's method.
pub(crate) fn nearest_sample(scan: impl IntoIterator<Item = Point>, q: Point) -> usize {
    let mut best = (0, f64::INFINITY);
    for (j, p) in scan.into_iter().enumerate() {
        let d = (p - q).length_squared();
        if d < best.1 {
            best = (j, d);
        }
    }
    best.0
}

/// The rational basis for inner weights `w` at parameter `u`; it sums to 1.
#[inline]
pub(crate) fn rational_basis(w: [f64; 2], u: f64) -> [f64; 4] {
    let b = bernstein(u);
    let nb = [b[0], b[1] * w[0], b[2] * w[1], b[3]];
    let d = nb[0] + nb[1] + nb[2] + nb[3];
    [nb[0] / d, nb[1] / d, nb[2] / d, nb[3] / d]
}

/// Builds a standard-form segment from homogeneous control points with arbitrary positive
/// weights, by the reparameterisation w_k' = w_k / (w0^((3−k)/3) · w3^(k/3)).
fn from_homogeneous(h: [(Point, f64); 4]) -> RationalCubic {
    let w0 = h[0].1;
    let w3 = h[3].1;
    let pts = [h[0].0 / w0, h[1].0 / h[1].1, h[2].0 / h[2].1, h[3].0 / w3];
    let norm = |k: i32, w: f64| w / (w0.powf((3 - k) as f64 / 3.0) * w3.powf(k as f64 / 3.0));
    RationalCubic::new(pts, [norm(1, h[1].1), norm(2, h[2].1)])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> RationalCubic {
        RationalCubic::new(
            [
                Point::new(0.0, 0.0),
                Point::new(1.0, 3.0),
                Point::new(4.0, 3.5),
                Point::new(5.0, 0.5),
            ],
            [0.4, 2.2],
        )
    }

    #[test]
    fn basis_sums_to_one_and_ends_interpolate() {
        let c = sample();
        for j in 0..=20 {
            let phi = c.rational_basis(j as f64 / 20.0);
            assert!((phi.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        assert_eq!(c.eval(0.0), c.points[0]);
        assert!(c.eval(1.0).distance(c.points[3]) < 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = sample();
        let h = 1e-6;
        for &u in &[0.1, 0.37, 0.8] {
            let j = c.jet(u);
            let fd1 = (c.eval(u + h) - c.eval(u - h)) / (2.0 * h);
            let h2 = 1e-4;
            let fd2 = (c.eval(u + h2) - j.point * 2.0 + c.eval(u - h2)) / (h2 * h2);
            assert!((j.d1 - fd1).length() < 1e-7, "{:?} {:?}", j.d1, fd1);
            assert!((j.d2 - fd2).length() < 1e-3, "{:?} {:?}", j.d2, fd2);
        }
        assert!((c.jet(0.0).d1 - c.start_derivative()).length() < 1e-12);
        assert!((c.jet(1.0).d1 - c.end_derivative()).length() < 1e-12);
    }

    #[test]
    fn projection_recovers_parameter_of_on_curve_point() {
        let c = sample();
        for &u in &[0.05, 0.5, 0.93] {
            let q = c.eval(u) + c.jet(u).d1.perp().normalized().unwrap() * 0.05;
            let (uu, d) = c.nearest(q, 32);
            assert!((uu - u).abs() < 1e-9, "{uu} vs {u}");
            assert!((d - 0.05).abs() < 1e-9);
        }
    }

    #[test]
    fn split_halves_trace_the_same_curve() {
        let c = sample();
        let (a, b) = c.split(0.3);
        for j in 0..=10 {
            let s = j as f64 / 10.0;
            let pa = a.eval(s);
            let pb = b.eval(s);
            assert!(c.nearest(pa, 64).1 < 1e-12);
            assert!(c.nearest(pb, 64).1 < 1e-12);
        }
        assert!(a.eval(1.0).distance(c.eval(0.3)) < 1e-12);
        assert!(b.eval(0.0).distance(c.eval(0.3)) < 1e-12);
    }
}
