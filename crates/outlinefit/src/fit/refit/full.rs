//! The HS paper's fitting scheme (§6.1–6.3, `--search full`): a metaheuristic searches the control points
//! C1, C2 and the weights w1, w2 of each segment directly, minimising the Eq. 4 error at
//! fixed centripetal parameters.
//!
//! * Odd segments (1, 3, …; indices 0, 2, … here) are free: C1 and C2 range over the
//!   bounding box of the segment's data (Eq. 9), w1, w2 over [0.01, 2].
//! * Even segments are fitted afterwards, constrained at each smooth joint with an already
//!   fitted neighbour so that the neighbour's inner control point, the joint and their own
//!   inner control point are collinear (G1): that control point is searched as a distance
//!   along the fixed direction; weights range over [0.01, 2.5].
//! * On a closed contour with an odd number of segments the last segment is fitted last,
//!   constrained at both ends (§6.3's end segment), so every smooth joint is G1.
//!
//! The paper's weight range starts at 0; 0.01 is used instead because a zero weight makes
//! the end derivative vanish and the joint tangent undefined. The segmentation is the one
//! the `lsq` fit found (see [`super`]).

use super::common::{finish_segment, on_boundary, rebuild, run_optimizer, RefitOptions};
use crate::curve::rational::{bernstein, RationalCubic};
use crate::fit::JointKind;
use crate::fit::{FittedContour, FittedSegment};
use crate::geom::{Bounds, Point};
use crate::optim::{Optimizer, Problem};
use crate::param::centripetal_parameters;
use std::time::Instant;

/// How one end of a segment is searched.
#[derive(Clone, Copy, Debug)]
enum Side {
    /// The inner control point ranges over the data box (2 variables).
    Free,
    /// The inner control point lies on a ray from the end point along this unit direction
    /// (1 variable: the distance).
    Ray(Point),
}

/// One segment as an optimisation problem over (start side, end side, w1, w2).
pub struct SegmentProblem<'a> {
    points: &'a [Point],
    bern: Vec<[f64; 4]>,
    start: Side,
    end: Side,
    bounds: Vec<(f64, f64)>,
}

impl<'a> SegmentProblem<'a> {
    /// The problem of a free (odd) segment of the paper's scheme: C1 and C2 range over the
    /// data's bounding box (Eq. 9), w1 and w2 over [0.01, 2]; `params` are fixed.
    pub fn free(points: &'a [Point], params: &[f64]) -> Self {
        Self::new(points, params, Side::Free, Side::Free, 2.0, 1.0)
    }

    fn new(
        points: &'a [Point],
        params: &[f64],
        start: Side,
        end: Side,
        max_weight: f64,
        box_scale: f64,
    ) -> Self {
        let Bounds { min: lo, max: hi } = Bounds::of(points.iter().copied());
        let diag = (hi - lo).length().max(1e-9);
        // Eq. 9's box is the data's extent; `box_scale` > 1 widens it by (scale − 1)/2
        // diagonals on every side (the extent alone can exclude the optimum).
        let margin = Point::new(1.0, 1.0) * (0.5 * (box_scale - 1.0).max(0.0) * diag);
        let (lo, hi) = (lo - margin, hi + margin);
        let diag = diag * box_scale.max(1.0);
        let mut bounds = Vec::with_capacity(6);
        for side in [start, end] {
            match side {
                Side::Free => {
                    bounds.push((lo.x, hi.x));
                    bounds.push((lo.y, hi.y));
                }
                Side::Ray(_) => bounds.push((1e-3 * diag, diag)),
            }
        }
        bounds.push((0.01, max_weight));
        bounds.push((0.01, max_weight));
        SegmentProblem {
            points,
            bern: params.iter().map(|&u| bernstein(u)).collect(),
            start,
            end,
            bounds,
        }
    }

    /// The curve a point of the search space stands for.
    pub fn curve(&self, x: &[f64]) -> RationalCubic {
        let c0 = self.points[0];
        let c3 = self.points[self.points.len() - 1];
        let mut k = 0;
        let mut inner = |side: Side, anchor: Point| match side {
            Side::Free => {
                k += 2;
                Point::new(x[k - 2], x[k - 1])
            }
            Side::Ray(d) => {
                k += 1;
                anchor + d * x[k - 1]
            }
        };
        let c1 = inner(self.start, c0);
        let c2 = inner(self.end, c3);
        let n = x.len();
        RationalCubic::new([c0, c1, c2, c3], [x[n - 2], x[n - 1]])
    }
}

impl Problem for SegmentProblem<'_> {
    fn dim(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        self.bounds[i]
    }

    /// Eq. 4 at the fixed parameters. Allocation-free.
    fn evaluate(&self, x: &[f64]) -> f64 {
        let c = self.curve(x);
        let w = c.all_weights();
        let mut e = 0.0;
        for (q, b) in self.points.iter().zip(&self.bern) {
            let mut num = Point::ZERO;
            let mut den = 0.0;
            for k in 0..4 {
                let bw = b[k] * w[k];
                num += c.points[k] * bw;
                den += bw;
            }
            e += (num / den - *q).length_squared();
        }
        e
    }
}

/// Refits every segment of `base` (whose segmentation and joint kinds are kept) with the
/// paper's scheme and `optimizer`. `contour_index` feeds the per-segment seeds.
pub(super) fn fit_contour(
    base: &FittedContour,
    optimizer: &dyn Optimizer,
    opts: &RefitOptions,
    contour_index: usize,
) -> FittedContour {
    let m = base.segments.len();
    if m == 0 {
        return base.clone();
    }
    // Fitting order: group 0 = free (even indices, except the last when m is odd), group 1 =
    // the odd indices, group 2 = the last segment when m is odd.
    let group = |k: usize| {
        if m % 2 == 1 && k == m - 1 && m > 1 {
            2
        } else {
            k % 2
        }
    };
    let mut fitted: Vec<Option<FittedSegment>> = vec![None; m];
    let mut run = Vec::new();
    for g in 0..3 {
        for k in (0..m).filter(|&k| group(k) == g) {
            let started = Instant::now();
            base.segment_points_into(k, &mut run);
            let params = centripetal_parameters(&run);
            let prev = (k + m - 1) % m;
            let next = (k + 1) % m;
            let start = match (&fitted[prev], base.joints[k].kind) {
                (Some(p), JointKind::Smooth) => ray(p.curve.points[3] - p.curve.points[2]),
                _ => Side::Free,
            };
            let end = match (&fitted[next], base.joints[next].kind) {
                (Some(nx), JointKind::Smooth) => ray(nx.curve.points[0] - nx.curve.points[1]),
                _ => Side::Free,
            };
            let max_weight = if g == 0 { 2.0 } else { 2.5 };
            let problem =
                SegmentProblem::new(&run, &params, start, end, max_weight, opts.box_scale);
            let outcome = run_optimizer(optimizer, &problem, opts, contour_index, k);
            let curve = problem.curve(&outcome.best);
            let on_box = on_boundary(&problem, &outcome.best);
            fitted[k] = Some(finish_segment(
                base, k, curve, &run, params, outcome, on_box, started, opts,
            ));
        }
    }
    let segments: Vec<FittedSegment> = fitted
        .into_iter()
        .zip(&base.segments)
        .map(|(f, b)| f.unwrap_or_else(|| b.clone()))
        .collect();
    rebuild(base, segments)
}

/// A ray side along the direction of `d`, or a free side if `d` is degenerate.
fn ray(d: Point) -> Side {
    d.normalized().map_or(Side::Free, Side::Ray)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::breaks::{find_breaks, BreakOptions};
    use crate::contour::Contour;
    use crate::fit::lsq::{fit_contour as lsq_fit, LsqOptions};
    use crate::fit::solve::{optimum_at_fixed_params, EndCondition, FitSettings};

    fn blob() -> FittedContour {
        let pts: Vec<Point> = (0..240)
            .map(|i| {
                let a = i as f64 / 240.0 * std::f64::consts::TAU;
                let r = 30.0 + 6.0 * (3.0 * a).sin();
                Point::new(50.0 + r * a.cos(), 50.0 + r * a.sin())
            })
            .collect();
        let seg = find_breaks(
            &Contour {
                points: pts,
                is_hole: false,
                parent: None,
                edge_spread: None,
            },
            &BreakOptions::for_image(50.0, 100, 100),
            None,
        );
        lsq_fit(
            &seg,
            &LsqOptions {
                tolerance: 0.3,
                settings: FitSettings::default(),
                tangent_window: 3.0,
                timings: false,
                export_bound: 0.02,
            },
        )
    }

    #[test]
    fn every_smooth_joint_is_g1_and_runs_are_reproducible() {
        let base = blob();
        let opts = RefitOptions {
            optimizer: crate::optim::Algorithm::Hs,
            search: crate::fit::refit::Search::Full,
            budget: 3000,
            seed: 5,
            timings: false,
            box_scale: 1.0,
            history: false,
        };
        let hs = crate::optim::HarmonySearch::default();
        let a = fit_contour(&base, &hs, &opts, 0);
        for j in &a.joints {
            if j.kind == JointKind::Smooth {
                assert!(j.angle < 1e-9, "angle {}", j.angle);
            }
        }
        let b = fit_contour(&base, &hs, &opts, 0);
        for (x, y) in a.segments.iter().zip(&b.segments) {
            assert_eq!(x.curve, y.curve);
        }
        // Free segments (even indices) cannot beat the unconstrained least-squares optimum
        // at the same parameters, and a 10× budget does not do worse overall.
        for (k, s) in a
            .segments
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 2 == 0 && *k + 1 < a.segments.len())
        {
            let run = base.segment_points(k);
            let (_, optimum) =
                optimum_at_fixed_params(&run, &s.params, EndCondition::Free, EndCondition::Free);
            assert!(
                s.error.sum_sq >= optimum * (1.0 - 1e-9),
                "segment {k}: {} < {}",
                s.error.sum_sq,
                optimum
            );
        }
        let more = fit_contour(
            &base,
            &hs,
            &RefitOptions {
                budget: 30_000,
                ..opts
            },
            0,
        );
        assert!(
            more.sum_sq() <= a.sum_sq(),
            "{} > {}",
            more.sum_sq(),
            a.sum_sq()
        );
    }

    #[test]
    fn objective_matches_eq4_of_the_curve() {
        let pts: Vec<Point> = (0..20)
            .map(|i| Point::new(i as f64, (i as f64 * 0.3).sin() * 4.0))
            .collect();
        let params = centripetal_parameters(&pts);
        let p = SegmentProblem::new(&pts, &params, Side::Free, Side::Free, 2.0, 1.0);
        let x = [3.0, 2.0, 12.0, -1.0, 0.7, 1.4];
        let c = p.curve(&x);
        let e: f64 = pts
            .iter()
            .zip(&params)
            .map(|(q, &u)| (c.eval(u) - *q).length_squared())
            .sum();
        assert!((p.evaluate(&x) - e).abs() < 1e-9 * e.max(1.0));
    }
}
