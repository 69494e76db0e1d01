//! SG-Bernstein basis functions and SG-Bézier curves (shape-adjustable generalized Bézier
//! curves), after Definition 1, Remark 1 and Definition 2 of the grey-wolf degree-reduction
//! paper (`sg-bezier-degree-reduction-gwo.txt`, which takes them from Hu et al. \[20\]).
//!
//! An SG-Bézier curve of degree n has n + 1 control points P_j and is
//! L(t) = Σ_j P_j l_{j,n}(t), t ∈ [0, 1], where the SG-Bernstein functions l_{j,n} are
//! polynomials of degree n + 1 that depend on a global shape parameter ω and local shape
//! parameters λ_j, μ_j. With ω = 0 they are the Bernstein polynomials of degree n, so the
//! curve is the ordinary Bézier curve.
//!
//! # The basis (signs restored)
//!
//! The text extraction of Definition 1 lost its minus signs (see `papers/NOTES.md`). With
//! them restored, for j = 0..⌊n/2⌋:
//!
//! ```text
//! l_{j,n}(t)   = [C(n,j) + (C(n+1,j) − C(n,j) − λ_j) ω + (λ_j + λ_{j+1} − C(n+1,j)) ω t] t^j (1−t)^{n−j}
//! l_{n−j,n}(t) = [C(n,j) + (μ_{j+1} − C(n,j)) ω − (μ_j + μ_{j+1} − C(n+1,j)) ω t] t^{n−j} (1−t)^j
//! ```
//!
//! with λ_0 = μ_0 = 0. The basis then sums to 1 for every ω, and the second line is the
//! mirror image of the first (l_{n−j,n}(t) = l_{j,n}(1−t) when μ = λ).
//!
//! # Which parameters are free (our reading of Definition 1, Remark 1 and Table 1)
//!
//! Let h = ⌊n/2⌋. The formulas use λ_0..λ_{h+1} and μ_0..μ_{h+1}; λ_0 = μ_0 = 0 and
//! Remark 1 fixes the values at index h + 1 that are not free:
//!
//! * **n even** (Remark 1(a)): λ_{h+1} = C(n+1,h) − μ_h and μ_{h+1} = C(n+1,h) − λ_h. The
//!   free parameters are ω, λ_1..λ_h, μ_1..μ_h (Table 1, "even"). For j = h both lines of
//!   Definition 1 define the same index n − h = h; with Remark 1(a) substituted they are the
//!   same polynomial, [C(n,h) + (C(n+1,h) − C(n,h) − λ_h) ω + (λ_h − μ_h) ω t] t^h (1−t)^h,
//!   so the middle function is that one polynomial (counted once).
//! * **n odd** (Remark 1(b), whose right-hand side the extraction garbled into
//!   "C(n+1,h+1) − μ_{h+1}"; the only reading that keeps a partition of unity and matches
//!   Table 1 is μ_{h+1} = C(n+1,h+1) − λ_{h+1}). The free parameters are ω, λ_1..λ_{h+1},
//!   μ_1..μ_h (Table 1, "odd"). The two middle functions l_{h,n} (first line, j = h) and
//!   l_{h+1,n} (second line, j = h) are distinct, so all n + 1 functions come straight from
//!   the two lines.
//!
//! Either way there are n + 1 shape parameters (Remark 3): ω plus n local ones. The paper
//! confines them to 0 ≤ ω ≤ 1 and 0 ≤ λ_j, μ_j ≤ C(n+1,j); the formulas (and the partition
//! of unity) hold for any real values, so [`SgShape::new`] checks only lengths and
//! finiteness and [`SgShape::within_paper_bounds`] reports the paper's box separately.
//! Definition 1 states n ≥ 2; the formulas also give a valid basis for n = 0 and n = 1, and
//! this module accepts them.
//!
//! Each l_{i,n} has the form (p + q t) t^i (1−t)^{n−i}, which in the Bernstein basis of
//! degree n + 1 has exactly two nonzero coefficients: p / C(n+1,i) on B_{i,n+1} and
//! (p + q) / C(n+1,i+1) on B_{i+1,n+1} ([`sg_to_bernstein`]). Written by hand: no
//! maintained crate implements SG-Bézier curves.

use outlinefit::curve::basis::binomial;
use outlinefit::curve::{bezier_derivative, ParamCurve};
use outlinefit::Point;

/// What is wrong with a set of SG-Bézier shape parameters or control points.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SgError {
    /// The number of free λ parameters does not match the degree.
    #[error("degree {degree} SG-Bézier needs {expected} free λ parameters, got {got}")]
    LambdaLen {
        /// The degree n.
        degree: usize,
        /// ⌊n/2⌋ for even n, ⌊n/2⌋ + 1 for odd n.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// The number of free μ parameters does not match the degree.
    #[error("degree {degree} SG-Bézier needs {expected} free μ parameters, got {got}")]
    MuLen {
        /// The degree n.
        degree: usize,
        /// ⌊n/2⌋.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A shape parameter is NaN or infinite.
    #[error("SG-Bézier shape parameters must be finite")]
    NonFinite,
    /// The output slice for the basis values has the wrong length.
    #[error("degree {degree} SG-Bernstein basis has {expected} functions, output slice has {got}")]
    OutputLen {
        /// The degree n.
        degree: usize,
        /// n + 1.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A curve needs at least one control point.
    #[error("an SG-Bézier curve needs at least one control point")]
    NoPoints,
}

/// The free shape parameters of an SG-Bernstein basis of some degree n (h = ⌊n/2⌋).
///
/// `lambda` holds λ_1..λ_h (even n) or λ_1..λ_{h+1} (odd n); `mu` holds μ_1..μ_h. λ_0 = μ_0
/// = 0 and the index-(h + 1) values not listed follow from Remark 1 (see the module docs).
/// The struct does not store n; [`SgShape::new`] and [`SgShape::validate`] check the lengths
/// against it.
#[derive(Clone, Debug, PartialEq)]
pub struct SgShape {
    /// The global shape parameter ω (the paper uses 0 ≤ ω ≤ 1; ω = 0 gives Bernstein).
    pub omega: f64,
    /// The free local parameters λ_1, λ_2, … (see the struct docs for how many).
    pub lambda: Vec<f64>,
    /// The free local parameters μ_1, μ_2, … (⌊n/2⌋ of them).
    pub mu: Vec<f64>,
}

impl SgShape {
    /// Number of free λ parameters for degree `n`: ⌊n/2⌋ for even n, ⌊n/2⌋ + 1 for odd n.
    pub fn lambda_len(n: usize) -> usize {
        n / 2 + n % 2
    }

    /// Number of free μ parameters for degree `n`: ⌊n/2⌋.
    pub fn mu_len(n: usize) -> usize {
        n / 2
    }

    /// Shape parameters for degree `n`, checked: the lengths must be
    /// [`lambda_len`](Self::lambda_len)`(n)` and [`mu_len`](Self::mu_len)`(n)`, and every
    /// value finite.
    pub fn new(n: usize, omega: f64, lambda: Vec<f64>, mu: Vec<f64>) -> Result<Self, SgError> {
        let s = SgShape { omega, lambda, mu };
        s.validate(n)?;
        Ok(s)
    }

    /// The shape whose basis is the Bernstein basis of degree `n`: ω = 0, with the local
    /// parameters at the middle of the paper's range, λ_j = μ_j = C(n+1,j)/2 (a symmetric
    /// choice, so raising ω from 0 keeps the basis mirror-symmetric).
    pub fn bezier(n: usize) -> Self {
        SgShape {
            omega: 0.0,
            lambda: (1..=Self::lambda_len(n))
                .map(|j| 0.5 * binomial(n + 1, j))
                .collect(),
            mu: (1..=Self::mu_len(n))
                .map(|j| 0.5 * binomial(n + 1, j))
                .collect(),
        }
    }

    /// Checks the lengths against degree `n` and that every value is finite.
    pub fn validate(&self, n: usize) -> Result<(), SgError> {
        let (el, em) = (Self::lambda_len(n), Self::mu_len(n));
        if self.lambda.len() != el {
            return Err(SgError::LambdaLen {
                degree: n,
                expected: el,
                got: self.lambda.len(),
            });
        }
        if self.mu.len() != em {
            return Err(SgError::MuLen {
                degree: n,
                expected: em,
                got: self.mu.len(),
            });
        }
        let finite = self.omega.is_finite()
            && self.lambda.iter().all(|v| v.is_finite())
            && self.mu.iter().all(|v| v.is_finite());
        if !finite {
            return Err(SgError::NonFinite);
        }
        Ok(())
    }

    /// Whether the parameters lie in the paper's box 0 ≤ ω ≤ 1, 0 ≤ λ_j, μ_j ≤ C(n+1,j) for
    /// j = 1..⌊n/2⌋ + 1, including the values Remark 1 derives. False on bad lengths.
    pub fn within_paper_bounds(&self, n: usize) -> bool {
        if self.validate(n).is_err() || !(0.0..=1.0).contains(&self.omega) {
            return false;
        }
        let (lam, mu) = self.full(n);
        (1..lam.len()).all(|j| {
            let c = binomial(n + 1, j);
            (0.0..=c).contains(&lam[j]) && (0.0..=c).contains(&mu[j])
        })
    }

    /// The full parameter lists λ_0..λ_{h+1} and μ_0..μ_{h+1}, with λ_0 = μ_0 = 0 and
    /// Remark 1 applied. Lengths must already be valid.
    fn full(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        let h = n / 2;
        let mut lam = vec![0.0; h + 2];
        let mut mu = vec![0.0; h + 2];
        lam[1..=self.lambda.len()].copy_from_slice(&self.lambda);
        mu[1..=self.mu.len()].copy_from_slice(&self.mu);
        if n.is_multiple_of(2) {
            // Remark 1(a); C(n+1,h) = C(n+1,h+1) for even n.
            let c = binomial(n + 1, h);
            lam[h + 1] = c - mu[h];
            mu[h + 1] = c - lam[h];
        } else {
            // Remark 1(b).
            mu[h + 1] = binomial(n + 1, h + 1) - lam[h + 1];
        }
        (lam, mu)
    }

    /// For each i = 0..=n, the pair (p_i, q_i) with l_{i,n}(t) = (p_i + q_i t) t^i (1−t)^{n−i}.
    /// Lengths must already be valid.
    fn factors(&self, n: usize) -> Vec<(f64, f64)> {
        let (lam, mu) = self.full(n);
        let w = self.omega;
        let mut pq = vec![(0.0, 0.0); n + 1];
        // Second line first, so that for even n the middle index ends up with the first
        // line's form (the two agree under Remark 1(a)).
        for j in 0..=n / 2 {
            let (cn, cn1) = (binomial(n, j), binomial(n + 1, j));
            pq[n - j] = (cn + (mu[j + 1] - cn) * w, -(mu[j] + mu[j + 1] - cn1) * w);
        }
        for j in 0..=n / 2 {
            let (cn, cn1) = (binomial(n, j), binomial(n + 1, j));
            pq[j] = (
                cn + (cn1 - cn - lam[j]) * w,
                (lam[j] + lam[j + 1] - cn1) * w,
            );
        }
        pq
    }
}

/// Writes the n + 1 SG-Bernstein basis values l_{0,n}(t)..l_{n,n}(t) into `out`.
///
/// Errors (leaving `out` untouched) when the shape's lengths do not fit degree `n`, a
/// parameter is not finite, or `out.len() != n + 1`.
pub fn sg_basis(n: usize, shape: &SgShape, t: f64, out: &mut [f64]) -> Result<(), SgError> {
    shape.validate(n)?;
    if out.len() != n + 1 {
        return Err(SgError::OutputLen {
            degree: n,
            expected: n + 1,
            got: out.len(),
        });
    }
    let s = 1.0 - t;
    for (i, (p, q)) in shape.factors(n).into_iter().enumerate() {
        out[i] = (p + q * t) * t.powi(i as i32) * s.powi((n - i) as i32);
    }
    Ok(())
}

/// The exact coefficients of every SG-Bernstein function in the Bernstein basis of degree
/// n + 1: row i holds the n + 2 coefficients of l_{i,n}, so
/// l_{i,n}(t) = Σ_k row_i\[k\] C(n+1,k) t^k (1−t)^{n+1−k}. Only entries i and i + 1 of row i
/// are nonzero.
pub fn sg_to_bernstein(n: usize, shape: &SgShape) -> Result<Vec<Vec<f64>>, SgError> {
    shape.validate(n)?;
    Ok(shape
        .factors(n)
        .into_iter()
        .enumerate()
        .map(|(i, (p, q))| {
            // (p + q t) t^i (1−t)^{n−i} = p t^i (1−t)^{n+1−i} + (p + q) t^{i+1} (1−t)^{n−i}.
            let mut row = vec![0.0; n + 2];
            row[i] = p / binomial(n + 1, i);
            row[i + 1] = (p + q) / binomial(n + 1, i + 1);
            row
        })
        .collect())
}

/// An SG-Bézier curve of degree n = `points.len() − 1` (Definition 2):
/// L(t) = Σ_j P_j l_{j,n}(t), t ∈ [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub struct SgBezier {
    /// The control points P_0..P_n.
    pub points: Vec<Point>,
    /// The shape parameters, with lengths for degree n.
    pub shape: SgShape,
}

impl SgBezier {
    /// A curve from its control points and shape; errors if there are no points or the
    /// shape does not fit degree `points.len() − 1`.
    pub fn new(points: Vec<Point>, shape: SgShape) -> Result<Self, SgError> {
        if points.is_empty() {
            return Err(SgError::NoPoints);
        }
        shape.validate(points.len() - 1)?;
        Ok(SgBezier { points, shape })
    }

    /// The plain Bézier curve on `points` as an SG-Bézier curve (ω = 0, see
    /// [`SgShape::bezier`]).
    pub fn from_bezier(points: Vec<Point>) -> Result<Self, SgError> {
        let n = points.len().saturating_sub(1);
        Self::new(points, SgShape::bezier(n))
    }

    /// The degree n (number of control points minus one).
    pub fn degree(&self) -> usize {
        self.points.len().saturating_sub(1)
    }

    /// Checks that the (public, hence mutable) fields are still consistent.
    pub fn validate(&self) -> Result<(), SgError> {
        if self.points.is_empty() {
            return Err(SgError::NoPoints);
        }
        self.shape.validate(self.degree())
    }

    /// The point at parameter `t`.
    ///
    /// # Panics
    ///
    /// If the public fields were changed so that they no longer fit each other (use
    /// [`validate`](Self::validate) or [`try_eval`](Self::try_eval) when in doubt).
    pub fn eval(&self, t: f64) -> Point {
        self.try_eval(t)
            .expect("SgBezier fields inconsistent: shape lengths do not match the degree")
    }

    /// The point at parameter `t`, or the reason the fields are inconsistent.
    pub fn try_eval(&self, t: f64) -> Result<Point, SgError> {
        if self.points.is_empty() {
            return Err(SgError::NoPoints);
        }
        let n = self.degree();
        let mut b = vec![0.0; n + 1];
        sg_basis(n, &self.shape, t, &mut b)?;
        Ok(self
            .points
            .iter()
            .zip(&b)
            .fold(Point::ZERO, |acc, (&p, &w)| acc + p * w))
    }

    /// The same curve as a polynomial Bézier curve of degree n + 1: its n + 2 control
    /// points in the Bernstein basis of degree n + 1 (from [`sg_to_bernstein`]).
    pub fn to_bernstein(&self) -> Result<Vec<Point>, SgError> {
        self.validate()?;
        let n = self.degree();
        let rows = sg_to_bernstein(n, &self.shape)?;
        let mut q = vec![Point::ZERO; n + 2];
        for (p, row) in self.points.iter().zip(&rows) {
            for (qk, &c) in q.iter_mut().zip(row) {
                *qk += *p * c;
            }
        }
        Ok(q)
    }
}

/// Points from the SG-Bernstein basis, derivatives from the curve's Bernstein form of
/// degree n + 1 ([`SgBezier::to_bernstein`]); a curve whose shape does not fit its degree
/// (which [`SgBezier::new`] refuses) gives NaN.
impl ParamCurve for SgBezier {
    fn point(&self, t: f64) -> Point {
        self.try_eval(t).unwrap_or(Point::new(f64::NAN, f64::NAN))
    }

    fn derivative(&self, t: f64) -> Point {
        match self.to_bernstein() {
            Ok(q) => bezier_derivative(&q, t),
            Err(_) => Point::new(f64::NAN, f64::NAN),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic test inputs from the project's seeded generator.
    struct Rng(rand_chacha::ChaCha8Rng);
    impl Rng {
        fn seeded(seed: u64) -> Self {
            Rng(rand::SeedableRng::seed_from_u64(seed))
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * rand::RngExt::random::<f64>(&mut self.0)
        }
    }

    /// Random shape for degree n: ω in [lo_w, hi_w], λ_j, μ_j in [0, C(n+1,j)].
    fn random_shape(rng: &mut Rng, n: usize, lo_w: f64, hi_w: f64) -> SgShape {
        let omega = rng.range(lo_w, hi_w);
        let lambda = (1..=SgShape::lambda_len(n))
            .map(|j| rng.range(0.0, binomial(n + 1, j)))
            .collect();
        let mu = (1..=SgShape::mu_len(n))
            .map(|j| rng.range(0.0, binomial(n + 1, j)))
            .collect();
        SgShape::new(n, omega, lambda, mu).unwrap()
    }

    /// Bernstein basis of degree n by the de Casteljau-style triangle (independent of
    /// `binom` and of `powi`).
    fn bernstein_triangle(n: usize, t: f64) -> Vec<f64> {
        let mut b = vec![1.0];
        for _ in 0..n {
            let mut nb = vec![0.0; b.len() + 1];
            for (k, &v) in b.iter().enumerate() {
                nb[k] += (1.0 - t) * v;
                nb[k + 1] += t * v;
            }
            b = nb;
        }
        b
    }

    fn ts() -> Vec<f64> {
        (0..=200).map(|i| i as f64 / 200.0).collect()
    }

    #[test]
    fn free_parameter_counts_match_table_1() {
        // n + 1 parameters in all: ω plus n local ones (Remark 3).
        for n in 0..12 {
            assert_eq!(SgShape::lambda_len(n) + SgShape::mu_len(n), n);
        }
        assert_eq!((SgShape::lambda_len(6), SgShape::mu_len(6)), (3, 3));
        assert_eq!((SgShape::lambda_len(7), SgShape::mu_len(7)), (4, 3));
    }

    #[test]
    fn partition_of_unity() {
        let mut rng = Rng::seeded(1);
        for n in 1..=10 {
            let mut b = vec![0.0; n + 1];
            for (lo, hi) in [(0.0, 1.0), (-1.0, 1.0)] {
                for _ in 0..20 {
                    let s = random_shape(&mut rng, n, lo, hi);
                    for t in ts() {
                        sg_basis(n, &s, t, &mut b).unwrap();
                        let sum: f64 = b.iter().sum();
                        assert!((sum - 1.0).abs() < 1e-14, "n={n} t={t} {s:?}: sum {sum}");
                    }
                }
            }
        }
    }

    #[test]
    fn omega_zero_is_bernstein() {
        let mut rng = Rng::seeded(2);
        for n in 0..=10 {
            let mut b = vec![0.0; n + 1];
            for _ in 0..10 {
                let s = random_shape(&mut rng, n, 0.0, 0.0);
                assert_eq!(s.omega, 0.0);
                for t in ts() {
                    sg_basis(n, &s, t, &mut b).unwrap();
                    let e = bernstein_triangle(n, t);
                    for i in 0..=n {
                        assert!((b[i] - e[i]).abs() < 1e-15, "n={n} i={i} t={t}");
                    }
                }
            }
        }
    }

    #[test]
    fn mirror_symmetry_when_mu_equals_lambda() {
        // μ_j = λ_j for j ≤ h; for odd n also μ_{h+1} = λ_{h+1}, which Remark 1(b) allows
        // only with λ_{h+1} = C(n+1,h+1)/2.
        let mut rng = Rng::seeded(3);
        for n in 1..=10 {
            let h = n / 2;
            let mut a = vec![0.0; n + 1];
            let mut b = vec![0.0; n + 1];
            for _ in 0..10 {
                let mut s = random_shape(&mut rng, n, -1.0, 1.0);
                s.mu = s.lambda[..h].to_vec();
                if n % 2 == 1 {
                    s.lambda[h] = 0.5 * binomial(n + 1, h + 1);
                }
                for t in ts() {
                    sg_basis(n, &s, t, &mut a).unwrap();
                    sg_basis(n, &s, 1.0 - t, &mut b).unwrap();
                    for j in 0..=n {
                        assert!(
                            (a[n - j] - b[j]).abs() < 1e-13,
                            "n={n} j={j} t={t}: {} vs {}",
                            a[n - j],
                            b[j]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn even_middle_lines_agree() {
        // For even n both lines of Definition 1 define l_{h,n}; under Remark 1(a) they agree.
        let mut rng = Rng::seeded(4);
        for n in (2..=10).step_by(2) {
            let h = n / 2;
            for _ in 0..10 {
                let s = random_shape(&mut rng, n, -1.0, 1.0);
                let (lam, mu) = s.full(n);
                let (cn, cn1, w) = (binomial(n, h), binomial(n + 1, h), s.omega);
                let first = (
                    cn + (cn1 - cn - lam[h]) * w,
                    (lam[h] + lam[h + 1] - cn1) * w,
                );
                let second = (cn + (mu[h + 1] - cn) * w, -(mu[h] + mu[h + 1] - cn1) * w);
                assert!((first.0 - second.0).abs() < 1e-12, "n={n}");
                assert!((first.1 - second.1).abs() < 1e-12, "n={n}");
            }
        }
    }

    #[test]
    fn bernstein_form_reproduces_basis() {
        let mut rng = Rng::seeded(5);
        for n in 0..=10 {
            let mut b = vec![0.0; n + 1];
            for _ in 0..10 {
                let s = random_shape(&mut rng, n, -1.0, 1.0);
                let rows = sg_to_bernstein(n, &s).unwrap();
                assert_eq!(rows.len(), n + 1);
                for t in ts() {
                    sg_basis(n, &s, t, &mut b).unwrap();
                    let e = bernstein_triangle(n + 1, t);
                    for i in 0..=n {
                        assert_eq!(rows[i].len(), n + 2);
                        // e[k] = C(n+1,k) t^k (1−t)^{n+1−k}.
                        let v2: f64 = rows[i].iter().zip(&e).map(|(c, e)| c * e).sum();
                        assert!((v2 - b[i]).abs() < 1e-13, "n={n} i={i} t={t}");
                    }
                }
            }
        }
    }

    #[test]
    fn omega_zero_curve_is_bezier() {
        let mut rng = Rng::seeded(6);
        for n in 1..=10 {
            let pts: Vec<Point> = (0..=n)
                .map(|_| Point::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)))
                .collect();
            let s = random_shape(&mut rng, n, 0.0, 0.0);
            let c = SgBezier::new(pts.clone(), s).unwrap();
            assert_eq!(c.degree(), n);
            for t in ts() {
                // de Casteljau.
                let mut q = pts.clone();
                for r in 1..=n {
                    for k in 0..=n - r {
                        q[k] = q[k].lerp(q[k + 1], t);
                    }
                }
                let p = c.eval(t);
                assert!(p.distance(q[0]) < 1e-13, "n={n} t={t}");
            }
        }
    }

    #[test]
    fn curve_bernstein_form_matches_eval() {
        let mut rng = Rng::seeded(7);
        for n in 1..=8 {
            let pts: Vec<Point> = (0..=n)
                .map(|_| Point::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)))
                .collect();
            let c = SgBezier::new(pts, random_shape(&mut rng, n, 0.0, 1.0)).unwrap();
            let q = c.to_bernstein().unwrap();
            assert_eq!(q.len(), n + 2);
            for t in ts() {
                let e = bernstein_triangle(n + 1, t);
                let p = q
                    .iter()
                    .zip(&e)
                    .fold(Point::ZERO, |acc, (&p, &w)| acc + p * w);
                assert!(p.distance(c.eval(t)) < 1e-12, "n={n} t={t}");
            }
        }
    }

    #[test]
    fn bad_lengths_are_errors() {
        assert_eq!(
            SgShape::new(6, 0.5, vec![1.0; 4], vec![1.0; 3]),
            Err(SgError::LambdaLen {
                degree: 6,
                expected: 3,
                got: 4
            })
        );
        assert_eq!(
            SgShape::new(7, 0.5, vec![1.0; 4], vec![1.0; 4]),
            Err(SgError::MuLen {
                degree: 7,
                expected: 3,
                got: 4
            })
        );
        assert_eq!(
            SgShape::new(3, f64::NAN, vec![1.0; 2], vec![1.0]),
            Err(SgError::NonFinite)
        );
        let good = SgShape::new(4, 0.5, vec![1.0; 2], vec![1.0; 2]).unwrap();
        let mut out = [0.0; 5];
        assert!(sg_basis(5, &good, 0.5, &mut out[..]).is_err());
        assert!(matches!(
            sg_basis(4, &good, 0.5, &mut out[..4]),
            Err(SgError::OutputLen { .. })
        ));
        assert!(sg_to_bernstein(3, &good).is_err());
        assert!(matches!(
            SgBezier::new(vec![Point::ZERO; 4], good.clone()),
            Err(SgError::MuLen { .. })
        ));
        assert_eq!(SgBezier::new(vec![], good.clone()), Err(SgError::NoPoints));
        let mut c = SgBezier::new(vec![Point::ZERO; 5], good).unwrap();
        c.points.pop();
        assert!(c.try_eval(0.5).is_err());
        assert!(c.to_bernstein().is_err());
    }

    #[test]
    fn paper_bounds() {
        // Example 5.1's curve: n = 6, ω = 0, λ_j = μ_j = 3.
        let s = SgShape::new(6, 0.0, vec![3.0; 3], vec![3.0; 3]).unwrap();
        assert!(s.within_paper_bounds(6));
        // Derived λ_4 = C(7,3) − μ_3 = 32 ≤ 35 is fine; λ_1 = 8 > C(7,1) = 7 is not.
        let s = SgShape::new(6, 0.0, vec![8.0, 3.0, 3.0], vec![3.0; 3]).unwrap();
        assert!(!s.within_paper_bounds(6));
        let s = SgShape::new(6, 1.5, vec![3.0; 3], vec![3.0; 3]).unwrap();
        assert!(!s.within_paper_bounds(6));
        assert!(SgShape::bezier(7).within_paper_bounds(7));
    }

    #[test]
    fn sg_bezier_answers_point_derivative_and_nearest() {
        let quintic = vec![
            Point::new(0.0, 0.0),
            Point::new(0.5, 1.5),
            Point::new(1.5, 2.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, -1.0),
            Point::new(4.0, 1.0),
        ];
        let mut shape = SgShape::bezier(5);
        shape.omega = 0.7;
        shape.lambda[0] = 1.0;
        shape.mu[1] = 4.0;
        let sg = SgBezier::new(quintic, shape).unwrap();
        outlinefit::curve::check_param_curve(&sg, "SG-Bézier");
    }
}
