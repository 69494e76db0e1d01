//! What every parametric curve of the crate answers: its point, its derivative and the
//! point nearest to a given one, over its parameter domain.
//!
//! Implemented by the polynomial cubic ([`CubicBez`]), the rational cubic
//! ([`RationalCubic`]), the Wang–Ball curve ([`WangBall`]) and the center line of a disk
//! Wang–Ball curve ([`DiskWangBall`]); the lab crate adds the SG-Bézier curve and the
//! B-spline. [`check_param_curve`] checks an implementation's answers against each other. Code that only needs points,
//! tangents or projections (sampling a curve for a picture, measuring a distance) is
//! written once against the trait.

use super::cubic::CubicBez;
use super::rational::RationalCubic;
use super::wang_ball::{DiskWangBall, WangBall};
use crate::geom::Point;

/// A curve P(t) in the plane over a parameter interval.
pub trait ParamCurve {
    /// The parameter interval `(start, end)`; `[0, 1]` unless the curve says otherwise.
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }

    /// P(t).
    fn point(&self, t: f64) -> Point;

    /// P'(t), the first derivative with respect to the parameter.
    fn derivative(&self, t: f64) -> Point;

    /// The point of the curve nearest to `q`, as `(t, distance)`. The default scans
    /// `samples + 1` evenly spaced parameters (at least 3) and narrows the bracket around
    /// the nearest of them by golden-section search to a parameter width of 1e-12 of the
    /// domain; curves with a faster exact method override it.
    fn nearest(&self, q: Point, samples: usize) -> (f64, f64) {
        nearest_by_scan(self, q, samples)
    }

    /// The curve at `count + 1` evenly spaced parameters over its domain (`count` at
    /// least 1), for drawing it as a polyline.
    fn sample(&self, count: usize) -> Vec<Point> {
        let (a, b) = self.domain();
        let count = count.max(1);
        (0..=count)
            .map(|i| self.point(a + (b - a) * (i as f64 / count as f64)))
            .collect()
    }
}

/// [`ParamCurve::nearest`]'s default: a scan, then golden-section search in the bracket of
/// the nearest sample.
pub(crate) fn nearest_by_scan<C: ParamCurve + ?Sized>(
    curve: &C,
    q: Point,
    samples: usize,
) -> (f64, f64) {
    let (a, b) = curve.domain();
    let samples = samples.max(2);
    let at = |j: usize| a + (b - a) * (j as f64 / samples as f64);
    let dist2 = |t: f64| (curve.point(t) - q).length_squared();
    let mut best = (0, f64::INFINITY);
    for j in 0..=samples {
        let d = dist2(at(j));
        if d < best.1 {
            best = (j, d);
        }
    }
    let (mut lo, mut hi) = (at(best.0.saturating_sub(1)), at((best.0 + 1).min(samples)));
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let (mut f1, mut f2) = (dist2(x1), dist2(x2));
    while hi - lo > 1e-12 * (b - a).abs().max(f64::MIN_POSITIVE) {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - ratio * (hi - lo);
            f1 = dist2(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + ratio * (hi - lo);
            f2 = dist2(x2);
        }
    }
    let t = 0.5 * (lo + hi);
    let d = dist2(t);
    // The scan's best sample may still be nearer (a bracket end, a flat minimum).
    if best.1 < d {
        (at(best.0), best.1.sqrt())
    } else {
        (t, d.sqrt())
    }
}

impl ParamCurve for CubicBez {
    fn point(&self, t: f64) -> Point {
        self.eval(t)
    }

    fn derivative(&self, t: f64) -> Point {
        self.deriv(t)
    }

    fn nearest(&self, q: Point, samples: usize) -> (f64, f64) {
        CubicBez::nearest(self, q, samples)
    }
}

impl ParamCurve for RationalCubic {
    fn point(&self, t: f64) -> Point {
        self.eval(t)
    }

    fn derivative(&self, t: f64) -> Point {
        self.jet(t).d1
    }

    fn nearest(&self, q: Point, samples: usize) -> (f64, f64) {
        RationalCubic::nearest(self, q, samples)
    }
}

impl ParamCurve for WangBall {
    fn point(&self, t: f64) -> Point {
        self.eval(t)
    }

    fn derivative(&self, t: f64) -> Point {
        WangBall::derivative(self, t)
    }
}

/// The center line C(t) of the disk curve.
impl ParamCurve for DiskWangBall {
    fn point(&self, t: f64) -> Point {
        self.center(t)
    }

    fn derivative(&self, t: f64) -> Point {
        self.center_derivative(t)
    }
}

/// The derivative at `t` of the Bézier curve with control points `points`:
/// n Σ (P_{i+1} − P_i) B_{i,n−1}(t), by de Casteljau on the differences.
pub fn bezier_derivative(points: &[Point], t: f64) -> Point {
    let n = points.len().saturating_sub(1);
    if n == 0 {
        return Point::ZERO;
    }
    let diffs: Vec<Point> = points
        .windows(2)
        .map(|w| (w[1] - w[0]) * n as f64)
        .collect();
    super::basis::de_casteljau(&diffs, t)
}

/// Panics unless `c` answers consistently, as every implementation must: the derivative agrees with a central
/// difference of the points, `sample` covers the domain, and `nearest` finds a point
/// at least as near as every one of a dense scan, and the point itself at distance 0.
pub fn check_param_curve(c: &dyn ParamCurve, name: &str) {
    let (a, b) = c.domain();
    let span = b - a;
    let scale = c.sample(50).iter().map(|p| p.length()).fold(1.0, f64::max);
    // Off the knots of a spline, where a central difference is only first-order.
    for k in 0..20 {
        let t = a + span * (k as f64 + 0.3) / 20.0;
        let h = 1e-6 * span;
        let numeric = (c.point(t + h) - c.point(t - h)) * (0.5 / h);
        let exact = c.derivative(t);
        assert!(
            (numeric - exact).length() <= 1e-6 * scale.max(exact.length()),
            "{name}: derivative at {t}: {exact:?} vs {numeric:?}"
        );
    }
    let pts = c.sample(8);
    assert_eq!(pts.len(), 9);
    assert!(pts[0].distance(c.point(a)) == 0.0 && pts[8].distance(c.point(b)) == 0.0);
    let dense = c.sample(2000);
    for q in [
        Point::new(0.3, 0.7),
        Point::new(-1.0, 2.0),
        Point::new(2.5, -0.5),
        c.point(a + 0.37 * span),
    ] {
        let (t, d) = c.nearest(q, 32);
        assert!(
            t >= a && t <= b,
            "{name}: nearest parameter {t} outside the domain"
        );
        assert!(
            (c.point(t).distance(q) - d).abs() <= 1e-12 * scale,
            "{name}"
        );
        let scanned = dense
            .iter()
            .map(|p| p.distance(q))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= scanned + 1e-12 * scale,
            "{name}: nearest {d} > scan {scanned} for {q:?}"
        );
    }
    let on = c.point(a + 0.37 * span);
    assert!(
        c.nearest(on, 32).1 <= 1e-9 * scale,
        "{name}: a point of the curve"
    );
}
#[cfg(test)]
mod tests {

    use super::*;
    use crate::curve::wang_ball::Disk;

    #[test]
    fn every_curve_type_answers_point_derivative_and_nearest() {
        let p = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 2.0),
            Point::new(2.5, 2.0),
            Point::new(3.0, 0.5),
        ];
        check_param_curve(&CubicBez::new(p[0], p[1], p[2], p[3]), "cubic");
        check_param_curve(&RationalCubic::new(p, [0.6, 1.7]), "rational cubic");
        let quintic = vec![
            Point::new(0.0, 0.0),
            Point::new(0.5, 1.5),
            Point::new(1.5, 2.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, -1.0),
            Point::new(4.0, 1.0),
        ];
        check_param_curve(&WangBall::new(quintic.clone()), "Wang–Ball");
        let disks = quintic
            .iter()
            .enumerate()
            .map(|(i, &c)| Disk::new(c, 0.1 + 0.05 * i as f64))
            .collect();
        check_param_curve(&DiskWangBall::new(disks), "disk Wang–Ball center");
    }

    #[test]
    fn default_nearest_agrees_with_the_cubics_newton() {
        struct Plain(CubicBez);
        impl ParamCurve for Plain {
            fn point(&self, t: f64) -> Point {
                self.0.eval(t)
            }
            fn derivative(&self, t: f64) -> Point {
                self.0.deriv(t)
            }
        }
        let c = CubicBez::new(
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(3.0, 3.0),
            Point::new(4.0, 0.0),
        );
        for q in [
            Point::new(2.0, 1.0),
            Point::new(-1.0, 1.0),
            Point::new(3.9, 2.2),
        ] {
            let (t0, d0) = c.nearest(q, 32);
            let (t1, d1) = Plain(c).nearest(q, 32);
            assert!((d0 - d1).abs() < 1e-12 && (t0 - t1).abs() < 1e-6, "{q:?}");
        }
    }
}
