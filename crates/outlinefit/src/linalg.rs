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

#[cfg(test)]
mod tests {
    use super::{cramer2, det3, solve_augmented, Singular};

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
