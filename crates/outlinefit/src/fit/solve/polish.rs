//! The Levenberg–Marquardt polish over control points and weights together, on the true
//! (orthogonal) distances.

use super::model::FitSettings;
use super::model::LinearModel;
use crate::curve::rational::bernstein;
use crate::curve::rational::RationalCubic;
use crate::geom::Point;
use crate::linalg::{solve_augmented, Singular};

/// Sum of squared point-to-curve distances, re-projecting parameters from their current
/// values.
pub(super) fn orthogonal_objective(
    curve: &RationalCubic,
    points: &[Point],
    params: &mut [f64],
) -> f64 {
    let n = points.len();
    let mut e = 0.0;
    let power = curve.power_form();
    for i in 1..n - 1 {
        let u = power.project_quick(points[i], params[i], 4);
        params[i] = u;
        e += (power.eval(u) - points[i]).length_squared();
    }
    e
}

/// Levenberg–Marquardt on the orthogonal distances: a Gauss–Newton method over the linear
/// unknowns, the log weights and every data parameter together (orthogonal distance
/// regression). The parameters are eliminated by a Schur complement, so each iteration
/// solves one system of at most 6 × 6; steps are accepted only if the sum of squared
/// point-to-curve distances (after re-projection) decreases.
pub(super) fn polish(
    model: &LinearModel<'_>,
    start_curve: RationalCubic,
    params: &mut [f64],
    settings: &FitSettings,
) -> (RationalCubic, u64) {
    let points = model.points;
    let n_pts = points.len();
    let mut z = model.unknowns_of(&start_curve);
    let nz = z.n;
    let nv = nz + 2;
    let (wlo, whi) = (settings.weight_range.0.ln(), settings.weight_range.1.ln());
    let mut lw = [start_curve.weights[0].ln(), start_curve.weights[1].ln()];
    let mut curve = start_curve;
    let mut trial_params = params.to_vec();
    let mut obj = orthogonal_objective(&curve, points, params);
    let mut evals = 1u64;
    let mut mu = 1e-4;
    let bounded = model.bounded();
    for _ in 0..settings.polish_iterations {
        if obj <= 1e-26 {
            break;
        }
        // Per point: residual r_i, Jacobian in θ (2 × nv) and P'(u_i).
        let mut jtj = [[0.0; 6]; 6];
        let mut jtr = [0.0; 6];
        // Cross terms b_i = P'ᵀ J_i and tangential residuals, needed after the θ solve.
        let mut cross_sum = [[0.0; 6]; 6];
        let mut cross_rhs = [0.0; 6];
        let w = curve.weights;
        for i in 1..n_pts - 1 {
            let u = params[i];
            let jet = curve.jet(u);
            let r = jet.point - points[i];
            let b = bernstein(u);
            let (_, cols) = model.columns(&b, w);
            let mut jac = [Point::ZERO; 6];
            jac[..nz].copy_from_slice(&cols[..nz]);
            let d = b[0] + b[1] * w[0] + b[2] * w[1] + b[3];
            for k in 0..2 {
                // ∂P/∂ln w_k = w_k B_k (C_k − P) / D.
                jac[nz + k] = (curve.points[k + 1] - jet.point) * (w[k] * b[k + 1] / d);
            }
            // A parameter held at an end of [0, 1] is treated as fixed: its point then pulls
            // with its full residual, not only the normal part.
            let pinned = u <= 0.0 || u >= 1.0;
            let a_i = jet.d1.length_squared() * (1.0 + mu) + 1e-300;
            let mut bi = [0.0; 6];
            if !pinned {
                for c in 0..nv {
                    bi[c] = jet.d1.dot(jac[c]);
                }
            }
            let tr = jet.d1.dot(r);
            for c in 0..nv {
                jtr[c] += jac[c].dot(r);
                cross_rhs[c] += bi[c] * tr / a_i;
                for e in c..nv {
                    jtj[c][e] += jac[c].dot(jac[e]);
                    cross_sum[c][e] += bi[c] * bi[e] / a_i;
                }
            }
        }
        for c in 0..nv {
            for e in 0..c {
                jtj[c][e] = jtj[e][c];
                cross_sum[c][e] = cross_sum[e][c];
            }
        }
        let mut improved = false;
        for _ in 0..8 {
            let mut m = [[0.0; 6]; 6];
            let mut g = [0.0; 6];
            for c in 0..nv {
                for e in 0..nv {
                    m[c][e] = jtj[c][e] - cross_sum[c][e];
                }
                g[c] = jtr[c] - cross_rhs[c];
            }
            // Damp with the reduced diagonal: the parameters absorb most of the tangential
            // motion, so the reduced system can be far smaller than JᵀJ.
            for c in 0..nv {
                m[c][c] += mu * m[c][c].abs().max(1e-18);
            }
            let mut system = [[0.0; 7]; 6];
            for i in 0..nv {
                system[i][..nv].copy_from_slice(&m[i][..nv]);
                system[i][6] = g[i];
            }
            let Some(delta) = solve_augmented(&mut system, nv, Singular::Fail) else {
                break;
            };
            let mut z_new = z;
            for j in 0..nz {
                z_new.z[j] -= delta[j];
            }
            for idx in bounded.into_iter().flatten() {
                z_new.z[idx] = z_new.z[idx].clamp(model.len_bounds.0, model.len_bounds.1);
            }
            let lw_new = [
                (lw[0] - delta[nz]).clamp(wlo, whi),
                (lw[1] - delta[nz + 1]).clamp(wlo, whi),
            ];
            let cand = model.curve(&z_new, [lw_new[0].exp(), lw_new[1].exp()]);
            // Parameter update from the eliminated block, then re-projection.
            for i in 1..n_pts - 1 {
                let u = params[i];
                if u <= 0.0 || u >= 1.0 {
                    trial_params[i] = u;
                    continue;
                }
                let jet = curve.jet(u);
                let r = jet.point - points[i];
                let b = bernstein(u);
                let (_, cols) = model.columns(&b, w);
                let dd = b[0] + b[1] * w[0] + b[2] * w[1] + b[3];
                let mut bd = 0.0;
                for j in 0..nz {
                    bd += jet.d1.dot(cols[j]) * delta[j];
                }
                for k in 0..2 {
                    let dp = (curve.points[k + 1] - jet.point) * (w[k] * b[k + 1] / dd);
                    bd += jet.d1.dot(dp) * delta[nz + k];
                }
                let a_i = jet.d1.length_squared() * (1.0 + mu) + 1e-300;
                trial_params[i] = (u - (jet.d1.dot(r) - bd) / a_i).clamp(0.0, 1.0);
            }
            let o = orthogonal_objective(&cand, points, &mut trial_params);
            evals += 1;
            if o < obj {
                let rel = (obj - o) / obj.max(1e-300);
                obj = o;
                z = z_new;
                lw = lw_new;
                curve = cand;
                params.copy_from_slice(&trial_params);
                mu = (mu * 0.2).max(1e-15);
                improved = rel > settings.polish_tolerance;
                break;
            }
            mu *= 10.0;
        }
        if !improved {
            break;
        }
    }
    (curve, evals)
}
