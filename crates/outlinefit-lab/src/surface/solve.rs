//! The linear half of the problem: for given data parameters, the poles that minimise the
//! error functional Y (Eqs. 16–17), and Y itself.
//!
//! Organized grids are separable: with B_u the m × (η+1) matrix of Bernstein values at the
//! row parameters and B_v the n × (σ+1) one at the column parameters, the collocation
//! matrix of Eq. 16 is B_v ⊗ B_u, and the least-squares poles of each coordinate are
//! Λ = (B_uᵀB_u)⁻¹ B_uᵀ D B_v (B_vᵀB_v)⁻¹, two small Cholesky solves instead of one
//! (η+1)(σ+1)-square system. Unorganized points accumulate the normal equations of Eq. 17
//! point by point. Either way Y = ‖D‖² − ⟨Ξᵀ D, Λ⟩ at the optimum, which is what the
//! metaheuristics evaluate hundreds of thousands of times; reported errors are summed
//! point by point instead ([`Fitter::error`]), free of that formula's cancellation.
//!
//! When the normal matrix is singular or nearly so (parameters that bunch onto fewer
//! distinct values than the degree needs, as random parameters may), the poles come from
//! the Moore–Penrose pseudo-inverse by SVD, as in the paper (§5.3).

use super::bezier::{axpy, sub, BezierSurface, P3};
use super::data::{Params, PointCloud};
use nalgebra::{Cholesky, DMatrix, DMatrixView, Dyn};
use outlinefit::curve::basis::bernstein;

/// Smallest ratio of the smallest to the largest squared Cholesky pivot accepted before
/// falling back to the pseudo-inverse.
const PIVOT_RATIO: f64 = 1e-13;

/// Fits poles to one point cloud at a fixed degree.
pub(crate) struct Fitter<'a> {
    cloud: &'a PointCloud,
    degree: (usize, usize),
    /// ‖D‖², the sum of squared coordinates.
    norm2: f64,
    /// Grids only: the coordinates as three m × n matrices.
    grid_coords: Option<[DMatrix<f64>; 3]>,
}

/// The Bernstein values of degree `n` at each of `ts`, one row per parameter.
pub(crate) fn basis_matrix(n: usize, ts: &[f64]) -> DMatrix<f64> {
    let mut b = [0.0; 32];
    let mut m = DMatrix::zeros(ts.len(), n + 1);
    for (r, &t) in ts.iter().enumerate() {
        bernstein(n, t, &mut b);
        for c in 0..=n {
            m[(r, c)] = b[c];
        }
    }
    m
}

/// The products b_i b_j (i ≤ j) of one point's basis values, row by row of the upper
/// triangle, into `out` (of length n(n+1)/2 for n values).
fn pair_products(b: &[f64], out: &mut [f64]) {
    let mut rest = out;
    for (i, &bi) in b.iter().enumerate() {
        let (row, tail) = rest.split_at_mut(b.len() - i);
        for (o, &bj) in row.iter_mut().zip(&b[i..]) {
            *o = bi * bj;
        }
        rest = tail;
    }
}

/// Cholesky factor of a symmetric positive definite matrix, or `None` when it is singular
/// or too ill-conditioned to trust.
fn factor(m: DMatrix<f64>) -> Option<Cholesky<f64, Dyn>> {
    let chol = Cholesky::new(m)?;
    let d = chol.l_dirty().diagonal();
    let (lo, hi) = d.iter().fold((f64::INFINITY, 0f64), |(lo, hi), &x| {
        (lo.min(x * x), hi.max(x * x))
    });
    (lo > PIVOT_RATIO * hi && lo.is_finite()).then_some(chol)
}

impl<'a> Fitter<'a> {
    pub(crate) fn new(cloud: &'a PointCloud, degree: (usize, usize)) -> Self {
        let norm2 = cloud
            .points
            .iter()
            .map(|p| p.iter().map(|c| c * c).sum::<f64>())
            .sum();
        let grid_coords = cloud.grid.map(|(m, n)| {
            let coord = |c: usize| DMatrix::from_fn(m, n, |p, q| cloud.points[p * n + q][c]);
            [coord(0), coord(1), coord(2)]
        });
        Fitter {
            cloud,
            degree,
            norm2,
            grid_coords,
        }
    }

    fn ku(&self) -> usize {
        self.degree.0 + 1
    }

    fn kv(&self) -> usize {
        self.degree.1 + 1
    }

    /// The least-squares surface for `params`.
    pub(crate) fn surface(&self, params: &Params) -> BezierSurface {
        let poles = match self.normal_solution(params) {
            Some((poles, _)) => poles,
            None => self.pseudo_inverse_poles(params),
        };
        BezierSurface {
            degree_u: self.degree.0,
            degree_v: self.degree.1,
            poles,
        }
    }

    /// Y at the least-squares poles for `params`, by ‖D‖² − ⟨ΞᵀD, Λ⟩ (the fast form the
    /// searches use), or summed point by point when the normal equations are singular.
    pub(crate) fn objective(&self, params: &Params) -> f64 {
        match self.normal_solution(params) {
            Some((_, explained)) => (self.norm2 - explained).max(0.0),
            None => {
                let s = self.surface(params);
                self.error(&s, params)
            }
        }
    }

    /// Poles from the normal equations and ⟨ΞᵀD, Λ⟩, or `None` when they are singular.
    fn normal_solution(&self, params: &Params) -> Option<(Vec<P3>, f64)> {
        let (ku, kv) = (self.ku(), self.kv());
        let mut poles = vec![[0.0; 3]; ku * kv];
        let mut explained = 0.0;
        if let Some(coords) = &self.grid_coords {
            let bu = basis_matrix(self.degree.0, &params.tau);
            let bv = basis_matrix(self.degree.1, &params.zeta);
            let cu = factor(bu.tr_mul(&bu))?;
            let cv = factor(bv.tr_mul(&bv))?;
            for (c, d) in coords.iter().enumerate() {
                let e = bu.tr_mul(&(d * &bv)); // ku × kv
                let left = cu.solve(&e);
                let p = cv.solve(&left.transpose()).transpose();
                explained += e.dot(&p);
                for i in 0..ku {
                    for j in 0..kv {
                        poles[i * kv + j][c] = p[(i, j)];
                    }
                }
            }
        } else {
            // A = Σ_p (b_u b_uᵀ) ⊗ (b_v b_vᵀ): with U2 and V2 holding each point's products
            // b_u,i b_u,i′ (i ≤ i′) and b_v,j b_v,j′ (j ≤ j′), every entry of A is an entry of
            // W = U2ᵀ V2, one matrix product (441 instead of 666 products per point at
            // degree 5, and a blocked, vectorised kernel). Both are filled one point at a
            // time, contiguously, and handed to the kernel as strided views.
            let k = ku * kv;
            let (pu, pv) = (ku * (ku + 1) / 2, kv * (kv + 1) / 2);
            let n = self.cloud.points.len();
            let mut u2 = vec![0.0; n * pu];
            let mut v2 = vec![0.0; n * pv];
            // ΞᵀD, one row per pole, accumulated point by point in the order a
            // matrix–vector product would.
            let mut xd = vec![[0.0; 3]; k];
            let (mut bu, mut bv) = ([0.0; 32], [0.0; 32]);
            for (idx, (u2p, v2p)) in u2
                .chunks_exact_mut(pu)
                .zip(v2.chunks_exact_mut(pv))
                .enumerate()
            {
                let (bu, bv) = (&mut bu[..ku], &mut bv[..kv]);
                bernstein(self.degree.0, params.tau[idx], bu);
                bernstein(self.degree.1, params.zeta[idx], bv);
                pair_products(bu, u2p);
                pair_products(bv, v2p);
                let d = self.cloud.points[idx];
                for (&bi, row) in bu.iter().zip(xd.chunks_exact_mut(kv)) {
                    for (&bj, acc) in bv.iter().zip(row) {
                        let xi = bi * bj;
                        for (a, dc) in acc.iter_mut().zip(d) {
                            *a += xi * dc;
                        }
                    }
                }
            }
            let b = DMatrix::from_fn(k, 3, |r, c| xd[r][c]);
            // U2ᵀ is pu × n with one column per point; V2 is n × pv with one row per point.
            let u2t = DMatrixView::from_slice(&u2, pu, n);
            let v2m = DMatrixView::from_slice_with_strides(&v2, n, pv, pv, 1);
            let w = u2t * v2m;
            let pair = |a: usize, b: usize, size: usize| {
                let (a, b) = if a <= b { (a, b) } else { (b, a) };
                a * size - a * (a + 1) / 2 + b
            };
            let a = DMatrix::from_fn(k, k, |r, c| {
                let (i, j, i2, j2) = (r / kv, r % kv, c / kv, c % kv);
                w[(pair(i, i2, ku), pair(j, j2, kv))]
            });
            let chol = factor(a)?;
            let x = chol.solve(&b);
            for r in 0..k {
                for c in 0..3 {
                    poles[r][c] = x[(r, c)];
                    explained += x[(r, c)] * b[(r, c)];
                }
            }
        }
        poles
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
            .then_some((poles, explained))
    }

    /// Poles by the pseudo-inverse (SVD) of the collocation matrix: Λ = Ξ⁺ D.
    fn pseudo_inverse_poles(&self, params: &Params) -> Vec<P3> {
        let (ku, kv) = (self.ku(), self.kv());
        let mut poles = vec![[0.0; 3]; ku * kv];
        let eps = 1e-12;
        if let Some(coords) = &self.grid_coords {
            let bu = basis_matrix(self.degree.0, &params.tau);
            let bv = basis_matrix(self.degree.1, &params.zeta);
            let (Ok(pu), Ok(pv)) = (bu.pseudo_inverse(eps), bv.pseudo_inverse(eps)) else {
                return poles;
            };
            for (c, d) in coords.iter().enumerate() {
                let p = &pu * d * pv.transpose();
                for i in 0..ku {
                    for j in 0..kv {
                        poles[i * kv + j][c] = p[(i, j)];
                    }
                }
            }
        } else {
            let n = self.cloud.points.len();
            let (mut bu, mut bv) = ([0.0; 32], [0.0; 32]);
            let mut xi = DMatrix::zeros(n, ku * kv);
            for idx in 0..n {
                bernstein(self.degree.0, params.tau[idx], &mut bu);
                bernstein(self.degree.1, params.zeta[idx], &mut bv);
                for i in 0..ku {
                    for j in 0..kv {
                        xi[(idx, i * kv + j)] = bu[i] * bv[j];
                    }
                }
            }
            let Ok(pinv) = xi.pseudo_inverse(eps) else {
                return poles;
            };
            let d = DMatrix::from_fn(n, 3, |r, c| self.cloud.points[r][c]);
            let p = pinv * d;
            for (r, pole) in poles.iter_mut().enumerate() {
                *pole = [p[(r, 0)], p[(r, 1)], p[(r, 2)]];
            }
        }
        poles
    }

    /// The residual vector Δ − S(τ, ζ) of every point, in the cloud's order.
    pub(crate) fn residuals(&self, surface: &BezierSurface, params: &Params) -> Vec<P3> {
        let points = &self.cloud.points;
        match self.cloud.grid {
            Some((m, n)) => {
                // H = B_u Λ (m × kv), then S(τ_p, ζ_q) = Σ_j H[p][j] b_j(ζ_q).
                let kv = self.kv();
                let mut bu = [0.0; 32];
                let mut h = vec![[0.0; 3]; m * kv];
                for p in 0..m {
                    bernstein(self.degree.0, params.tau[p], &mut bu);
                    for i in 0..self.ku() {
                        for j in 0..kv {
                            axpy(&mut h[p * kv + j], bu[i], &surface.poles[i * kv + j]);
                        }
                    }
                }
                let bv = basis_matrix(self.degree.1, &params.zeta);
                let mut out = Vec::with_capacity(m * n);
                for p in 0..m {
                    for q in 0..n {
                        let mut s = [0.0; 3];
                        for j in 0..kv {
                            axpy(&mut s, bv[(q, j)], &h[p * kv + j]);
                        }
                        out.push(sub(&points[p * n + q], &s));
                    }
                }
                out
            }
            None => points
                .iter()
                .enumerate()
                .map(|(k, d)| sub(d, &surface.eval(params.tau[k], params.zeta[k])))
                .collect(),
        }
    }

    /// Y (Eq. 4 or 5) of `surface` at `params`, summed point by point.
    pub(crate) fn error(&self, surface: &BezierSurface, params: &Params) -> f64 {
        self.residuals(surface, params)
            .iter()
            .map(|r| r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
            .sum()
    }
}
