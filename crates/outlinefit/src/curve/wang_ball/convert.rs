//! Exact conversion between the Wang–Ball and Bernstein bases: rational arithmetic on
//! i128 for the conversion matrices, and floating inversion where the exact one overflows.

use super::basis::basis_shape;
use crate::curve::basis::binomial_exact;
use crate::geom::Point;

/// A reduced fraction `num / den` with `den > 0`; every operation is overflow-checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Ratio {
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
pub(super) fn wang_ball_to_bernstein_exact(n: usize) -> Option<Vec<Vec<Ratio>>> {
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
pub(super) fn invert_exact(m: &[Vec<Ratio>]) -> Option<Vec<Vec<Ratio>>> {
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
pub(super) fn wang_ball_to_bernstein(n: usize) -> Vec<Vec<f64>> {
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
pub(super) fn bernstein_to_wang_ball(n: usize) -> Vec<Vec<f64>> {
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
pub(crate) fn wang_ball_points_to_bezier(points: &[Point]) -> Vec<Point> {
    assert!(points.len() >= 2, "need at least two control points");
    apply(&wang_ball_to_bernstein(points.len() - 1), points)
}

/// Converts Bézier control points (degree = `points.len() − 1 ≥ 1`) to the Wang–Ball control
/// points of the same curve.
pub(crate) fn bezier_points_to_wang_ball(points: &[Point]) -> Vec<Point> {
    assert!(points.len() >= 2, "need at least two control points");
    apply(&bernstein_to_wang_ball(points.len() - 1), points)
}

pub(super) fn check_degree(len: usize) -> usize {
    assert!(
        len >= 2,
        "a Wang–Ball curve needs at least two control points"
    );
    len - 1
}
