//! Wang–Ball curves and disk Wang–Ball (DWB) curves.
//!
//! A Wang–Ball curve of degree n is `W(t) = Σ_{i=0}^{n} W_{i,n}(t) p_i`, `t ∈ [0, 1]`, where
//! the Wang–Ball basis `W_{i,n}` (Eq. 2 of "Approximate merging of disk Wang–Ball curves
//! with BEESO", §2.1) is, with
//! `h = ⌊n/2⌋` and `H = ⌈n/2⌉`:
//!
//! * `W_i(t) = (2t)^i (1−t)^{i+2}` for `0 ≤ i ≤ h − 1`,
//! * `W_h(t) = (2t)^h (1−t)^H`,
//! * `W_H(t) = (2(1−t))^h t^H`,
//! * `W_i(t) = W_{n−i}(1−t)` for the remaining indices `H + 1 ≤ i ≤ n`.
//!
//! For even n the two middle formulas describe the same function (`h = H`), which is used
//! once. The paper's text extraction lost the floor and ceiling brackets of Eq. 2; they are
//! restored here, which makes the basis a partition of unity for every n (a test checks
//! it). Like the Bernstein basis, the Wang–Ball basis spans the
//! polynomials of degree ≤ n, so every Wang–Ball curve is a Bézier curve of the same degree
//! and vice versa ([`wang_ball_to_bernstein`], [`bernstein_to_wang_ball`]). For n ≤ 3 it is
//! the Said–Ball / cubic Ball basis; its lower-degree factors make evaluation cheaper than
//! de Casteljau for high degrees.
//!
//! A disk Wang–Ball curve (Eq. 1 and 3) has control *disks* `(p_i, r_i)` instead of points
//! and describes the family of disks `(C(t), R(t))` whose center curve `C` and radius function
//! `R` use the same Wang–Ball basis. For approximate merging of two adjacent DWB curves
//! (§2.2.2) the paper subdivides the merged curve at `λ = L₁ / (L₁ + L₂)`, the ratio of the
//! arc lengths of the two center curves ([`merge_lambda`]).
//!
//! No maintained crate implements Wang–Ball curves, so this module is hand-written.

use super::basis::{binomial_exact, de_casteljau_split};
use crate::geom::Point;

/// `⌊n/2⌋` and, for an index `i ≤ ⌊n/2⌋` of a left-half basis function, the exponents
/// `(a, b)` of `2^a t^a (1−t)^b`.
#[inline]
fn left_exponents(n: usize, i: usize) -> (i32, i32) {
    let h = n / 2;
    debug_assert!(i <= h);
    if i < h {
        (i as i32, i as i32 + 2)
    } else {
        (h as i32, n.div_ceil(2) as i32)
    }
}

/// For basis index `i` of degree `n`: the exponents `(a, b)` of the left-half function
/// `2^a s^a (1−s)^b` it is built from and whether it is mirrored (`s = 1 − t`).
#[inline]
fn basis_shape(n: usize, i: usize) -> (i32, i32, bool) {
    if i <= n / 2 {
        let (a, b) = left_exponents(n, i);
        (a, b, false)
    } else {
        let (a, b) = left_exponents(n, n - i);
        (a, b, true)
    }
}

/// `t^e` with `0^0 = 1` and a zero result for negative exponents (never used).
#[inline]
fn pw(t: f64, e: i32) -> f64 {
    if e < 0 {
        0.0
    } else {
        t.powi(e)
    }
}

/// Evaluates the Wang–Ball basis of degree `n` at `t` into `out` (`out[i] = W_{i,n}(t)`).
///
/// # Panics
/// If `n == 0` or `out.len() != n + 1`.
pub fn wang_ball_basis(n: usize, t: f64, out: &mut [f64]) {
    assert!(n >= 1, "Wang–Ball degree must be at least 1");
    assert_eq!(out.len(), n + 1, "output length must be n + 1");
    for (i, o) in out.iter_mut().enumerate() {
        let (a, b, mirrored) = basis_shape(n, i);
        let s = if mirrored { 1.0 - t } else { t };
        *o = 2f64.powi(a) * pw(s, a) * pw(1.0 - s, b);
    }
}

/// Evaluates the derivatives `W'_{i,n}(t)` of the Wang–Ball basis of degree `n` into `out`.
///
/// # Panics
/// If `n == 0` or `out.len() != n + 1`.
pub fn wang_ball_basis_derivative(n: usize, t: f64, out: &mut [f64]) {
    assert!(n >= 1, "Wang–Ball degree must be at least 1");
    assert_eq!(out.len(), n + 1, "output length must be n + 1");
    for (i, o) in out.iter_mut().enumerate() {
        let (a, b, mirrored) = basis_shape(n, i);
        let s = if mirrored { 1.0 - t } else { t };
        let (af, bf) = (a as f64, b as f64);
        // d/ds [2^a s^a (1−s)^b] = 2^a [a s^{a−1} (1−s)^b − b s^a (1−s)^{b−1}].
        let mut d = 0.0;
        if a > 0 {
            d += af * pw(s, a - 1) * pw(1.0 - s, b);
        }
        if b > 0 {
            d -= bf * pw(s, a) * pw(1.0 - s, b - 1);
        }
        d *= 2f64.powi(a);
        *o = if mirrored { -d } else { d };
    }
}

// ---------------------------------------------------------------------------------------
// Exact rational arithmetic for the conversion matrices.

/// A reduced fraction `num / den` with `den > 0`; every operation is overflow-checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Ratio {
    num: i128,
    den: i128,
}

fn gcd(mut a: i128, mut b: i128) -> i128 {
    a = a.abs();
    b = b.abs();
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

impl Ratio {
    const ZERO: Ratio = Ratio { num: 0, den: 1 };
    const ONE: Ratio = Ratio { num: 1, den: 1 };

    fn new(num: i128, den: i128) -> Option<Ratio> {
        if den == 0 {
            return None;
        }
        let g = gcd(num, den).max(1);
        let (mut num, mut den) = (num / g, den / g);
        if den < 0 {
            num = num.checked_neg()?;
            den = den.checked_neg()?;
        }
        Some(Ratio { num, den })
    }

    fn is_zero(self) -> bool {
        self.num == 0
    }

    fn mul(self, o: Ratio) -> Option<Ratio> {
        // Cross-reduce first to keep the intermediate products small.
        let g1 = gcd(self.num, o.den).max(1);
        let g2 = gcd(o.num, self.den).max(1);
        let num = (self.num / g1).checked_mul(o.num / g2)?;
        let den = (self.den / g2).checked_mul(o.den / g1)?;
        Ratio::new(num, den)
    }

    fn div(self, o: Ratio) -> Option<Ratio> {
        if o.is_zero() {
            return None;
        }
        self.mul(Ratio::new(o.den, o.num)?)
    }

    fn sub(self, o: Ratio) -> Option<Ratio> {
        let g = gcd(self.den, o.den).max(1);
        let l = self.den / g;
        let den = l.checked_mul(o.den)?;
        let num = self
            .num
            .checked_mul(o.den / g)?
            .checked_sub(o.num.checked_mul(l)?)?;
        Ratio::new(num, den)
    }

    fn to_f64(self) -> f64 {
        // Both parts are exact in f64 while they stay below 2^53; beyond that the result is
        // still within a few ulps.
        self.num as f64 / self.den as f64
    }
}

/// The exact matrix `T` with `W_{i,n} = Σ_j T[j][i] B_{j,n}` (`None` on overflow).
fn wang_ball_to_bernstein_exact(n: usize) -> Option<Vec<Vec<Ratio>>> {
    let mut m = vec![vec![Ratio::ZERO; n + 1]; n + 1];
    for i in 0..=n {
        let (a, b, mirrored) = basis_shape(n, i);
        let (a, b) = (a as usize, b as usize);
        let deg = a + b;
        // 2^a s^a (1−s)^b · (s + (1−s))^{n−deg}
        //   = Σ_k 2^a C(n−deg, k) s^{a+k} (1−s)^{n−a−k},  and  s^j (1−s)^{n−j} = B_j / C(n, j).
        let pow2 = 1i128.checked_shl(a as u32)?;
        for k in 0..=(n - deg) {
            let j = a + k;
            let c = Ratio::new(
                pow2.checked_mul(binomial_exact(n - deg, k)?)?,
                binomial_exact(n, j)?,
            )?;
            // B_j(1 − t) = B_{n−j}(t).
            let row = if mirrored { n - j } else { j };
            m[row][i] = c;
        }
    }
    Some(m)
}

/// Exact inverse by Gauss–Jordan elimination over the rationals (`None` on overflow or if
/// singular).
fn invert_exact(m: &[Vec<Ratio>]) -> Option<Vec<Vec<Ratio>>> {
    let n = m.len();
    let mut a: Vec<Vec<Ratio>> = m.to_vec();
    let mut inv = vec![vec![Ratio::ZERO; n]; n];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = Ratio::ONE;
    }
    for col in 0..n {
        let piv = (col..n).find(|&r| !a[r][col].is_zero())?;
        a.swap(col, piv);
        inv.swap(col, piv);
        let p = a[col][col];
        for k in 0..n {
            a[col][k] = a[col][k].div(p)?;
            inv[col][k] = inv[col][k].div(p)?;
        }
        for r in 0..n {
            if r == col || a[r][col].is_zero() {
                continue;
            }
            let f = a[r][col];
            for k in 0..n {
                a[r][k] = a[r][k].sub(f.mul(a[col][k])?)?;
                inv[r][k] = inv[r][k].sub(f.mul(inv[col][k])?)?;
            }
        }
    }
    Some(inv)
}

/// Floating-point fallback: Gauss–Jordan with partial pivoting.
fn invert_f64(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = m.len();
    let mut a = m.to_vec();
    let mut inv = vec![vec![0.0; n]; n];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs()))
            .expect("non-empty");
        a.swap(col, piv);
        inv.swap(col, piv);
        let p = a[col][col];
        for k in 0..n {
            a[col][k] /= p;
            inv[col][k] /= p;
        }
        for r in 0..n {
            if r == col {
                continue;
            }
            let f = a[r][col];
            if f == 0.0 {
                continue;
            }
            for k in 0..n {
                a[r][k] -= f * a[col][k];
                inv[r][k] -= f * inv[col][k];
            }
        }
    }
    inv
}

fn to_f64_matrix(m: &[Vec<Ratio>]) -> Vec<Vec<f64>> {
    m.iter()
        .map(|row| row.iter().map(|r| r.to_f64()).collect())
        .collect()
}

/// The matrix `T` converting Wang–Ball control points of degree `n` to Bézier control
/// points: `bezier[j] = Σ_i T[j][i] · wang_ball[i]`; equivalently `W_{i,n} = Σ_j T[j][i] B_{j,n}`.
///
/// Method: each basis function is a scaled monomial `2^a t^a (1−t)^b` (possibly mirrored,
/// `t → 1 − t`) of degree `a + b ≤ n`; multiplying by `(t + (1−t))^{n−a−b}` and using
/// `t^j (1−t)^{n−j} = B_{j,n} / C(n, j)` gives the exact entries
/// `2^a C(n−a−b, k) / C(n, a+k)`. They are computed as exact fractions of 128-bit integers
/// and rounded once to `f64`, so every entry is correctly rounded (for all practical n).
///
/// # Panics
/// If `n == 0` or the exact computation overflows (far beyond any usable degree).
pub fn wang_ball_to_bernstein(n: usize) -> Vec<Vec<f64>> {
    assert!(n >= 1, "Wang–Ball degree must be at least 1");
    let exact = wang_ball_to_bernstein_exact(n).expect("degree too large for exact conversion");
    to_f64_matrix(&exact)
}

/// The matrix `S = T⁻¹` converting Bézier control points of degree `n` to Wang–Ball control
/// points: `wang_ball[i] = Σ_j S[i][j] · bezier[j]`.
///
/// Method: `T` of [`wang_ball_to_bernstein`] is inverted exactly by Gauss–Jordan elimination
/// over reduced fractions of 128-bit integers (overflow-checked), then each entry is rounded
/// once to `f64`. This is exact for every degree up to at least 30 (see the tests); should the
/// fractions ever overflow, the function falls back to a partially pivoted floating-point
/// inversion of `T`.
///
/// # Panics
/// If `n == 0`.
pub fn bernstein_to_wang_ball(n: usize) -> Vec<Vec<f64>> {
    assert!(n >= 1, "Wang–Ball degree must be at least 1");
    match wang_ball_to_bernstein_exact(n).and_then(|m| invert_exact(&m)) {
        Some(inv) => to_f64_matrix(&inv),
        None => invert_f64(&wang_ball_to_bernstein(n)),
    }
}

fn apply<T>(m: &[Vec<f64>], v: &[T]) -> Vec<T>
where
    T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
{
    m.iter()
        .map(|row| {
            let mut acc = v[0] * row[0];
            for k in 1..v.len() {
                acc = acc + v[k] * row[k];
            }
            acc
        })
        .collect()
}

/// Converts Wang–Ball control points (degree = `points.len() − 1 ≥ 1`) to the Bézier control
/// points of the same curve.
pub fn wang_ball_points_to_bezier(points: &[Point]) -> Vec<Point> {
    assert!(points.len() >= 2, "need at least two control points");
    apply(&wang_ball_to_bernstein(points.len() - 1), points)
}

/// Converts Bézier control points (degree = `points.len() − 1 ≥ 1`) to the Wang–Ball control
/// points of the same curve.
pub fn bezier_points_to_wang_ball(points: &[Point]) -> Vec<Point> {
    assert!(points.len() >= 2, "need at least two control points");
    apply(&bernstein_to_wang_ball(points.len() - 1), points)
}

fn check_degree(len: usize) -> usize {
    assert!(
        len >= 2,
        "a Wang–Ball curve needs at least two control points"
    );
    len - 1
}

/// A planar Wang–Ball curve `W(t) = Σ W_{i,n}(t) p_i`, `t ∈ [0, 1]`, of degree
/// `n = points.len() − 1 ≥ 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct WangBall {
    /// The control points `p_0 … p_n`.
    pub points: Vec<Point>,
}

impl WangBall {
    /// Creates a curve from its control points (at least two).
    pub fn new(points: Vec<Point>) -> Self {
        check_degree(points.len());
        WangBall { points }
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        check_degree(self.points.len())
    }

    /// The point at parameter `t`.
    pub fn eval(&self, t: f64) -> Point {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis(n, t, &mut w);
        self.points
            .iter()
            .zip(&w)
            .fold(Point::ZERO, |acc, (&p, &wi)| acc + p * wi)
    }

    /// The derivative `W'(t)`.
    pub fn derivative(&self, t: f64) -> Point {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis_derivative(n, t, &mut w);
        self.points
            .iter()
            .zip(&w)
            .fold(Point::ZERO, |acc, (&p, &wi)| acc + p * wi)
    }

    /// The Bézier control points of the same curve (same degree).
    pub fn to_bezier(&self) -> Vec<Point> {
        wang_ball_points_to_bezier(&self.points)
    }

    /// The Wang–Ball form of the Bézier curve with control points `bezier` (at least two).
    pub fn from_bezier(bezier: &[Point]) -> Self {
        WangBall {
            points: bezier_points_to_wang_ball(bezier),
        }
    }

    /// Splits the curve at `t`: the first part traces `W` on `[0, t]`, the second on
    /// `[t, 1]`, each reparametrised to `[0, 1]`. Done by de Casteljau on the Bézier form.
    pub fn split(&self, t: f64) -> (WangBall, WangBall) {
        let (l, r) = de_casteljau_split(&self.to_bezier(), t);
        (WangBall::from_bezier(&l), WangBall::from_bezier(&r))
    }
}

/// A disk: center and radius.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Disk {
    /// The center.
    pub center: Point,
    /// The radius (non-negative for a proper disk).
    pub radius: f64,
}

impl Disk {
    /// Creates a disk.
    pub const fn new(center: Point, radius: f64) -> Self {
        Disk { center, radius }
    }
}

/// A disk Wang–Ball curve (Eq. 1): `(W)(t) = Σ W_{i,n}(t) (p_i, r_i) = (C(t), R(t))` with
/// center curve `C` and radius function `R` (Eq. 3), degree `n = disks.len() − 1 ≥ 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct DiskWangBall {
    /// The control disks `(p_0, r_0) … (p_n, r_n)`.
    pub disks: Vec<Disk>,
}

impl DiskWangBall {
    /// Creates a DWB curve from its control disks (at least two).
    pub fn new(disks: Vec<Disk>) -> Self {
        check_degree(disks.len());
        DiskWangBall { disks }
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        check_degree(self.disks.len())
    }

    /// The center curve `C(t) = Σ W_{i,n}(t) p_i` as a Wang–Ball curve.
    pub fn center_curve(&self) -> WangBall {
        WangBall::new(self.disks.iter().map(|d| d.center).collect())
    }

    /// The disk `(C(t), R(t))` at parameter `t`.
    pub fn eval(&self, t: f64) -> Disk {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis(n, t, &mut w);
        self.disks
            .iter()
            .zip(&w)
            .fold(Disk::new(Point::ZERO, 0.0), |acc, (d, &wi)| {
                Disk::new(acc.center + d.center * wi, acc.radius + d.radius * wi)
            })
    }

    /// The center `C(t)`.
    pub fn center(&self, t: f64) -> Point {
        self.eval(t).center
    }

    /// The radius function `R(t) = Σ W_{i,n}(t) r_i`.
    pub fn radius(&self, t: f64) -> f64 {
        self.eval(t).radius
    }

    /// The derivative `C'(t)` of the center curve.
    pub fn center_derivative(&self, t: f64) -> Point {
        self.center_curve().derivative(t)
    }

    /// The derivative `R'(t)` of the radius function.
    pub fn radius_derivative(&self, t: f64) -> f64 {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis_derivative(n, t, &mut w);
        self.disks
            .iter()
            .zip(&w)
            .map(|(d, &wi)| d.radius * wi)
            .sum()
    }

    /// The arc length `∫₀¹ |C'(t)| dt` of the center curve.
    ///
    /// Adaptive 16-point Gauss–Legendre quadrature: an interval is accepted when the rule on it
    /// and the sum of the rule on its two halves agree to `1e-14` times the total (the
    /// tolerance is shared among subintervals), otherwise it is bisected (depth ≤ 20). On
    /// smooth curves this is accurate to about 1e-13 relative; cusps (`C' = 0`) are resolved
    /// by the bisection.
    pub fn center_arc_length(&self) -> f64 {
        let c = self.center_curve();
        let f = |t: f64| c.derivative(t).length();
        // Rounding noise in C' scales with the control polygon, so the tolerance does too
        // (this keeps (near-)degenerate curves from bisecting to the depth limit).
        let p0 = c.points[0];
        let span = c.points.iter().map(|p| p.distance(p0)).fold(0.0, f64::max);
        crate::quad::adaptive(&f, 0.0, 1.0, 1e-2 * span)
    }
}

/// The subdivision parameter of §2.2.2 for merging the adjacent DWB curves `a` (left) and
/// `b` (right): `λ = ∫₀¹|C'_a| / (∫₀¹|C'_a| + ∫₀¹|C'_b|)`, the share of the left center
/// curve in the total arc length. Returns 0.5 if both center curves have zero length.
pub fn merge_lambda(a: &DiskWangBall, b: &DiskWangBall) -> f64 {
    let la = a.center_arc_length();
    let lb = b.center_arc_length();
    let total = la + lb;
    if total > 0.0 {
        la / total
    } else {
        0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_points(rng: &mut ChaCha8Rng, count: usize) -> Vec<Point> {
        (0..count)
            .map(|_| Point::new(rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0)))
            .collect()
    }

    fn bezier_eval(points: &[Point], t: f64) -> Point {
        let mut w = points.to_vec();
        for level in 1..w.len() {
            for k in 0..w.len() - level {
                w[k] = w[k].lerp(w[k + 1], t);
            }
        }
        w[0]
    }

    fn ts(count: usize) -> impl Iterator<Item = f64> {
        (0..=count).map(move |k| k as f64 / count as f64)
    }

    #[test]
    fn basis_is_a_partition_of_unity() {
        for n in 1..=12 {
            let mut w = vec![0.0; n + 1];
            for t in ts(200) {
                wang_ball_basis(n, t, &mut w);
                let s: f64 = w.iter().sum();
                assert!((s - 1.0).abs() < 1e-14, "n={n} t={t} sum={s}");
                assert!(w.iter().all(|&x| x >= 0.0));
            }
        }
    }

    #[test]
    fn cubic_basis_is_the_ball_basis() {
        let mut w = [0.0; 4];
        for t in ts(100) {
            wang_ball_basis(3, t, &mut w);
            let s = 1.0 - t;
            let expect = [s * s, 2.0 * t * s * s, 2.0 * t * t * s, t * t];
            for i in 0..4 {
                assert!((w[i] - expect[i]).abs() < 1e-15, "i={i} t={t}");
            }
        }
    }

    #[test]
    fn quadratic_and_linear_bases_are_bernstein() {
        let mut w2 = [0.0; 3];
        let mut w1 = [0.0; 2];
        for t in ts(50) {
            wang_ball_basis(2, t, &mut w2);
            wang_ball_basis(1, t, &mut w1);
            let s = 1.0 - t;
            assert!((w2[0] - s * s).abs() < 1e-15);
            assert!((w2[1] - 2.0 * s * t).abs() < 1e-15);
            assert!((w2[2] - t * t).abs() < 1e-15);
            assert!((w1[0] - s).abs() < 1e-15 && (w1[1] - t).abs() < 1e-15);
        }
    }

    #[test]
    fn conversion_matrices_are_inverse_and_match_the_basis() {
        for n in 1..=12 {
            let t_mat = wang_ball_to_bernstein(n);
            let s_mat = bernstein_to_wang_ball(n);
            for i in 0..=n {
                for j in 0..=n {
                    let p: f64 = (0..=n).map(|k| t_mat[i][k] * s_mat[k][j]).sum();
                    let e = if i == j { 1.0 } else { 0.0 };
                    assert!((p - e).abs() < 1e-12, "n={n} ({i},{j}) {p}");
                }
            }
            // W_i = Σ_j T[j][i] B_j at sample points.
            let mut w = vec![0.0; n + 1];
            for t in ts(37) {
                wang_ball_basis(n, t, &mut w);
                for i in 0..=n {
                    let b: f64 = (0..=n)
                        .map(|j| {
                            t_mat[j][i]
                                * binomial_exact(n, j).unwrap() as f64
                                * t.powi(j as i32)
                                * (1.0 - t).powi((n - j) as i32)
                        })
                        .sum();
                    assert!((b - w[i]).abs() < 1e-13, "n={n} i={i} t={t}");
                }
            }
        }
    }

    #[test]
    fn exact_inverse_is_available_to_high_degree() {
        for n in 1..=30 {
            let m = wang_ball_to_bernstein_exact(n).expect("forward overflow");
            assert!(
                invert_exact(&m).is_some(),
                "exact inverse overflowed at n={n}"
            );
        }
    }

    #[test]
    fn round_trip_through_bezier() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for n in 1..=12 {
            for _ in 0..5 {
                let p = random_points(&mut rng, n + 1);
                let wb = WangBall::new(p.clone());
                let back = WangBall::from_bezier(&wb.to_bezier());
                assert_eq!(back.degree(), n);
                for (a, b) in p.iter().zip(&back.points) {
                    assert!(a.distance(*b) < 1e-12, "n={n}: {a:?} vs {b:?}");
                }
            }
        }
    }

    #[test]
    fn curve_equals_its_bezier_conversion() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for n in 1..=12 {
            let wb = WangBall::new(random_points(&mut rng, n + 1));
            let bez = wb.to_bezier();
            for t in ts(100) {
                let d = wb.eval(t).distance(bezier_eval(&bez, t));
                assert!(d < 1e-12, "n={n} t={t} d={d}");
            }
        }
    }

    #[test]
    fn curve_interpolates_end_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        for n in 1..=12 {
            let p = random_points(&mut rng, n + 1);
            let wb = WangBall::new(p.clone());
            assert!(wb.eval(0.0).distance(p[0]) < 1e-14);
            assert!(wb.eval(1.0).distance(p[n]) < 1e-14);
        }
    }

    #[test]
    fn derivative_matches_central_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        let h = 1e-6;
        for n in 1..=12 {
            let wb = WangBall::new(random_points(&mut rng, n + 1));
            for t in ts(40).map(|t| 0.01 + 0.98 * t) {
                let fd = (wb.eval(t + h) - wb.eval(t - h)) / (2.0 * h);
                let d = wb.derivative(t);
                assert!(
                    (fd - d).length() < 1e-6 * (1.0 + d.length()),
                    "n={n} t={t}: {d:?} vs {fd:?}"
                );
            }
            // Basis derivatives at the ends, compared with one-sided differences.
            let mut d0 = vec![0.0; n + 1];
            let (mut a, mut b) = (vec![0.0; n + 1], vec![0.0; n + 1]);
            wang_ball_basis_derivative(n, 0.0, &mut d0);
            wang_ball_basis(n, 0.0, &mut a);
            wang_ball_basis(n, h, &mut b);
            for i in 0..=n {
                assert!((d0[i] - (b[i] - a[i]) / h).abs() < 1e-4, "n={n} i={i}");
            }
        }
    }

    #[test]
    fn split_halves_reproduce_the_curve() {
        let mut rng = ChaCha8Rng::seed_from_u64(15);
        for n in 1..=12 {
            let wb = WangBall::new(random_points(&mut rng, n + 1));
            for &s in &[0.3, 0.5, 0.81] {
                let (l, r) = wb.split(s);
                assert_eq!((l.degree(), r.degree()), (n, n));
                for u in ts(50) {
                    assert!(l.eval(u).distance(wb.eval(s * u)) < 1e-11, "n={n} left");
                    let tr = s + (1.0 - s) * u;
                    assert!(r.eval(u).distance(wb.eval(tr)) < 1e-11, "n={n} right");
                }
            }
        }
    }

    fn line_dwb(n: usize, a: Point, b: Point) -> DiskWangBall {
        // Bézier points evenly spaced on the segment give a uniformly parametrised line.
        let bez: Vec<Point> = (0..=n).map(|k| a.lerp(b, k as f64 / n as f64)).collect();
        let wb = WangBall::from_bezier(&bez);
        DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 1.0)).collect())
    }

    #[test]
    fn dwb_evaluates_center_and_radius_with_the_same_basis() {
        let mut rng = ChaCha8Rng::seed_from_u64(16);
        for n in 1..=8 {
            let pts = random_points(&mut rng, n + 1);
            let radii: Vec<f64> = (0..=n).map(|_| rng.random_range(0.1..2.0)).collect();
            let dwb = DiskWangBall::new(
                pts.iter()
                    .zip(&radii)
                    .map(|(&p, &r)| Disk::new(p, r))
                    .collect(),
            );
            let center = WangBall::new(pts.clone());
            let mut w = vec![0.0; n + 1];
            for t in ts(30) {
                let d = dwb.eval(t);
                wang_ball_basis(n, t, &mut w);
                let r: f64 = w.iter().zip(&radii).map(|(a, b)| a * b).sum();
                assert!(d.center.distance(center.eval(t)) < 1e-13);
                assert!((d.radius - r).abs() < 1e-13);
                assert!((dwb.radius(t) - r).abs() < 1e-13);
            }
            assert!((dwb.radius(0.0) - radii[0]).abs() < 1e-14);
            assert!((dwb.radius(1.0) - radii[n]).abs() < 1e-14);
            let h = 1e-6;
            let fd = (dwb.radius(0.4 + h) - dwb.radius(0.4 - h)) / (2.0 * h);
            assert!((dwb.radius_derivative(0.4) - fd).abs() < 1e-6);
        }
    }

    #[test]
    fn straight_line_arc_length_is_the_chord() {
        for n in 1..=12 {
            let (a, b) = (Point::new(1.0, -2.0), Point::new(4.0, 2.0));
            let dwb = line_dwb(n, a, b);
            let l = dwb.center_arc_length();
            assert!((l - 5.0).abs() < 1e-12, "n={n} l={l}");
        }
        // A non-uniformly parametrised line (still straight): length is still the chord.
        let wb = WangBall::new(vec![
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.0),
            Point::new(2.5, 0.0),
            Point::new(3.0, 0.0),
        ]);
        let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.5)).collect());
        assert!((dwb.center_arc_length() - 3.0).abs() < 1e-12);
    }

    #[test]
    fn quarter_circle_arc_length() {
        // Standard cubic Bézier approximation of the unit quarter circle (radial error
        // ≤ 2.7e-4), converted to Wang–Ball form.
        let k = 4.0 / 3.0 * (2f64.sqrt() - 1.0);
        let bez = [
            Point::new(1.0, 0.0),
            Point::new(1.0, k),
            Point::new(k, 1.0),
            Point::new(0.0, 1.0),
        ];
        let wb = WangBall::from_bezier(&bez);
        let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.1)).collect());
        let l = dwb.center_arc_length();
        let quarter = std::f64::consts::FRAC_PI_2;
        assert!((l - quarter).abs() < 2e-4 * quarter, "l={l}");
        // And against a fine polyline of the curve itself.
        let m = 200_000;
        let poly: f64 = (0..m)
            .map(|i| {
                let (a, b) = (i as f64 / m as f64, (i + 1) as f64 / m as f64);
                bezier_eval(&bez, a).distance(bezier_eval(&bez, b))
            })
            .sum();
        assert!((l - poly).abs() < 1e-10, "l={l} poly={poly}");
    }

    #[test]
    fn arc_length_handles_a_cusp() {
        // Bézier cubic with C'(0.5) = 0 (a cusp): x = 3t² − 2t³ style symmetric curve.
        let bez = [
            Point::new(0.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(0.0, 1.0),
            Point::new(2.0, 0.0),
        ];
        let wb = WangBall::from_bezier(&bez);
        let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.1)).collect());
        let l = dwb.center_arc_length();
        let m = 400_000;
        let poly: f64 = (0..m)
            .map(|i| {
                let (a, b) = (i as f64 / m as f64, (i + 1) as f64 / m as f64);
                bezier_eval(&bez, a).distance(bezier_eval(&bez, b))
            })
            .sum();
        assert!((l - poly).abs() < 1e-8, "l={l} poly={poly}");
    }

    #[test]
    fn merge_lambda_is_the_arc_length_share() {
        let a = line_dwb(3, Point::new(0.0, 0.0), Point::new(3.0, 4.0));
        let b = line_dwb(4, Point::new(3.0, 4.0), Point::new(3.0, 9.0));
        assert!((merge_lambda(&a, &b) - 0.5).abs() < 1e-14);
        let c = line_dwb(2, Point::new(3.0, 4.0), Point::new(3.0, 19.0));
        assert!((merge_lambda(&a, &c) - 0.25).abs() < 1e-14);
        assert!((merge_lambda(&c, &a) - 0.75).abs() < 1e-14);
        let p = DiskWangBall::new(vec![Disk::new(Point::new(1.0, 1.0), 0.5); 3]);
        assert_eq!(merge_lambda(&p, &p), 0.5);
    }
}
