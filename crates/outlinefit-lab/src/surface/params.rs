//! The classical data parameterizations of §5.2: uniform (Eq. 11), chordal (Eq. 12) and
//! centripetal (Eq. 13).
//!
//! On an organized grid they are the paper's: each column gives row parameters τ_p^q by
//! accumulated chord lengths (or their square roots, or equal steps), each row gives
//! column parameters ζ_q^p, and τ_p, ζ_q are their averages over the columns and rows.
//!
//! Unorganized points have no order to accumulate chords along, and the paper does not say
//! how it applied the rules to its Example III. Here the points are projected onto their
//! principal plane (the two leading eigenvectors of their covariance) and the rules are
//! applied along each principal axis to the points sorted by their coordinate on it: τ from
//! the first axis, ζ from the second; uniform gives the k-th point in that order k/(κ−1),
//! chordal the accumulated gaps between consecutive projected coordinates (the normalised
//! coordinate itself) and centripetal the accumulated square roots of those gaps. This is
//! the usual base-plane parameterization of scattered data; it cannot unfold a surface
//! that folds over its principal plane, as Example III does.

use super::bezier::{sub, P3};
use super::data::{Params, PointCloud};

/// How consecutive gaps become parameter steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// Equal steps (Eq. 11).
    Uniform,
    /// Steps proportional to the gap (Eq. 12).
    Chordal,
    /// Steps proportional to the square root of the gap (Eq. 13).
    Centripetal,
}

impl Rule {
    fn step(self, gap: f64) -> f64 {
        match self {
            Rule::Uniform => 1.0,
            Rule::Chordal => gap,
            Rule::Centripetal => gap.sqrt(),
        }
    }
}

/// Parameters in [0, 1] from consecutive gaps: 0 first, 1 last, steps by `rule`; equal
/// steps when every gap is zero.
fn accumulate(rule: Rule, gaps: impl Iterator<Item = f64> + Clone, out: &mut [f64]) {
    let mut steps: Vec<f64> = gaps.map(|g| rule.step(g)).collect();
    let total: f64 = steps.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        steps.iter_mut().for_each(|s| *s = 1.0);
    }
    let total: f64 = steps.iter().sum();
    out[0] = 0.0;
    let mut acc = 0.0;
    for (k, s) in steps.iter().enumerate() {
        acc += s;
        out[k + 1] = acc / total;
    }
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
}

fn length(a: &P3, b: &P3) -> f64 {
    let d = sub(a, b);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The data parameters of `cloud` by `rule`.
pub fn classical(cloud: &PointCloud, rule: Rule) -> Params {
    match cloud.grid {
        Some((m, n)) => grid(&cloud.points, m, n, rule),
        None => scattered(&cloud.points, rule),
    }
}

fn grid(points: &[P3], m: usize, n: usize, rule: Rule) -> Params {
    let at = |p: usize, q: usize| &points[p * n + q];
    let mut tau = vec![0.0; m];
    let mut zeta = vec![0.0; n];
    let mut line = vec![0.0; m.max(n)];
    for q in 0..n {
        accumulate(
            rule,
            (1..m).map(|p| length(at(p, q), at(p - 1, q))),
            &mut line[..m],
        );
        tau.iter_mut()
            .zip(&line)
            .for_each(|(t, l)| *t += l / n as f64);
    }
    for p in 0..m {
        accumulate(
            rule,
            (1..n).map(|q| length(at(p, q), at(p, q - 1))),
            &mut line[..n],
        );
        zeta.iter_mut()
            .zip(&line)
            .for_each(|(z, l)| *z += l / m as f64);
    }
    // Averages of values that are exactly 0 and 1 at the ends stay so up to rounding.
    tau[0] = 0.0;
    tau[m - 1] = 1.0;
    zeta[0] = 0.0;
    zeta[n - 1] = 1.0;
    Params { tau, zeta }
}

/// Coordinates of the points on their two principal axes.
pub(crate) fn principal_coordinates(points: &[P3]) -> (Vec<f64>, Vec<f64>) {
    let n = points.len() as f64;
    let mut c = [0.0; 3];
    for p in points {
        for k in 0..3 {
            c[k] += p[k] / n;
        }
    }
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    for p in points {
        let d = nalgebra::Vector3::from(sub(p, &c));
        cov += d * d.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let axis = |k: usize| eig.eigenvectors.column(order[k]).into_owned();
    let (a1, a2) = (axis(0), axis(1));
    let project = |a: &nalgebra::Vector3<f64>| {
        points
            .iter()
            .map(|p| a.dot(&nalgebra::Vector3::from(sub(p, &c))))
            .collect::<Vec<f64>>()
    };
    (project(&a1), project(&a2))
}

fn scattered(points: &[P3], rule: Rule) -> Params {
    let (s, t) = principal_coordinates(points);
    let along = |coord: &[f64]| {
        let mut order: Vec<usize> = (0..coord.len()).collect();
        order.sort_by(|&a, &b| coord[a].total_cmp(&coord[b]).then(a.cmp(&b)));
        let mut sorted = vec![0.0; coord.len()];
        accumulate(
            rule,
            order.windows(2).map(|w| coord[w[1]] - coord[w[0]]),
            &mut sorted,
        );
        let mut out = vec![0.0; coord.len()];
        for (rank, &k) in order.iter().enumerate() {
            out[k] = sorted[rank];
        }
        out
    };
    Params {
        tau: along(&s),
        zeta: along(&t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_rules_follow_the_equations() {
        // A 3 × 4 grid whose rows are spaced 1 and 3 apart and columns 1, 1 and 4 apart:
        // chordal τ = (0, 1/4, 1), ζ = (0, 1/6, 2/6, 1); centripetal uses square roots.
        let xs = [0.0, 1.0, 2.0, 6.0];
        let ys = [0.0, 1.0, 4.0];
        let points: Vec<P3> = ys
            .iter()
            .flat_map(|&y| xs.iter().map(move |&x| [x, y, 0.0]))
            .collect();
        let cloud = PointCloud {
            points,
            grid: Some((3, 4)),
        };
        let c = classical(&cloud, Rule::Chordal);
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15);
        assert!(close(&c.tau, &[0.0, 0.25, 1.0]), "{:?}", c.tau);
        assert!(
            close(&c.zeta, &[0.0, 1.0 / 6.0, 2.0 / 6.0, 1.0]),
            "{:?}",
            c.zeta
        );
        let p = classical(&cloud, Rule::Centripetal);
        let s3 = 3f64.sqrt();
        assert!(close(&p.tau, &[0.0, 1.0 / (1.0 + s3), 1.0]), "{:?}", p.tau);
        assert!(close(&p.zeta, &[0.0, 0.25, 0.5, 1.0]), "{:?}", p.zeta);
        let u = classical(&cloud, Rule::Uniform);
        assert!(close(&u.tau, &[0.0, 0.5, 1.0]));
        assert!(close(&u.zeta, &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]));
    }

    #[test]
    fn scattered_chordal_is_the_normalised_principal_coordinate() {
        // Points on a tilted plane: chordal τ is the affine image of the first coordinate.
        // Uneven a, and b symmetric about 0 for every a, so that a and b are uncorrelated
        // and the first principal axis is exactly (1, 0, ½).
        let points: Vec<P3> = (0..8)
            .flat_map(|i| {
                let a = (i * i) as f64 / 7.0;
                [-1.0, -0.5, 0.0, 0.5, 1.0].map(|b| [a, b, 0.5 * a])
            })
            .collect();
        let cloud = PointCloud { points, grid: None };
        let c = classical(&cloud, Rule::Chordal);
        let a: Vec<f64> = cloud.points.iter().map(|p| p[0]).collect();
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        let expect: Vec<f64> = a.iter().map(|x| (x - lo) / (hi - lo)).collect();
        let forward = c
            .tau
            .iter()
            .zip(&expect)
            .all(|(t, e)| (t - e).abs() < 1e-12);
        let backward = c
            .tau
            .iter()
            .zip(&expect)
            .all(|(t, e)| (t - (1.0 - e)).abs() < 1e-12);
        assert!(forward || backward, "{:?}", c.tau);
    }
}
