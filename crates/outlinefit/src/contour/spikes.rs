//! Spikes: tips that the threshold cut short, extended to where their straight sides
//! meet when the coverage supports it.

use super::lines::fit_line;
use super::lines::lap;
use super::lines::turn_angle;
use super::lines::unit;
use super::lines::ArcWalk;
use crate::geom::Point;
use crate::raster::Bitmap;

/// Sharpest turn (degrees, over chords of `SPIKE_REACH` px) that counts as a spike tip.
const SPIKE_TURN_DEG: f64 = 100.0;
// `extend_spikes` stores turns of at most 90° without their arctangent.
const _: () = assert!(SPIKE_TURN_DEG > 90.0);
/// Arc length (px) to the chord ends of the spike detector.
const SPIKE_REACH: f64 = 2.0;
/// Arc length (px) next to a tip left out of its side lines (rounded, or thinner than a
/// pixel so that its edge is biased).
const SPIKE_SKIP: f64 = 1.5;
/// Arc length (px) of each side line of a spike.
const SPIKE_SIDE: f64 = 5.0;
/// Largest distance (px) of a side point from its line.
const SPIKE_RESIDUAL: f64 = 0.2;
/// Longest extension (px) of a tip along its sides, with grey-level evidence.
const SPIKE_MAX_EXTENSION: f64 = 4.0;
/// Rise of coverage (above its lowest so far) that ends a needle's ridge: another shape.
/// Along a line thinner than a pixel the coverage wavers with the pixel grid by ~0.2.
const SPIKE_RIDGE_RISE: f64 = 0.3;
/// Shortest trail (px) of faint ink ahead of a tip that counts as the rest of a needle.
const SPIKE_RIDGE_MIN: f64 = 2.0;
/// Longest extension (px) of a needle tip along its ridge of faint ink.
const SPIKE_RIDGE_REACH: f64 = 24.0;
/// Coverage (or paper, for a slit) below which the ridge of a needle has ended: a
/// box-filtered needle thinner than a pixel has about its width as coverage.
const SPIKE_RIDGE_FLOOR: f64 = 0.06;
/// Longest extension (px) of a tip of a bilevel image, which shows no evidence beyond
/// the last pixel (side lines that meet up to three times farther are followed this far).
const SPIKE_MAX_EXTENSION_BILEVEL: f64 = 2.0;
/// Longest extension (px) of a bilevel tip however thin its spike.
const SPIKE_MAX_EXTENSION_BILEVEL_THIN: f64 = 4.0;

/// Extends the tips of spikes (and the ends of slits) that thresholding and smoothing cut
/// short: where the outline turns by more than `SPIKE_TURN_DEG` and both sides are
/// straight beyond the tip, the tip moves to the intersection of the side lines, if the
/// coverage between the old and the new tip shows ink (paper, for a slit) fading towards
/// it. On a bilevel image, whose pixels show nothing thinner than a pixel, the move is
/// shorter. Measured on a 40° needle: the tip comes back from 3 px short to within 1 px.
pub(super) fn extend_spikes(points: &mut Vec<Point>, bitmap: &Bitmap) {
    let n = points.len();
    if n < 12 {
        return;
    }
    let mut arc = Vec::with_capacity(n + 1);
    arc.push(0.0);
    for i in 0..n {
        arc.push(arc[i] + points[i].distance(points[(i + 1) % n]));
    }
    let total = arc[n];
    if total < 4.0 * (SPIKE_SKIP + SPIKE_SIDE) {
        return;
    }
    let nn = n as i64;
    let walk = ArcWalk { cumulative: &arc };
    let at = |k: i64| points[lap(k, nn).0 as usize];
    let back_by = |i: i64, len: f64| walk.back_by(i, len);
    let ahead_by = |i: i64, len: f64| walk.ahead_by(i, len);
    let limit = SPIKE_TURN_DEG.to_radians();
    // Only turns above the limit are compared with each other; one whose two chords do not
    // point against each other (a turn of at most 90°, below the 100° limit) is stored as
    // a quarter turn without its arctangent, which keeps every comparison below as it was.
    let turn: Vec<f64> = (0..nn)
        .map(|i| {
            let back = at(i) - at(back_by(i, SPIKE_REACH));
            let ahead = at(ahead_by(i, SPIKE_REACH)) - at(i);
            if back.dot(ahead) >= 0.0 {
                std::f64::consts::FRAC_PI_2
            } else {
                turn_angle(back, ahead)
            }
        })
        .collect();
    let bilevel = bitmap.is_bilevel();
    // (first replaced unrolled index, count, new tip)
    let mut edits: Vec<(i64, i64, Point)> = Vec::new();
    let mut last_end = i64::MIN;
    for i in 0..nn {
        let t = turn[i as usize];
        if t < limit {
            continue;
        }
        let (b, a) = (back_by(i, SPIKE_REACH), ahead_by(i, SPIKE_REACH));
        let t_at = |k: i64| turn[lap(k, nn).0 as usize];
        if !((b + 1..i).all(|k| t > t_at(k)) && (i + 1..a).all(|k| t >= t_at(k))) {
            continue;
        }
        let inner_back = back_by(i, SPIKE_SKIP);
        let outer_back = back_by(i, SPIKE_SKIP + SPIKE_SIDE);
        let inner_ahead = ahead_by(i, SPIKE_SKIP);
        let outer_ahead = ahead_by(i, SPIKE_SKIP + SPIKE_SIDE);
        if outer_back <= last_end || inner_back - outer_back < 3 || outer_ahead - inner_ahead < 3 {
            continue;
        }
        let (Some((la, ra)), Some((lb, rb))) = (
            fit_line((outer_back..=inner_back).map(at)),
            fit_line((inner_ahead..=outer_ahead).map(at)),
        ) else {
            continue;
        };
        if ra > SPIKE_RESIDUAL || rb > SPIKE_RESIDUAL {
            continue;
        }
        let cross = la.direction.cross(lb.direction);
        if cross.abs() < 1e-6 {
            continue;
        }
        let x = la.origin + la.direction * ((lb.origin - la.origin).cross(lb.direction) / cross);
        let tip = at(i);
        let reach = x.distance(tip);
        if !x.is_finite() || reach < 0.25 {
            continue;
        }
        let max_move = if bilevel {
            let (Some(a), Some(b)) = (unit(at(outer_back) - x), unit(at(outer_ahead) - x)) else {
                continue;
            };
            bilevel_tip_loss(a.dot(b).clamp(-1.0, 1.0).acos() / 2.0)
        } else {
            SPIKE_MAX_EXTENSION
        };
        if reach > 3.0 * max_move && (bilevel || reach > SPIKE_RIDGE_REACH) {
            continue;
        }
        // The new tip must lie ahead of the old one, away from both sides.
        let Some(u) = unit(x - tip) else {
            continue;
        };
        let mid_sides = (at(inner_back) + at(inner_ahead)) * 0.5;
        if (tip - mid_sides).dot(u) <= 0.0 {
            continue;
        }
        if reach > max_move && !bilevel {
            // A needle whose sides meet far ahead: its thinnest part is below the
            // threshold but not invisible. Follow the ridge of faint ink (or the valley of
            // faint paper, for a slit) straight ahead while it lasts.
            let ink = bitmap.sample(tip - u * 0.75) >= bitmap.threshold();
            let value = |p: Point| {
                let v = bitmap.sample(p);
                if ink {
                    v
                } else {
                    1.0 - v
                }
            };
            let step = 0.25;
            // The ink fades towards the tip; where it rises again, another shape begins.
            let mut last = 0.0;
            let mut low = value(tip);
            let mut s = step;
            while s <= reach + 1.0 {
                let v = value(tip + u * s);
                if v < SPIKE_RIDGE_FLOOR || v > low + SPIKE_RIDGE_RISE {
                    break;
                }
                low = low.min(v);
                last = s;
                s += step;
            }
            // Any edge fades over about a pixel (the pixel footprint and the bilinear
            // interpolation); only a longer trail of faint ink is a needle.
            if last < SPIKE_RIDGE_MIN {
                continue;
            }
            let x = tip + u * last;
            edits.push((inner_back + 1, inner_ahead - inner_back - 1, x));
            last_end = inner_ahead;
            continue;
        }
        if !bilevel {
            // Ink (or paper, for a slit) must fade from the old tip towards the new one.
            let inner = bitmap.sample(tip - u * 0.75) >= bitmap.threshold();
            let mid = bitmap.sample((tip + x) * 0.5);
            let beyond = bitmap.sample(x + u * 1.0);
            let fades = if inner {
                mid > beyond + 0.05 && mid > 0.05
            } else {
                mid + 0.05 < beyond && mid < 0.95
            };
            if !fades {
                continue;
            }
        }
        // On a bilevel image the side lines near a thin tip lean inwards (the last pixels
        // are thinner than the spike), so their intersection overshoots: go at most
        // `max_move` towards it.
        let x = tip + u * reach.min(max_move);
        edits.push((inner_back + 1, inner_ahead - inner_back - 1, x));
        last_end = inner_ahead;
    }
    drop_wrapping_edit(&mut edits, nn);
    if edits.is_empty() {
        return;
    }
    let (remove, insert_at) = mark_edits(&edits, n);
    let mut out = Vec::with_capacity(n);
    for j in 0..n {
        if let Some(x) = insert_at[j] {
            out.push(x);
        }
        if !remove[j] {
            out.push(points[j]);
        }
    }
    *points = out;
}

/// Drops the last of the edits (first replaced unrolled index, count, new point) of a
/// closed outline of `n` points when it would overlap the first one across the closing
/// joint.
pub(super) fn drop_wrapping_edit(edits: &mut Vec<(i64, i64, Point)>, n: i64) {
    if let [(first_start, _, _), .., (last_start, last_count, _)] = edits[..] {
        if last_start + last_count > first_start + n {
            edits.pop();
        }
    }
}

/// For edits (first replaced unrolled index, count, new point) of a closed outline of `n`
/// points: which points are removed, and the new point inserted before each index.
pub(super) fn mark_edits(edits: &[(i64, i64, Point)], n: usize) -> (Vec<bool>, Vec<Option<Point>>) {
    let nn = n as i64;
    let mut remove = vec![false; n];
    let mut insert_at = vec![None; n];
    for &(first, count, x) in edits {
        for k in first..first + count {
            remove[lap(k, nn).0 as usize] = true;
        }
        insert_at[lap(first, nn).0 as usize] = Some(x);
    }
    (remove, insert_at)
}

/// How far (px) a bilevel image may have cut a spike of half-opening α (radians) short:
/// the first pixel centre inside a wedge lies on average ½·√(π / tan α) from its tip
/// (pixel centres as points of unit density, which holds for thin wedges at any
/// orientation). At least `SPIKE_MAX_EXTENSION_BILEVEL` (a 30° star point is cut by
/// about that much), at most `SPIKE_MAX_EXTENSION_BILEVEL_THIN`.
fn bilevel_tip_loss(half_opening: f64) -> f64 {
    let expected = 0.5 * (std::f64::consts::PI / half_opening.tan().max(1e-9)).sqrt();
    expected.clamp(
        SPIKE_MAX_EXTENSION_BILEVEL,
        SPIKE_MAX_EXTENSION_BILEVEL_THIN,
    )
}
