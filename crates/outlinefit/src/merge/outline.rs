//! Merging runs of smooth segments of a traced outline into disk Wang–Ball curves
//! (`trace --merge`).
//!
//! After fitting, each contour is walked from a corner (or from its first joint when it has
//! none). Within every stretch of segments joined by smooth joints, segments are merged
//! greedily: starting from a segment, the run is extended one segment at a time while a
//! single polynomial center curve of degree n (default 5) fits the run's data points within
//! the tolerance; the longest run of at least two segments that fits is replaced, and the
//! walk continues after it.
//!
//! The center curve of a run is fitted in the Bézier form (the same polynomials as the
//! Wang–Ball form; converted exactly afterwards):
//! * its end points are the run's end joints, so the outline stays closed;
//! * where a run ends at a smooth joint, its end tangent is the joint's unit tangent
//!   (`P₁ = P₀ + α T₀`, `P_{n−1} = P_n − β T₁`, α, β > 0 solved with the rest), so the
//!   outline stays G1 there; at a corner the end tangent is free;
//! * the other control points by linear least squares at chord-length parameters, refined by
//!   parameter correction (each parameter moved to its point's projection, then refitted)
//!   until the largest distance is within tolerance or stops improving.
//!
//! The radius function carries the fit-error envelope: the radii solve a bounded least
//! squares problem (radii ≥ 0) matching each data point's distance to the center curve at
//! its parameter, then all radii are raised by the largest shortfall (the Wang–Ball basis
//! sums to 1, so this lifts `R` uniformly). Every data point therefore lies within the disk
//! at its own parameter: the merged curve is a center line with an error band.
//!
//! The reported merging error generalises the center term of Eq. 10 to k replaced segments:
//! `Σ_s ∫₀¹ |S_s(u) − C(τ_{s−1} + (τ_s − τ_{s−1}) u)|² du`, where `τ_s` is the center
//! curve's parameter at the joint between segments s and s + 1 and `S_s` the replaced
//! rational segment (16-point Gauss–Legendre; the integrand is rational, not polynomial).

use super::bounded::minimize_lower_bounded;
use crate::curve::basis::{bernstein, de_casteljau};
use crate::curve::wang_ball::{
    bezier_points_to_wang_ball, wang_ball_basis, wang_ball_points_to_bezier, Disk, DiskWangBall,
};
use crate::curve::CubicBez;
use crate::fit::{FittedContour, JointKind};
use crate::geom::Point;
use crate::linalg::cramer2;
use crate::param::{parameters_into, Parameterization};
use crate::quad::GaussLegendre;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Lowest merged degree: a run needs free control points beyond its end tangents.
pub(crate) const MIN_OUTLINE_DEGREE: usize = 3;

/// Parameter-correction rounds per fit.
const CORRECTIONS: usize = 12;

/// Options of outline merging.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct OutlineMergeOptions {
    /// Degree of the merged center curves and radius functions. Default 5.
    pub degree: usize,
    /// Largest allowed distance (px) from a data point to the merged center curve.
    pub tolerance: f64,
}

/// One control disk in reports.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DiskReport {
    /// Center x.
    pub x: f64,
    /// Center y.
    pub y: f64,
    /// Radius.
    pub r: f64,
}

/// A run of segments of a contour replaced by one disk Wang–Ball curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MergedCurve {
    /// Index of the first replaced segment.
    pub first_segment: usize,
    /// Number of replaced segments (≥ 2), counted cyclically from `first_segment`.
    pub segment_count: usize,
    /// Degree of the Wang–Ball curve.
    pub degree: usize,
    /// Control disks (Wang–Ball form): centers of the center curve and radii of the error
    /// band.
    pub disks: Vec<DiskReport>,
    /// Number of data points of the run.
    pub point_count: usize,
    /// Largest distance from a data point to the center curve (px), ≤ the tolerance.
    pub max_distance: f64,
    /// Root mean square of those distances (px).
    pub rms_distance: f64,
    /// Eq. 10's center term over the replaced segments (px²), see the module docs.
    pub merging_error: f64,
}

impl MergedCurve {
    /// The disk Wang–Ball curve.
    pub fn curve(&self) -> DiskWangBall {
        DiskWangBall {
            disks: self
                .disks
                .iter()
                .map(|d| Disk::new(Point::new(d.x, d.y), d.r))
                .collect(),
        }
    }

    /// The center curve as polynomial cubics within `bound` (px) of it, for SVG: the exact
    /// Bézier form of the center curve, then the C1-constrained reduction to a cubic (end
    /// points and end derivatives kept; for a cubic that leaves nothing free); where that is
    /// more than `bound` away, the G1 cubic (end tangent directions kept, their magnitudes by
    /// least squares); where that fails too, the parameter range is halved. The distance is
    /// measured at 31 parameters per piece as `max |B(t) − H(t)|`, which bounds the
    /// geometric distance there. Pieces meet G1: each keeps its sub-curve's end tangents.
    pub fn center_cubics(&self, bound: f64) -> Vec<CubicBez> {
        let centers: Vec<Point> = self.disks.iter().map(|d| Point::new(d.x, d.y)).collect();
        let bezier = wang_ball_points_to_bezier(&centers);
        let mut out = Vec::new();
        cubics_into(&bezier, bound, 0, &mut out);
        out
    }

    /// Whether segment `k` of a contour with `n` segments is replaced by this curve.
    pub fn covers(&self, k: usize, n: usize) -> bool {
        (k + n - self.first_segment) % n < self.segment_count
    }
}

/// One piece of a contour as drawn: a fitted segment, or a run of segments replaced by a
/// merged curve.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Piece<'a> {
    /// Segment `k` of the contour, drawn as it was fitted.
    Segment(usize),
    /// A merged curve, drawn in place of its run of segments.
    Merged(&'a MergedCurve),
}

/// The pieces of `contour` with its `merged` curves, in drawing order. A merged run that
/// wraps past the end of the segment list makes the walk start at its first segment.
pub(crate) fn walk_pieces<'a>(
    contour: &FittedContour,
    merged: &'a [MergedCurve],
) -> Vec<Piece<'a>> {
    let n = contour.segments.len();
    if merged.is_empty() {
        return (0..n).map(Piece::Segment).collect();
    }
    let start = merged
        .iter()
        .find(|m| m.first_segment + m.segment_count > n)
        .map_or(0, |m| m.first_segment % n);
    let mut out = Vec::new();
    let mut walked = 0;
    while walked < n {
        let k = (start + walked) % n;
        match merged.iter().find(|m| m.first_segment == k) {
            Some(m) if m.segment_count >= 1 => {
                out.push(Piece::Merged(m));
                walked += m.segment_count;
            }
            _ => {
                out.push(Piece::Segment(k));
                walked += 1;
            }
        }
    }
    out
}

/// What the SVG draws of `contour` with its `merged` curves, in order: for each segment
/// (or run of segments replaced by a merged curve) its start point and its polynomial
/// cubics ([`walk_pieces`]).
pub(crate) fn drawing_pieces(
    contour: &FittedContour,
    merged: &[MergedCurve],
    bound: f64,
) -> Vec<(Point, Vec<CubicBez>)> {
    walk_pieces(contour, merged)
        .into_iter()
        .map(|piece| match piece {
            Piece::Segment(k) => {
                let s = &contour.segments[k];
                (s.curve.points[0], s.drawn_cubics(bound).into_owned())
            }
            Piece::Merged(m) => (
                contour.segments[m.first_segment].curve.points[0],
                m.center_cubics(bound),
            ),
        })
        .collect()
}

/// Number of curves drawn for `contour` with its `merged` curves: segments not replaced
/// by merged curves, plus the merged curves.
pub(crate) fn curve_count(contour: &FittedContour, merged: &[MergedCurve]) -> usize {
    let replaced: usize = merged.iter().map(|m| m.segment_count).sum();
    contour.segments.len() - replaced.min(contour.segments.len()) + merged.len()
}

/// The merged curves of one contour, in walking order (the first may wrap past the end of
/// the segment list). Contours with fewer than three segments are left alone, and so is
/// every contour when the degree is outside `MIN_OUTLINE_DEGREE..=MAX_DEGREE` or the
/// tolerance is not a positive number ([`crate::Config::validate`] reports those).
pub(crate) fn merge_contour(
    contour: &FittedContour,
    options: &OutlineMergeOptions,
) -> Vec<MergedCurve> {
    let n = contour.segments.len();
    let valid = (MIN_OUTLINE_DEGREE..=super::MAX_DEGREE).contains(&options.degree)
        && options.tolerance > 0.0
        && options.tolerance.is_finite();
    if !valid || n < 3 || contour.joints.len() != n {
        return Vec::new();
    }
    // Start the walk at a corner if there is one: stretches then never wrap inside.
    let start = (0..n)
        .find(|&i| contour.joints[i].kind == JointKind::Corner)
        .unwrap_or(0);
    let mut merged = Vec::new();
    let mut i = 0;
    while i < n {
        // Longest run from segment start + i that fits.
        let mut best: Option<MergedCurve> = None;
        let mut len = 2;
        while i + len <= n {
            let last = (start + i + len - 1) % n;
            // Segment `last` must be joined smoothly to its predecessor.
            if contour.joints[last].kind != JointKind::Smooth {
                break;
            }
            match fit_run(contour, (start + i) % n, len, options) {
                Some(m) => best = Some(m),
                None => break,
            }
            len += 1;
        }
        match best {
            Some(m) => {
                i += m.segment_count;
                merged.push(m);
            }
            None => i += 1,
        }
    }
    merged
}

/// Fits one center curve (and radius function) to the `len` segments from `first`; `None`
/// when it does not stay within tolerance or the problem degenerates.
fn fit_run(
    contour: &FittedContour,
    first: usize,
    len: usize,
    options: &OutlineMergeOptions,
) -> Option<MergedCurve> {
    let n_seg = contour.segments.len();
    let degree = options.degree;
    // The run's data points, shared joints once; remember where each joint falls.
    let mut points: Vec<Point> = Vec::new();
    let mut joint_at = Vec::with_capacity(len + 1);
    let mut scratch = Vec::new();
    for k in 0..len {
        let s = (first + k) % n_seg;
        contour.segment_points_into(s, &mut scratch);
        if scratch.len() < 2 {
            return None;
        }
        if k == 0 {
            joint_at.push(0);
            points.extend_from_slice(&scratch);
        } else {
            points.extend_from_slice(&scratch[1..]);
        }
        joint_at.push(points.len() - 1);
    }
    let first_seg = &contour.segments[first];
    let last_seg = &contour.segments[(first + len - 1) % n_seg];
    let p0 = first_seg.curve.points[0];
    let pn = last_seg.curve.points[3];
    // Tangent constraints where the run meets smooth joints.
    let t0 = (contour.joints[first].kind == JointKind::Smooth)
        .then(|| first_seg.curve.start_tangent())
        .flatten();
    let end_joint = (first + len) % n_seg;
    let t1 = (contour.joints[end_joint].kind == JointKind::Smooth)
        .then(|| last_seg.curve.end_tangent())
        .flatten();
    if points.len() < degree + 2 {
        return None;
    }
    let mut params = chord_params(&points);
    let mut best: Option<(f64, Vec<Point>, Vec<f64>)> = None;
    for _ in 0..CORRECTIONS {
        let ctrl = solve_center(&points, &params, degree, p0, pn, t0, t1)?;
        let bez = Bezier::new(ctrl.clone());
        for (t, &p) in params.iter_mut().zip(&points) {
            *t = bez.project(p, *t);
        }
        // The ends are the joints themselves.
        let count = params.len();
        params[0] = 0.0;
        params[count - 1] = 1.0;
        let worst = points
            .iter()
            .zip(&params)
            .map(|(&p, &t)| bez.eval(t).distance(p))
            .fold(0.0, f64::max);
        let improved = best.as_ref().is_none_or(|b| worst < b.0 * (1.0 - 1e-6));
        if improved {
            best = Some((worst, ctrl, params.clone()));
        }
        if worst <= options.tolerance || !improved {
            break;
        }
    }
    let (worst, ctrl, params) = best?;
    if worst.is_nan() || worst > options.tolerance {
        return None;
    }
    let bez = Bezier::new(ctrl.clone());
    let distances: Vec<f64> = points
        .iter()
        .zip(&params)
        .map(|(&p, &t)| bez.eval(t).distance(p))
        .collect();
    let rms = (distances.iter().map(|d| d * d).sum::<f64>() / distances.len() as f64).sqrt();
    let radii = envelope_radii(&params, &distances, degree)?;
    let centers = bezier_points_to_wang_ball(&ctrl);
    // Eq. 10's center term over the replaced segments.
    let rule = GaussLegendre::new(16);
    let mut merging_error = 0.0;
    for k in 0..len {
        let seg = &contour.segments[(first + k) % n_seg].curve;
        let (a, b) = (params[joint_at[k]], params[joint_at[k + 1]]);
        merging_error += rule.integrate(
            |u| (seg.eval(u) - bez.eval(a + (b - a) * u)).length_squared(),
            0.0,
            1.0,
        );
    }
    let disks = centers
        .iter()
        .zip(&radii)
        .map(|(c, &r)| DiskReport { x: c.x, y: c.y, r })
        .collect();
    Some(MergedCurve {
        first_segment: first,
        segment_count: len,
        degree,
        disks,
        point_count: points.len(),
        max_distance: worst,
        rms_distance: rms,
        merging_error,
    })
}

/// Deepest halving of [`MergedCurve::center_cubics`] (2¹² pieces at most).
const MAX_CUBIC_DEPTH: u32 = 12;

/// Largest `|B(t) − H(t)|` at 31 interior parameters.
fn parametric_distance(bezier: &[Point], cubic: &CubicBez) -> f64 {
    (1..32)
        .map(|i| {
            let t = i as f64 / 32.0;
            de_casteljau(bezier, t).distance(cubic.eval(t))
        })
        .fold(0.0, f64::max)
}

fn cubics_into(bezier: &[Point], bound: f64, depth: u32, out: &mut Vec<CubicBez>) {
    let cubic = c1_cubic(bezier);
    let worst = parametric_distance(bezier, &cubic);
    if worst <= bound || depth >= MAX_CUBIC_DEPTH || !worst.is_finite() {
        out.push(cubic);
        return;
    }
    // Before halving, let the end-derivative magnitudes go (tangent directions kept, so
    // the pieces still meet G1): often one cubic is then enough.
    if let Some(g1) = g1_cubic(bezier) {
        if parametric_distance(bezier, &g1) <= bound {
            out.push(g1);
            return;
        }
    }
    let (left, right) = split(bezier, 0.5);
    cubics_into(&left, bound, depth + 1, out);
    cubics_into(&right, bound, depth + 1, out);
}

/// The cubic with the same end points and end derivatives as a Bézier curve of degree
/// n ≥ 1: `P₁ = B₀ + n/3 (B₁ − B₀)`, `P₂ = B_n − n/3 (B_n − B_{n−1})`.
pub(crate) fn c1_cubic(bezier: &[Point]) -> CubicBez {
    let n = bezier.len() - 1;
    let k = n as f64 / 3.0;
    let (b0, bn) = (bezier[0], bezier[n]);
    CubicBez::new(
        b0,
        b0 + (bezier[1] - b0) * k,
        bn - (bn - bezier[n - 1]) * k,
        bn,
    )
}

/// The cubic with the Bézier curve's end points and end tangent directions whose two
/// tangent magnitudes minimise `Σ |B(t_k) − H(t_k)|²` over 31 interior parameters (a 2×2
/// linear least-squares problem); `None` when a magnitude would not be positive.
fn g1_cubic(bezier: &[Point]) -> Option<CubicBez> {
    let n = bezier.len() - 1;
    let (b0, bn) = (bezier[0], bezier[n]);
    let d0 = (bezier[1] - b0).normalized()?;
    let d1 = (bn - bezier[n - 1]).normalized()?;
    // With P1 = b0 + a d0 and P2 = bn − b d1 the cubic is
    // H(t) = (B₀ + B₁)(t) b0 + (B₂ + B₃)(t) bn + a B₁(t) d0 − b B₂(t) d1.
    let (mut m00, mut m01, mut m11, mut r0, mut r1) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 1..32 {
        let t = i as f64 / 32.0;
        let s = 1.0 - t;
        let fixed = b0 * (s * s * s + 3.0 * t * s * s) + bn * (3.0 * t * t * s + t * t * t);
        let u = d0 * (3.0 * t * s * s);
        let v = d1 * (-3.0 * t * t * s);
        let target = de_casteljau(bezier, t) - fixed;
        m00 += u.dot(u);
        m01 += u.dot(v);
        m11 += v.dot(v);
        r0 += u.dot(target);
        r1 += v.dot(target);
    }
    let (det, [a, b]) = cramer2([[m00, m01], [m01, m11]], [r0, r1]);
    if det.abs() <= 1e-300 {
        return None;
    }
    (a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite())
        .then(|| CubicBez::new(b0, b0 + d0 * a, bn - d1 * b, bn))
}

/// De Casteljau subdivision at `t`.
fn split(points: &[Point], t: f64) -> (Vec<Point>, Vec<Point>) {
    let mut work = points.to_vec();
    let len = work.len();
    let mut left = Vec::with_capacity(len);
    let mut right = Vec::with_capacity(len);
    for r in 0..len {
        left.push(work[0]);
        right.push(work[len - 1 - r]);
        for i in 0..len - 1 - r {
            work[i] = work[i].lerp(work[i + 1], t);
        }
    }
    right.reverse();
    (left, right)
}

/// Chord-length parameters in [0, 1].
fn chord_params(points: &[Point]) -> Vec<f64> {
    let mut t = Vec::with_capacity(points.len());
    parameters_into(points, Parameterization::Chordal, &mut t);
    t
}

/// Least-squares Bézier control points with fixed ends and optional end tangents (α, β > 0
/// required); `None` if degenerate or a tangent would reverse.
fn solve_center(
    points: &[Point],
    params: &[f64],
    n: usize,
    p0: Point,
    pn: Point,
    t0: Option<Point>,
    t1: Option<Point>,
) -> Option<Vec<Point>> {
    // Unknown layout: [α if t0] [β if t1] then x, y of every free inner point.
    let inner_from = if t0.is_some() { 2 } else { 1 };
    let inner_to = if t1.is_some() { n - 2 } else { n - 1 };
    let scalars = usize::from(t0.is_some()) + usize::from(t1.is_some());
    let free = inner_to + 1 - inner_from;
    let cols = scalars + 2 * free;
    let mut a = DMatrix::<f64>::zeros(2 * points.len(), cols);
    let mut rhs = DVector::<f64>::zeros(2 * points.len());
    let mut b = vec![0.0; n + 1];
    for (row, (&p, &t)) in points.iter().zip(params).enumerate() {
        bernstein(n, t, &mut b);
        let mut fixed = p0 * (b[0]) + pn * b[n];
        let mut c = 0;
        if let Some(t0) = t0 {
            fixed += p0 * b[1];
            a[(2 * row, c)] = b[1] * t0.x;
            a[(2 * row + 1, c)] = b[1] * t0.y;
            c += 1;
        }
        if let Some(t1) = t1 {
            fixed += pn * b[n - 1];
            a[(2 * row, c)] = -b[n - 1] * t1.x;
            a[(2 * row + 1, c)] = -b[n - 1] * t1.y;
            c += 1;
        }
        for (k, j) in (inner_from..=inner_to).enumerate() {
            a[(2 * row, c + 2 * k)] = b[j];
            a[(2 * row + 1, c + 2 * k + 1)] = b[j];
        }
        rhs[2 * row] = p.x - fixed.x;
        rhs[2 * row + 1] = p.y - fixed.y;
    }
    let z = a.svd(true, true).solve(&rhs, 1e-12).ok()?;
    if z.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut ctrl = vec![Point::ZERO; n + 1];
    ctrl[0] = p0;
    ctrl[n] = pn;
    let mut c = 0;
    if let Some(t0) = t0 {
        if z[c] <= 0.0 {
            return None;
        }
        ctrl[1] = p0 + t0 * z[c];
        c += 1;
    }
    if let Some(t1) = t1 {
        if z[c] <= 0.0 {
            return None;
        }
        ctrl[n - 1] = pn - t1 * z[c];
        c += 1;
    }
    for (k, j) in (inner_from..=inner_to).enumerate() {
        ctrl[j] = Point::new(z[c + 2 * k], z[c + 2 * k + 1]);
    }
    Some(ctrl)
}

/// Wang–Ball radii of degree `n` whose radius function is ≥ every distance at its parameter
/// (bounded least squares, then lifted by the largest shortfall).
fn envelope_radii(params: &[f64], distances: &[f64], n: usize) -> Option<Vec<f64>> {
    let m = n + 1;
    let mut g = DMatrix::<f64>::zeros(m, m);
    let mut b = DVector::<f64>::zeros(m);
    let mut w = vec![0.0; m];
    for (&t, &d) in params.iter().zip(distances) {
        wang_ball_basis(n, t, &mut w);
        for i in 0..m {
            b[i] += w[i] * d;
            for j in 0..m {
                g[(i, j)] += w[i] * w[j];
            }
        }
    }
    // A tiny ridge keeps the system definite when few points land near some basis function.
    let ridge = 1e-12 * g.diagonal().max().max(f64::MIN_POSITIVE);
    for i in 0..m {
        g[(i, i)] += ridge;
    }
    let mut r: Vec<f64> = minimize_lower_bounded(&g, &b, &vec![0.0; m])
        .ok()?
        .iter()
        .copied()
        .collect();
    let mut shortfall: f64 = 0.0;
    for (&t, &d) in params.iter().zip(distances) {
        wang_ball_basis(n, t, &mut w);
        let radius: f64 = w.iter().zip(&r).map(|(a, b)| a * b).sum();
        shortfall = shortfall.max(d - radius);
    }
    // A relative hair more than the shortfall absorbs the rounding of the lift itself.
    let lift = shortfall.max(0.0) * (1.0 + 1e-9) + 1e-12;
    for v in &mut r {
        *v += lift;
    }
    Some(r)
}

/// A polynomial Bézier curve of any degree with its first two hodographs.
pub(crate) struct Bezier {
    points: Vec<Point>,
    d1: Vec<Point>,
    d2: Vec<Point>,
}

impl Bezier {
    pub(crate) fn new(points: Vec<Point>) -> Self {
        let d1 = hodograph(&points);
        let d2 = hodograph(&d1);
        Bezier { points, d1, d2 }
    }

    pub(crate) fn eval(&self, t: f64) -> Point {
        de_casteljau(&self.points, t)
    }

    /// Local projection of `p` by Newton steps from `t`, kept in [0, 1].
    fn project(&self, p: Point, mut t: f64) -> f64 {
        for _ in 0..6 {
            let c = self.eval(t) - p;
            let d1 = de_casteljau(&self.d1, t);
            let d2 = de_casteljau(&self.d2, t);
            let g = c.dot(d1);
            let dg = d1.dot(d1) + c.dot(d2);
            if dg.is_nan() || dg <= 0.0 {
                break;
            }
            let next = (t - g / dg).clamp(0.0, 1.0);
            if (next - t).abs() < 1e-14 {
                t = next;
                break;
            }
            t = next;
        }
        t
    }
}

fn hodograph(points: &[Point]) -> Vec<Point> {
    let n = points.len().saturating_sub(1) as f64;
    points.windows(2).map(|w| (w[1] - w[0]) * n).collect()
}

#[cfg(test)]
mod tests;
