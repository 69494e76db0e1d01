//! Bernstein polynomials of any degree, binomial coefficients and de Casteljau's
//! algorithm: the basis every Bézier-type curve and surface of the crate builds on (the
//! rational cubic keeps its own fixed-size degree-3 basis, `super::bernstein`).

use crate::geom::Point;

/// Binomial coefficient C(n, k) as an `f64`; 0 for k > n. Exact for n ≤ 50 (every
/// intermediate product stays below 2^53), within a few ulps beyond.
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut r = 1.0;
    for i in 1..=k {
        // r = C(n − k + i, i) after this step: an integer at every step.
        r = r * (n - k + i) as f64 / i as f64;
    }
    r
}

/// Exact binomial coefficient C(n, k) (`None` on overflow); 0 for k > n.
pub(crate) fn binomial_exact(n: usize, k: usize) -> Option<i128> {
    if k > n {
        return Some(0);
    }
    let k = k.min(n - k);
    let mut c: i128 = 1;
    for j in 0..k {
        // c · (n − j) / (j + 1) stays an integer at every step.
        c = c.checked_mul((n - j) as i128)? / (j as i128 + 1);
    }
    Some(c)
}

/// The Bernstein polynomials of degree `n` at `t`, written into `out[..=n]`, by the
/// triangular recurrence B_k^j = (1 − t) B_k^{j−1} + t B_{k−1}^{j−1} (no binomials, no
/// powers; stable on [0, 1]).
pub fn bernstein(n: usize, t: f64, out: &mut [f64]) {
    let s = 1.0 - t;
    out[0] = 1.0;
    for j in 1..=n {
        let mut saved = 0.0;
        for k in 0..j {
            let b = out[k];
            out[k] = saved + s * b;
            saved = t * b;
        }
        out[j] = saved;
    }
}

/// The Bernstein polynomials of degree `n` at `t` and their first and second derivatives,
/// each into `b[..=n]`, `d1[..=n]`, `d2[..=n]`; `d1` and `d2` come from the lower degrees:
/// d/dt B_i^n = n (B_{i−1}^{n−1} − B_i^{n−1}).
pub fn bernstein_jet(n: usize, t: f64, b: &mut [f64], d1: &mut [f64], d2: &mut [f64]) {
    // b holds degree n − 2, then n − 1, then n, differences taken on the way.
    for v in d1[..=n].iter_mut().chain(d2[..=n].iter_mut()) {
        *v = 0.0;
    }
    if n >= 2 {
        bernstein(n - 2, t, b);
        let c = (n * (n - 1)) as f64;
        for i in 0..=n - 2 {
            d2[i] += c * b[i];
            d2[i + 1] -= 2.0 * c * b[i];
            d2[i + 2] += c * b[i];
        }
    }
    if n >= 1 {
        bernstein(n - 1, t, b);
        let c = n as f64;
        for i in 0..n {
            d1[i] -= c * b[i];
            d1[i + 1] += c * b[i];
        }
    }
    bernstein(n, t, b);
}

/// The point at `t` of the Bézier curve with control points `points` (the origin for
/// none), by de Casteljau's algorithm: on the stack up to degree 23.
pub(crate) fn de_casteljau(points: &[Point], t: f64) -> Point {
    match points.len() {
        0 => Point::ZERO,
        1 => points[0],
        len => {
            let mut tmp: [Point; 24] = [Point::ZERO; 24];
            if len > tmp.len() {
                // Past the stack buffer (merged curves stop at degree 20), a copy.
                let mut v = points.to_vec();
                for r in 1..len {
                    for i in 0..len - r {
                        v[i] = v[i].lerp(v[i + 1], t);
                    }
                }
                return v[0];
            }
            tmp[..len].copy_from_slice(points);
            for r in 1..len {
                for i in 0..len - r {
                    tmp[i] = tmp[i].lerp(tmp[i + 1], t);
                }
            }
            tmp[0]
        }
    }
}

/// The control points of the same Bézier curve one degree higher:
/// Q_i = (i/(n+1)) P_{i−1} + (1 − i/(n+1)) P_i for i = 0..=n+1.
pub fn elevate(points: &[Point]) -> Vec<Point> {
    let n = points.len();
    if n == 0 {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(n + 1);
    out.push(points[0]);
    for i in 1..n {
        let a = i as f64 / n as f64;
        out.push(points[i - 1] * a + points[i] * (1.0 - a));
    }
    out.push(points[n - 1]);
    out
}

/// Splits Bézier control points at `t` by de Casteljau's algorithm.
pub(crate) fn de_casteljau_split(points: &[Point], t: f64) -> (Vec<Point>, Vec<Point>) {
    let n = points.len();
    let mut work = points.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = Vec::with_capacity(n);
    left.push(work[0]);
    right.push(work[n - 1]);
    for level in 1..n {
        for k in 0..n - level {
            work[k] = work[k].lerp(work[k + 1], t);
        }
        left.push(work[0]);
        right.push(work[n - 1 - level]);
    }
    right.reverse();
    (left, right)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elevation_keeps_the_curve() {
        let p = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(4.0, -1.0),
            Point::new(5.0, 2.0),
        ];
        let q = elevate(&elevate(&p));
        assert_eq!(q.len(), 6);
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert!(de_casteljau(&p, t).distance(de_casteljau(&q, t)) < 1e-13);
        }
        assert!(elevate(&[]).is_empty());
    }

    #[test]
    fn binomials_are_exact_and_agree() {
        assert_eq!(binomial(0, 0), 1.0);
        assert_eq!(binomial(7, 3), 35.0);
        assert_eq!(binomial(11, 5), 462.0);
        assert_eq!(binomial(3, 4), 0.0);
        assert_eq!(binomial_exact(3, 4), Some(0));
        // Pascal's rule holds exactly; the float agrees exactly up to n = 50 and within
        // 4 ulps up to 60 (C(55, 26) is a first miss).
        for n in 1..=60 {
            for k in 1..n {
                let c = binomial_exact(n, k).unwrap();
                let below =
                    binomial_exact(n - 1, k - 1).unwrap() + binomial_exact(n - 1, k).unwrap();
                assert_eq!(c, below, "C({n}, {k})");
                let f = binomial(n, k);
                if n <= 50 {
                    assert_eq!(f, c as f64, "C({n}, {k})");
                } else {
                    assert!(
                        (f - c as f64).abs() <= 4.0 * f64::EPSILON * f,
                        "C({n}, {k})"
                    );
                }
            }
        }
        assert_eq!(binomial_exact(200, 100), None);
    }

    #[test]
    fn bernstein_matches_the_closed_form_and_its_derivatives() {
        for n in 0..=12 {
            for &t in &[0.0, 0.13, 0.5, 0.77, 1.0] {
                let (mut b, mut d1, mut d2) = ([0.0; 32], [0.0; 32], [0.0; 32]);
                bernstein_jet(n, t, &mut b, &mut d1, &mut d2);
                let h = 1e-5;
                for k in 0..=n {
                    let f =
                        |t: f64| binomial(n, k) * t.powi(k as i32) * (1.0 - t).powi((n - k) as i32);
                    assert!((b[k] - f(t)).abs() < 1e-14, "n {n} k {k} t {t}");
                    let fd1 = (f(t + h) - f(t - h)) / (2.0 * h);
                    let fd2 = (f(t + h) - 2.0 * f(t) + f(t - h)) / (h * h);
                    assert!(
                        (d1[k] - fd1).abs() < 1e-6 * (1.0 + fd1.abs()),
                        "d1 n {n} k {k}"
                    );
                    assert!(
                        (d2[k] - fd2).abs() < 1e-3 * (1.0 + fd2.abs()),
                        "d2 n {n} k {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn de_casteljau_matches_the_bernstein_sum_and_splits() {
        let points: Vec<Point> = (0..7)
            .map(|i| Point::new(i as f64 * 3.0, ((i * i) % 5) as f64 - 2.0))
            .collect();
        let n = points.len() - 1;
        let mut b = [0.0; 8];
        for &t in &[0.0, 0.2, 0.5, 0.9, 1.0] {
            bernstein(n, t, &mut b);
            let sum = (0..=n).fold(Point::ZERO, |acc, k| acc + points[k] * b[k]);
            assert!(de_casteljau(&points, t).distance(sum) < 1e-12, "t {t}");
            let (left, right) = de_casteljau_split(&points, t);
            for &s in &[0.0, 0.3, 1.0] {
                let on_left = de_casteljau(&left, s);
                let on_right = de_casteljau(&right, s);
                assert!(on_left.distance(de_casteljau(&points, t * s)) < 1e-12);
                assert!(on_right.distance(de_casteljau(&points, t + (1.0 - t) * s)) < 1e-12);
            }
        }
        // Past the stack buffer the points are copied; the result is the same curve.
        let long: Vec<Point> = (0..30).map(|i| Point::new(i as f64, 0.0)).collect();
        assert!((de_casteljau(&long, 0.25).x - 29.0 * 0.25).abs() < 1e-12);
    }
}
