//! B-spline basis functions (Cox–de Boor recurrence) and clamped B-spline curves.
//!
//! The routines are Piegl & Tiller's (*The NURBS Book*, Algorithms A2.1 `FindSpan` and
//! A2.2 `BasisFuns`): the k = order non-zero basis functions at u are computed together
//! by the triangular Cox–de Boor scheme, stable and without divisions by zero for
//! repeated knots. Written by hand rather than taken from a crate because the least-squares
//! fit needs the basis values themselves (the rows of its collocation matrix), which the
//! curve-evaluation crates (e.g. `bspline`) do not expose; the two algorithms are thirty
//! lines.

use outlinefit::Point;

/// Index `s` of the knot span `[knots[s], knots[s+1])` containing `u`, for a clamped knot
/// vector of `n_ctrl + order` knots; `u` at (or beyond) the last knot belongs to the last
/// non-empty span and `u` before the first knot to the first, so every `u` gets a span.
pub fn find_span(knots: &[f64], order: usize, n_ctrl: usize, u: f64) -> usize {
    let degree = order - 1;
    if u >= knots[n_ctrl] {
        return n_ctrl - 1;
    }
    if u <= knots[degree] {
        return degree;
    }
    // Binary search for knots[s] <= u < knots[s+1], s in [degree, n_ctrl - 1].
    let (mut lo, mut hi) = (degree, n_ctrl);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if u < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// The `order` basis functions N_{span−order+1..=span, order}(u) that can be non-zero on
/// knot span `span`, written to `out[..order]` (they are ≥ 0 and sum to 1).
/// Requires `order` ≤ [`MAX_ORDER`] and `out.len()` ≥ `order`.
pub fn basis_functions(knots: &[f64], span: usize, order: usize, u: f64, out: &mut [f64]) {
    let mut left = [0.0f64; MAX_ORDER];
    let mut right = [0.0f64; MAX_ORDER];
    out[0] = 1.0;
    for j in 1..order {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom != 0.0 { out[r] / denom } else { 0.0 };
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

/// Largest supported order (degree 31): the basis routine keeps its scratch on the stack.
pub const MAX_ORDER: usize = 32;

/// A clamped B-spline curve of a given order (degree + 1) in the plane.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    /// Order k = degree + 1 (4 for cubic).
    pub order: usize,
    /// Knot vector, `control_points.len() + order` non-decreasing values, the first and
    /// last `order` equal (clamped).
    pub knots: Vec<f64>,
    /// Control points (de Boor points).
    pub control_points: Vec<Point>,
}

impl BSpline {
    /// The point at parameter `u` (clamped to the knot range).
    pub fn point(&self, u: f64) -> Point {
        let n = self.control_points.len();
        let k = self.order;
        let span = find_span(&self.knots, k, n, u);
        let u = u.clamp(self.knots[k - 1], self.knots[n]);
        let mut b = [0.0f64; MAX_ORDER];
        basis_functions(&self.knots, span, k, u, &mut b);
        let mut p = Point::ZERO;
        for (j, bj) in b[..k].iter().enumerate() {
            p += self.control_points[span + 1 - k + j] * *bj;
        }
        p
    }

    /// The parameter interval [t_{k−1}, t_n] on which the curve is defined.
    pub fn domain(&self) -> (f64, f64) {
        let n = self.control_points.len();
        (self.knots[self.order - 1], self.knots[n])
    }

    /// The derivative as a B-spline: order k − 1 on the knots without the first and the
    /// last, control points (k − 1)(P_{i+1} − P_i)/(t_{i+k} − t_{i+1}) (zero where the
    /// knots coincide). `None` for order 1 (or one control point), whose derivative is zero
    /// wherever it exists.
    pub fn derivative_curve(&self) -> Option<BSpline> {
        let (k, n) = (self.order, self.control_points.len());
        if k < 2 || n < 2 {
            return None;
        }
        let t = &self.knots;
        let control_points = (0..n - 1)
            .map(|i| {
                let h = t[i + k] - t[i + 1];
                if h > 0.0 {
                    (self.control_points[i + 1] - self.control_points[i]) * ((k - 1) as f64 / h)
                } else {
                    Point::ZERO
                }
            })
            .collect();
        Some(BSpline {
            order: k - 1,
            knots: t[1..t.len() - 1].to_vec(),
            control_points,
        })
    }
}

impl outlinefit::ParamCurve for BSpline {
    fn domain(&self) -> (f64, f64) {
        BSpline::domain(self)
    }

    fn point(&self, u: f64) -> Point {
        BSpline::point(self, u)
    }

    fn derivative(&self, u: f64) -> Point {
        self.derivative_curve().map_or(Point::ZERO, |d| d.point(u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cox–de Boor by its defining recurrence, for checking.
    fn naive(knots: &[f64], i: usize, k: usize, u: f64) -> f64 {
        if k == 1 {
            return if knots[i] <= u && u < knots[i + 1] {
                1.0
            } else {
                0.0
            };
        }
        let mut v = 0.0;
        let d1 = knots[i + k - 1] - knots[i];
        if d1 > 0.0 {
            v += (u - knots[i]) / d1 * naive(knots, i, k - 1, u);
        }
        let d2 = knots[i + k] - knots[i + 1];
        if d2 > 0.0 {
            v += (knots[i + k] - u) / d2 * naive(knots, i + 1, k - 1, u);
        }
        v
    }

    #[test]
    fn basis_matches_the_recurrence_and_sums_to_one() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0];
        let (k, n) = (4, 8);
        for step in 0..100 {
            let u = step as f64 / 100.0;
            let s = find_span(&knots, k, n, u);
            assert!(knots[s] <= u && u < knots[s + 1]);
            let mut b = [0.0; MAX_ORDER];
            basis_functions(&knots, s, k, u, &mut b);
            assert!((b[..k].iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for j in 0..k {
                let i = s + 1 - k + j;
                assert!((b[j] - naive(&knots, i, k, u)).abs() < 1e-14, "u={u} i={i}");
            }
        }
        assert_eq!(find_span(&knots, k, n, 1.0), 7);
        assert_eq!(find_span(&knots, k, n, -1.0), 3);
    }

    #[test]
    fn clamped_spline_interpolates_its_end_control_points_and_reproduces_a_line() {
        // Greville abscissae as control points reproduce the line y = x (linear precision).
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.6, 1.0, 1.0, 1.0, 1.0];
        let greville: Vec<f64> = (0..6)
            .map(|i| (knots[i + 1] + knots[i + 2] + knots[i + 3]) / 3.0)
            .collect();
        let s = BSpline {
            order: 4,
            knots,
            control_points: greville.iter().map(|&g| Point::new(g, 2.0 * g)).collect(),
        };
        for step in 0..=10 {
            let u = step as f64 / 10.0;
            let p = s.point(u);
            assert!((p.x - u).abs() < 1e-14 && (p.y - 2.0 * u).abs() < 1e-14);
        }
    }

    #[test]
    fn b_spline_answers_the_curve_trait() {
        // Uneven knots, a repeated inner knot (C1 there), and a domain other than [0, 1].
        let s = BSpline {
            order: 4,
            knots: vec![1.0, 1.0, 1.0, 1.0, 1.5, 2.2, 2.2, 3.0, 3.0, 3.0, 3.0],
            control_points: vec![
                Point::new(0.0, 0.0),
                Point::new(0.5, 1.5),
                Point::new(1.5, 2.0),
                Point::new(2.0, 0.0),
                Point::new(3.0, -1.0),
                Point::new(3.5, 0.5),
                Point::new(4.0, 1.0),
            ],
        };
        outlinefit::curve::check_param_curve(&s, "B-spline");
        // The clamped ends: P'(a) = (k − 1)(P1 − P0)/(t_k − t_1).
        let d = outlinefit::ParamCurve::derivative(&s, 1.0);
        assert!((d - Point::new(0.5, 1.5) * (3.0 / 0.5)).length() < 1e-12);
    }
}
