//! Break points: where a closed contour is cut into segments.
//!
//! Curvature is measured as a turning angle over a window of arc length: at point i the
//! angle between the chord arriving from s_i − h and the chord leaving to s_i + h. This is
//! robust to the residual noise of sub-pixel boundaries, and the window `h` is scaled to the
//! image so that 64 px and 1024 px glyphs behave alike ([`BreakOptions::for_image`]).
//!
//! * **Corners** (G0 joints): local maxima of the turning angle above the corner angle.
//! * **Inflections** (smooth joints): sign changes of the signed turning angle between two
//!   lobes that both bend clearly (above a noise floor), located at the zero crossing by
//!   linear interpolation between samples.
//! * **Curvature extrema** (smooth joints): local maxima of |turning angle| above the noise
//!   floor, located to sub-sample accuracy by the parabola through the three neighbouring
//!   samples, as in Algorithm 1 of the fireworks paper.
//!
//! A break that falls between two samples is inserted into the point list as a new point
//! (linear interpolation along the polygon), so every break is a data point.

use crate::contour::Contour;
use crate::geom::{angle_between, line_crossing, wrap_once, AngleFloor, Point};
use crate::raster::Bitmap;
use serde::{Deserialize, Serialize};

/// Options of break detection.
#[derive(Clone, Debug)]
pub(crate) struct BreakOptions {
    /// A turning angle above this (degrees) over the window makes a corner.
    pub corner_angle: f64,
    /// Arc-length half-window (px) of the turning-angle measure.
    pub window: f64,
    /// Smallest turning angle (radians) over the window that counts as bending, for
    /// inflections and curvature extrema.
    pub bend_floor: f64,
}

impl BreakOptions {
    /// Options for an image of the given size: the window is 1/100 of the larger side,
    /// clamped to [2, 8] px (2 px on a 64 px glyph, 2.6 px at 256 px, 8 px from 800 px up).
    pub(crate) fn for_image(corner_angle: f64, width: u32, height: u32) -> Self {
        let side = width.max(height) as f64;
        BreakOptions {
            corner_angle,
            window: (side / 100.0).clamp(2.0, 8.0),
            bend_floor: 0.12,
        }
    }
}

/// Why a break was placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum BreakReason {
    /// A corner of the outline.
    Corner,
    /// A change of the sign of curvature.
    Inflection,
    /// A local maximum of |curvature|.
    CurvatureExtremum,
    /// Added so that a closed contour without features has at least two segments.
    Fallback,
    /// Added by the fitting strategy to meet the tolerance.
    Split,
    /// Added by the fidelity repair where the drawn outline left its data
    /// ([`crate::fidelity`]).
    Repair,
}

/// How two neighbouring segments meet at a break.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointKind {
    /// Tangent discontinuity (G0 only), found as a corner of the outline.
    Corner,
    /// Shared unit tangent (G1).
    Smooth,
}

/// One break point of a contour.
#[derive(Clone, Copy, Debug, Serialize)]
pub(crate) struct Break {
    /// Index of the break in the contour's point list.
    pub index: usize,
    /// Corner (G0) or smooth (G1) joint.
    pub kind: JointKind,
    /// Why it is there.
    pub reason: BreakReason,
}

/// A contour with its break points.
#[derive(Clone, Debug)]
pub(crate) struct SegmentedContour {
    /// Data points (the contour's, with sub-sample breaks inserted).
    pub points: Vec<Point>,
    /// True for the border of a hole.
    pub is_hole: bool,
    /// Index of the enclosing contour.
    pub parent: Option<usize>,
    /// BreakPlacement sorted by index. At least two for any contour with three or more points.
    pub breaks: Vec<Break>,
}

/// Arc-length positions of a closed polygon: `s[i]` for each point and the total length.
pub(crate) fn arc_lengths(points: &[Point]) -> (Vec<f64>, f64) {
    let n = points.len();
    let mut s = Vec::with_capacity(n);
    let mut acc = 0.0;
    for i in 0..n {
        s.push(acc);
        acc += points[i].distance(points[(i + 1) % n]);
    }
    (s, acc)
}

/// The point at arc length `target` (any real; wrapped) of a closed polygon, searching from
/// index `hint`.
fn point_at(points: &[Point], s: &[f64], total: f64, hint: usize, target: f64) -> Point {
    let mut i = hint;
    point_from(points, s, total, &mut i, target)
}

/// [`point_at`] that leaves in `at` the index of the polygon edge it found: a scan whose
/// targets move forward with the points passes that index back as the next hint, and
/// then finds each edge in a step or two instead of walking the whole window.
#[inline(always)]
fn point_from(points: &[Point], s: &[f64], total: f64, at: &mut usize, target: f64) -> Point {
    let n = points.len();
    // Targets lie within a window of a point: at most one lap away.
    let t = wrap_once(target, total);
    let seg_end = |i: usize| if i + 1 < n { s[i + 1] } else { total };
    let holds = |i: usize| s[i] <= t && t < seg_end(i);
    // The next point without an integer division (`% n`): a scan calls this six times
    // per point.
    let next_of = |i: usize| if i + 1 < n { i + 1 } else { 0 };
    // Most targets lie on the hint's edge or the next one (a scan's targets move forward
    // about as fast as its points): those two are tried before any walk.
    let mut i = *at;
    if !holds(i) {
        let next = next_of(i);
        if holds(next) {
            i = next;
        } else {
            // Walk from the hint in the needed direction. Walking towards t never passes
            // it, so the shorter way round stays the same.
            let forward = wrap_once(t - s[i], total) < total / 2.0;
            let mut guard = 0;
            while !holds(i) && guard < n {
                i = if forward {
                    (i + 1) % n
                } else {
                    (i + n - 1) % n
                };
                guard += 1;
            }
        }
    }
    *at = i;
    let len = seg_end(i) - s[i];
    let f = if len > 0.0 { (t - s[i]) / len } else { 0.0 };
    points[i].lerp(points[next_of(i)], f)
}

/// Signed turning angle at every point over half-window `h` (positive turning clockwise on
/// screen, i.e. towards +y from +x), for a contour with arc positions `s` and length
/// `total` ([`arc_lengths`]).
///
/// A point that turns certainly less than `floor` gets, instead of its angle, half the
/// floor with the angle's sign (0 where the angle is exactly 0): every test
/// [`find_breaks`] makes of it against the floor, its sign or larger angles then decides
/// as the angle would, and [`Turns::exact`] gives the angle itself where a value is used.
fn turning_angles(points: &[Point], s: &[f64], total: f64, h: f64, floor: f64) -> Turns {
    let n = points.len();
    if n < 3 || total <= 0.0 {
        return Turns {
            theta: vec![0.0; n],
            chords: vec![(Point::ZERO, Point::ZERO); n],
        };
    }
    // Half the floor must stay far from underflow: its square decides a sign test.
    let screen = (floor >= 1e-3).then(|| AngleFloor::new(floor));
    let h = h.min(total / 4.0);
    let (mut behind, mut ahead) = (0, 0);
    let chords: Vec<(Point, Point)> = (0..n)
        .map(|i| {
            let a = point_from(points, s, total, &mut behind, s[i] - h);
            let b = point_from(points, s, total, &mut ahead, s[i] + h);
            (points[i] - a, b - points[i])
        })
        .collect();
    let theta = chords
        .iter()
        .map(|&(din, dout)| {
            let cross = din.cross(dout);
            match screen {
                // atan2(0, d > 0) is +0 exactly.
                Some(_) if cross == 0.0 && din.dot(dout) > 0.0 => 0.0,
                // A cross product this far from underflow gives a non-zero angle.
                Some(f)
                    if cross.abs() > 1e-200 * din.dot(dout).abs()
                        && f.certainly_below(din, dout) =>
                {
                    0.5 * floor.copysign(cross)
                }
                _ => signed_turn(din, dout),
            }
        })
        .collect();
    Turns { theta, chords }
}

/// The turning angles of a contour's points, some given only against a floor (see
/// [`turning_angles`]).
struct Turns {
    theta: Vec<f64>,
    /// The arriving and leaving chords of every point.
    chords: Vec<(Point, Point)>,
}

impl Turns {
    /// The signed turning angle at point `i`.
    fn exact(&self, i: usize) -> f64 {
        let (din, dout) = self.chords[i];
        signed_turn(din, dout)
    }
}

/// The angle between `din` and `dout`, negative when `dout` turns anticlockwise on screen.
fn signed_turn(din: Point, dout: Point) -> f64 {
    let ang = angle_between(din, dout);
    if din.cross(dout) < 0.0 {
        -ang
    } else {
        ang
    }
}

/// Turning angle at every point between two chords that skip the point's core: the
/// arriving chord from s − 2h to s − h/2 and the leaving chord from s + h/2 to s + 2h.
/// Anti-aliasing and smoothing round a sharp corner over about a pixel; skipping the core
/// measures the full angle of the corner instead of the rounded one.
///
/// An angle certainly below `floor` is given as [`BELOW_FLOOR`] instead: the corners are
/// the local maxima above the floor, which such a value cannot change.
fn corner_angles(points: &[Point], s: &[f64], total: f64, h: f64, floor: f64) -> Vec<f64> {
    let n = points.len();
    let floor = AngleFloor::new(floor);
    // One hint per offset, carried from point to point.
    let mut hints = [0; 4];
    (0..n)
        .map(|i| {
            let [h0, h1, h2, h3] = &mut hints;
            let at = |d: f64, hint: &mut usize| point_from(points, s, total, hint, s[i] + d);
            let arriving = at(-0.5 * h, h1) - at(-2.0 * h, h0);
            let leaving = at(2.0 * h, h3) - at(0.5 * h, h2);
            if floor.certainly_below(arriving, leaving) {
                BELOW_FLOOR
            } else {
                angle_between(arriving, leaving)
            }
        })
        .collect()
}

/// The angle [`corner_angles`] gives a point that turns certainly less than the corner
/// floor: below every angle.
const BELOW_FLOOR: f64 = -1.0;

/// Marks every point whose arc distance (the shorter way round a closed contour of
/// length `total`, arc positions `s`) to one of `centres` is at most `reach`. Each centre
/// walks outwards both ways while its points are within reach, so the cost is the points
/// marked, not the points times the centres.
fn within_reach(s: &[f64], total: f64, centres: &[usize], reach: f64) -> Vec<bool> {
    let n = s.len();
    let mut near = vec![false; n];
    let close = |c: usize, j: usize| {
        let d = (s[c] - s[j]).abs();
        d.min(total - d) <= reach
    };
    for &c in centres {
        // The arc distance grows along each direction until the walks meet on the far
        // side, so each walk stops at its first point out of reach.
        for step in [1, n - 1] {
            let mut j = c;
            for _ in 0..n {
                if !close(c, j) {
                    break;
                }
                near[j] = true;
                j = (j + step) % n;
            }
        }
    }
    near
}

/// Largest distance from the polygon's points with arc position in [from, to] (relative to
/// point i) to the line through `a` and `b`.
#[allow(clippy::too_many_arguments)]
fn max_off_line(
    points: &[Point],
    s: &[f64],
    total: f64,
    i: usize,
    from: f64,
    to: f64,
    a: Point,
    b: Point,
) -> f64 {
    let n = points.len();
    let Some(dir) = (b - a).normalized() else {
        return f64::INFINITY;
    };
    let mut worst: f64 = 0.0;
    for k in 1..n {
        for j in [(i + k) % n, (i + n - k) % n] {
            let mut d = s[j] - s[i];
            if d > total / 2.0 {
                d -= total;
            } else if d < -total / 2.0 {
                d += total;
            }
            if d >= from && d <= to {
                worst = worst.max((points[j] - a).cross(dir).abs());
            }
        }
        let reach = s[(i + k) % n] - s[i];
        if reach.rem_euclid(total) > to.abs().max(from.abs()) + 2.0 && k > 4 {
            break;
        }
    }
    worst
}

/// Finds corners, inflections and curvature extrema of a closed contour.
///
/// A corner whose two sides are straight near it (within 0.2 px over 1.5 windows) is
/// sharpened: the rounded points of its core (within h/2 of arc length) are replaced by the
/// intersection of the two side lines, which is where the true corner of an anti-aliased
/// or smoothed outline lies. With `pixels` (a grey-level image) a corner more than
/// [`UNCHECKED_CORNER_MOVE`] px from the rounded outline is sharpened only where the grey
/// levels show the wedge between the two ([`wedge_has_ink`]): a blunt or rounded tip
/// between straight sides (the apex of a serif "A" at 600 dpi) keeps its shape.
pub(crate) fn find_breaks(
    contour: &Contour,
    opts: &BreakOptions,
    pixels: Option<&Bitmap>,
) -> SegmentedContour {
    // Bilevel pixels show no wedge: their corners are sharpened without evidence.
    let grey = pixels.filter(|p| !p.is_bilevel());
    let n0 = contour.points.len();
    if n0 < 3 {
        return build_segmented(contour.points.clone(), contour, Vec::new());
    }
    let h = opts.window;
    let corner = opts.corner_angle.to_radians();
    // Pass 1: corners on the original points, sharpened where the sides are straight.
    let (points, corner_idx) = {
        let src = &contour.points;
        let (s, total) = arc_lengths(src);
        let h = h.min(total / 8.0);
        let ca = corner_angles(src, &s, total, h, corner);
        let within = |i: usize, j: usize| {
            let d = (s[j] - s[i]).abs();
            d.min(total - d) <= h
        };
        let mut corners: Vec<usize> = Vec::new();
        for i in 0..n0 {
            if ca[i] <= corner {
                continue;
            }
            let mut is_max = true;
            for k in 1..n0 / 2 {
                let (a, b) = ((i + n0 - k) % n0, (i + k) % n0);
                if !within(i, a) && !within(i, b) {
                    break;
                }
                if (within(i, a) && ca[a] >= ca[i]) || (within(i, b) && ca[b] > ca[i]) {
                    is_max = false;
                    break;
                }
            }
            if is_max {
                corners.push(i);
            }
        }
        // Sharpen: (index, replacement point) for straight-sided corners.
        let mut out: Vec<Point> = Vec::with_capacity(n0);
        let mut out_corners = Vec::new();
        let mut skip = vec![false; n0];
        let mut replace: Vec<Option<Point>> = vec![None; n0];
        // Square ends: a U-turn whose core is a short straight end between two corners.
        let mut replace_end: Vec<Option<(Point, Point)>> = vec![None; n0];
        for &i in &corners {
            let at = |d: f64| point_at(src, &s, total, i, s[i] + d);
            let (a0, a1, b0, b1) = (at(-2.0 * h), at(-0.5 * h), at(0.5 * h), at(2.0 * h));
            let straight = max_off_line(src, &s, total, i, -2.0 * h, -0.5 * h, a0, a1) < 0.2
                && max_off_line(src, &s, total, i, 0.5 * h, 2.0 * h, b0, b1) < 0.2;
            let square_end = (straight && ca[i] > SQUARE_END_TURN.to_radians())
                .then(|| square_end_corners(src, &s, total, i, h, (a0, a1), (b0, b1)))
                .flatten();
            // The rounded core of the corner (within h/2 of arc) gives way to the new
            // corner point(s).
            let skip_core = |skip: &mut [bool]| {
                for k in 1..n0 {
                    let mut any = false;
                    for j in [(i + k) % n0, (i + n0 - k) % n0] {
                        let d = (s[j] - s[i]).abs();
                        if d.min(total - d) < 0.5 * h {
                            skip[j] = true;
                            any = true;
                        }
                    }
                    if !any {
                        break;
                    }
                }
            };
            if let Some(ends) = square_end {
                skip_core(&mut skip);
                replace_end[i] = Some(ends);
                continue;
            }
            if let (true, Some(x)) = (straight, line_intersection(a0, a1, b0, b1)) {
                let moved = x.distance(src[i]);
                let evident = moved <= UNCHECKED_CORNER_MOVE
                    || grey.is_none_or(|p| wedge_has_ink(p, src[i], x, a0, b1));
                if moved < h && evident {
                    skip_core(&mut skip);
                    replace[i] = Some(x);
                }
            }
        }
        for i in 0..n0 {
            if let Some((x, y)) = replace_end[i] {
                out.push(x);
                out_corners.push(out.len() - 1);
                out.push(y);
                out_corners.push(out.len() - 1);
            } else if let Some(x) = replace[i] {
                out.push(x);
                out_corners.push(out.len() - 1);
            } else if !skip[i] {
                // `corners` is in increasing order.
                if corners.binary_search(&i).is_ok() {
                    out_corners.push(out.len());
                }
                out.push(src[i]);
            }
        }
        (out, out_corners)
    };
    let n = points.len();
    let mut found: Vec<(usize, f64, JointKind, BreakReason)> = corner_idx
        .iter()
        .map(|&i| (i, 0.0, JointKind::Corner, BreakReason::Corner))
        .collect();
    if n >= 3 {
        // Pass 2: smooth features on the sharpened polygon, away from corners.
        let (s, total) = arc_lengths(&points);
        let floor = opts.bend_floor;
        let turns = turning_angles(&points, &s, total, h, floor);
        let theta = &turns.theta;
        let within = |i: usize, j: usize| {
            let d = (s[j] - s[i]).abs();
            d.min(total - d) <= h
        };
        let is_local_max = |i: usize| {
            let v = theta[i].abs();
            let mut k = 1;
            while k < n / 2 {
                let (a, b) = ((i + n - k) % n, (i + k) % n);
                if !within(i, a) && !within(i, b) {
                    break;
                }
                if (within(i, a) && theta[a].abs() >= v) || (within(i, b) && theta[b].abs() > v) {
                    return false;
                }
                k += 1;
            }
            true
        };
        let near = within_reach(&s, total, &corner_idx, 2.0 * h);
        let near_corner = |i: usize| near[i];
        for i in 0..n {
            if near_corner(i) {
                continue;
            }
            // Curvature extremum, refined by a parabola through three samples.
            if theta[i].abs() > floor && is_local_max(i) {
                let (a, c) = (
                    turns.exact((i + n - 1) % n).abs(),
                    turns.exact((i + 1) % n).abs(),
                );
                let b = theta[i].abs();
                let denom = a - 2.0 * b + c;
                let off = if denom.abs() > 1e-12 {
                    (0.5 * (a - c) / denom).clamp(-0.5, 0.5)
                } else {
                    0.0
                };
                let (idx, frac) = if off >= 0.0 {
                    (i, off)
                } else {
                    ((i + n - 1) % n, 1.0 + off)
                };
                found.push((idx, frac, JointKind::Smooth, BreakReason::CurvatureExtremum));
            }
            // Inflection between i and i+1: a sign change with clear bending on both sides.
            // A single turning angle of exactly zero between opposite signs is an inflection
            // right at that sample (as on a symmetric curve): the inflection sits at i + 1.
            // (A longer straight run between opposite turns is not an inflection point.)
            let j = (i + 1) % n;
            let zeros = usize::from(theta[j] == 0.0);
            let k = (j + zeros) % n;
            if theta[i] * theta[k] < 0.0 && !near_corner(j) {
                let lobe = |start: usize, step: isize, sign: f64| {
                    let mut m: f64 = 0.0;
                    let mut k = start as isize;
                    for _ in 0..n {
                        let idx = k.rem_euclid(n as isize) as usize;
                        if theta[idx] * sign <= 0.0 {
                            break;
                        }
                        m = m.max(theta[idx].abs());
                        k += step;
                    }
                    m
                };
                if lobe(i, -1, theta[i].signum()) > floor && lobe(k, 1, theta[k].signum()) > floor {
                    if zeros == 0 {
                        let (ti, tj) = (turns.exact(i).abs(), turns.exact(j).abs());
                        let f = ti / (ti + tj);
                        found.push((i, f, JointKind::Smooth, BreakReason::Inflection));
                    } else {
                        found.push((j, 0.0, JointKind::Smooth, BreakReason::Inflection));
                    }
                }
            }
        }
    }
    build_segmented(points, contour, found)
}

/// Largest distance (px) from the rounded outline to a sharpened corner that needs no
/// grey-level evidence: anti-aliasing and the edge estimate round a sharp corner by about
/// this much, and at this scale the pixels cannot tell a sharp corner from a rounded one.
const UNCHECKED_CORNER_MOVE: f64 = 1.5;

/// Share of the coverage a sharp wedge would give that the pixels must show halfway
/// between the rounded outline and the sharpened corner: blur spreads a wedge's ink, but
/// not below a third of it (a Gaussian of σ = 1 px keeps 0.68 of a 2 px wide band at its
/// centre), while a blunt tip shows paper there.
const WEDGE_INK_SHARE: f64 = 0.3;

/// True when the pixels show the wedge between the rounded tip `tip` of a corner and the
/// intersection `x` of its sides (through `a` and `b`, one point on each): halfway between
/// the two, the material behind the tip (ink, or paper for a hole's corner) covers at
/// least [`WEDGE_INK_SHARE`] of what a sharp wedge of that opening would there.
fn wedge_has_ink(pixels: &Bitmap, tip: Point, x: Point, a: Point, b: Point) -> bool {
    let (Some(u), Some(da), Some(db)) = (
        (x - tip).normalized(),
        (a - x).normalized(),
        (b - x).normalized(),
    ) else {
        return true;
    };
    let half_opening = 0.5 * da.dot(db).clamp(-1.0, 1.0).acos();
    let mid = (tip + x) * 0.5;
    let width = 2.0 * mid.distance(x) * half_opening.tan();
    let ink = pixels.sample(tip - u * 0.75) >= pixels.threshold();
    let v = pixels.sample(mid);
    let share = if ink { v } else { 1.0 - v };
    share >= WEDGE_INK_SHARE * width.min(1.0)
}

/// Intersection of the line through a0, a1 with the line through b0, b1, if they are not
/// (nearly) parallel.
fn line_intersection(a0: Point, a1: Point, b0: Point, b1: Point) -> Option<Point> {
    line_crossing(a0, a1 - a0, b0, b1 - b0, 1e-9)
}

/// A corner turning by more than this (degrees) may be a square end: two corners closer
/// together than the corner window.
const SQUARE_END_TURN: f64 = 140.0;

/// The two corners of a square end at corner `i`, whose straight sides run along
/// `side_a` (arriving) and `side_b` (leaving): the end is the line through the tip along
/// the chord across it, and each corner is where a side meets it. `None` unless both
/// corners lie within `h` of the tip, at least 0.8 px apart, and the outline between them
/// stays within 0.3 px of the end.
fn square_end_corners(
    src: &[Point],
    s: &[f64],
    total: f64,
    i: usize,
    h: f64,
    side_a: (Point, Point),
    side_b: (Point, Point),
) -> Option<(Point, Point)> {
    let at = |d: f64| point_at(src, s, total, i, s[i] + d);
    // The sides of a square end run (nearly) parallel, one there and one back.
    let (da, db) = (
        (side_a.1 - side_a.0).normalized()?,
        (side_b.1 - side_b.0).normalized()?,
    );
    if da.dot(db) > -SQUARE_END_PARALLEL.to_radians().cos() {
        return None;
    }
    // The end runs across the sides, through the point of the core that reaches farthest
    // along them.
    let dir = da.perp();
    let tip = (0..=16)
        .map(|k| at(-0.5 * h + k as f64 * h / 16.0))
        .max_by(|p, q| p.dot(da).total_cmp(&q.dot(da)))?;
    let (e0, e1) = (tip - dir, tip + dir);
    let x = line_intersection(side_a.0, side_a.1, e0, e1)?;
    let y = line_intersection(e0, e1, side_b.0, side_b.1)?;
    let close = |p: Point| p.distance(src[i]) < h;
    if !(close(x) && close(y)) || x.distance(y) < 0.8 {
        return None;
    }
    // The end itself: the points near the tip lie on the end line, and the outline
    // passes close to both corners (a round end misses them by 0.41 of its radius).
    let end_fit = max_off_line(src, s, total, i, -0.25 * h, 0.25 * h, x, y);
    let reach = |p: Point| {
        (0..=16)
            .map(|k| at(-h + k as f64 * h / 8.0).distance(p))
            .fold(f64::INFINITY, f64::min)
    };
    (end_fit < 0.3 && reach(x) < SQUARE_END_CORNER_GAP && reach(y) < SQUARE_END_CORNER_GAP)
        .then_some((x, y))
}

/// Largest angle (degrees) between the two sides of a square end, one reversed.
const SQUARE_END_PARALLEL: f64 = 20.0;

/// Largest distance (px) between a square end's corner and its outline.
const SQUARE_END_CORNER_GAP: f64 = 0.5;

/// Inserts sub-sample breaks as points, merges breaks that land within 0.5 px of each
/// other (corners win), and guarantees at least two breaks.
fn build_segmented(
    src: Vec<Point>,
    contour: &Contour,
    mut found: Vec<(usize, f64, JointKind, BreakReason)>,
) -> SegmentedContour {
    let src = &src;
    let n = src.len();
    // Snap fractions near a sample onto it.
    for f in found.iter_mut() {
        if f.1 < 0.2 {
            f.1 = 0.0;
        } else if f.1 > 0.8 {
            f.0 = (f.0 + 1) % n.max(1);
            f.1 = 0.0;
        }
    }
    found.sort_by(|a, b| {
        (a.0, a.1)
            .partial_cmp(&(b.0, b.1))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut points = Vec::with_capacity(n + found.len());
    let mut breaks: Vec<Break> = Vec::new();
    let mut k = 0;
    for i in 0..n {
        points.push(src[i]);
        let here = points.len() - 1;
        while k < found.len() && found[k].0 == i {
            let (_, frac, kind, reason) = found[k];
            let index = if frac == 0.0 {
                here
            } else {
                points.push(src[i].lerp(src[(i + 1) % n], frac));
                points.len() - 1
            };
            push_break(
                &mut breaks,
                &points,
                Break {
                    index,
                    kind,
                    reason,
                },
            );
            k += 1;
        }
    }
    // Close the loop: the last break may sit next to the first.
    if breaks.len() >= 2 {
        let (first, last) = (breaks[0], breaks[breaks.len() - 1]);
        if points[first.index].distance(points[last.index]) < 0.5 {
            if last.kind == JointKind::Corner && first.kind != JointKind::Corner {
                breaks.remove(0);
            } else {
                breaks.pop();
            }
        }
    }
    let m = points.len();
    if m >= 3 && breaks.len() < 2 {
        // A contour without features: cut it at the point farthest from the first break
        // (or from point 0), so that a closed contour is never one segment.
        let anchor = breaks.first().map_or(0, |b| b.index);
        let far = (0..m)
            .max_by(|&a, &b| {
                let da = points[a].distance(points[anchor]);
                let db = points[b].distance(points[anchor]);
                da.total_cmp(&db)
            })
            .unwrap_or(m / 2);
        if breaks.is_empty() {
            breaks.push(Break {
                index: anchor,
                kind: JointKind::Smooth,
                reason: BreakReason::Fallback,
            });
        }
        if far != anchor {
            breaks.push(Break {
                index: far,
                kind: JointKind::Smooth,
                reason: BreakReason::Fallback,
            });
        }
        breaks.sort_by_key(|b| b.index);
    }
    SegmentedContour {
        points,
        is_hole: contour.is_hole,
        parent: contour.parent,
        breaks,
    }
}

/// Appends a break unless the previous one is within 0.5 px; a corner replaces a smooth
/// break.
fn push_break(breaks: &mut Vec<Break>, points: &[Point], b: Break) {
    if let Some(last) = breaks.last_mut() {
        if points[last.index].distance(points[b.index]) < 0.5 {
            if b.kind == JointKind::Corner && last.kind != JointKind::Corner {
                *last = b;
            }
            return;
        }
    }
    breaks.push(b);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_within_reach_of_centres_are_those_of_the_direct_test() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for case in 0..200 {
            let n = rng.random_range(3..120);
            // Arc positions with uneven steps, some of them zero (repeated points).
            let mut s = vec![0.0];
            for _ in 1..n {
                let step = if rng.random_bool(0.1) {
                    0.0
                } else {
                    rng.random_range(0.1..3.0)
                };
                s.push(s[s.len() - 1] + step);
            }
            let total = s[n - 1] + rng.random_range(0.1..3.0);
            let centres: Vec<usize> = (0..rng.random_range(0..6))
                .map(|_| rng.random_range(0..n))
                .collect();
            let reach = rng.random_range(0.0..total * 0.7);
            let near = within_reach(&s, total, &centres, reach);
            for i in 0..n {
                let direct = centres.iter().any(|&c| {
                    let d = (s[c] - s[i]).abs();
                    d.min(total - d) <= reach
                });
                assert_eq!(near[i], direct, "case {case}, point {i}");
            }
        }
    }

    fn contour(points: Vec<Point>) -> Contour {
        Contour {
            points,
            is_hole: false,
            parent: None,
            edge_spread: None,
        }
    }

    fn square(side: f64, step: f64) -> Vec<Point> {
        let mut pts = Vec::new();
        let k = (side / step) as usize;
        let corners = [
            Point::new(0.0, 0.0),
            Point::new(side, 0.0),
            Point::new(side, side),
            Point::new(0.0, side),
        ];
        for c in 0..4 {
            let (a, b) = (corners[c], corners[(c + 1) % 4]);
            for j in 0..k {
                pts.push(a.lerp(b, j as f64 / k as f64));
            }
        }
        pts
    }

    #[test]
    fn screened_turns_decide_every_test_as_the_angles_do() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let floor = 0.12;
        let mut screened = 0;
        for _ in 0..50 {
            // A wobbly closed curve on a pixel grid: straight steps, gentle and sharp turns.
            let n = rng.random_range(40..200);
            let r: Vec<f64> = (0..n).map(|_| 20.0 + rng.random_range(-0.3..0.3)).collect();
            let points: Vec<Point> = (0..n)
                .map(|i| {
                    let t = i as f64 / n as f64 * std::f64::consts::TAU;
                    let p = Point::new(r[i] * t.cos(), r[i] * t.sin());
                    if rng.random_bool(0.3) {
                        Point::new(p.x.round(), p.y.round())
                    } else {
                        p
                    }
                })
                .collect();
            let (s, total) = arc_lengths(&points);
            let turns = turning_angles(&points, &s, total, 1.5, floor);
            for (i, &t) in turns.theta.iter().enumerate() {
                let exact = turns.exact(i);
                if t.to_bits() == exact.to_bits() {
                    continue;
                }
                screened += 1;
                // A screened turn is below the floor, with the angle's sign, never zero.
                assert!(
                    exact.abs() < floor && t.abs() < floor,
                    "{i}: {t} for {exact}"
                );
                assert!(t * exact > 0.0, "{i}: {t} for {exact}");
            }
        }
        assert!(screened > 1_000, "{screened}");
    }

    #[test]
    fn square_has_four_corners_at_its_vertices() {
        let seg = find_breaks(
            &contour(square(40.0, 1.0)),
            &BreakOptions::for_image(50.0, 64, 64),
            None,
        );
        let corners: Vec<Point> = seg
            .breaks
            .iter()
            .filter(|b| b.kind == JointKind::Corner)
            .map(|b| seg.points[b.index])
            .collect();
        assert_eq!(corners.len(), 4, "{:?}", seg.breaks);
        for v in [
            Point::new(0.0, 0.0),
            Point::new(40.0, 0.0),
            Point::new(40.0, 40.0),
            Point::new(0.0, 40.0),
        ] {
            assert!(
                corners.iter().any(|c| c.distance(v) < 1e-9),
                "{v:?} not found in {corners:?}"
            );
        }
    }

    #[test]
    fn circle_has_no_corners_but_at_least_two_breaks() {
        let pts: Vec<Point> = (0..200)
            .map(|i| {
                let a = i as f64 / 200.0 * std::f64::consts::TAU;
                Point::new(50.0 + 30.0 * a.cos(), 50.0 + 30.0 * a.sin())
            })
            .collect();
        let seg = find_breaks(
            &contour(pts),
            &BreakOptions::for_image(50.0, 100, 100),
            None,
        );
        assert!(seg.breaks.iter().all(|b| b.kind == JointKind::Smooth));
        assert!(seg.breaks.len() >= 2);
    }

    #[test]
    fn inflection_of_an_s_curve_is_found_between_samples() {
        // Two half circles joined into a closed "S"-like lens: use a sine wave closed by a
        // far-away return path, and look for inflections near the sine's zero crossings.
        let mut pts = Vec::new();
        for i in 0..=160 {
            let x = i as f64 * 0.5;
            pts.push(Point::new(
                x,
                50.0 + 10.0 * (x / 80.0 * std::f64::consts::TAU).sin(),
            ));
        }
        pts.push(Point::new(80.0, 100.0));
        pts.push(Point::new(0.0, 100.0));
        let seg = find_breaks(
            &contour(pts),
            &BreakOptions::for_image(60.0, 100, 100),
            None,
        );
        let infl: Vec<Point> = seg
            .breaks
            .iter()
            .filter(|b| b.reason == BreakReason::Inflection)
            .map(|b| seg.points[b.index])
            .collect();
        assert!(
            infl.iter()
                .any(|p| (p.x - 40.0).abs() < 0.75 && (p.y - 50.0).abs() < 0.75),
            "{infl:?}"
        );
        // Curvature extrema of the sine at x = 20 and x = 60.
        let ext: Vec<Point> = seg
            .breaks
            .iter()
            .filter(|b| b.reason == BreakReason::CurvatureExtremum)
            .map(|b| seg.points[b.index])
            .collect();
        assert!(ext.iter().any(|p| (p.x - 20.0).abs() < 0.75), "{ext:?}");
        assert!(ext.iter().any(|p| (p.x - 60.0).abs() < 0.75), "{ext:?}");
    }
}
