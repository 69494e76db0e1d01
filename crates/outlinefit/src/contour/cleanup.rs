//! Clean-up of a placed outline: close points and small backsteps removed, small
//! self-crossing folds cut, sharp turns kept as anchors, and the resampling to about
//! 0.8 px spacing.

use super::lines::norm;
use super::lines::segment_crossing;
use super::lines::turn_angle;
use super::workspace::Workspace;
use crate::geom::AngleFloor;
use crate::geom::Point;

/// Points closer than this (px) to their predecessor are removed.
const MIN_SPACING: f64 = 0.3;
/// A point that steps backwards is dropped only within this distance (px) of the last kept
/// point.
const MAX_BACKSTEP: f64 = 1.0;
/// At most this many backsteps in a row are dropped.
const MAX_BACKSTEP_RUN: usize = 3;
/// How many points ahead the loop cutter looks for a crossing.
const LOOP_REACH: usize = 6;
/// Target spacing (px) of the resampled points.
const TARGET_SPACING: f64 = 0.8;
/// A turn above this (degrees) between consecutive segments makes a point an exact sample.
const ANCHOR_TURN_DEG: f64 = 20.0;

impl Workspace {
    /// Removes points within `MIN_SPACING` of the last kept one and points that step a
    /// little backwards along the last kept point's tangent (the zigzag that refinement
    /// leaves at concave corners), then cuts the small loops that remain. Anchors are kept
    /// in preference.
    ///
    /// A backstep is dropped only while it stays within `MAX_BACKSTEP` of the last kept
    /// point and at most `MAX_BACKSTEP_RUN` in a row: the test trusts one tangent, and an
    /// unbounded rule let a single bad tangent (at a tapering tip, or a square corner whose
    /// next side runs exactly across it) discard every following point, losing whole parts
    /// of the shape (a wisp became 2 points, the foot of an italic 2 was cut corner to
    /// corner).
    pub(super) fn remove_close_and_backsteps(&mut self) {
        let n = self.points.len();
        self.anchors.resize(n, false);
        let mut kept = 0usize;
        let mut dropped_run = 0usize;
        for i in 0..n {
            let p = self.points[i];
            if kept > 0 {
                let q = self.points[kept - 1];
                let step = p - q;
                let too_close = step.length_squared() < MIN_SPACING * MIN_SPACING;
                let backwards = step.dot(self.tangents[kept - 1]) < 0.0
                    && step.length_squared() < MAX_BACKSTEP * MAX_BACKSTEP
                    && dropped_run < MAX_BACKSTEP_RUN;
                if too_close || backwards {
                    if self.anchors[i] && !self.anchors[kept - 1] && !backwards {
                        // Keep the anchor instead of its near neighbour.
                        self.points[kept - 1] = p;
                        self.tangents[kept - 1] = self.tangents[i];
                        self.anchors[kept - 1] = true;
                    }
                    if backwards && !too_close {
                        dropped_run += 1;
                    }
                    continue;
                }
            }
            dropped_run = 0;
            self.points[kept] = p;
            self.tangents[kept] = self.tangents[i];
            self.anchors[kept] = self.anchors[i];
            kept += 1;
        }
        // Across the closing joint.
        while kept > 3 && norm(self.points[kept - 1] - self.points[0]) < MIN_SPACING {
            if self.anchors[kept - 1] && !self.anchors[0] {
                self.points[0] = self.points[kept - 1];
                self.anchors[0] = true;
            }
            kept -= 1;
        }
        self.points.truncate(kept);
        self.tangents.truncate(kept);
        self.anchors.truncate(kept);
        self.cut_small_loops();
    }

    /// Where the polyline crosses itself within `LOOP_REACH` points (a fold left by two
    /// overshooting sides of a concave corner), the points inside the loop are replaced by
    /// the crossing point.
    fn cut_small_loops(&mut self) {
        let n = self.points.len();
        if n < 8 {
            return;
        }
        let mut out_points = Vec::with_capacity(n);
        let mut out_tangents = Vec::with_capacity(n);
        let mut out_anchors = Vec::with_capacity(n);
        let mut i = 0;
        while i < n {
            out_points.push(self.points[i]);
            out_tangents.push(self.tangents[i]);
            out_anchors.push(self.anchors[i]);
            let (a, b) = (self.points[i], self.points[(i + 1) % n]);
            let mut cut = None;
            // Keep the loop search inside the list (it never wraps past the end), so the
            // first point survives and the walk stays in order.
            for j in (i + 2..(i + 2 + LOOP_REACH).min(n - 1)).rev() {
                if let Some(x) = segment_crossing(a, b, self.points[j], self.points[j + 1]) {
                    cut = Some((j, x));
                    break;
                }
            }
            match cut {
                Some((j, x)) => {
                    out_points.push(x);
                    out_tangents.push(self.tangents[j]);
                    out_anchors.push(false);
                    i = j + 1;
                }
                None => i += 1,
            }
        }
        if out_points.len() >= 3 {
            self.points = out_points;
            self.tangents = out_tangents;
            self.anchors = out_anchors;
        }
    }

    /// Marks as anchors the points where the outline turns by more than `ANCHOR_TURN_DEG`.
    pub(super) fn mark_turns(&mut self) {
        let n = self.points.len();
        if n < 3 {
            return;
        }
        let limit = ANCHOR_TURN_DEG.to_radians();
        // Most points turn far less than the limit: those skip the arctangent.
        let floor = AngleFloor::new(limit);
        for i in 0..n {
            let p = self.points[i];
            let (back, ahead) = (
                p - self.points[(i + n - 1) % n],
                self.points[(i + 1) % n] - p,
            );
            if !floor.certainly_below(back, ahead) && turn_angle(back, ahead) > limit {
                self.anchors[i] = true;
            }
        }
    }

    /// Resamples the closed polyline to about `TARGET_SPACING`, keeping anchors exactly.
    pub(super) fn resample(&self) -> Vec<Point> {
        let pts = &self.points;
        let n = pts.len();
        if n < 3 {
            return pts.clone();
        }
        let start = self.anchors.iter().position(|&a| a).unwrap_or(0);
        let mut out = Vec::with_capacity(n);
        let mut i = start;
        loop {
            // The span from anchor i to the next anchor (or around the whole loop).
            let mut j = (i + 1) % n;
            let mut length = norm(pts[j] - pts[i]);
            while !self.anchors[j] && j != start {
                let k = (j + 1) % n;
                length += norm(pts[k] - pts[j]);
                j = k;
            }
            let pieces = ((length / TARGET_SPACING).round() as usize).max(1);
            out.push(pts[i]);
            let step = length / pieces as f64;
            let mut seg = i;
            let mut seg_start = 0.0;
            let mut seg_len = norm(pts[(seg + 1) % n] - pts[seg]);
            for m in 1..pieces {
                let target = m as f64 * step;
                while seg_start + seg_len < target && (seg + 1) % n != j {
                    seg_start += seg_len;
                    seg = (seg + 1) % n;
                    seg_len = norm(pts[(seg + 1) % n] - pts[seg]);
                }
                let t = if seg_len > 0.0 {
                    ((target - seg_start) / seg_len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                out.push(pts[seg].lerp(pts[(seg + 1) % n], t));
            }
            if j == start {
                break;
            }
            i = j;
        }
        // The contour is kept to the end of the trace: without the room it grew into.
        out.shrink_to_fit();
        out
    }
}
