//! Parameter correction: the classical geometric answer to the nonlinear half of the
//! problem, which the paper does not try.
//!
//! Start from the centripetal parameters; then alternate (1) the least-squares poles for
//! the current parameters with (2) new parameters that minimise the error against the
//! current surface, until Y stops falling. Step (2) is a safeguarded Newton iteration:
//! for unorganized points the foot point of each point on the surface, by Newton on
//! (u, v); on an organized grid, where all points of a row share one τ and all points of a
//! column one ζ, the τ of each row minimising that row's squared distances, then likewise
//! each column's ζ, by one-dimensional Newton. Both steps lower Y, so Y falls
//! monotonically.
//!
//! Alternation converges linearly and slows near the optimum. On a grid the unknowns are
//! few (the interior row and column parameters; the first and last rows and columns keep
//! 0 and 1 as in the classical rules, which makes the answer unique: without them any
//! sub-patch of the surface would fit as well), so a Levenberg–Marquardt polish on the
//! variable-projection functional (the residual with the poles eliminated by least
//! squares, Golub–Pereyra) follows and converges quadratically on exact data.

use super::bezier::{axpy, dot, sub, BezierSurface, P3};
use super::data::{Params, PointCloud};
use super::solve::Fitter;
use nalgebra::{DMatrix, DVector};
use outlinefit::curve::basis::{bernstein, bernstein_jet};

/// Most alternation rounds.
/// Most alternation rounds on a grid (the polish follows) and for unorganized points.
const MAX_ROUNDS: [usize; 2] = [30, 1500];
/// Alternation stops when a round lowers Y by less than this fraction: on a grid, and for
/// unorganized points.
const MIN_GAIN: [f64; 2] = [1e-4, 1e-7];
/// Most Levenberg–Marquardt iterations of the grid polish.
const MAX_LM: usize = 100;
/// Newton steps of a foot point per alternation round (the next round's poles move the
/// surface anyway).
const NEWTON_STEPS: usize = 1;
/// Levenberg–Marquardt stops when an iteration lowers Y by less than this fraction.
const LM_GAIN: f64 = 1e-8;

/// What a correction did.
pub(crate) struct Correction {
    /// The corrected parameters.
    pub params: Params,
    /// Alternation rounds plus polish iterations that lowered Y.
    pub rounds: usize,
}

/// Corrects `start` for `cloud` (see the module docs).
pub(crate) fn correct(fitter: &Fitter, cloud: &PointCloud, start: Params) -> Correction {
    let mut params = start;
    let mut surface = fitter.surface(&params);
    let mut y = fitter.error(&surface, &params);
    let mut rounds = 0;
    let kind = usize::from(cloud.grid.is_none());
    while rounds < MAX_ROUNDS[kind] && y > 0.0 {
        let mut next = params.clone();
        match cloud.grid {
            Some((m, n)) => {
                refine_grid(&surface, cloud, (m, n), &mut next, Lines::Rows);
                refine_grid(&surface, cloud, (m, n), &mut next, Lines::Columns);
            }
            None => {
                for (k, d) in cloud.points.iter().enumerate() {
                    let (u, v) = foot_point(&surface, d, next.tau[k], next.zeta[k]);
                    next.tau[k] = u;
                    next.zeta[k] = v;
                }
            }
        }
        let s2 = fitter.surface(&next);
        let y2 = fitter.error(&s2, &next);
        if y2.is_nan() || y2 >= y {
            break;
        }
        let gain = (y - y2) / y;
        (params, surface, y) = (next, s2, y2);
        rounds += 1;
        if gain < MIN_GAIN[kind] {
            break;
        }
    }
    if let Some((m, n)) = cloud.grid {
        rounds += polish_grid(fitter, m, n, &mut params);
    }
    Correction { params, rounds }
}

/// The parameter t ∈ [0, 1] minimising Σ_k ‖target(k) − C_k(t)‖², from `t0`, where C_k is
/// the Bézier curve of degree `deg` with control points `ctrl[k * (deg + 1)..][..deg + 1]`.
fn refine_line(
    deg: usize,
    ctrl: &[P3],
    count: usize,
    target: impl Fn(usize) -> P3,
    t0: f64,
) -> f64 {
    let k1 = deg + 1;
    let (mut b, mut d1, mut d2) = ([0.0; 32], [0.0; 32], [0.0; 32]);
    let value = |t: f64, b: &mut [f64; 32]| {
        bernstein(deg, t, b);
        (0..count)
            .map(|k| {
                let mut c = [0.0; 3];
                for i in 0..k1 {
                    axpy(&mut c, b[i], &ctrl[k * k1 + i]);
                }
                let r = sub(&target(k), &c);
                dot(&r, &r)
            })
            .sum::<f64>()
    };
    let mut t = t0;
    let mut f = value(t, &mut b);
    for _ in 0..3 {
        bernstein_jet(deg, t, &mut b, &mut d1, &mut d2);
        let (mut g, mut h, mut gn) = (0.0, 0.0, 0.0);
        for k in 0..count {
            let (mut c, mut c1, mut c2) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            for i in 0..k1 {
                let p = &ctrl[k * k1 + i];
                axpy(&mut c, b[i], p);
                axpy(&mut c1, d1[i], p);
                axpy(&mut c2, d2[i], p);
            }
            let r = sub(&target(k), &c);
            g -= dot(&r, &c1);
            h += dot(&c1, &c1) - dot(&r, &c2);
            gn += dot(&c1, &c1);
        }
        let curvature = if h > 0.0 { h } else { gn };
        if curvature.is_nan() || curvature <= 0.0 || g == 0.0 {
            break;
        }
        let mut step = -g / curvature;
        let mut moved = false;
        for _ in 0..8 {
            let t1 = (t + step).clamp(0.0, 1.0);
            let f1 = value(t1, &mut b);
            if f1 < f {
                (t, f, moved) = (t1, f1, true);
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    t
}

/// Which parameters of a grid [`refine_grid`] moves.
#[derive(Clone, Copy, PartialEq)]
enum Lines {
    /// One τ per row.
    Rows,
    /// One ζ per column.
    Columns,
}

/// New interior row parameters τ_p (or column parameters ζ_q) against `surface`, the other
/// direction's parameters held.
fn refine_grid(
    surface: &BezierSurface,
    cloud: &PointCloud,
    (m, n): (usize, usize),
    params: &mut Params,
    lines: Lines,
) {
    let kv = surface.degree_v + 1;
    // Along the moved parameter: its degree, its values, the number of lines; across: the
    // held degree, values and count.
    let (deg, other_deg, other, count, across) = match lines {
        Lines::Rows => (surface.degree_u, surface.degree_v, &params.zeta, m, n),
        Lines::Columns => (surface.degree_v, surface.degree_u, &params.tau, n, m),
    };
    let pole = |along: usize, held: usize| match lines {
        Lines::Rows => &surface.poles[along * kv + held],
        Lines::Columns => &surface.poles[held * kv + along],
    };
    // One curve per crossing line, in the moved parameter: C_k[a] = Σ_h Λ(a, h) b_h(other_k).
    let mut ctrl = vec![[0.0; 3]; across * (deg + 1)];
    let mut b = [0.0; 32];
    for k in 0..across {
        bernstein(other_deg, other[k], &mut b);
        for a in 0..=deg {
            for h in 0..=other_deg {
                axpy(&mut ctrl[k * (deg + 1) + a], b[h], pole(a, h));
            }
        }
    }
    let point = |line: usize, k: usize| match lines {
        Lines::Rows => cloud.points[line * n + k],
        Lines::Columns => cloud.points[k * n + line],
    };
    for line in 1..count - 1 {
        let values = match lines {
            Lines::Rows => &mut params.tau,
            Lines::Columns => &mut params.zeta,
        };
        values[line] = refine_line(deg, &ctrl, across, |k| point(line, k), values[line]);
    }
}

/// The parameters in [0, 1]² of the point of `surface` nearest to `d`, from (u, v), by
/// safeguarded Newton steps (Gauss–Newton where the Hessian is not positive definite).
pub(crate) fn foot_point(surface: &BezierSurface, d: &P3, mut u: f64, mut v: f64) -> (f64, f64) {
    let dist2 = |u: f64, v: f64| {
        let r = sub(d, &surface.eval(u, v));
        dot(&r, &r)
    };
    let mut f = dist2(u, v);
    for _ in 0..NEWTON_STEPS {
        let j = surface.jet(u, v);
        let r = sub(d, &j.s);
        let (gu, gv) = (-dot(&r, &j.su), -dot(&r, &j.sv));
        let (a, b, c) = (dot(&j.su, &j.su), dot(&j.su, &j.sv), dot(&j.sv, &j.sv));
        let (mut h11, mut h12, mut h22) = (
            a - dot(&r, &j.suu),
            b - dot(&r, &j.suv),
            c - dot(&r, &j.svv),
        );
        if !(h11 > 0.0 && h11 * h22 - h12 * h12 > 0.0) {
            (h11, h12, h22) = (a, b, c);
        }
        let det = h11 * h22 - h12 * h12;
        if det.is_nan() || det <= 0.0 {
            break;
        }
        let mut du = -(h22 * gu - h12 * gv) / det;
        let mut dv = -(h11 * gv - h12 * gu) / det;
        let mut moved = false;
        for _ in 0..6 {
            let (u1, v1) = ((u + du).clamp(0.0, 1.0), (v + dv).clamp(0.0, 1.0));
            let f1 = dist2(u1, v1);
            if f1 < f {
                (u, v, f, moved) = (u1, v1, f1, true);
                break;
            }
            du *= 0.5;
            dv *= 0.5;
        }
        if !moved {
            break;
        }
    }
    (u, v)
}

/// Levenberg–Marquardt on the interior grid parameters with the poles eliminated by least
/// squares (variable projection with Kaufman's Jacobian −P⊥ ∂S/∂θ, P⊥ the projection onto
/// the complement of the collocation matrix's columns); returns the iterations that lowered
/// Y. Steps are solved by QR of the damped Jacobian, not by normal equations, whose squared
/// condition number would stall the iteration in the flat valleys of nearly equivalent
/// parameterizations.
fn polish_grid(fitter: &Fitter, m: usize, n: usize, params: &mut Params) -> usize {
    let free = (m - 2) + (n - 2);
    if free == 0 {
        return 0;
    }
    let mn = m * n;
    // Residual vector (coordinate-major: all x, then all y, then all z) at the
    // least-squares poles, and that surface.
    let residual = |p: &Params| -> (DVector<f64>, BezierSurface) {
        let s = fitter.surface(p);
        let r = fitter.residuals(&s, p);
        (DVector::from_fn(3 * mn, |i, _| r[i % mn][i / mn]), s)
    };
    let (mut r0, mut surface) = residual(params);
    let mut y0 = r0.norm_squared();
    let mut lambda: f64 = 1e-3;
    let mut improved = 0;
    for _ in 0..MAX_LM {
        if y0 == 0.0 {
            break;
        }
        // Orthonormal bases of the two Bernstein matrices: the collocation matrix is their
        // Kronecker product, so the projection onto its columns is X ↦ Q_u Q_uᵀ X Q_v Q_vᵀ
        // on each coordinate's residuals arranged as an m × n matrix X.
        let qu = super::solve::basis_matrix(surface.degree_u, &params.tau)
            .qr()
            .q();
        let qv = super::solve::basis_matrix(surface.degree_v, &params.zeta)
            .qr()
            .q();
        // −∂S/∂θ per coordinate, projected: J_c = P⊥ (−∂S_c/∂θ).
        let mut jac = DMatrix::zeros(3 * mn, free);
        for a in 0..m {
            for b in 0..n {
                let j = surface.jet(params.tau[a], params.zeta[b]);
                let row = a * n + b;
                for c in 0..3 {
                    if (1..m - 1).contains(&a) {
                        jac[(c * mn + row, a - 1)] = -j.su[c];
                    }
                    if (1..n - 1).contains(&b) {
                        jac[(c * mn + row, m - 2 + b - 1)] = -j.sv[c];
                    }
                }
            }
        }
        for col in 0..free {
            for c in 0..3 {
                let x = DMatrix::from_row_slice(
                    m,
                    n,
                    &jac.column(col).as_slice()[c * mn..(c + 1) * mn],
                );
                let inner = qu.tr_mul(&x) * &qv;
                let proj = &qu * inner * qv.transpose();
                for a in 0..m {
                    for b in 0..n {
                        jac[(c * mn + a * n + b, col)] -= proj[(a, b)];
                    }
                }
            }
        }
        let scale: Vec<f64> = (0..free).map(|k| jac.column(k).norm().max(1e-12)).collect();
        // ‖J δ + r‖² = ‖R δ + Qᵀ r‖² + const: one QR of J per iteration, then each damping
        // factor solves a small stacked problem.
        let qr = jac.qr();
        let r_mat = qr.r();
        let mut qtr = -&r0;
        qr.q_tr_mul(&mut qtr);
        let qtr = qtr.rows(0, free).into_owned();
        let mut accepted = false;
        for _ in 0..12 {
            // min ‖R δ − Qᵀ(−r)‖² + λ ‖diag(scale) δ‖², by QR of the stacked matrix.
            let mut aug = DMatrix::zeros(2 * free, free);
            aug.rows_mut(0, free).copy_from(&r_mat);
            for k in 0..free {
                aug[(free + k, k)] = lambda.sqrt() * scale[k];
            }
            let mut rhs = DVector::zeros(2 * free);
            rhs.rows_mut(0, free).copy_from(&qtr);
            let small = aug.qr();
            small.q_tr_mul(&mut rhs);
            let Some(delta) = small
                .r()
                .solve_upper_triangular(&rhs.rows(0, free).into_owned())
            else {
                lambda *= 4.0;
                continue;
            };
            let mut p1 = params.clone();
            for i in 0..free {
                let t = if i < m - 2 {
                    &mut p1.tau[i + 1]
                } else {
                    &mut p1.zeta[i - (m - 2) + 1]
                };
                *t = (*t + delta[i]).clamp(0.0, 1.0);
            }
            let (r1, s1) = residual(&p1);
            let y1 = r1.norm_squared();
            if y1 < y0 {
                let gain = (y0 - y1) / y0;
                (*params, surface, r0, y0) = (p1, s1, r1, y1);
                lambda = (lambda / 3.0).max(1e-15);
                accepted = true;
                improved += 1;
                if gain < LM_GAIN {
                    return improved;
                }
                break;
            }
            lambda *= 4.0;
        }
        if !accepted {
            break;
        }
    }
    improved
}
