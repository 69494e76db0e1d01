//! Small dense linear systems on the stack: Gaussian elimination with partial pivoting on
//! an augmented matrix of at most `N` unknowns, without allocation (the fit solves
//! millions of 2 × 2 to 6 × 6 systems; `tests/no_alloc.rs` checks that the weight search
//! allocates nothing).

/// The 2 × 2 system `m x = r` by Cramer's rule: `(det, x)` with det = m00 m11 − m01 m10,
/// x0 = (r0 m11 − r1 m01)/det and x1 = (m00 r1 − m10 r0)/det. The caller judges `det`
/// (each fit has its own test for a singular system, and its own fall-back) before it
/// uses `x`, which is not finite when `det` is 0.
#[inline]
pub(crate) fn cramer2(m: [[f64; 2]; 2], r: [f64; 2]) -> (f64, [f64; 2]) {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let x = [
        (r[0] * m[1][1] - r[1] * m[0][1]) / det,
        (m[0][0] * r[1] - m[1][0] * r[0]) / det,
    ];
    (det, x)
}

/// The determinant of a 3 × 3 matrix by expansion along its first row:
/// m00 (m11 m22 − m12 m21) − m01 (m10 m22 − m12 m20) + m02 (m10 m21 − m11 m20).
/// With it, Cramer's rule solves the small 3 × 3 normal systems whose callers test the
/// determinant themselves.
#[inline]
pub(crate) fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// What to do with a pivot that is (numerically) zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Singular {
    /// Leave the column out: a pivot below 1e-300 is skipped and its unknown is 0, so a
    /// rank-deficient (ridge-regularised) least-squares system still gives an answer.
    SkipColumn,
    /// Give up: a pivot that is NaN or at most 1e-300, or a result that is not finite,
    /// makes the solve return `None` (a Levenberg–Marquardt step is then refused).
    Fail,
}

/// Solves the first `n` rows of the augmented system `m` with [`Singular::SkipColumn`]:
/// always an answer.
pub(crate) fn solve_rank_tolerant<const N: usize, const W: usize>(
    m: &mut [[f64; W]; N],
    n: usize,
) -> [f64; N] {
    solve_augmented(m, n, Singular::SkipColumn).unwrap_or([0.0; N])
}

/// Solves the first `n` rows of the augmented system `m` (columns 0..n hold the matrix,
/// the last column `W − 1` the right-hand side; columns n..W−1 must be zero) in place.
pub(crate) fn solve_augmented<const N: usize, const W: usize>(
    m: &mut [[f64; W]; N],
    n: usize,
    singular: Singular,
) -> Option<[f64; N]> {
    if n == 2 {
        return solve_two(m, singular);
    }
    solve_general(m, n, singular)
}

/// [`solve_augmented`] for any `n`: elimination with partial pivoting, then back
/// substitution.
fn solve_general<const N: usize, const W: usize>(
    m: &mut [[f64; W]; N],
    n: usize,
    singular: Singular,
) -> Option<[f64; N]> {
    let rhs = W - 1;
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if m[row][col].abs() > m[piv][col].abs() {
                piv = row;
            }
        }
        m.swap(col, piv);
        let p = m[col][col];
        match singular {
            Singular::SkipColumn if p.abs() < 1e-300 => continue,
            Singular::Fail if p.is_nan() || p.abs() <= 1e-300 => return None,
            _ => {}
        }
        for row in col + 1..n {
            let f = m[row][col] / p;
            // Skipping zero factors keeps a zero's sign and an infinity out of the rows.
            if singular == Singular::SkipColumn && f == 0.0 {
                continue;
            }
            for k in col..W {
                m[row][k] -= f * m[col][k];
            }
        }
    }
    let mut x = [0.0; N];
    for row in (0..n).rev() {
        let mut s = m[row][rhs];
        for k in row + 1..n {
            s -= m[row][k] * x[k];
        }
        let p = m[row][row];
        x[row] = match singular {
            Singular::SkipColumn if p.abs() < 1e-300 => 0.0,
            _ => s / p,
        };
    }
    match singular {
        Singular::SkipColumn => Some(x),
        Singular::Fail => x.iter().all(|v| v.is_finite()).then_some(x),
    }
}

/// [`solve_augmented`] of two unknowns, written out: the same operations in the same
/// order, so the same bits (the segment fit's tangent lengths are two unknowns, solved a
/// few million times on a page). The zero columns between the two unknowns and the
/// right-hand side are left alone: the general loop only ever subtracts zeros from them,
/// and no step reads them.
#[inline]
fn solve_two<const N: usize, const W: usize>(
    m: &mut [[f64; W]; N],
    singular: Singular,
) -> Option<[f64; N]> {
    let rhs = W - 1;
    let zero_pivot = |p: f64| match singular {
        Singular::SkipColumn => p.abs() < 1e-300,
        Singular::Fail => p.is_nan() || p.abs() <= 1e-300,
    };
    if m[1][0].abs() > m[0][0].abs() {
        m.swap(0, 1);
    }
    let p = m[0][0];
    if zero_pivot(p) {
        if singular == Singular::Fail {
            return None;
        }
    } else {
        let f = m[1][0] / p;
        if !(singular == Singular::SkipColumn && f == 0.0) {
            m[1][0] -= f * m[0][0];
            m[1][1] -= f * m[0][1];
            m[1][rhs] -= f * m[0][rhs];
        }
    }
    if singular == Singular::Fail && zero_pivot(m[1][1]) {
        return None;
    }
    let solve = |s: f64, p: f64| match singular {
        Singular::SkipColumn if p.abs() < 1e-300 => 0.0,
        _ => s / p,
    };
    let mut x = [0.0; N];
    x[1] = solve(m[1][rhs], m[1][1]);
    x[0] = solve(m[0][rhs] - m[0][1] * x[1], m[0][0]);
    match singular {
        Singular::SkipColumn => Some(x),
        Singular::Fail => x.iter().all(|v| v.is_finite()).then_some(x),
    }
}

#[cfg(test)]
mod tests {
    use super::{cramer2, det3, solve_augmented, solve_general, solve_two, Singular};

    /// The written-out solve of two unknowns gives the general elimination's bits, for
    /// both policies, on random systems (rows swapped or not) and on singular, tiny,
    /// NaN and infinite ones.
    #[test]
    fn two_unknowns_match_the_general_elimination_bit_for_bit() {
        let mut systems: Vec<[[f64; 5]; 4]> = Vec::new();
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 * 20.0 - 10.0
        };
        for _ in 0..5000 {
            let mut m = [[0.0; 5]; 4];
            for row in m.iter_mut().take(2) {
                row[0] = next();
                row[1] = next();
                row[4] = next();
            }
            systems.push(m);
        }
        let special = [0.0, -0.0, 1e-301, 1e-320, f64::NAN, f64::INFINITY, 1e300];
        for &a in &special {
            for &b in &special {
                systems.push([
                    [a, 1.0, 0.0, 0.0, 2.0],
                    [b, 3.0, 0.0, 0.0, -1.0],
                    [0.0; 5],
                    [0.0; 5],
                ]);
                systems.push([
                    [1.0, a, 0.0, 0.0, b],
                    [2.0, 2.0 * a, 0.0, 0.0, 1.0],
                    [0.0; 5],
                    [0.0; 5],
                ]);
            }
        }
        let bits = |r: Option<[f64; 4]>| r.map(|v| v.map(f64::to_bits));
        for m in systems {
            for policy in [Singular::SkipColumn, Singular::Fail] {
                let (mut a, mut b) = (m, m);
                assert_eq!(
                    bits(solve_two(&mut a, policy)),
                    bits(solve_general(&mut b, 2, policy)),
                    "{m:?} {policy:?}"
                );
            }
        }
    }

    #[test]
    fn det3_of_known_matrices() {
        assert_eq!(
            det3([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            1.0
        );
        assert_eq!(
            det3([[2.0, 0.0, 1.0], [1.0, 3.0, 2.0], [1.0, 1.0, 2.0]]),
            6.0
        );
        // Swapping two rows flips the sign; a repeated row gives 0.
        assert_eq!(
            det3([[1.0, 3.0, 2.0], [2.0, 0.0, 1.0], [1.0, 1.0, 2.0]]),
            -6.0
        );
        assert_eq!(
            det3([[1.0, 2.0, 3.0], [1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]),
            0.0
        );
    }

    #[test]
    fn cramer2_solves_and_reports_its_determinant() {
        // 3x + y = 9, x + 2y = 8: x = 2, y = 3.
        let (det, x) = cramer2([[3.0, 1.0], [1.0, 2.0]], [9.0, 8.0]);
        assert_eq!(det, 5.0);
        assert!((x[0] - 2.0).abs() < 1e-15 && (x[1] - 3.0).abs() < 1e-15);
        // Not symmetric: 2x − y = 1, 4x + y = 11: x = 2, y = 3.
        let (det, x) = cramer2([[2.0, -1.0], [4.0, 1.0]], [1.0, 11.0]);
        assert_eq!(det, 6.0);
        assert!((x[0] - 2.0).abs() < 1e-15 && (x[1] - 3.0).abs() < 1e-15);
        let (det, x) = cramer2([[1.0, 2.0], [2.0, 4.0]], [1.0, 2.0]);
        assert_eq!(det, 0.0);
        assert!(!x[0].is_finite());
    }

    #[test]
    fn solves_a_pivoting_system_and_treats_singular_ones_by_policy() {
        // x = (1, −2, 3) with a zero in the first pivot position.
        let a = [[0.0, 2.0, 1.0], [1.0, 1.0, 1.0], [2.0, 1.0, -1.0]];
        let x = [1.0, -2.0, 3.0];
        for singular in [Singular::SkipColumn, Singular::Fail] {
            let mut m = [[0.0; 5]; 4];
            for i in 0..3 {
                m[i][..3].copy_from_slice(&a[i]);
                m[i][4] = (0..3).map(|k| a[i][k] * x[k]).sum();
            }
            let got = solve_augmented(&mut m, 3, singular).unwrap();
            for i in 0..3 {
                assert!((got[i] - x[i]).abs() < 1e-14, "{singular:?} {got:?}");
            }
            assert_eq!(got[3], 0.0);
        }
        // Rank 1: skipping gives an answer with the dependent unknown at 0; failing, none.
        let singular_rows = || [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]];
        let mut m = singular_rows();
        assert_eq!(
            solve_augmented(&mut m, 2, Singular::SkipColumn),
            Some([3.0, 0.0])
        );
        let mut m = singular_rows();
        assert_eq!(solve_augmented(&mut m, 2, Singular::Fail), None);
    }
}
