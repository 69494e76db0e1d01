//! Fits one stroke's centres and radii as a chain of cubic disk Wang–Ball curves: corners
//! where the centre line turns sharply, G1 joints elsewhere, a split wherever the centre
//! misses the tolerance or the radius misses it.
//!
//! The centre curve of each piece is the outline fit's polynomial cubic (`fit::solve`,
//! tangent ends at smooth joints, free ends at corners and stroke ends). The radius is a
//! cubic in the same parameter with its end values fixed at the joints (so the width is
//! continuous along the stroke) and its two inner coefficients by least squares. Both are
//! then written in the Wang–Ball basis: a cubic disk Wang–Ball curve is exactly a centre
//! cubic with a cubic radius.

use crate::breaks::JointKind;
use crate::curve::wang_ball::{bezier_points_to_wang_ball, Disk, DiskWangBall};
use crate::curve::RationalCubic;
use crate::fit::lsq::drawn_residual;
use crate::fit::solve::{fit_segment, segment_error, EndCondition, FitSettings, SegmentSolution};
use crate::geom::{angle_between, Point};
use serde::Serialize;

/// Fewest data points of a piece made by a split.
const MIN_PIECE: usize = 4;

/// The centre curve's fit: a polynomial cubic with parameter correction by projection and
/// no orthogonal polish. The skeleton's centres are noisier than the polish's gain (a few
/// thousandths of a pixel on outlines), and the polish was half of the trace's time.
pub(crate) fn centre_settings() -> FitSettings {
    FitSettings {
        polish_iterations: 0,
        reparam_rounds: 4,
        ..FitSettings::polynomial()
    }
}

/// How a stroke is fitted.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StrokeFitOptions {
    pub(crate) tolerance: f64,
    /// Corner angle, radians.
    pub(crate) corner_angle: f64,
    /// One radius for the whole stroke.
    pub(crate) constant_width: bool,
}

/// One fitted piece of a stroke.
#[derive(Clone, Debug, Serialize)]
pub struct StrokeSegment {
    /// The piece as a cubic disk Wang–Ball curve: its four control disks, written in
    /// reports as `[x, y, r]`.
    #[serde(rename = "control_disks", serialize_with = "disks_as_triples")]
    pub curve: DiskWangBall,
    /// The centre curve in Bézier form (what the SVG draws).
    #[serde(skip)]
    pub(crate) bezier: [Point; 4],
    /// Data points fitted (both ends included).
    pub point_count: usize,
    /// Largest distance from a skeleton centre to the centre curve, px.
    pub centre_max: f64,
    /// Largest difference between a measured radius and the curve's, px.
    pub radius_max: f64,
    /// How this piece meets the next one (the last piece of an open stroke: `None`).
    pub joint: Option<JointKind>,
}

fn disks_as_triples<S: serde::Serializer>(c: &DiskWangBall, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(c.disks.len()))?;
    for d in &c.disks {
        seq.serialize_element(&[d.center.x, d.center.y, d.radius])?;
    }
    seq.end()
}

impl StrokeSegment {
    /// The length of the centre curve as 32 chords: enough to space samples along it.
    /// (The adaptive arc length never settles on a piece of zero length, a dot's.)
    pub(crate) fn chord_length(&self) -> f64 {
        let mut prev = self.curve.center(0.0);
        (1..=32)
            .map(|k| {
                let p = self.curve.center(k as f64 / 32.0);
                let d = p.distance(prev);
                prev = p;
                d
            })
            .sum()
    }
}

/// The fitted chain of a stroke, and its error sums.
pub(crate) struct FittedChain {
    pub(crate) segments: Vec<StrokeSegment>,
    pub(crate) centre_rms: f64,
    pub(crate) radius_rms: f64,
}

/// Arc length of each point from the first.
fn arc(points: &[Point]) -> Vec<f64> {
    let mut s = vec![0.0; points.len()];
    for i in 1..points.len() {
        s[i] = s[i - 1] + points[i].distance(points[i - 1]);
    }
    s
}

/// Indices of the corners of an open run (closed runs are rotated to start at a corner
/// before they come here): local maxima of the turning angle over ±`h` px that exceed
/// `angle`.
fn corners(points: &[Point], h: f64, angle: f64, closed: bool) -> Vec<usize> {
    let n = points.len();
    let s = arc(points);
    let total = s[n - 1]
        + if closed {
            points[n - 1].distance(points[0])
        } else {
            0.0
        };
    let at = |i: usize, offset: f64| -> Option<Point> {
        let target = s[i] + offset;
        if !closed && (target < 0.0 || target > s[n - 1]) {
            return None;
        }
        let t = target.rem_euclid(total.max(1e-9));
        let k = s.partition_point(|&v| v <= t).clamp(1, n) - 1;
        Some(points[k])
    };
    let turn: Vec<f64> = (0..n)
        .map(|i| match (at(i, -h), at(i, h)) {
            (Some(a), Some(b)) => angle_between(points[i] - a, b - points[i]),
            _ => 0.0,
        })
        .collect();
    let mut found = Vec::new();
    for i in 0..n {
        if turn[i] <= angle {
            continue;
        }
        // The largest turn within ±h (earliest index on ties).
        let is_max = (0..n).all(|j| {
            let d = (s[i] - s[j]).abs();
            let d = if closed { d.min(total - d) } else { d };
            d > h || turn[j] < turn[i] || (turn[j] == turn[i] && j >= i)
        });
        if is_max {
            found.push(i);
        }
    }
    found
}

/// Unit tangent at point `i` of an open run: from the mean of the points up to `w` px
/// before it to the mean of those up to `w` px after it.
fn tangent_at(points: &[Point], s: &[f64], i: usize, w: f64) -> Point {
    let mean = |range: &mut dyn Iterator<Item = usize>| {
        let (mut sum, mut k) = (Point::new(0.0, 0.0), 0.0);
        for j in range {
            sum += points[j];
            k += 1.0;
        }
        (k > 0.0).then(|| sum * (1.0 / k))
    };
    let before = mean(&mut (0..i).rev().take_while(|&j| s[i] - s[j] <= w));
    let after = mean(&mut (i + 1..points.len()).take_while(|&j| s[j] - s[i] <= w));
    let a = before.unwrap_or(points[i]);
    let b = after.unwrap_or(points[i]);
    (b - a).normalized().unwrap_or(Point::new(1.0, 0.0))
}

/// The radius at point `i`: a least-squares line in arc length over ±`w` px, evaluated
/// at `i` (so a tapering stroke's end gets its end value, not the window's mean).
fn radius_at(radii: &[f64], s: &[f64], i: usize, w: f64) -> f64 {
    let (mut n, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for j in 0..radii.len() {
        let x = s[j] - s[i];
        if x.abs() <= w {
            n += 1.0;
            sx += x;
            sy += radii[j];
            sxx += x * x;
            sxy += x * radii[j];
        }
    }
    let det = n * sxx - sx * sx;
    if det.abs() < 1e-9 {
        return sy / n.max(1.0);
    }
    (sxx * sy - sx * sxy) / det
}

fn bernstein(t: f64) -> [f64; 4] {
    let m = 1.0 - t;
    [m * m * m, 3.0 * m * m * t, 3.0 * m * t * t, t * t * t]
}

/// The radius cubic with ends `r0`, `r3` closest (least squares) to `radii` at `params`.
fn fit_radius(radii: &[f64], params: &[f64], r0: f64, r3: f64) -> [f64; 4] {
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (&r, &t) in radii.iter().zip(params) {
        let b = bernstein(t);
        let rest = r - b[0] * r0 - b[3] * r3;
        a11 += b[1] * b[1];
        a12 += b[1] * b[2];
        a22 += b[2] * b[2];
        b1 += b[1] * rest;
        b2 += b[2] * rest;
    }
    let det = a11 * a22 - a12 * a12;
    if det.abs() < 1e-12 {
        // Too few points: the straight interpolation.
        return [r0, (2.0 * r0 + r3) / 3.0, (r0 + 2.0 * r3) / 3.0, r3];
    }
    let r1 = (b1 * a22 - b2 * a12) / det;
    let r2 = (a11 * b2 - a12 * b1) / det;
    [r0, r1, r2, r3]
}

fn radius_eval(c: &[f64; 4], t: f64) -> f64 {
    bernstein(t).iter().zip(c).map(|(b, r)| b * r).sum()
}

/// A joint of the chain being built.
#[derive(Clone, Copy)]
struct Joint {
    index: usize,
    tangent: Option<Point>,
    radius: f64,
}

/// Fits a stroke. `closed` strokes have their last point joined back to the first.
/// `constant` is the stroke's one radius with `constant_width`.
pub(crate) fn fit_stroke(
    points: &[Point],
    radii: &[f64],
    closed: bool,
    opts: &StrokeFitOptions,
) -> FittedChain {
    let typical = median(radii);
    let h = typical.max(2.0);
    // Closed strokes: rotate to start at a corner (or anywhere) and repeat the first point
    // at the end.
    let (pts, rad, start_corner) = if closed {
        let c = corners(points, h, opts.corner_angle, true);
        let first = c.first().copied().unwrap_or(0);
        let mut p: Vec<Point> = points[first..]
            .iter()
            .chain(&points[..first])
            .copied()
            .collect();
        let mut r: Vec<f64> = radii[first..]
            .iter()
            .chain(&radii[..first])
            .copied()
            .collect();
        p.push(p[0]);
        r.push(r[0]);
        (p, r, !c.is_empty())
    } else {
        (points.to_vec(), radii.to_vec(), false)
    };
    let n = pts.len();
    let s = arc(&pts);
    let constant = opts.constant_width.then_some(typical);
    let w = h.max(3.0);
    let joint_radius = |i: usize| constant.unwrap_or_else(|| radius_at(&rad, &s, i, w).max(0.0));
    if n < 2 {
        return single_disk(pts[0], constant.unwrap_or(rad[0]));
    }
    let mut cuts: Vec<usize> = corners(
        &pts[..if closed { n - 1 } else { n }],
        h,
        opts.corner_angle,
        false,
    )
    .into_iter()
    .filter(|&i| i >= MIN_PIECE && i + MIN_PIECE < n)
    .collect();
    cuts.insert(0, 0);
    cuts.push(n - 1);
    cuts.dedup();
    let closing_tangent = (closed && !start_corner).then(|| {
        // The tangent where a smooth closed stroke starts and ends.
        let k = (1..n).take_while(|&j| s[j] <= w).last().unwrap_or(1);
        let back = (0..n - 1)
            .rev()
            .take_while(|&j| s[n - 1] - s[j] <= w)
            .last()
            .unwrap_or(n - 2);
        (pts[k] - pts[back])
            .normalized()
            .unwrap_or(Point::new(1.0, 0.0))
    });
    let mut joints: Vec<(Joint, JointKind)> = cuts
        .iter()
        .map(|&i| {
            let kind = if i == 0 || i == n - 1 {
                if closing_tangent.is_some() {
                    JointKind::Smooth
                } else {
                    JointKind::Corner
                }
            } else {
                JointKind::Corner
            };
            let tangent = if i == 0 || i == n - 1 {
                closing_tangent
            } else {
                None
            };
            (
                Joint {
                    index: i,
                    tangent,
                    radius: joint_radius(i),
                },
                kind,
            )
        })
        .collect();
    if closed {
        // Both ends are the same point: one radius.
        let r = joints[0].0.radius;
        if let Some(last) = joints.last_mut() {
            last.0.radius = r;
        }
    }
    let mut segments = Vec::new();
    let (mut centre_sq, mut radius_sq, mut count) = (0.0, 0.0, 0usize);
    let mut k = 0;
    while k + 1 < joints.len() {
        let (a, b) = (joints[k].0, joints[k + 1].0);
        let run = &pts[a.index..=b.index];
        let run_r = &rad[a.index..=b.index];
        let start = a.tangent.map_or(EndCondition::Free, EndCondition::Tangent);
        let end = b.tangent.map_or(EndCondition::Free, EndCondition::Tangent);
        let mut sol = fit_segment(run, start, end, &centre_settings());
        let mut err = segment_error(&sol.curve, run, &sol.params);
        // A curve that loops out between two points is as far off as its loop.
        err.max_distance = err.max_distance.max(drawn_residual(run, &sol));
        if err.max_distance > opts.tolerance && run.len() < 2 * MIN_PIECE + 1 {
            // Too short to split: the straight piece, if it is closer.
            let line = straight(run, start, end);
            let mut line_err = segment_error(&line.curve, run, &line.params);
            line_err.max_distance = line_err.max_distance.max(drawn_residual(run, &line));
            if line_err.max_distance < err.max_distance {
                (sol, err) = (line, line_err);
            }
        }
        let radius = constant.map_or_else(
            || fit_radius(run_r, &sol.params, a.radius, b.radius),
            |r| [r; 4],
        );
        let (mut radius_max, mut worst_r) = (0.0f64, 0);
        for (j, (&r, &t)) in run_r.iter().zip(&sol.params).enumerate() {
            let d = (radius_eval(&radius, t) - r).abs();
            if d > radius_max {
                (radius_max, worst_r) = (d, j);
            }
        }
        let misses = err.max_distance > opts.tolerance
            || (constant.is_none() && radius_max > opts.tolerance);
        if misses && run.len() > 2 * MIN_PIECE {
            // Split at the worst centre point (or the worst radius), kept away from the ends.
            let worst = if err.max_distance > opts.tolerance {
                worst_point(&sol.curve, run, &sol.params)
            } else {
                worst_r
            };
            let at = a.index + worst.clamp(MIN_PIECE, run.len() - 1 - MIN_PIECE);
            let joint = Joint {
                index: at,
                tangent: Some(tangent_at(&pts, &s, at, w)),
                radius: joint_radius(at),
            };
            joints.insert(k + 1, (joint, JointKind::Smooth));
            continue;
        }
        for (j, (&r, &t)) in run_r.iter().zip(&sol.params).enumerate() {
            if j + 1 == run.len() && k + 2 < joints.len() {
                break; // the next piece's first point
            }
            let d = sol.curve.eval(t).distance(run[j]);
            centre_sq += d * d;
            let dr = radius_eval(&radius, t) - r;
            radius_sq += dr * dr;
            count += 1;
        }
        let bezier = sol.curve.points;
        let centres = bezier_points_to_wang_ball(&bezier);
        let radii_wb = bezier_points_to_wang_ball(&radius.map(|r| Point::new(r, 0.0)));
        let disks = centres
            .iter()
            .zip(&radii_wb)
            .map(|(&c, r)| Disk::new(c, r.x))
            .collect();
        let last = k + 2 == joints.len();
        segments.push(StrokeSegment {
            curve: DiskWangBall::new(disks),
            bezier,
            point_count: run.len(),
            centre_max: err.max_distance,
            radius_max,
            joint: if last && !closed {
                None
            } else {
                Some(joints[k + 1].1)
            },
        });
        k += 1;
    }
    let count = count.max(1) as f64;
    FittedChain {
        segments,
        centre_rms: (centre_sq / count).sqrt(),
        radius_rms: (radius_sq / count).sqrt(),
    }
}

/// The straight piece from the first point to the last (handles a third of the chord, along
/// the end tangents where they are given), with each point's parameter its projection.
fn straight(run: &[Point], start: EndCondition, end: EndCondition) -> SegmentSolution {
    let (a, b) = (run[0], run[run.len() - 1]);
    let chord = b - a;
    let len = chord.length() / 3.0;
    let c1 = match start {
        EndCondition::Tangent(t) => a + t * len,
        EndCondition::Free => a + chord * (1.0 / 3.0),
    };
    let c2 = match end {
        EndCondition::Tangent(t) => b - t * len,
        EndCondition::Free => b - chord * (1.0 / 3.0),
    };
    let curve = RationalCubic::new([a, c1, c2, b], [1.0, 1.0]);
    let l2 = chord.length_squared().max(1e-12);
    let mut params: Vec<f64> = run
        .iter()
        .map(|p| ((*p - a).dot(chord) / l2).clamp(0.0, 1.0))
        .collect();
    // Parameters must not decrease along the run.
    for k in 1..params.len() {
        params[k] = params[k].max(params[k - 1]);
    }
    SegmentSolution {
        curve,
        params,
        evaluations: 0,
    }
}

/// The index of the point farthest from its place on the curve.
fn worst_point(curve: &RationalCubic, run: &[Point], params: &[f64]) -> usize {
    let mut worst = (0.0, run.len() / 2);
    for (j, (&p, &t)) in run.iter().zip(params).enumerate() {
        let d = curve.eval(t).distance(p);
        if d > worst.0 {
            worst = (d, j);
        }
    }
    worst.1
}

/// A stroke of one point: a degenerate piece, one disk.
fn single_disk(p: Point, r: f64) -> FittedChain {
    FittedChain {
        segments: vec![StrokeSegment {
            curve: DiskWangBall::new(vec![Disk::new(p, r); 4]),
            bezier: [p; 4],
            point_count: 1,
            centre_max: 0.0,
            radius_max: 0.0,
            joint: None,
        }],
        centre_rms: 0.0,
        radius_rms: 0.0,
    }
}

/// The median of a list (0 for an empty one).
pub(crate) fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}
