//! Small dense linear systems on the stack: Gaussian elimination with partial pivoting on
//! an augmented matrix of at most `N` unknowns, without allocation (the fit solves
//! millions of 2 × 2 to 6 × 6 systems; `tests/no_alloc.rs` checks that the weight search
//! allocates nothing).

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
    use super::{solve_augmented, Singular};

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
