//! Least squares with lower bounds: minimise `½ xᵀ G x − bᵀ x` subject to `x_i ≥ l_i`, for a
//! symmetric positive definite `G` (the normal matrix of a least-squares problem).
//!
//! Lawson and Hanson's active-set method (their NNLS, shifted to general lower bounds):
//! variables start on their bounds; the one whose gradient most wants to leave its bound
//! is freed, the problem is solved on the free set, and a step that would cross a bound is
//! shortened there and that variable is fixed again. Each outer step strictly lowers the
//! objective, so the method ends with the exact constrained minimum after finitely many
//! steps (for the few variables of a disk curve: a handful of Cholesky solves).
//!
//! Hand-written: the problems have at most a few dozen variables, and a general QP or
//! conic solver crate would be a much larger dependency for this one use.

use nalgebra::{DMatrix, DVector};

/// Why a bounded least-squares problem could not be solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct NotPositiveDefinite;

/// The minimiser of `½ xᵀ G x − bᵀ x` over `x ≥ lower` (componentwise).
///
/// `G` must be symmetric positive definite on every subset of variables (it is when it is
/// positive definite); otherwise [`NotPositiveDefinite`].
pub(crate) fn minimize_lower_bounded(
    g: &DMatrix<f64>,
    b: &DVector<f64>,
    lower: &[f64],
) -> Result<DVector<f64>, NotPositiveDefinite> {
    let n = lower.len();
    debug_assert!(g.nrows() == n && g.ncols() == n && b.len() == n);
    if n == 0 {
        return Ok(DVector::zeros(0));
    }
    // The unconstrained minimum is the answer whenever it is feasible (the common case).
    let unconstrained = g.clone().cholesky().ok_or(NotPositiveDefinite)?.solve(b);
    if unconstrained.iter().zip(lower).all(|(x, l)| x >= l) {
        return Ok(unconstrained);
    }
    let scale = b.amax().max(g.amax()).max(f64::MIN_POSITIVE);
    let tol = 1e-13 * scale;
    let mut x = DVector::from_column_slice(lower);
    let mut free = vec![false; n];
    // Each outer step frees one variable and lowers the objective; 4n + 8 steps is far more
    // than the method needs and only guards against rounding-induced cycling.
    for _ in 0..4 * n + 8 {
        let gradient = g * &x - b;
        let Some((j, &gj)) = gradient
            .iter()
            .enumerate()
            .filter(|(i, _)| !free[*i])
            .min_by(|a, b| a.1.total_cmp(b.1))
        else {
            break; // every variable is free: x is the unconstrained minimum
        };
        if gj >= -tol {
            break; // Karush–Kuhn–Tucker conditions hold
        }
        free[j] = true;
        // Inner loop: move towards the minimum on the free set, fixing variables that hit
        // their bounds on the way.
        loop {
            let z = solve_on_free_set(g, b, lower, &free)?;
            let blocked: Vec<usize> = (0..n).filter(|&i| free[i] && z[i] <= lower[i]).collect();
            if blocked.is_empty() {
                x = z;
                break;
            }
            let alpha = blocked
                .iter()
                .map(|&i| {
                    let denom = x[i] - z[i];
                    if denom > 0.0 {
                        ((x[i] - lower[i]) / denom).clamp(0.0, 1.0)
                    } else {
                        0.0
                    }
                })
                .fold(1.0, f64::min);
            x += (z - &x) * alpha;
            let mut fixed_any = false;
            for i in 0..n {
                if free[i] && x[i] <= lower[i] + 1e-15 * lower[i].abs().max(1.0) {
                    free[i] = false;
                    x[i] = lower[i];
                    fixed_any = true;
                }
            }
            if !fixed_any || !free.iter().any(|&f| f) {
                break;
            }
        }
    }
    Ok(x)
}

/// The minimum over the free variables with the others on their bounds.
fn solve_on_free_set(
    g: &DMatrix<f64>,
    b: &DVector<f64>,
    lower: &[f64],
    free: &[bool],
) -> Result<DVector<f64>, NotPositiveDefinite> {
    let idx: Vec<usize> = (0..free.len()).filter(|&i| free[i]).collect();
    let mut z = DVector::from_column_slice(lower);
    if idx.is_empty() {
        return Ok(z);
    }
    let k = idx.len();
    let mut sub = DMatrix::zeros(k, k);
    let mut rhs = DVector::zeros(k);
    for (a, &i) in idx.iter().enumerate() {
        rhs[a] = b[i];
        for (j, &fj) in free.iter().enumerate() {
            if !fj {
                rhs[a] -= g[(i, j)] * lower[j];
            }
        }
        for (c, &j) in idx.iter().enumerate() {
            sub[(a, c)] = g[(i, j)];
        }
    }
    let solved = sub.cholesky().ok_or(NotPositiveDefinite)?.solve(&rhs);
    for (a, &i) in idx.iter().enumerate() {
        z[i] = solved[a];
    }
    Ok(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn objective(g: &DMatrix<f64>, b: &DVector<f64>, x: &DVector<f64>) -> f64 {
        0.5 * x.dot(&(g * x)) - b.dot(x)
    }

    /// The exact answer by trying every active set (small n only).
    fn brute_force(g: &DMatrix<f64>, b: &DVector<f64>, lower: &[f64]) -> DVector<f64> {
        let n = lower.len();
        let mut best: Option<(f64, DVector<f64>)> = None;
        for mask in 0..(1u32 << n) {
            let free: Vec<bool> = (0..n).map(|i| mask & (1 << i) != 0).collect();
            let z = solve_on_free_set(g, b, lower, &free).unwrap();
            if z.iter().zip(lower).any(|(x, l)| *x < l - 1e-12) {
                continue;
            }
            let f = objective(g, b, &z);
            if best.as_ref().is_none_or(|(bf, _)| f < *bf) {
                best = Some((f, z));
            }
        }
        best.unwrap().1
    }

    #[test]
    fn matches_brute_force_on_random_problems() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut constrained = 0;
        for trial in 0..300 {
            let n = 1 + trial % 7;
            let a = DMatrix::from_fn(n + 3, n, |_, _| rng.random_range(-1.0..1.0));
            let g = a.transpose() * &a + DMatrix::identity(n, n) * 1e-3;
            let b = DVector::from_fn(n, |_, _| rng.random_range(-1.0..1.0));
            let lower: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
            let x = minimize_lower_bounded(&g, &b, &lower).unwrap();
            let want = brute_force(&g, &b, &lower);
            assert!(x.iter().zip(&lower).all(|(x, l)| x >= l), "trial {trial}");
            let (fx, fw) = (objective(&g, &b, &x), objective(&g, &b, &want));
            assert!(
                fx <= fw + 1e-12 * fw.abs().max(1.0),
                "trial {trial}: {fx} > {fw}"
            );
            assert!((&x - &want).amax() < 1e-8, "trial {trial}: {x} vs {want}");
            if x.iter().zip(&lower).any(|(x, l)| x == l) {
                constrained += 1;
            }
        }
        assert!(
            constrained > 100,
            "the test should exercise the bounds: {constrained}"
        );
    }

    #[test]
    fn feasible_unconstrained_minimum_is_returned_as_is() {
        let g = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
        let b = DVector::from_column_slice(&[1.0, 1.0]);
        let x = minimize_lower_bounded(&g, &b, &[-10.0, -10.0]).unwrap();
        let r = &g * &x - &b;
        assert!(r.amax() < 1e-15);
    }

    #[test]
    fn singular_matrix_is_an_error() {
        let g = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let b = DVector::from_column_slice(&[1.0, 0.0]);
        assert_eq!(
            minimize_lower_bounded(&g, &b, &[0.0, 0.0]),
            Err(NotPositiveDefinite)
        );
    }
}
