//! Polynomial cubic Bézier segments: what SVG can draw. [`super::approx`] turns a
//! rational cubic into a short G1 run of them.

use super::power::{PowerCubic, CONVERGED_STEP};
use super::RationalCubic;
use crate::geom::Point;

/// A polynomial cubic Bézier segment, B(t) = Σ B_k(t) P_k, t ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicBez {
    /// Control points P0, P1, P2, P3.
    pub points: [Point; 4],
}

impl CubicBez {
    /// A cubic from its four control points.
    #[inline]
    pub const fn new(p0: Point, p1: Point, p2: Point, p3: Point) -> Self {
        CubicBez {
            points: [p0, p1, p2, p3],
        }
    }

    /// B(t).
    #[inline]
    pub fn eval(&self, t: f64) -> Point {
        let b = super::bernstein(t);
        let p = &self.points;
        p[0] * b[0] + p[1] * b[1] + p[2] * b[2] + p[3] * b[3]
    }

    /// B'(t), the first derivative with respect to the parameter.
    #[inline]
    pub fn deriv(&self, t: f64) -> Point {
        let p = &self.points;
        let s = 1.0 - t;
        ((p[1] - p[0]) * (s * s) + (p[2] - p[1]) * (2.0 * s * t) + (p[3] - p[2]) * (t * t)) * 3.0
    }

    /// B''(t), the second derivative with respect to the parameter.
    #[inline]
    pub fn deriv2(&self, t: f64) -> Point {
        let p = &self.points;
        let a = p[2] - p[1] * 2.0 + p[0];
        let b = p[3] - p[2] * 2.0 + p[1];
        (a * (1.0 - t) + b * t) * 6.0
    }

    /// Unit tangent at the start: the direction of P1 − P0, or of P2 − P0 when P1 = P0, or
    /// of the chord when both coincide with P0. `None` only when all four points coincide.
    pub fn start_tangent(&self) -> Option<Point> {
        first_direction(
            self.points[0],
            [self.points[1], self.points[2], self.points[3]],
        )
    }

    /// Unit tangent at the end (pointing in the direction of travel), with the same
    /// fallbacks as [`CubicBez::start_tangent`] mirrored.
    pub fn end_tangent(&self) -> Option<Point> {
        first_direction(
            self.points[3],
            [self.points[2], self.points[1], self.points[0]],
        )
        .map(|d| -d)
    }

    /// Refines a parameter guess `t0` so that B(t) is the point of the curve nearest to `q`
    /// (damped Newton's method on (B(t) − q)·B'(t) = 0, clamped to [0, 1], accepting only
    /// steps that do not increase the distance). Returns `(t, |B(t) − q|)`. Converges to the
    /// nearest point in the basin of `t0`; use [`CubicBez::nearest`] for the global one.
    pub fn refine_projection(&self, q: Point, t0: f64) -> (f64, f64) {
        PowerCubic::polynomial(&self.points).refine_projection(q, t0, CONVERGED_STEP)
    }

    /// The global nearest point of the curve to `q`: a scan of `samples + 1` evenly spaced
    /// parameters picks the start, Newton refines it. Returns `(t, distance)`.
    pub fn nearest(&self, q: Point, samples: usize) -> (f64, f64) {
        let samples = samples.max(2);
        let mut best_t = 0.0;
        let mut best_d = f64::INFINITY;
        for j in 0..=samples {
            let t = j as f64 / samples as f64;
            let d = (self.eval(t) - q).length_squared();
            if d < best_d {
                best_d = d;
                best_t = t;
            }
        }
        self.refine_projection(q, best_t)
    }
}

impl From<CubicBez> for RationalCubic {
    /// The same curve as a rational cubic with unit weights.
    fn from(c: CubicBez) -> RationalCubic {
        RationalCubic::new(c.points, [1.0, 1.0])
    }
}

/// The first non-degenerate direction from `origin` towards `candidates`, in order.
pub(super) fn first_direction(origin: Point, candidates: [Point; 3]) -> Option<Point> {
    candidates.iter().find_map(|&c| (c - origin).normalized())
}

/// Where the rational curve leaves C0: towards C1, else C2, else C3 (zero if all coincide).
pub(super) fn start_direction(curve: &RationalCubic) -> Point {
    let p = &curve.points;
    first_direction(p[0], [p[1], p[2], p[3]]).unwrap_or(Point::ZERO)
}

/// Direction of travel where the rational curve arrives at C3: from C2, else C1, else C0.
pub(super) fn end_direction(curve: &RationalCubic) -> Point {
    let p = &curve.points;
    first_direction(p[3], [p[2], p[1], p[0]]).map_or(Point::ZERO, |d| -d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_finite_differences() {
        let c = CubicBez::new(
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(4.0, 3.5),
            Point::new(5.0, 0.5),
        );
        let h = 1e-6;
        for &t in &[0.0, 0.2, 0.7, 1.0] {
            let fd1 = (c.eval(t + h) - c.eval(t - h)) / (2.0 * h);
            let fd2 = (c.eval(t + h) - c.eval(t) * 2.0 + c.eval(t - h)) / (h * h);
            assert!((c.deriv(t) - fd1).length() < 1e-7);
            assert!((c.deriv2(t) - fd2).length() < 1e-3);
        }
        // The cubic agrees with the rational evaluator at unit weights.
        let r: RationalCubic = c.into();
        for j in 0..=10 {
            let t = j as f64 / 10.0;
            assert!(c.eval(t).distance(r.eval(t)) < 1e-14);
        }
    }

    #[test]
    fn nearest_recovers_parameter_of_offset_point() {
        let c = CubicBez::new(
            Point::new(0.0, 0.0),
            Point::new(10.0, 30.0),
            Point::new(40.0, 35.0),
            Point::new(50.0, 5.0),
        );
        for &t in &[0.03, 0.5, 0.91] {
            let normal = c.deriv(t).perp().normalized().unwrap();
            let (tt, d) = c.nearest(c.eval(t) + normal * 0.3, 32);
            assert!((tt - t).abs() < 1e-9, "{tt} vs {t}");
            assert!((d - 0.3).abs() < 1e-9);
        }
    }
}
