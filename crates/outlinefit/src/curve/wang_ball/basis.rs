//! The Wang–Ball basis of degree n and its derivative (Eq. 2).

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
pub(super) fn basis_shape(n: usize, i: usize) -> (i32, i32, bool) {
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
pub(crate) fn wang_ball_basis(n: usize, t: f64, out: &mut [f64]) {
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
pub(super) fn wang_ball_basis_derivative(n: usize, t: f64, out: &mut [f64]) {
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
