//! Optimised placement of the smooth break points (`--breaks optimize`), after the idea of
//! the fireworks curve-to-B-spline paper (`shared/papers/fireworks-curve-to-bspline.txt`):
//! a metaheuristic chooses where the pieces meet, least squares fits everything else.
//!
//! The `lsq` chain ([`super::lsq`]) fixes the segment count and the corners; its smooth
//! joints sit where curvature analysis and error-driven splitting happened to put them.
//! This module keeps every corner and the number of smooth joints, and moves the smooth
//! joints along the contour to lower the total Eq. 4 error (Σ |P(u_i) − Q_i|² over every
//! segment, the `sum_sq` of the report):
//!
//! * **Variables.** Each movable smooth joint is one continuous coordinate, a data-point
//!   index rounded to the nearest point. It may move within its own *cell*: the points
//!   between the midpoints of its two neighbouring segments, less half of [`MIN_GAP`] on
//!   each side. Cells never overlap, so joints cannot cross, every segment keeps at least
//!   [`MIN_GAP`] + 1 points, and the curvature placement is a point of the search box. A
//!   joint whose cell is a single point (short neighbouring segments) stays put. The
//!   cells make the search local: a joint can travel up to half of each neighbouring
//!   segment, not past its neighbours; a global reshuffle was not worth the much larger
//!   box at the budgets that keep a trace within seconds.
//! * **Objective.** For a candidate placement every segment touched is refitted exactly as
//!   `lsq` fits it ([`super::lsq`]'s per-piece fit: polynomial cubic when within the
//!   tolerance, the weight search otherwise), with the unit tangent of each smooth joint
//!   estimated at its new position the way `lsq` estimates it, and shared by both
//!   neighbours, so G1 stays exact. The value is the summed Eq. 4 error. Fits are memoised
//!   by (start, end) joint, since the optimizer revisits rounded positions often.
//! * **Constraints, by penalty.** A placement is feasible when every segment's largest
//!   residual is within the tolerance (or within the largest distance the curvature
//!   placement already had on that stretch, when that was above the tolerance), and the
//!   stretch needs no more SVG cubics than before. An infeasible placement scores its
//!   error plus 10⁶ · (1 + excess), so the optimizer is steered back but never chooses it.
//! * **Independence.** Cells never overlap, so the stretches between two corners are
//!   independent problems, each optimised alone (dimension = its movable joints). A
//!   contour without corners is one cyclic problem over all its joints.
//! * **Never worse.** A stretch takes the optimised placement only when it is feasible and
//!   its error is lower than the curvature placement's; otherwise it keeps the original.
//!   So the total error of every contour is ≤ the `curvature` result, with the same
//!   segment count, the same corners and exact G1 at every smooth joint.
//! * **Budget and seed.** A stretch gets `budget × movable joints` objective evaluations
//!   ([`PlacementOptions::budget`]). Its generator is seeded from the base seed, the
//!   contour index and the stretch's first segment (`meta::segment_seed`), so
//!   results do not depend on thread count or order.
//!
//! Limits: the search is local (see the cells); the tangent at a joint is an estimate
//! from the data, not a variable, so the optimum over tangents is not sought; and the
//! fireworks algorithm's known weakness (the best firework barely moves, see
//! [`crate::optim::Fireworks`]) applies here too, which is why the curvature placement is
//! always kept as a fallback rather than trusted to be found.

use super::lsq::{assemble, estimate_tangent, fit_piece, JointSpec, LsqOptions, Piece};
use super::refit::segment_seed;
use super::{FittedContour, JointKind};
use crate::error::{Error, Result};
use crate::geom::Point;
use crate::optim::{Algorithm, Problem, SeededRng};
use rand::SeedableRng;
use serde::Serialize;
use std::cell::RefCell;
use std::collections::HashMap;
use std::str::FromStr;

/// How the smooth break points of a contour are placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BreakPlacement {
    /// Where curvature analysis and the `lsq` chain's splitting put them (the default).
    #[default]
    Curvature,
    /// Curvature corners kept; smooth joints moved by a metaheuristic to lower the total
    /// Eq. 4 error at the same segment count (`optimize_contour`).
    Optimize,
}

impl BreakPlacement {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            BreakPlacement::Curvature => "curvature",
            BreakPlacement::Optimize => "optimize",
        }
    }
}

impl FromStr for BreakPlacement {
    type Err = Error;

    fn from_str(s: &str) -> Result<BreakPlacement> {
        match s {
            "curvature" => Ok(BreakPlacement::Curvature),
            "optimize" => Ok(BreakPlacement::Optimize),
            _ => Err(Error::InvalidOption {
                name: "breaks",
                message: format!("unknown mode `{s}` (expected curvature or optimize)"),
            }),
        }
    }
}

/// The optimizer that places break points unless another is named: fireworks, as in the
/// paper.
pub(crate) const DEFAULT_OPTIMIZER: Algorithm = Algorithm::Fwa;

/// Default objective evaluations per movable smooth joint. On the bundled samples the
/// fireworks placement removes 18 % of the total error at 20, 27 % at 60, 38 % at 200,
/// 56 % at 600 and 60 % at 2 000 evaluations; 600 gets most of it at about 0.5 s per
/// sample image on one core.
pub(crate) const DEFAULT_BUDGET: u64 = 600;

/// Fewest point-to-point steps between two joints a move may leave (so every segment
/// keeps at least `MIN_GAP + 1` data points).
pub(crate) const MIN_GAP: usize = 3;

/// Penalty per unit of constraint violation (see the module docs).
const PENALTY: f64 = 1e6;

/// Salt mixed into the base seed, so that placement and a metaheuristic refit with the
/// same seed do not draw the same numbers.
const SEED_SALT: u64 = 0xB4EA_C5B1_0C4E_D000;

/// Options of the break placement.
#[derive(Clone, Debug)]
pub struct PlacementOptions {
    /// The metaheuristic.
    pub optimizer: Algorithm,
    /// Objective evaluations per movable smooth joint of a stretch.
    pub budget: u64,
    /// Base seed of the per-stretch generators.
    pub seed: u64,
    /// How segments are fitted (the `lsq` options of the trace).
    pub lsq: LsqOptions,
}

/// Segment fits of one contour, memoised by their end joints.
struct Fits<'a> {
    points: &'a [Point],
    lsq: &'a LsqOptions,
    /// (start index, start smooth, end index, end smooth) → fit.
    pieces: RefCell<HashMap<(usize, bool, usize, bool), Piece>>,
    tangents: RefCell<HashMap<usize, Point>>,
    buf: RefCell<Vec<Point>>,
}

impl<'a> Fits<'a> {
    fn new(points: &'a [Point], lsq: &'a LsqOptions) -> Self {
        Fits {
            points,
            lsq,
            pieces: RefCell::new(HashMap::new()),
            tangents: RefCell::new(HashMap::new()),
            buf: RefCell::new(Vec::new()),
        }
    }

    /// The joint at point `index`, with the tangent `lsq` would estimate there.
    fn joint(&self, index: usize, kind: JointKind) -> JointSpec {
        let tangent =
            (kind == JointKind::Smooth).then(|| {
                *self.tangents.borrow_mut().entry(index).or_insert_with(|| {
                    estimate_tangent(self.points, index, self.lsq.tangent_window)
                })
            });
        JointSpec {
            index,
            kind,
            tangent,
        }
    }

    /// (Eq. 4 error, largest residual, SVG cubics) of the segment between two joints.
    fn measure(&self, a: &JointSpec, b: &JointSpec) -> (f64, f64, usize) {
        let key = (
            a.index,
            a.kind == JointKind::Smooth,
            b.index,
            b.kind == JointKind::Smooth,
        );
        if let Some(p) = self.pieces.borrow_mut().get_mut(&key) {
            return summary(p, self.points, a.index, b.index, self.lsq.export_bound);
        }
        let mut piece = fit_piece(
            self.points,
            a,
            b,
            self.lsq,
            true,
            &mut self.buf.borrow_mut(),
        );
        let s = summary(
            &mut piece,
            self.points,
            a.index,
            b.index,
            self.lsq.export_bound,
        );
        self.pieces.borrow_mut().insert(key, piece);
        s
    }

    /// The fit of the segment between two joints (memoised).
    fn piece(&self, a: &JointSpec, b: &JointSpec) -> Piece {
        self.measure(a, b);
        let key = (
            a.index,
            a.kind == JointKind::Smooth,
            b.index,
            b.kind == JointKind::Smooth,
        );
        match self.pieces.borrow().get(&key) {
            Some(p) => p.clone(),
            None => fit_piece(
                self.points,
                a,
                b,
                self.lsq,
                true,
                &mut self.buf.borrow_mut(),
            ),
        }
    }
}

/// (Eq. 4 error, largest residual, SVG cubics within `bound`) of a fitted piece.
fn summary(
    piece: &mut Piece,
    points: &[Point],
    a: usize,
    b: usize,
    bound: f64,
) -> (f64, f64, usize) {
    let n = points.len();
    let sol = &piece.solution;
    let sum_sq = sol
        .params
        .iter()
        .enumerate()
        .map(|(i, &u)| (sol.curve.eval(u) - points[(a + i) % n]).length_squared())
        .sum();
    debug_assert_eq!(sol.params.len(), (b + n - a) % n + 1);
    (sum_sq, piece.max_residual, piece.pieces(bound))
}

/// One stretch of a contour as an optimisation problem (see the module docs).
struct Stretch<'a> {
    fits: &'a Fits<'a>,
    /// Unwrapped positions of every joint of the contour (curvature placement).
    positions: &'a [i64],
    kinds: &'a [JointKind],
    /// Segments of the stretch, in order (segment k runs from joint k to joint k + 1).
    segments: Vec<usize>,
    /// The movable joints, one per variable.
    variables: Vec<usize>,
    /// Cell of each variable, as inclusive unwrapped positions.
    cells: Vec<(i64, i64)>,
    /// Largest residual a feasible placement may have.
    residual_limit: f64,
    /// Most SVG cubics a feasible placement may need.
    piece_limit: usize,
}

impl Stretch<'_> {
    /// Unwrapped positions of every joint with the variables at `x`.
    fn placement(&self, x: &[f64]) -> Vec<i64> {
        let mut p = self.positions.to_vec();
        for ((&j, &(lo, hi)), &v) in self.variables.iter().zip(&self.cells).zip(x) {
            p[j] = (v.round() as i64).clamp(lo, hi);
        }
        p
    }

    /// (Eq. 4 error, largest residual, SVG cubics) of the stretch at a placement.
    fn measure(&self, placement: &[i64]) -> (f64, f64, usize) {
        let n = self.fits.points.len() as i64;
        let m = self.positions.len();
        let joint = |j: usize| {
            self.fits
                .joint(placement[j].rem_euclid(n) as usize, self.kinds[j])
        };
        let mut total = (0.0, 0.0_f64, 0);
        for &k in &self.segments {
            let (e, r, p) = self.fits.measure(&joint(k), &joint((k + 1) % m));
            total = (total.0 + e, total.1.max(r), total.2 + p);
        }
        total
    }

    /// The penalised objective of a measured placement.
    fn score(&self, (sum_sq, residual, pieces): (f64, f64, usize)) -> f64 {
        let excess = (residual - self.residual_limit).max(0.0)
            + pieces.saturating_sub(self.piece_limit) as f64;
        if excess > 0.0 {
            sum_sq + PENALTY * (1.0 + excess)
        } else {
            sum_sq
        }
    }
}

impl Problem for Stretch<'_> {
    fn dim(&self) -> usize {
        self.variables.len()
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        // Half a step beyond each end, so the end points are as likely as inner ones.
        let (lo, hi) = self.cells[i];
        (lo as f64 - 0.49, hi as f64 + 0.49)
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        self.score(self.measure(&self.placement(x)))
    }
}

/// Moves the smooth joints of an `lsq` chain to lower its total Eq. 4 error, keeping the
/// corners, the segment count and exact G1 (see the module docs). The result is never
/// worse than `base` on any stretch between corners. `contour_index` feeds the seeds.
pub(crate) fn optimize_contour(
    base: &FittedContour,
    opts: &PlacementOptions,
    contour_index: usize,
) -> Result<FittedContour> {
    let optimizer = opts.optimizer.build();
    let points = &base.points;
    let n = points.len();
    let m = base.joints.len();
    if n < 3 || m < 2 || base.segments.len() != m {
        return Ok(base.clone());
    }
    let kinds: Vec<JointKind> = base.joints.iter().map(|j| j.kind).collect();
    if !kinds.contains(&JointKind::Smooth) {
        return Ok(base.clone());
    }
    // Unwrapped positions, strictly increasing from joint 0 (one turn = n).
    let origin = base.joints[0].index as i64;
    let positions: Vec<i64> = base
        .joints
        .iter()
        .map(|j| origin + (j.index as i64 - origin).rem_euclid(n as i64))
        .collect();
    if positions.windows(2).any(|w| w[1] <= w[0]) {
        return Ok(base.clone());
    }
    // Cells: each gap between neighbouring joints is shared out between its two ends.
    let gap = MIN_GAP as i64;
    let mut cells: Vec<(i64, i64)> = positions.iter().map(|&p| (p, p)).collect();
    for k in 0..m {
        let (a, b) = if k + 1 < m {
            (positions[k], positions[k + 1])
        } else {
            (positions[k], positions[0] + n as i64)
        };
        let half = (b - a - gap).max(0) / 2;
        if kinds[k] == JointKind::Smooth {
            cells[k].1 = a + half;
        }
        let next = (k + 1) % m;
        if kinds[next] == JointKind::Smooth {
            cells[next].0 = if k + 1 < m {
                b - half
            } else {
                b - half - n as i64
            };
        }
    }
    // Stretches: from each corner to the next; without corners, the whole contour.
    let corners: Vec<usize> = (0..m).filter(|&j| kinds[j] == JointKind::Corner).collect();
    let stretches: Vec<Vec<usize>> = if corners.is_empty() {
        vec![(0..m).collect()]
    } else {
        corners
            .iter()
            .map(|&c| {
                let mut segs = vec![c];
                let mut k = (c + 1) % m;
                while kinds[k] != JointKind::Corner {
                    segs.push(k);
                    k = (k + 1) % m;
                }
                segs
            })
            .collect()
    };
    let fits = Fits::new(points, &opts.lsq);
    let mut chosen = positions.clone();
    let mut changed = false;
    for segments in stretches {
        let variables: Vec<usize> = segments
            .iter()
            .copied()
            .filter(|&j| kinds[j] == JointKind::Smooth && cells[j].1 > cells[j].0)
            .collect();
        if variables.is_empty() {
            continue;
        }
        let original_distance = segments
            .iter()
            .map(|&k| base.segments[k].error.max_distance)
            .fold(0.0, f64::max);
        let mut stretch = Stretch {
            fits: &fits,
            positions: &positions,
            kinds: &kinds,
            cells: variables.iter().map(|&j| cells[j]).collect(),
            variables,
            segments,
            residual_limit: opts.lsq.tolerance.max(original_distance),
            piece_limit: usize::MAX,
        };
        let (original_error, _, original_pieces) = stretch.measure(&positions);
        stretch.piece_limit = original_pieces;
        let mut rng = SeededRng::seed_from_u64(segment_seed(
            opts.seed ^ SEED_SALT,
            contour_index,
            stretch.segments[0],
        ));
        let budget = opts.budget.saturating_mul(stretch.variables.len() as u64);
        let outcome = optimizer.minimize(&stretch, budget, &mut rng, false);
        if outcome.best.len() != stretch.dim() || !outcome.value.is_finite() {
            continue;
        }
        let placement = stretch.placement(&outcome.best);
        let measured = stretch.measure(&placement);
        let feasible = stretch.score(measured) == measured.0;
        if feasible && measured.0 < original_error {
            for &j in &stretch.variables {
                chosen[j] = placement[j];
            }
            changed = true;
        }
    }
    if !changed {
        return Ok(base.clone());
    }
    let specs: Vec<JointSpec> = (0..m)
        .map(|j| fits.joint(chosen[j].rem_euclid(n as i64) as usize, kinds[j]))
        .collect();
    let pieces: Vec<Piece> = (0..m)
        .map(|k| fits.piece(&specs[k], &specs[(k + 1) % m]))
        .collect();
    Ok(assemble(
        points,
        base.is_hole,
        base.parent,
        &specs,
        pieces,
        &opts.lsq,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::breaks::{find_breaks, BreakOptions};
    use crate::contour::Contour;
    use crate::Config;

    /// A smooth closed blob whose curvature varies, so break positions matter.
    fn blob(n: usize) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                let r = 40.0 + 9.0 * (3.0 * a).sin() + 4.0 * (5.0 * a).cos();
                Point::new(64.0 + r * a.cos(), 64.0 + r * a.sin())
            })
            .collect()
    }

    fn base_and_options(budget: u64) -> (FittedContour, PlacementOptions) {
        let c = Contour {
            points: blob(400),
            is_hole: false,
            parent: None,
            edge_spread: None,
        };
        let config = Config {
            timings: false,
            tolerance: 0.1,
            break_budget: budget,
            ..Config::default()
        };
        let opts = config.placement_options();
        let seg = find_breaks(&c, &BreakOptions::for_image(50.0, 128, 128), None);
        (super::super::lsq::fit_contour(&seg, &opts.lsq), opts)
    }

    #[test]
    fn optimised_placement_lowers_the_error_and_keeps_count_and_g1() {
        let (base, opts) = base_and_options(DEFAULT_BUDGET);
        assert!(base.segments.len() >= 3, "{}", base.segments.len());
        let moved = optimize_contour(&base, &opts, 0).unwrap();
        assert_eq!(moved.segments.len(), base.segments.len());
        assert!(
            moved.sum_sq() < 0.95 * base.sum_sq(),
            "{} vs {}",
            moved.sum_sq(),
            base.sum_sq()
        );
        assert!(
            moved.max_distance() <= 0.1 + 1e-9,
            "{}",
            moved.max_distance()
        );
        for j in &moved.joints {
            assert_eq!(j.kind, JointKind::Smooth);
            assert!(j.angle < 1e-9, "{}", j.angle);
        }
        // Joints stay in order and apart.
        let n = moved.points.len();
        for k in 0..moved.segments.len() {
            assert!(moved.segments[k].point_count > MIN_GAP, "segment {k}");
            assert!(moved.segments[k].point_count < n);
        }
    }

    #[test]
    fn same_seed_same_placement_and_a_bad_mode_is_refused() {
        let (base, opts) = base_and_options(20);
        let a = optimize_contour(&base, &opts, 3).unwrap();
        let b = optimize_contour(&base, &opts, 3).unwrap();
        let ia: Vec<usize> = a.joints.iter().map(|j| j.index).collect();
        let ib: Vec<usize> = b.joints.iter().map(|j| j.index).collect();
        assert_eq!(ia, ib);
        assert_eq!(a.sum_sq(), b.sum_sq());
        assert!("sideways".parse::<BreakPlacement>().is_err());
        assert_eq!(
            "optimize".parse::<BreakPlacement>().unwrap(),
            BreakPlacement::Optimize
        );
    }
}
