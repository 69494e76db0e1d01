//! The default strategy: separable least squares with exact G1 joints, error-driven
//! splitting and merging.
//!
//! 1. Every break of the contour becomes a joint. A smooth joint gets one unit tangent,
//!    estimated from the data around it (weighted quadratic fit in arc length), and both
//!    neighbouring segments are fitted with that same tangent, so G1 holds exactly.
//! 2. Each segment is fitted by [`fit_segment`](super::solve::fit_segment): a polynomial
//!    cubic first (control points by least squares, parameters by projection), and where
//!    that misses the tolerance by less than 4×, the weights of a rational cubic are
//!    searched in [0.01, 2.5].
//! 3. A segment whose largest point-to-curve distance exceeds the tolerance is split at its
//!    worst point (a new smooth joint) until every segment is within tolerance or too short
//!    to split. While splitting, only short pieces (under [`SPLIT_WEIGHTS_POINTS`] data
//!    points) search weights before they are split: a long piece that the polynomial cubic
//!    misses is split at once, and its halves are fitted as polynomial cubics first.
//! 4. Adjacent segments meeting at a smooth joint are merged back while the merged fit stays
//!    within tolerance, so the outline keeps few segments; every merge candidate searches
//!    weights where its polynomial cubic misses. A closed contour keeps at least two
//!    segments.
//! 5. A segment that still misses the tolerance but is too short to split gets a corner at
//!    its worst point when both sides then fit, and the merge runs again around the new
//!    corners.
//! 6. While splitting and merging, a polynomial cubic only decides whether its run fits:
//!    on a run of [`DECISION_SUBSAMPLE_POINTS`] or more it is fitted on every other
//!    point (and measured on all), it stops at the first round of parameter correction
//!    within [`EARLY_STOP`] of the tolerance, and only the pieces that end as segments
//!    run their remaining rounds on all their points ([`finish_piece`]).
//!
//! No split or merge crosses a corner, so a contour with two or more corners is fitted run
//! by run (corner to corner), in parallel on a large contour.

use super::solve::{
    every, fit_polynomial_until, fit_segment_from, resume_polynomial, segment_error, spread_params,
    EndCondition, FitSettings, SegmentSolution, Stopped,
};
use super::{DrawnCubics, FittedContour, FittedSegment, Joint, JointKind};
use crate::breaks::{arc_lengths, SegmentedContour};
use crate::curve::approx::drawing_bound;
use crate::curve::power::PowerCubic;
use crate::curve::{approximate_with_cubics, CubicBez, RationalCubic};
use crate::geom::{angle_between, cyclic_run, segment_distance, Point};
use crate::linalg::det3;
use std::time::Instant;

/// Options of the `lsq` strategy.
#[derive(Clone, Debug)]
pub struct LsqOptions {
    /// Largest allowed point-to-curve distance (px).
    pub tolerance: f64,
    /// Settings of each segment fit.
    pub settings: FitSettings,
    /// Half-width (px of arc length) of the data window used to estimate joint tangents.
    pub tangent_window: f64,
    /// Record wall times.
    pub timings: bool,
    /// Distance bound of the SVG's polynomial approximation of rational segments (px); the
    /// chain prefers merges that do not add SVG pieces.
    pub export_bound: f64,
}

impl LsqOptions {
    /// The options of a trace with fitting tolerance `tolerance` (px): the SVG's drawing
    /// bound matched to it ([`drawing_bound`]), the weight search on a subset of a long
    /// run's points, no orthogonal-distance polish.
    pub fn for_tolerance(tolerance: f64, timings: bool) -> Self {
        LsqOptions {
            tolerance,
            // Parameter correction without the orthogonal-distance polish: the polish
            // lowers Eq. 4 a little but costs most of the time, and the tolerance is met
            // without it.
            settings: FitSettings {
                polish_iterations: 0,
                search_points: Some(LSQ_SEARCH_POINTS),
                ..FitSettings::default()
            },
            tangent_window: 3.0,
            timings,
            export_bound: drawing_bound(tolerance),
        }
    }
}

/// Data points the weight search of a segment evaluates (see
/// [`FitSettings::search_points`]). 20 rather than 24: on the scan of `make_scan.py`
/// 0.98x the processor time (wall time within noise) for 14 more of its 33 540
/// segments, and every corpus ratio to potrace the same to two decimals. 16 saved 4 % of
/// the scan's wall time but raised dev-more64's area error by 0.4 % (0.354x -> 0.356x
/// potrace's).
const LSQ_SEARCH_POINTS: usize = 20;

/// Rounds of parameter correction of a segment's polynomial cubic (projection of every
/// point onto the curve, then the control points solved again): four rather than the
/// default two. On the scan of `make_scan.py` the cubic then fits where it had stopped
/// short of converging, and the weight search is needed less often: 3.6 % fewer SVG
/// cubics and 0.92x the mean distance to the data (together with
/// [`SPLIT_WEIGHTS_POINTS`]); three rounds gave 1.4 % fewer cubics, five 5.4 % fewer but
/// more repaired contours (79 instead of 61).
const POLYNOMIAL_ROUNDS: usize = 4;

/// A polynomial cubic still more than this many tolerances from a point after its first
/// round of parameter correction, half as many after the second, a third after the
/// third, a quarter after the fourth (24, 12, 8, 6), stops there and the piece is split:
/// it would miss the tolerance after every round. On the scan of `make_scan.py` half of
/// the 103 000 polynomial fits end outside the tolerance, with 70 % of the points fitted;
/// one fit that ends within it passes a bound on the way. The distance is the one the
/// round's projection finds anyway, so the test costs nothing. With the weight search's
/// give-up read the same way, 0.92x the scan's processor time, 3 more of its 37 312 SVG
/// cubics, and the corpus's ratios to potrace the same to two decimals. Half the bound
/// (12) saved more time but added 2 % to dev-shapes' segments and 3 % to dev-icon's
/// area error.
const POLYNOMIAL_GIVE_UP: f64 = 24.0;

/// Data points below which a piece searches weights before it is split. A longer piece
/// that its polynomial cubic misses is split at once: the weight search costs about four
/// polynomial fits, ends within tolerance on a third of the pieces, and a rational segment
/// is mostly drawn with two SVG cubics anyway, as many as the two halves of a split. On
/// the scan of `make_scan.py` (with [`POLYNOMIAL_ROUNDS`]) about 0.92x the time and 3.6 %
/// fewer SVG cubics. With weights searched only while merging (no limit), the square
/// ends of a comb's 1.5 px teeth, runs of a few points whose halves are too short to
/// split, failed the check, and the repair's pixel trace widened every tooth by up to a
/// pixel. Twice the shortest run that is split ([`MIN_SPLIT_POINTS`]), so a piece whose
/// halves cannot be split again always has the weight search.
const SPLIT_WEIGHTS_POINTS: usize = 14;

/// Shortest run (data points, ends included) that is split when it misses the tolerance.
const MIN_SPLIT_POINTS: usize = 7;

/// A polynomial cubic that is within this fraction of the tolerance after a round of
/// parameter correction before its last decides that its run fits ([`decide_piece`]):
/// its remaining rounds run only if the piece becomes a segment ([`finish_piece`]). Its
/// later rounds lower the sum of squared distances, not always the farthest one, so a
/// cubic just within the tolerance early may end outside it; from 0.7 of it, every
/// piece of the corpus ended within it and the 912 corpus SVGs and reports are the same
/// as with every round run (0.8 changed 3 of them, the whole tolerance 50). On `batch`
/// over the corpus 0.966x the instructions (`valgrind --tool=callgrind`; the whole
/// tolerance 0.957x): three quarters of the pieces that fit stop after one round.
const EARLY_STOP: f64 = 0.7;

/// A weight search whose curve is still this many tolerances from a point after its
/// first round of parameter correction stops there, and the piece is split. On the
/// 600 dpi scan of `make_scan.py`, 16 600 of 26 000 searches end outside the tolerance,
/// a fifth of the trace's processor time; stopping those that are more than 2
/// tolerances off after one round changed the page by 4 of 33 588 segments, and the
/// corpus by under 0.1 % of its segments and area error per subset.
const RATIONAL_GIVE_UP: f64 = 2.0;

/// A joint while the chain is being built.
#[derive(Clone, Copy, Debug)]
pub(super) struct JointSpec {
    /// Index of the joint in the contour's point list.
    pub(super) index: usize,
    /// Corner or smooth.
    pub(super) kind: JointKind,
    /// Unit tangent in the direction of travel (smooth joints only).
    pub(super) tangent: Option<Point>,
}

/// A segment's current fit.
#[derive(Clone, Debug)]
pub(super) struct Piece {
    /// The fitted curve and parameters.
    pub(super) solution: SegmentSolution,
    /// Largest |P(u_i) − Q_i| at the fitted parameters (an upper bound of the true
    /// point-to-curve distance, used for split and merge decisions).
    pub(super) max_residual: f64,
    /// The polynomial cubics the segment becomes in SVG, once they were needed: only
    /// merge decisions and the final segments need them, so a candidate that is split or
    /// discarded never pays for them.
    cubics: Option<Vec<CubicBez>>,
    /// Set when the polynomial cubic's rounds stopped as soon as it was close enough to
    /// decide ([`decide_piece`]), with whether the piece may search weights:
    /// [`finish_piece`] runs the rest.
    stopped: Option<(Stopped, bool)>,
}

impl Piece {
    /// A polynomial fit: drawn by its own cubic (made when needed, as a rational
    /// segment's are: most pieces are split or merged away first).
    fn polynomial(solution: SegmentSolution, max_residual: f64) -> Piece {
        Piece {
            solution,
            max_residual,
            cubics: None,
            stopped: None,
        }
    }

    /// Makes the SVG cubics (within `bound`) if they are not there yet.
    pub(super) fn ensure_cubics(&mut self, bound: f64) -> &[CubicBez] {
        let curve = &self.solution.curve;
        self.cubics
            .get_or_insert_with(|| approximate_with_cubics(curve, bound))
    }

    /// Number of polynomial cubics the segment becomes in SVG (within `bound`).
    pub(super) fn pieces(&mut self, bound: f64) -> usize {
        self.ensure_cubics(bound).len()
    }
}

/// Number of points of the cyclic run from `a` to `b`, both included.
fn run_len(n: usize, a: usize, b: usize) -> usize {
    if b > a {
        b - a + 1
    } else {
        n - a + b + 1
    }
}

/// Unit tangent (direction of increasing index) at point `i` of a closed polygon, from a
/// weighted least-squares quadratic in arc length over ±`window` px.
pub(crate) fn estimate_tangent(points: &[Point], i: usize, window: f64) -> Point {
    let n = points.len();
    // Collect (s, point) on both sides.
    let mut acc = [[0.0; 3]; 3]; // normal matrix for basis (1, s, s²)
    let mut rx = [0.0; 3];
    let mut ry = [0.0; 3];
    let p0 = points[i];
    let mut add = |s: f64, p: Point| {
        let w = (-(s / window).powi(2)).exp();
        let b = [1.0, s, s * s];
        for r in 0..3 {
            for c in 0..3 {
                acc[r][c] += w * b[r] * b[c];
            }
            rx[r] += w * b[r] * (p.x - p0.x);
            ry[r] += w * b[r] * (p.y - p0.y);
        }
    };
    add(0.0, p0);
    for dir in [1isize, -1] {
        let mut s = 0.0;
        let mut prev = p0;
        for k in 1..n.min(64) {
            let j = (i as isize + dir * k as isize).rem_euclid(n as isize) as usize;
            s += prev.distance(points[j]);
            prev = points[j];
            if s > 2.0 * window {
                break;
            }
            add(dir as f64 * s, points[j]);
        }
    }
    let solve3 = |r: [f64; 3]| -> Option<f64> {
        // Cramer's rule for the s-coefficient.
        let d = det3(acc);
        if d.abs() < 1e-12 {
            return None;
        }
        let mut m = acc;
        for row in 0..3 {
            m[row][1] = r[row];
        }
        Some(det3(m) / d)
    };
    let fallback = || {
        let a = points[(i + n - 1) % n];
        let b = points[(i + 1) % n];
        (b - a).normalized().unwrap_or(Point::new(1.0, 0.0))
    };
    match (solve3(rx), solve3(ry)) {
        (Some(dx), Some(dy)) => Point::new(dx, dy).normalized().unwrap_or_else(fallback),
        _ => fallback(),
    }
}

/// Fits the run of `points` from joint `a` to joint `b` as the chain's segments end up
/// fitted: a polynomial cubic when it is within tolerance, otherwise (with `weights`)
/// the weight search when that is better. `buf` receives the run's points. (The chain
/// itself decides with [`decide_piece`] and finishes its segments with
/// [`finish_piece`]: the same curves on a run shorter than
/// [`DECISION_SUBSAMPLE_POINTS`].)
pub(super) fn fit_piece(
    points: &[Point],
    a: &JointSpec,
    b: &JointSpec,
    opts: &LsqOptions,
    weights: bool,
    buf: &mut Vec<Point>,
) -> Piece {
    fit_or_decide(points, a, b, opts, weights, false, buf)
}

/// [`fit_piece`] for a decision: whether the run fits within the tolerance, and if not,
/// its best fit. A polynomial cubic stops at the first round of parameter correction
/// that brings it within [`EARLY_STOP`] of the tolerance, where [`fit_piece`] runs all
/// its rounds, and on a long run it is fitted on every other point
/// ([`decide_on_subsample`]): most
/// such pieces are split pieces and merge candidates that are merged into longer ones
/// later, and [`finish_piece`] finishes those that become segments. On the corpus,
/// three quarters of the merge candidates and most of the first pieces between breaks
/// end within the tolerance, and many after one or two of their four rounds.
fn decide_piece(
    points: &[Point],
    a: &JointSpec,
    b: &JointSpec,
    opts: &LsqOptions,
    weights: bool,
    buf: &mut Vec<Point>,
) -> Piece {
    fit_or_decide(points, a, b, opts, weights, true, buf)
}

/// The settings of a piece's polynomial cubic.
fn polynomial_settings(opts: &LsqOptions) -> FitSettings {
    FitSettings {
        polish_iterations: opts.settings.polish_iterations,
        reparam_rounds: POLYNOMIAL_ROUNDS,
        give_up: Some(POLYNOMIAL_GIVE_UP * opts.tolerance),
        ..FitSettings::polynomial()
    }
}

/// The end conditions of the run from joint `a` to joint `b`.
fn end_conditions(a: &JointSpec, b: &JointSpec) -> (EndCondition, EndCondition) {
    (
        a.tangent.map_or(EndCondition::Free, EndCondition::Tangent),
        b.tangent.map_or(EndCondition::Free, EndCondition::Tangent),
    )
}

/// [`fit_piece`] (`decide` false) or [`decide_piece`].
fn fit_or_decide(
    points: &[Point],
    a: &JointSpec,
    b: &JointSpec,
    opts: &LsqOptions,
    weights: bool,
    decide: bool,
    buf: &mut Vec<Point>,
) -> Piece {
    let polynomial = polynomial_settings(opts);
    cyclic_run(points, a.index, b.index, buf);
    let (start, end) = end_conditions(a, b);
    if decide && buf.len() >= DECISION_SUBSAMPLE_POINTS {
        return decide_on_subsample(buf, start, end, opts, weights);
    }
    // A polynomial cubic is what SVG draws exactly: prefer it whenever it is within
    // tolerance; otherwise search the weights. For a decision, the first round within
    // [`EARLY_STOP`] of the tolerance ends it (the farthest foot, which the round finds
    // anyway, bounds the drawn residual from below).
    let bound = EARLY_STOP * opts.tolerance;
    let mut stopped_residual = 0.0;
    let within = |curve: &RationalCubic, params: &[f64], far: f64| {
        if !decide || far > bound {
            return false;
        }
        stopped_residual = residual_given_inner(buf, curve, params, far);
        stopped_residual <= bound
    };
    let (poly, stopped) = fit_polynomial_until(buf, start, end, &polynomial, within);
    if let Some(stopped) = stopped {
        return Piece {
            stopped: Some((stopped, weights)),
            ..Piece::polynomial(poly, stopped_residual)
        };
    }
    let poly_residual = drawn_residual(buf, &poly);
    with_weights(buf, start, end, opts, weights, poly, poly_residual)
}

/// Data points from which a run's decision ([`decide_piece`]) fits its polynomial cubic
/// on every [`DECISION_STRIDE`]-th point only. The points lie about 0.8 px apart along
/// a smooth edge, so half of them place the cubic almost where all of them do; what the
/// decision concludes is measured on all of them (the curve's distance to every point,
/// at its foot, and to every chord), and the segments it keeps run their last rounds on
/// all of them ([`finish_piece`]). On the scan of `make_scan.py` 0.960x the
/// instructions (`valgrind --tool=callgrind`), 34 306 SVG cubics instead of 34 607; on
/// `batch` over the corpus 0.957x, the area error lower on seven of the eight subsets
/// (2-6 %) and 1.3 % higher on dev-icon (five round icons take one or two segments
/// fewer), segments per subset within 0.3 %. From 16 points: 0.95x the scan's processor
/// time instead of 0.92x; every k-th point with k chosen so that about 12 (8) remain:
/// 2.5 % (3.4 %) more SVG cubics on the scan, since a sparser fit misses more often.
const DECISION_SUBSAMPLE_POINTS: usize = 12;

/// A long run's decision fits every this many points (and the last).
const DECISION_STRIDE: usize = 2;

/// [`decide_piece`] of a long run (`buf`, [`DECISION_SUBSAMPLE_POINTS`] or more): its
/// polynomial cubic is fitted on every [`DECISION_STRIDE`]-th point, and whatever it
/// decides is measured on all of them. A cubic that stops early, or that ends within the
/// tolerance after all its rounds, is left for [`finish_piece`] to run at least its last
/// round on all the points.
fn decide_on_subsample(
    buf: &[Point],
    start: EndCondition,
    end: EndCondition,
    opts: &LsqOptions,
    weights: bool,
) -> Piece {
    let polynomial = polynomial_settings(opts);
    let sub: Vec<Point> = every(buf, DECISION_STRIDE).collect();
    let bound = EARLY_STOP * opts.tolerance;
    let mut accepted: Option<(Vec<f64>, f64)> = None;
    let within = |curve: &RationalCubic, params: &[f64], far: f64| {
        if far > bound {
            return false;
        }
        let (all, inner) = spread_params(curve, buf, params, DECISION_STRIDE);
        if inner > bound {
            return false;
        }
        let residual = residual_given_inner(buf, curve, &all, inner);
        let fits = residual <= bound;
        if fits {
            accepted = Some((all, residual));
        }
        fits
    };
    let (poly, stopped) = fit_polynomial_until(&sub, start, end, &polynomial, within);
    // The last round of every segment runs on all its points. If that cubic misses the
    // tolerance after all, this one, within it on all the points, stays: no weights are
    // searched for it.
    let last = POLYNOMIAL_ROUNDS - 1;
    if let (Some(stopped), Some((params, residual))) = (stopped, accepted) {
        let solution = SegmentSolution { params, ..poly };
        return Piece {
            stopped: Some((
                Stopped {
                    rounds: stopped.rounds.min(last),
                },
                false,
            )),
            ..Piece::polynomial(solution, residual)
        };
    }
    let (params, _) = spread_params(&poly.curve, buf, &poly.params, DECISION_STRIDE);
    let poly = SegmentSolution { params, ..poly };
    let poly_residual = drawn_residual(buf, &poly);
    if poly_residual <= opts.tolerance {
        return Piece {
            stopped: Some((Stopped { rounds: last }, false)),
            ..Piece::polynomial(poly, poly_residual)
        };
    }
    with_weights(buf, start, end, opts, weights, poly, poly_residual)
}

/// The piece of a run (`buf`) whose polynomial cubic `poly` is `poly_residual` from its
/// points: `poly` when that is within the tolerance or `weights` is false, else the
/// weight search's rational cubic where it is closer.
fn with_weights(
    buf: &[Point],
    start: EndCondition,
    end: EndCondition,
    opts: &LsqOptions,
    weights: bool,
    poly: SegmentSolution,
    poly_residual: f64,
) -> Piece {
    // Weights bend a cubic only so far: past a few tolerances the weight search is
    // not worth its cost, and the segment will be split anyway.
    if !weights || poly_residual <= opts.tolerance || poly_residual > 4.0 * opts.tolerance {
        return Piece::polynomial(poly, poly_residual);
    }
    // Start from the polynomial fit's feet, which are close to the rational curve's:
    // one round of parameter correction then does what two do from centripetal ones. A
    // search still [`RATIONAL_GIVE_UP`] tolerances off after its first round is dropped.
    let warm = FitSettings {
        reparam_rounds: 1,
        give_up: Some(RATIONAL_GIVE_UP * opts.tolerance),
        ..opts.settings
    };
    let solution = fit_segment_from(buf, start, end, &warm, Some(&poly.params));
    let max_residual = drawn_residual(buf, &solution);
    if max_residual >= poly_residual {
        return Piece::polynomial(poly, poly_residual);
    }
    Piece {
        solution,
        max_residual,
        cubics: None,
        stopped: None,
    }
}

/// Runs the remaining rounds of a piece that [`decide_piece`] stopped early, on all its
/// points (on a run shorter than [`DECISION_SUBSAMPLE_POINTS`] the same curve as
/// [`fit_piece`]'s), and where that misses the tolerance after all (more rounds lower
/// the sum of squared distances, not always the farthest), the same weight search (none
/// for a piece decided on every other point). Only when both miss is the stopped cubic,
/// within the tolerance on all its points, kept.
fn finish_piece(
    points: &[Point],
    a: &JointSpec,
    b: &JointSpec,
    opts: &LsqOptions,
    piece: &mut Piece,
    buf: &mut Vec<Point>,
) {
    let Some((stopped, weights)) = piece.stopped.take() else {
        return;
    };
    cyclic_run(points, a.index, b.index, buf);
    let (start, end) = end_conditions(a, b);
    let settings = polynomial_settings(opts);
    let poly = resume_polynomial(buf, start, end, &settings, piece.solution.clone(), stopped);
    let poly_residual = drawn_residual(buf, &poly);
    let finished = with_weights(buf, start, end, opts, weights, poly, poly_residual);
    if finished.max_residual <= opts.tolerance {
        *piece = finished;
    }
}

/// Largest distance between a fitted segment and its run of points, both ways: from each
/// point to the curve at its parameter, and from the curve halfway between two
/// consecutive parameters to the chord of those points. The second catches a curve that
/// passes through every point but loops out between two of them (a short segment with
/// long tangent handles), which the first cannot see.
pub(crate) fn drawn_residual(points: &[Point], sol: &SegmentSolution) -> f64 {
    residual_at(points, &sol.curve, &sol.params)
}

/// [`drawn_residual`] of `curve` with the points at parameters `params`.
fn residual_at(points: &[Point], curve: &RationalCubic, params: &[f64]) -> f64 {
    let power = curve.power_form();
    let at_points = points
        .iter()
        .zip(params)
        .map(|(q, &u)| power.eval(u).distance(*q))
        .fold(0.0, f64::max);
    at_points.max(between_points(points, &power, params))
}

/// [`residual_at`] when the largest distance of the inner points (all but the first and
/// the last) from the curve at their parameters is already known: `inner`, as a round of
/// parameter correction measures it at the feet it finds (`reproject`, with the same
/// power form and so the same bits). Only the two ends and the chords are measured.
fn residual_given_inner(
    points: &[Point],
    curve: &RationalCubic,
    params: &[f64],
    inner: f64,
) -> f64 {
    let power = curve.power_form();
    let last = points.len() - 1;
    let ends = [0, last]
        .map(|i| power.eval(params[i]).distance(points[i]))
        .into_iter()
        .fold(inner, f64::max);
    ends.max(between_points(points, &power, params))
}

/// The largest distance from the curve halfway between two consecutive parameters to
/// the chord of those points (see [`drawn_residual`]).
fn between_points(points: &[Point], power: &PowerCubic, params: &[f64]) -> f64 {
    points
        .windows(2)
        .zip(params.windows(2))
        .map(|(q, u)| segment_distance(power.eval(0.5 * (u[0] + u[1])), q[0], q[1]))
        .fold(0.0, f64::max)
}

/// The joints of `seg`'s breaks, each smooth one with its tangent estimated from the
/// data around it.
fn joint_specs(seg: &SegmentedContour, opts: &LsqOptions) -> Vec<JointSpec> {
    seg.breaks
        .iter()
        .map(|b| JointSpec {
            index: b.index,
            kind: b.kind,
            tangent: (b.kind == JointKind::Smooth)
                .then(|| estimate_tangent(&seg.points, b.index, opts.tangent_window)),
        })
        .collect()
}

/// Fits a closed chain of segments to a segmented contour.
pub(crate) fn fit_contour(seg: &SegmentedContour, opts: &LsqOptions) -> FittedContour {
    let points = &seg.points;
    let n = points.len();
    let joints = joint_specs(seg, opts);
    if n < 3 || joints.len() < 2 {
        return FittedContour {
            points: points.clone(),
            is_hole: seg.is_hole,
            parent: seg.parent,
            segments: Vec::new(),
            joints: Vec::new(),
            tolerance: opts.tolerance,
        };
    }
    let corners: Vec<usize> = (0..joints.len())
        .filter(|&k| joints[k].kind == JointKind::Corner)
        .collect();
    let (joints, pieces) = if corners.len() >= 2 {
        fit_between_corners(points, joints, &corners, opts)
    } else {
        fit_chain(points, joints, true, opts)
    };
    assemble(points, seg.is_hole, seg.parent, &joints, pieces, opts)
}

/// A chain's joints and the pieces between them, as [`fit_chain`] returns them.
type ChainFit = (Vec<JointSpec>, Vec<Piece>);

/// Fewest contour points for which the runs between corners of one contour are fitted in
/// parallel (see [`fit_between_corners`]).
const PARALLEL_RUN_POINTS: usize = 4000;

/// Fits a contour with two or more corners run by run: no split or merge crosses a corner,
/// so the runs from one corner to the next are independent chains, fitted in parallel on
/// a large contour. The joints come back in the contour's order, starting where they
/// started.
fn fit_between_corners(
    points: &[Point],
    joints: Vec<JointSpec>,
    corners: &[usize],
    opts: &LsqOptions,
) -> ChainFit {
    let (n, m) = (points.len(), joints.len());
    // The corners are distinct (two or more), so each run spans fewer than all joints.
    let runs: Vec<Vec<JointSpec>> = corners
        .iter()
        .enumerate()
        .map(|(r, &c)| {
            let next = corners[(r + 1) % corners.len()];
            (0..run_len(m, c, next))
                .map(|k| joints[(c + k) % m])
                .collect()
        })
        .collect();
    let fit_run = |run: Vec<JointSpec>| fit_chain(points, run, false, opts);
    let fitted: Vec<ChainFit> = if n >= PARALLEL_RUN_POINTS {
        use rayon::prelude::*;
        // Longest runs first: a large shape's longest run can hold a fifth of its points,
        // and started last it would finish alone. Each run is its own task; the results
        // go back to the contour's order.
        let points_of = |run: &[JointSpec]| run_len(n, run[0].index, run[run.len() - 1].index);
        let mut indexed: Vec<(usize, Vec<JointSpec>)> = runs.into_iter().enumerate().collect();
        indexed.sort_by_key(|(_, run)| std::cmp::Reverse(points_of(run)));
        let mut done: Vec<(usize, ChainFit)> = indexed
            .into_par_iter()
            .with_max_len(1)
            .map(|(r, run)| (r, fit_run(run)))
            .collect();
        done.sort_unstable_by_key(|&(r, _)| r);
        done.into_iter().map(|(_, fitted)| fitted).collect()
    } else {
        runs.into_iter().map(fit_run).collect()
    };
    // Each run ends on the corner that starts the next one.
    let mut all_joints = Vec::with_capacity(m);
    let mut all_pieces = Vec::with_capacity(m);
    for (mut run_joints, run_pieces) in fitted {
        run_joints.pop();
        all_joints.extend(run_joints);
        all_pieces.extend(run_pieces);
    }
    // Start again at the first joint of the original order that is left.
    let first = joints[0].index;
    let lead = (0..all_joints.len())
        .min_by_key(|&k| (all_joints[k].index + n - first) % n)
        .unwrap_or(0);
    all_joints.rotate_left(lead);
    all_pieces.rotate_left(lead);
    (all_joints, all_pieces)
}

/// Fits a chain of joints: each piece between consecutive joints, then splitting and
/// merging. A `closed` chain runs from its last joint back to its first and keeps at least
/// two segments; an open one (a run from one corner to the next) has one piece fewer than
/// joints and never merges across its end joints.
fn fit_chain(
    points: &[Point],
    mut joints: Vec<JointSpec>,
    closed: bool,
    opts: &LsqOptions,
) -> ChainFit {
    let n = points.len();
    let mut buf = Vec::new();
    // While splitting, only a short piece searches weights (see `SPLIT_WEIGHTS_POINTS`);
    // a merge candidate always does.
    let split_fit = |a: &JointSpec, b: &JointSpec, buf: &mut Vec<Point>| -> Piece {
        let weights = run_len(n, a.index, b.index) < SPLIT_WEIGHTS_POINTS;
        decide_piece(points, a, b, opts, weights, buf)
    };

    // Runs (between two joint indices) known not to fit within tolerance: a split
    // records the run it split, so merging cannot try it again. A long run was tried as
    // a polynomial cubic only (see `SPLIT_WEIGHTS_POINTS`); merging does not retry it
    // with weights either (measured: 1.6 % fewer SVG cubics for 1.2x the scan's time).
    let mut failed: std::collections::HashSet<(usize, usize)> = std::collections::HashSet::new();

    // Initial fits and splitting.
    let count = if closed {
        joints.len()
    } else {
        joints.len() - 1
    };
    let mut pieces: Vec<Piece> = (0..count)
        .map(|k| split_fit(&joints[k], &joints[(k + 1) % joints.len()], &mut buf))
        .collect();
    let mut k = 0;
    while k < pieces.len() {
        let m = joints.len();
        let (a, b) = (joints[k], joints[(k + 1) % m]);
        let len = run_len(n, a.index, b.index);
        if pieces[k].max_residual > opts.tolerance && len >= MIN_SPLIT_POINTS {
            // Split at the worst point, away from the ends.
            cyclic_run(points, a.index, b.index, &mut buf);
            let worst = worst_point(&pieces[k].solution, &buf, 3..len - 3).unwrap_or(len / 2);
            let index = (a.index + worst) % n;
            let mid = JointSpec {
                index,
                kind: JointKind::Smooth,
                tangent: Some(estimate_tangent(points, index, opts.tangent_window)),
            };
            failed.insert((a.index, b.index));
            joints.insert(k + 1, mid);
            let left = split_fit(&a, &mid, &mut buf);
            let right = split_fit(&mid, &b, &mut buf);
            pieces[k] = left;
            pieces.insert(k + 1, right);
            // Re-examine segment k (the left half) before moving on.
            continue;
        }
        k += 1;
    }

    // Merging across smooth joints, then corners in runs too short to split, whose
    // neighbours may then merge across their other ends. A second corner pass finds only
    // pieces that failed the first (a merge never leaves a piece over the tolerance) and
    // ends the loop.
    loop {
        merge_pieces(
            points,
            &mut joints,
            &mut pieces,
            &mut failed,
            closed,
            opts,
            &mut buf,
        );
        if !corner_short_misses(points, &mut joints, &mut pieces, opts, &mut buf) {
            break;
        }
    }
    // The pieces that are segments now, stopped as soon as they fitted, get the rest of
    // their rounds.
    let m = joints.len();
    for (k, piece) in pieces.iter_mut().enumerate() {
        finish_piece(
            points,
            &joints[k],
            &joints[(k + 1) % m],
            opts,
            piece,
            &mut buf,
        );
    }
    (joints, pieces)
}

/// Merges adjacent pieces across smooth joints while the merged fit stays within
/// tolerance and draws with no more SVG cubics. A failed merge of the run between two
/// given joints is remembered in `failed`: it would fail again. An open chain merges at
/// its inner joints only.
fn merge_pieces(
    points: &[Point],
    joints: &mut Vec<JointSpec>,
    pieces: &mut Vec<Piece>,
    failed: &mut std::collections::HashSet<(usize, usize)>,
    closed: bool,
    opts: &LsqOptions,
    buf: &mut Vec<Point>,
) {
    loop {
        let mut merged_any = false;
        // An open chain merges at its inner joints only.
        let mut j = usize::from(!closed);
        while j + usize::from(!closed) < joints.len() && joints.len() > 2 {
            let m = joints.len();
            if joints[j].kind == JointKind::Smooth {
                let prev = (j + m - 1) % m;
                let next = (j + 1) % m;
                let key = (joints[prev].index, joints[next].index);
                if failed.contains(&key) {
                    j += 1;
                    continue;
                }
                let mut candidate =
                    decide_piece(points, &joints[prev], &joints[next], opts, true, buf);
                // Accept when within tolerance and not more SVG pieces than before.
                let bound = opts.export_bound;
                if candidate.max_residual > opts.tolerance
                    || adds_pieces(&mut candidate, pieces, prev, j, bound)
                {
                    failed.insert(key);
                } else {
                    // Segment `prev` runs joints[prev] → joints[j]; it absorbs segment j.
                    joints.remove(j);
                    let prev_after = if j == 0 { joints.len() - 1 } else { j - 1 };
                    pieces.remove(j);
                    pieces[prev_after] = candidate;
                    merged_any = true;
                    continue;
                }
            }
            j += 1;
        }
        if !merged_any {
            break;
        }
    }
}

/// Gives each piece that still misses the tolerance but is too short to split
/// ([`MIN_SPLIT_POINTS`]) a corner at its worst point, where the check's repair would
/// put it, when both sides then fit within the tolerance; its end joints keep their
/// tangents. Returns whether it added a corner. Such a piece is mostly a step of a
/// staircase (an image upscaled from a bilevel one) between two smooth joints, which no
/// cubic with both end tangents fixed follows: without the corner the check finds the
/// drawn path off its data there and its repair puts the corner in a round of its own,
/// refitting every run it cuts (on the 800 px bicubic horse, 64 such pieces cost a repair
/// round as long as the whole fit).
fn corner_short_misses(
    points: &[Point],
    joints: &mut Vec<JointSpec>,
    pieces: &mut Vec<Piece>,
    opts: &LsqOptions,
    buf: &mut Vec<Point>,
) -> bool {
    let n = points.len();
    let mut inserted = false;
    let mut k = 0;
    while k < pieces.len() {
        let (a, b) = (joints[k], joints[(k + 1) % joints.len()]);
        let len = run_len(n, a.index, b.index);
        if pieces[k].max_residual <= opts.tolerance || !(3..MIN_SPLIT_POINTS).contains(&len) {
            k += 1;
            continue;
        }
        cyclic_run(points, a.index, b.index, buf);
        let worst = worst_point(&pieces[k].solution, buf, 1..len - 1).unwrap_or(1);
        let corner = JointSpec {
            index: (a.index + worst) % n,
            kind: JointKind::Corner,
            tangent: None,
        };
        let left = decide_piece(points, &a, &corner, opts, true, buf);
        let right = decide_piece(points, &corner, &b, opts, true, buf);
        if left.max_residual.max(right.max_residual) <= opts.tolerance {
            joints.insert(k + 1, corner);
            pieces[k] = left;
            pieces.insert(k + 1, right);
            inserted = true;
            k += 2;
        } else {
            k += 1;
        }
    }
    inserted
}

/// The first of the points `run[range]` farthest from `solution`'s curve at their
/// parameters; `None` when the range is empty.
fn worst_point(
    solution: &SegmentSolution,
    run: &[Point],
    range: std::ops::Range<usize>,
) -> Option<usize> {
    let mut worst = None;
    let mut worst_d = -1.0;
    for i in range {
        let d = solution.curve.eval(solution.params[i]).distance(run[i]);
        if d > worst_d {
            worst_d = d;
            worst = Some(i);
        }
    }
    worst
}

/// True when the `merged` candidate is drawn with more SVG cubics than `pieces[left]` and
/// `pieces[right]` together. Every segment is drawn with at least one cubic, so the two
/// halves are approximated only as far as the comparison needs: a merged segment of one or
/// two cubics never adds any, and the halves it replaces need not be drawn at all.
fn adds_pieces(
    merged: &mut Piece,
    pieces: &mut [Piece],
    left: usize,
    right: usize,
    bound: f64,
) -> bool {
    let m = merged.pieces(bound);
    if m <= 2 {
        return false;
    }
    let l = pieces[left].pieces(bound);
    m > l + 1 && m > l + pieces[right].pieces(bound)
}

/// Builds the public result: final error statistics and joint data.
pub(super) fn assemble(
    points: &[Point],
    is_hole: bool,
    parent: Option<usize>,
    joints: &[JointSpec],
    pieces: Vec<Piece>,
    opts: &LsqOptions,
) -> FittedContour {
    let m = joints.len();
    let ends = |k: usize| (joints[k].index, joints[(k + 1) % m].index);
    let segments = finish_pieces(
        points,
        pieces.into_iter().enumerate().map(|(k, p)| (ends(k), p)),
        opts,
    );
    let joints_out = joint_report(&segments, joints.iter().map(|j| (j.index, j.kind)), points);
    FittedContour {
        points: points.to_vec(),
        is_hole,
        parent,
        segments,
        joints: joints_out,
        tolerance: opts.tolerance,
    }
}

/// The segments of fitted `pieces`, each given with the indices of its end points: error
/// measures and drawn cubics. They are independent: on a large contour they are computed
/// in parallel (in order, so on any number of threads the same).
fn finish_pieces(
    points: &[Point],
    pieces: impl Iterator<Item = ((usize, usize), Piece)>,
    opts: &LsqOptions,
) -> Vec<FittedSegment> {
    let (arc, _) = arc_lengths(points);
    let finish = |(a, b): (usize, usize), piece: Piece, buf: &mut Vec<Point>| -> FittedSegment {
        let started = Instant::now();
        cyclic_run(points, a, b, buf);
        let error = segment_error(&piece.solution.curve, buf, &piece.solution.params);
        let seconds = if opts.timings {
            started.elapsed().as_secs_f64()
        } else {
            0.0
        };
        FittedSegment {
            drawn: DrawnCubics::new(
                piece.solution.curve,
                opts.export_bound,
                piece.cubics.unwrap_or_else(|| {
                    approximate_with_cubics(&piece.solution.curve, opts.export_bound)
                }),
            ),
            curve: piece.solution.curve,
            start: a,
            end: b,
            point_count: buf.len(),
            params: piece.solution.params,
            arc_range: [arc[a], arc[b]],
            error,
            evaluations: piece.solution.evaluations,
            seconds,
            on_search_boundary: None,
            history: Vec::new(),
        }
    };
    if points.len() >= PARALLEL_RUN_POINTS {
        use rayon::prelude::*;
        let pieces: Vec<_> = pieces.collect();
        pieces
            .into_par_iter()
            .map_init(Vec::new, |buf, (ends, piece)| finish(ends, piece, buf))
            .collect()
    } else {
        let mut buf = Vec::new();
        pieces
            .map(|(ends, piece)| finish(ends, piece, &mut buf))
            .collect()
    }
}

/// Fits `seg` again where it differs from `previous` (the same data points, fitted
/// earlier) or where `dirty` says so, and keeps the rest: a run from one corner of `seg`
/// to the next whose both ends are corners of `previous`, with no corner between them,
/// keeps `previous`'s segments unless `dirty(a, b)` holds for its end indices. Every other
/// run is fitted as [`fit_contour`] fits it. The repair uses it to refit only around what
/// went wrong: a page's large contour costs what its faulty runs cost, not a whole fit.
/// Also returns the data points fitted again (each run's, both ends included).
pub(crate) fn refit_runs(
    previous: &FittedContour,
    seg: &SegmentedContour,
    dirty: &(dyn Fn(usize, usize) -> bool + Sync),
    opts: &LsqOptions,
) -> (FittedContour, usize) {
    let points = &seg.points;
    let n = points.len();
    let corners = seg
        .breaks
        .iter()
        .filter(|b| b.kind == JointKind::Corner)
        .count();
    if corners < 2 || previous.points != *points || previous.segments.is_empty() {
        return (fit_contour(seg, opts), n);
    }
    // Where each of `previous`'s segments starts, and its corners.
    let starting: std::collections::HashMap<usize, usize> = previous
        .segments
        .iter()
        .enumerate()
        .map(|(k, s)| (s.start, k))
        .collect();
    let corner_of_previous = |index: usize| {
        starting
            .get(&index)
            .is_some_and(|&k| previous.joints[k].kind == JointKind::Corner)
    };
    // `previous`'s segments from corner `a` to corner `b`, when no corner lies between.
    let kept_run = |a: usize, b: usize| -> Option<std::ops::Range<usize>> {
        if !corner_of_previous(a) || !corner_of_previous(b) || dirty(a, b) {
            return None;
        }
        let first = starting[&a];
        let m = previous.segments.len();
        for step in 0..m {
            let k = (first + step) % m;
            if step > 0 && previous.joints[k].kind == JointKind::Corner {
                return None;
            }
            if previous.segments[k].end == b {
                return Some(first..first + step + 1);
            }
        }
        None
    };
    let joints = joint_specs(seg, opts);
    let m = joints.len();
    let corner_at: Vec<usize> = (0..m)
        .filter(|&k| joints[k].kind == JointKind::Corner)
        .collect();
    // Each run in order: kept segments, or new pieces with their joints.
    enum Run {
        Kept(std::ops::Range<usize>),
        /// The run's joints and pieces, and its data points.
        Fitted(Vec<JointSpec>, Vec<Piece>, usize),
    }
    let run = |r: usize| {
        let c = corner_at[r];
        let next = corner_at[(r + 1) % corner_at.len()];
        let (a, b) = (joints[c].index, joints[next].index);
        match kept_run(a, b) {
            Some(range) => Run::Kept(range),
            None => {
                let len = (next + m - c) % m + 1;
                let run: Vec<JointSpec> = (0..len).map(|k| joints[(c + k) % m]).collect();
                let (run_joints, pieces) = fit_chain(points, run, false, opts);
                Run::Fitted(run_joints, pieces, (b + n - a) % n + 1)
            }
        }
    };
    // Runs are independent: in parallel on a large contour, in order.
    let runs: Vec<Run> = if n >= PARALLEL_RUN_POINTS {
        use rayon::prelude::*;
        (0..corner_at.len()).into_par_iter().map(run).collect()
    } else {
        (0..corner_at.len()).map(run).collect()
    };
    let mut segments: Vec<FittedSegment> = Vec::new();
    let mut kinds: Vec<(usize, JointKind)> = Vec::new();
    let mut refitted = 0;
    for run in runs {
        match run {
            Run::Kept(range) => {
                let count = previous.segments.len();
                for k in range {
                    let k = k % count;
                    segments.push(previous.segments[k].clone());
                    kinds.push((previous.joints[k].index, previous.joints[k].kind));
                }
            }
            Run::Fitted(run_joints, pieces, count) => {
                refitted += count;
                let ends = run_joints.windows(2).map(|w| (w[0].index, w[1].index));
                kinds.extend(
                    run_joints[..run_joints.len() - 1]
                        .iter()
                        .map(|j| (j.index, j.kind)),
                );
                segments.extend(finish_pieces(points, ends.zip(pieces), opts));
            }
        }
    }
    // Start again at the first joint of `seg`'s order that is left.
    let first = joints[0].index;
    let lead = (0..kinds.len())
        .min_by_key(|&k| (kinds[k].0 + n - first) % n)
        .unwrap_or(0);
    segments.rotate_left(lead);
    kinds.rotate_left(lead);
    let joints_out = joint_report(&segments, kinds.into_iter(), points);
    (
        FittedContour {
            points: points.clone(),
            is_hole: seg.is_hole,
            parent: seg.parent,
            segments,
            joints: joints_out,
            tolerance: opts.tolerance,
        },
        refitted,
    )
}

/// Joint data (kind, tangent angle, β of Eq. 8) for a closed chain: joint i is where
/// segment i − 1 ends and segment i starts.
pub(crate) fn joint_report(
    segments: &[FittedSegment],
    joints: impl Iterator<Item = (usize, JointKind)>,
    points: &[Point],
) -> Vec<Joint> {
    let m = segments.len();
    joints
        .enumerate()
        .map(|(i, (index, kind))| {
            let prev = &segments[(i + m - 1) % m].curve;
            let next = &segments[i].curve;
            let d_in = prev.end_derivative();
            let d_out = next.start_derivative();
            let beta = if d_in.length() > 0.0 {
                d_out.length() / d_in.length()
            } else {
                f64::INFINITY
            };
            Joint {
                kind,
                position: points[index],
                index,
                angle: angle_between(d_in, d_out),
                beta,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::breaks::{find_breaks, Break, BreakOptions, BreakReason};
    use crate::contour::Contour;
    use crate::curve::RationalCubic;

    fn ellipse(n: usize) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                Point::new(60.0 + 40.0 * a.cos(), 50.0 + 25.0 * a.sin())
            })
            .collect()
    }

    #[test]
    fn ellipse_is_fitted_within_tolerance_with_exact_g1_and_few_segments() {
        let c = Contour {
            points: ellipse(220),
            is_hole: false,
            parent: None,
            edge_spread: None,
        };
        let seg = find_breaks(&c, &BreakOptions::for_image(50.0, 128, 128), None);
        let opts = LsqOptions {
            tolerance: 0.05,
            settings: FitSettings::default(),
            tangent_window: 3.0,
            timings: false,
            export_bound: 0.02,
        };
        let fitted = fit_contour(&seg, &opts);
        assert!(
            fitted.max_distance() <= 0.05 + 1e-9,
            "{}",
            fitted.max_distance()
        );
        // Rational cubics represent conics exactly: an ellipse needs few segments.
        assert!(
            fitted.segments.len() <= 4,
            "{} segments",
            fitted.segments.len()
        );
        for j in &fitted.joints {
            assert_eq!(j.kind, JointKind::Smooth);
            assert!(j.angle < 1e-9, "joint angle {}", j.angle);
            assert!(j.beta > 0.0 && j.beta.is_finite());
        }
        // The chain is closed: each segment ends where the next starts.
        let m = fitted.segments.len();
        for k in 0..m {
            let end = fitted.segments[k].curve.points[3];
            let start = fitted.segments[(k + 1) % m].curve.points[0];
            assert_eq!(end, start);
        }
    }

    /// Every segment of a fitted chain is measured and finished on all its points, though
    /// the chain decides long runs on every other point and stops each polynomial cubic
    /// at the first round close enough to decide: its parameters are one per point, its
    /// residual is the drawn residual over all of them and within the tolerance, and a
    /// short run's segment is the uninterrupted fit of its run, to the bit.
    #[test]
    fn every_segment_of_a_chain_is_measured_and_finished_on_all_its_points() {
        // A wavy closed curve: many curvature extrema, most merged away.
        let points: Vec<Point> = (0..400)
            .map(|i| {
                let a = i as f64 / 400.0 * std::f64::consts::TAU;
                let r = 60.0 + 6.0 * (5.0 * a).sin() + 0.02 * (37.0 * a).sin();
                Point::new(100.0 + r * a.cos(), 100.0 + r * a.sin())
            })
            .collect();
        let c = Contour {
            points,
            is_hole: false,
            parent: None,
            edge_spread: None,
        };
        let seg = find_breaks(&c, &BreakOptions::for_image(50.0, 256, 256), None);
        let opts = LsqOptions::for_tolerance(0.3, false);
        let joints = joint_specs(&seg, &opts);
        let (joints, pieces) = fit_chain(&seg.points, joints, true, &opts);
        assert!(pieces.len() >= 4, "{} pieces", pieces.len());
        let mut buf = Vec::new();
        let (mut decided_early, mut long, mut short) = (0, 0, 0);
        let m = joints.len();
        for (k, piece) in pieces.iter().enumerate() {
            assert!(piece.stopped.is_none());
            let (a, b) = (&joints[k], &joints[(k + 1) % m]);
            cyclic_run(&seg.points, a.index, b.index, &mut buf);
            let run = buf.clone();
            assert_eq!(piece.solution.params.len(), run.len(), "segment {k}");
            let drawn = drawn_residual(&run, &piece.solution);
            assert_eq!(piece.max_residual.to_bits(), drawn.to_bits(), "segment {k}");
            assert!(piece.max_residual <= opts.tolerance, "segment {k}");
            if run.len() < DECISION_SUBSAMPLE_POINTS {
                short += 1;
                let full = fit_piece(&seg.points, a, b, &opts, true, &mut buf);
                assert_eq!(piece.solution.curve, full.solution.curve, "segment {k}");
                assert_eq!(piece.solution.params, full.solution.params);
                assert_eq!(piece.solution.evaluations, full.solution.evaluations);
                assert_eq!(piece.max_residual, full.max_residual);
            } else {
                long += 1;
            }
            let decided = decide_piece(&seg.points, a, b, &opts, true, &mut buf);
            decided_early += usize::from(decided.stopped.is_some());
        }
        // Not vacuous: long runs were decided on half their points, and some of the final
        // segments had been decided early.
        assert!(long > 0 && decided_early > 0, "{long} long, {short} short");
    }

    /// A long run's decision, fitted on every other point, is measured on all of them:
    /// one parameter per point, and its residual the drawn residual over all of them,
    /// both when it fits (and stops early, to be finished) and when it misses.
    #[test]
    fn a_long_runs_decision_on_half_its_points_is_measured_on_all() {
        let n = 41;
        assert!(n >= DECISION_SUBSAMPLE_POINTS);
        let points: Vec<Point> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * 1.5;
                let wobble = 0.03 * ((i * 5) as f64).sin();
                Point::new(40.0 * a.cos() + wobble, 40.0 * a.sin())
            })
            .collect();
        let a = JointSpec {
            index: 0,
            kind: JointKind::Corner,
            tangent: None,
        };
        let b = JointSpec { index: n - 1, ..a };
        let mut buf = Vec::new();
        for (tolerance, fits) in [(0.3, true), (0.005, false)] {
            let opts = LsqOptions::for_tolerance(tolerance, false);
            let piece = decide_piece(&points, &a, &b, &opts, false, &mut buf);
            assert_eq!(piece.solution.params.len(), n);
            let drawn = drawn_residual(&points, &piece.solution);
            assert_eq!(piece.max_residual.to_bits(), drawn.to_bits());
            assert_eq!(
                piece.max_residual <= tolerance,
                fits,
                "{}",
                piece.max_residual
            );
            assert_eq!(piece.stopped.is_some(), fits);
        }
    }

    /// The decision's residual, from the farthest inner foot that the round measured, is
    /// the whole drawn residual to the bit after every round of several runs (noisy arcs,
    /// free and tangent ends), the first and last points and the chords included.
    #[test]
    fn the_residual_from_a_rounds_farthest_foot_is_the_whole_residual() {
        let mut compared = 0;
        for (k, n) in [5usize, 6, 9, 23, 60].into_iter().enumerate() {
            let points: Vec<Point> = (0..n)
                .map(|i| {
                    let a = i as f64 / n as f64 * 2.5;
                    let wobble = 0.2 * ((i * 7 + k) as f64).sin();
                    Point::new(30.0 * a.cos() + wobble, 20.0 * a.sin() - wobble)
                })
                .collect();
            let tangent = |i: usize| EndCondition::Tangent(estimate_tangent(&points, i, 3.0));
            for (start, end) in [
                (EndCondition::Free, EndCondition::Free),
                (tangent(0), tangent(n - 1)),
            ] {
                let settings = FitSettings {
                    reparam_rounds: POLYNOMIAL_ROUNDS,
                    polish_iterations: 0,
                    ..FitSettings::polynomial()
                };
                fit_polynomial_until(&points, start, end, &settings, |curve, params, far| {
                    let whole = residual_at(&points, curve, params);
                    let given = residual_given_inner(&points, curve, params, far);
                    assert_eq!(whole.to_bits(), given.to_bits(), "{n} points");
                    compared += 1;
                    false
                });
            }
        }
        assert!(compared >= 20, "{compared} rounds compared");
    }

    /// `n` points at even parameters on the rational cubic (0, 0), (0, 20), (20, 20),
    /// (20, 0) with inner weights 2: a bulging arch that no polynomial cubic comes within
    /// 0.1 px of.
    fn arch(n: usize) -> Vec<Point> {
        let p = |x, y| Point::new(x, y);
        let curve = RationalCubic::new(
            [p(0.0, 0.0), p(0.0, 20.0), p(20.0, 20.0), p(20.0, 0.0)],
            [2.0, 2.0],
        );
        (0..n)
            .map(|i| curve.eval(i as f64 / (n - 1) as f64))
            .collect()
    }

    /// While splitting, a run of `SPLIT_WEIGHTS_POINTS` or more points that its polynomial
    /// cubic misses is split at once, though it lies exactly on a rational cubic that the
    /// weight search would find: it ends as two or more pieces within the tolerance, and
    /// the merge does not join them into one segment across the split run.
    #[test]
    fn a_long_run_is_split_into_pieces_within_tolerance() {
        let n = 40;
        assert!(n >= SPLIT_WEIGHTS_POINTS);
        let points = arch(n);
        let opts = LsqOptions::for_tolerance(0.08, false);
        let corner = |index| JointSpec {
            index,
            kind: JointKind::Corner,
            tangent: None,
        };
        let (a, b) = (corner(0), corner(n - 1));
        let mut buf = Vec::new();
        let polynomial = fit_piece(&points, &a, &b, &opts, false, &mut buf);
        assert!(polynomial.solution.curve.is_polynomial());
        assert!(polynomial.max_residual > 0.1, "{}", polynomial.max_residual);
        let (joints, pieces) = fit_chain(&points, vec![a, b], false, &opts);
        assert_eq!(joints.len(), pieces.len() + 1);
        assert!(pieces.len() >= 2);
        for p in &pieces {
            assert!(p.max_residual <= 0.08, "{}", p.max_residual);
        }
    }

    /// A line that turns by 60° two points after a smooth joint and runs on for two
    /// points to the next: no cubic leaving along the first line and arriving along the
    /// second follows the turn, and the run of five points is too short to split. The
    /// chain puts a corner at the turn, every piece is then within the tolerance, and the
    /// lines merge across the smooth joints up to the corner.
    #[test]
    fn a_turn_too_short_to_split_gets_a_corner_inside_it() {
        let p = Point::new;
        let (dx, dy) = (0.5, 0.75f64.sqrt());
        let mut points: Vec<Point> = (0..=12).map(|k| p(0.8 * k as f64, 0.0)).collect();
        points.extend((1..=12).map(|k| p(9.6 + 0.8 * dx * k as f64, 0.8 * dy * k as f64)));
        let last = points.len() - 1;
        let opts = LsqOptions::for_tolerance(0.02, false);
        let joint = |index, tangent: Option<Point>| JointSpec {
            index,
            kind: if tangent.is_some() {
                JointKind::Smooth
            } else {
                JointKind::Corner
            },
            tangent,
        };
        let (first, second) = (Some(p(1.0, 0.0)), Some(p(dx, dy)));
        let (i1, i2) = (10, 14);
        assert!(run_len(points.len(), i1, i2) < MIN_SPLIT_POINTS);
        let mut buf = Vec::new();
        let smooth = fit_piece(
            &points,
            &joint(i1, first),
            &joint(i2, second),
            &opts,
            true,
            &mut buf,
        );
        assert!(smooth.max_residual > 0.02, "{}", smooth.max_residual);
        let chain = vec![
            joint(0, None),
            joint(i1, first),
            joint(i2, second),
            joint(last, None),
        ];
        let (joints, pieces) = fit_chain(&points, chain, false, &opts);
        for piece in &pieces {
            assert!(piece.max_residual <= 0.02, "{}", piece.max_residual);
        }
        // The corner at the turn, and the lines on both sides merged up to it.
        let kinds: Vec<(usize, JointKind)> = joints.iter().map(|j| (j.index, j.kind)).collect();
        assert_eq!(
            kinds,
            [
                (0, JointKind::Corner),
                (12, JointKind::Corner),
                (last, JointKind::Corner)
            ]
        );
    }

    /// A 60 px square whose sides wave by 1.5 px, 60 points a side, corners at 0, 60,
    /// 120, 180.
    fn wavy_square() -> SegmentedContour {
        let mut points = Vec::new();
        let corners = [(0.0, 0.0), (60.0, 0.0), (60.0, 60.0), (0.0, 60.0)];
        for side in 0..4 {
            let (a, b) = (corners[side], corners[(side + 1) % 4]);
            let (a, b) = (Point::new(a.0, a.1), Point::new(b.0, b.1));
            let normal = Point::new(-(b.y - a.y) / 60.0, (b.x - a.x) / 60.0);
            for k in 0..60 {
                let t = k as f64 / 60.0;
                let wave = 1.5 * (t * std::f64::consts::TAU * 2.0).sin();
                points.push(a + (b - a) * t + normal * wave);
            }
        }
        let breaks = (0..4)
            .map(|k| Break {
                index: 60 * k,
                kind: JointKind::Corner,
                reason: BreakReason::Corner,
            })
            .collect();
        SegmentedContour {
            points,
            is_hole: false,
            parent: None,
            breaks,
        }
    }

    #[test]
    fn refit_runs_keeps_clean_runs_and_tightens_the_dirty_one() {
        let seg = wavy_square();
        let loose = LsqOptions::for_tolerance(0.3, false);
        let previous = fit_contour(&seg, &loose);
        // Nothing dirty and the same corners: every segment is kept as it was.
        let (same, none) = refit_runs(&previous, &seg, &|_, _| false, &loose);
        assert_eq!(none, 0);
        let curves = |c: &FittedContour| c.segments.iter().map(|s| s.curve).collect::<Vec<_>>();
        assert_eq!(curves(&same), curves(&previous));
        // The run from corner 60 to corner 120 fitted at 0.05 px; the others untouched.
        let tight = LsqOptions::for_tolerance(0.05, false);
        let (refit, refitted) = refit_runs(&previous, &seg, &|a, _| a == 60, &tight);
        assert_eq!(refitted, 61);
        let in_run = |s: &FittedSegment| s.start >= 60 && s.end <= 120 && s.start < s.end;
        let outside = |c: &FittedContour| {
            c.segments
                .iter()
                .filter(|s| !in_run(s))
                .map(|s| s.curve)
                .collect::<Vec<_>>()
        };
        assert_eq!(outside(&refit), outside(&previous));
        for s in refit.segments.iter().filter(|s| in_run(s)) {
            assert!(
                s.error.max_distance <= 0.05 + 1e-9,
                "{}",
                s.error.max_distance
            );
        }
        assert!(
            refit.segments.iter().filter(|s| in_run(s)).count()
                > previous.segments.iter().filter(|s| in_run(s)).count()
        );
        // Still a closed chain, G1 at every smooth joint, corners where they were.
        let m = refit.segments.len();
        assert_eq!(refit.joints.len(), m);
        for k in 0..m {
            assert_eq!(
                refit.segments[k].curve.points[3],
                refit.segments[(k + 1) % m].curve.points[0]
            );
            assert_eq!(refit.joints[k].index, refit.segments[k].start);
        }
        for j in &refit.joints {
            if j.kind == JointKind::Smooth {
                assert!(j.angle < 1e-9, "joint angle {}", j.angle);
            } else {
                assert_eq!(j.index % 60, 0);
            }
        }
    }

    #[test]
    fn tangent_of_a_circle_is_perpendicular_to_the_radius() {
        let pts = ellipse(300)
            .into_iter()
            .map(|p| Point::new(60.0 + (p.x - 60.0), 50.0 + (p.y - 50.0) * 1.6))
            .collect::<Vec<_>>();
        let t = estimate_tangent(&pts, 10, 3.0);
        let radial = pts[10] - Point::new(60.0, 50.0);
        assert!(
            t.dot(radial).abs() / radial.length() < 2e-3,
            "{}",
            t.dot(radial)
        );
    }
}
