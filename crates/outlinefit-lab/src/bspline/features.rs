//! Feature points of a parametric curve from its curvature (Algorithm 1 of the
//! fireworks curve-to-B-spline paper, `shared/papers/fireworks-curve-to-bspline.txt`).
//!
//! The curvature κ(u) is evaluated exactly (symbolic derivatives, see
//! [`ParametricCurve::curvature`]) on a uniform grid of the parameter range. Then, as in
//! Algorithm 1:
//!
//! * **Inflections**: a grid value κᵢ = 0 with κᵢ₋₁·κᵢ₊₁ < 0 is one; otherwise a sign
//!   change κᵢ·κᵢ₊₁ < 0 is located by the root of the parabola through (uᵢ, κᵢ),
//!   (uᵢ₊½, κᵢ₊½), (uᵢ₊₁, κᵢ₊₁).
//! * **Extreme curvature**: a local maximum of |κ| at a grid point is located by the vertex
//!   of the parabola through the three neighbouring values. Algorithm 1 writes the test on
//!   the signed ρ (local minima included); only maxima of |κ| are kept here,
//!   because a minimum of |κ| is where the curve is flattest, the least informative place
//!   for a sample.
//!
//! Beyond the paper: the parabola estimate (error O(h²)–O(h³)) is then polished to machine
//! accuracy by a bracketed root search (Illinois) on κ for an inflection and on the exact
//! κ′ for an extremum, inside the grid cells that bracket it. Variations at round-off level
//! (κ of a circle or a line) are ignored: a sign change needs |κ| above 1e-10 of the
//! largest |κ| on the grid, a maximum must stand out from both neighbours by 1e-12 of its
//! value. Grid points where κ is undefined (r′ = 0, a cusp) are skipped.

use super::expr::ParametricCurve;
use serde::Serialize;

/// What kind of feature point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureKind {
    /// The curvature changes sign.
    Inflection,
    /// |κ| has a local maximum.
    ExtremeCurvature,
}

/// A feature point of a curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FeaturePoint {
    /// Curve parameter.
    pub u: f64,
    /// Inflection or extreme curvature.
    pub kind: FeatureKind,
    /// Signed curvature there.
    pub curvature: f64,
}

/// Default number of grid intervals over the parameter range.
pub const DEFAULT_GRID: usize = 1000;

/// The inflections and curvature maxima of `curve` strictly inside (a, b), sorted by u,
/// found on a grid of `intervals` ≥ 2 equal cells (see the module docs). Features closer
/// than 1e-9·(b − a) to an end are left out (the ends are samples anyway).
pub fn feature_points(
    curve: &ParametricCurve,
    a: f64,
    b: f64,
    intervals: usize,
) -> Vec<FeaturePoint> {
    let n = intervals.max(2);
    let h = (b - a) / n as f64;
    let grid = |i: usize| if i == n { b } else { a + i as f64 * h };
    let kappa: Vec<f64> = (0..=n).map(|i| curve.curvature(grid(i))).collect();
    let scale = kappa
        .iter()
        .filter(|k| k.is_finite())
        .fold(0.0f64, |m, k| m.max(k.abs()));
    if scale == 0.0 {
        return Vec::new();
    }
    let tiny = 1e-10 * scale;
    let mut out = Vec::new();
    let curvature = |u: f64| curve.curvature(u);
    // Inflections.
    for i in 0..n {
        let (k0, k1) = (kappa[i], kappa[i + 1]);
        if !(k0.is_finite() && k1.is_finite()) {
            continue;
        }
        if i > 0 && k0 == 0.0 {
            let km = kappa[i - 1];
            if km.is_finite() && km * k1 < 0.0 && km.abs().max(k1.abs()) > tiny {
                out.push((grid(i), FeatureKind::Inflection));
            }
            continue;
        }
        if k0 * k1 < 0.0 && k0.abs().max(k1.abs()) > tiny {
            let (u0, u1) = (grid(i), grid(i + 1));
            let um = 0.5 * (u0 + u1);
            let guess = parabola_root(u0, um, u1, k0, curvature(um), k1);
            out.push((
                bracketed_root(&curvature, u0, u1, k0, k1, guess),
                FeatureKind::Inflection,
            ));
        }
    }
    // Maxima of |κ|.
    let dabs = |u: f64| {
        let k = curve.curvature(u);
        k.signum() * curve.curvature_derivative(u)
    };
    for i in 1..n {
        let (am, a0, ap) = (kappa[i - 1].abs(), kappa[i].abs(), kappa[i + 1].abs());
        if !(am.is_finite() && a0.is_finite() && ap.is_finite()) || a0 == 0.0 {
            continue;
        }
        let margin = 1e-12 * a0;
        // `>` on the left and `≥` on the right so a two-point plateau counts once.
        if !(a0 > am + margin && a0 >= ap + margin) {
            continue;
        }
        let (u0, u1, u2) = (grid(i - 1), grid(i), grid(i + 1));
        let guess = parabola_vertex(u0, u1, u2, am, a0, ap);
        let (g0, g2) = (dabs(u0), dabs(u2));
        let u = if g0 > 0.0 && g2 < 0.0 {
            bracketed_root(&dabs, u0, u2, g0, g2, guess)
        } else {
            guess
        };
        out.push((u, FeatureKind::ExtremeCurvature));
    }
    let edge = 1e-9 * (b - a);
    let mut points: Vec<FeaturePoint> = out
        .into_iter()
        .filter(|(u, _)| u.is_finite() && *u > a + edge && *u < b - edge)
        .map(|(u, kind)| FeaturePoint {
            u,
            kind,
            curvature: curve.curvature(u),
        })
        .collect();
    points.sort_by(|p, q| p.u.total_cmp(&q.u));
    points.dedup_by(|q, p| (q.u - p.u).abs() <= edge);
    points
}

/// The root in [u0, u2] of the parabola through (u0, f0), (u1, f1), (u2, f2), f0·f2 < 0
/// (the paper's inflection step); the secant root if the parabola degenerates.
fn parabola_root(u0: f64, u1: f64, u2: f64, f0: f64, f1: f64, f2: f64) -> f64 {
    // Newton form: p(u) = f0 + d1 (u − u0) + d2 (u − u0)(u − u1).
    let d1 = (f1 - f0) / (u1 - u0);
    let d12 = (f2 - f1) / (u2 - u1);
    let d2 = (d12 - d1) / (u2 - u0);
    // In t = u − u0: d2 t² + (d1 − d2 (u1 − u0)) t + f0 = 0.
    let (qa, qb, qc) = (d2, d1 - d2 * (u1 - u0), f0);
    let secant = u0 - f0 * (u2 - u0) / (f2 - f0);
    let disc = qb * qb - 4.0 * qa * qc;
    if qa == 0.0 || disc < 0.0 {
        return secant;
    }
    let sq = disc.sqrt();
    // Numerically stable pair of roots.
    let q = -0.5 * (qb + qb.signum() * sq);
    let candidates = [q / qa, if q != 0.0 { qc / q } else { f64::NAN }];
    candidates
        .into_iter()
        .map(|t| u0 + t)
        .find(|u| *u >= u0 && *u <= u2)
        .unwrap_or(secant)
}

/// The vertex of the parabola through three points with u0 < u1 < u2 (the paper's
/// extreme-curvature step), clamped to [u0, u2]; u1 if the parabola degenerates.
fn parabola_vertex(u0: f64, u1: f64, u2: f64, f0: f64, f1: f64, f2: f64) -> f64 {
    let num = (u1 - u0).powi(2) * (f1 - f2) - (u1 - u2).powi(2) * (f1 - f0);
    let den = (u1 - u0) * (f1 - f2) - (u1 - u2) * (f1 - f0);
    if den == 0.0 || !den.is_finite() {
        return u1;
    }
    (u1 - 0.5 * num / den).clamp(u0, u2)
}

/// A root of `f` in [lo, hi] where f(lo) = flo and f(hi) = fhi have opposite signs,
/// to within a few ulps: the estimate `guess` first narrows the bracket, then the
/// Illinois variant of regula falsi (with bisection steps if it stalls).
fn bracketed_root(
    f: &dyn Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
    mut flo: f64,
    mut fhi: f64,
    guess: f64,
) -> f64 {
    if guess > lo && guess < hi {
        let fg = f(guess);
        if fg == 0.0 {
            return guess;
        }
        if fg.is_finite() {
            if fg.signum() == flo.signum() {
                lo = guess;
                flo = fg;
            } else {
                hi = guess;
                fhi = fg;
            }
        }
    }
    let tol = 4.0 * f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300);
    let mut side = 0i8;
    for iter in 0..200 {
        if hi - lo <= tol {
            break;
        }
        let mut m = (lo * fhi - hi * flo) / (fhi - flo);
        if iter % 8 == 7 || !(m > lo && m < hi) {
            m = 0.5 * (lo + hi);
        }
        let fm = f(m);
        if fm == 0.0 || !fm.is_finite() {
            return m;
        }
        if fm.signum() == flo.signum() {
            lo = m;
            flo = fm;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        } else {
            hi = m;
            fhi = fm;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        }
    }
    if flo.abs() < fhi.abs() {
        lo
    } else {
        hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipse_curvature_maxima_at_the_ends_of_the_major_axis() {
        // x = 2 cos 2πu, y = sin 2πu on [0.1, 1.1]: |κ| is largest where the curve meets
        // the major axis, u = 0.5 and 1.0; no inflection.
        let c = ParametricCurve::parse("2*cos(2*pi*u)", "sin(2*pi*u)").unwrap();
        let f = feature_points(&c, 0.1, 1.1, DEFAULT_GRID);
        assert_eq!(f.len(), 2, "{f:?}");
        for (p, want) in f.iter().zip([0.5, 1.0]) {
            assert_eq!(p.kind, FeatureKind::ExtremeCurvature);
            assert!((p.u - want).abs() < 1e-6, "{} vs {want}", p.u);
            assert!((p.curvature - 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn ellipse_maxima_at_awkward_grid_offsets() {
        // A grid that never hits the extremum: range [0.1234567, 0.9], grid of 997 cells.
        let c = ParametricCurve::parse("2*cos(2*pi*u)", "sin(2*pi*u)").unwrap();
        let f = feature_points(&c, 0.1234567, 0.9, 997);
        assert_eq!(f.len(), 1, "{f:?}");
        assert!((f[0].u - 0.5).abs() < 1e-9, "{}", f[0].u);
    }

    #[test]
    fn cubic_inflection_and_curvature_maxima() {
        // y = u³ − u over x = u: κ = 6u / (1 + (3u² − 1)²)^{3/2}; inflection at u = 0 (use
        // the range [−1, 1.3] so that 0 is not a grid point), |κ| maxima where
        // d/du [6u / (1 + (3u²−1)²)^{3/2}] = 0.
        let c = ParametricCurve::parse("u", "u^3 - u").unwrap();
        let f = feature_points(&c, -1.0, 1.3, 1000);
        let infl: Vec<_> = f
            .iter()
            .filter(|p| p.kind == FeatureKind::Inflection)
            .collect();
        assert_eq!(infl.len(), 1, "{f:?}");
        assert!(infl[0].u.abs() < 1e-12, "{}", infl[0].u);
        let ext: Vec<f64> = f
            .iter()
            .filter(|p| p.kind == FeatureKind::ExtremeCurvature)
            .map(|p| p.u)
            .collect();
        assert_eq!(ext.len(), 2, "{f:?}");
        // Reference maxima by a fine golden-section search on |κ| near each.
        for &u in &ext {
            let k = |v: f64| -c.curvature(v).abs();
            let (mut lo, mut hi) = (u - 0.01, u + 0.01);
            for _ in 0..200 {
                let m1 = lo + 0.382 * (hi - lo);
                let m2 = lo + 0.618 * (hi - lo);
                if k(m1) < k(m2) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            assert!(
                (u - 0.5 * (lo + hi)).abs() < 1e-6,
                "{u} vs {}",
                0.5 * (lo + hi)
            );
            // And the exact condition κ′ = 0 holds to round-off.
            assert!(c.curvature_derivative(u).abs() < 1e-9);
        }
        // Symmetry: the maxima are at ±u*.
        assert!((ext[0] + ext[1]).abs() < 1e-12);
    }

    #[test]
    fn inflection_exactly_on_a_grid_point_counts_once() {
        let c = ParametricCurve::parse("u", "u^3").unwrap();
        let f = feature_points(&c, -1.0, 1.0, 1000);
        let infl: Vec<_> = f
            .iter()
            .filter(|p| p.kind == FeatureKind::Inflection)
            .collect();
        assert_eq!(infl.len(), 1, "{f:?}");
        assert_eq!(infl[0].u, 0.0);
    }

    #[test]
    fn circles_and_lines_have_no_features() {
        let c = ParametricCurve::parse("cos(2*pi*u)", "sin(2*pi*u)").unwrap();
        assert!(feature_points(&c, 0.0, 1.0, 1000).is_empty());
        let c = ParametricCurve::parse("3*u + 1", "2 - u").unwrap();
        assert!(feature_points(&c, 0.0, 1.0, 1000).is_empty());
    }

    #[test]
    fn parabola_steps_of_the_paper() {
        // Exact for a parabola.
        let r = parabola_root(0.0, 0.5, 1.0, -0.25, 0.0, 0.75);
        assert!((r - 0.5).abs() < 1e-15);
        let v = parabola_vertex(0.0, 0.4, 1.0, 0.09, 0.01, 0.49);
        assert!((v - 0.3).abs() < 1e-14, "{v}");
    }
}
