//! Edge placement on bilevel images: corner candidates, the weighted local regression
//! of the crack midpoints, corners placed where their side lines meet and kept only if
//! the pixels agree, and the guard that falls back to smoothed midpoints.

use super::lines::fit_line;
use super::lines::intersect;
use super::lines::norm;
use super::lines::turn_angle;
use super::lines::unit;
use super::lines::Line;
use super::mask::Crack;
use super::mask::PaddedMask;
use super::workspace::Workspace;
use crate::geom::floor_i64;
use crate::geom::signed_area;
use crate::geom::wrap;
use crate::geom::Point;
use crate::linalg::{cramer2, det3};

/// Chord length, in cracks, of the bilevel corner detector.
const CORNER_REACH: usize = 3;
/// Smallest chord angle (degrees) that makes a bilevel corner.
const CORNER_ANGLE_DEG: f64 = 55.0;
/// Chord length, in cracks, of the second bilevel corner detector...
const CORNER_LONG_REACH: usize = 7;
/// ...and its smallest chord angle (degrees).
const CORNER_LONG_ANGLE_DEG: f64 = 70.0;
/// Loops of fewer cracks (shapes under about 12 px across) get no corners: at that size a
/// digitised disk and a digitised polygon are indistinguishable, and they are smoothed.
const MIN_CORNER_LOOP: usize = 48;
/// Smallest turn (degrees) between the fitted side lines of a bilevel corner: the vertices
/// of a small digitised circle (a digital octagon, 45° turns) must not become corners.
const CORNER_LINE_ANGLE_DEG: f64 = 50.0;
/// Points fitted on each side of a bilevel corner with curved sides, or close neighbours.
const CORNER_FIT_POINTS: usize = 8;
/// Cracks on each side of a corner candidate kept out of the first regression.
const CORNER_ZONE: usize = 2;
/// Corner placement: points next to the corner skipped on each side...
const CORNER_FIT_SKIP: usize = 2;
/// ...and the farthest raw midpoint fitted to a straight side.
const CORNER_FIT_FAR: usize = 48;
/// Weight of a placed corner in the regression windows that end at it.
const CORNER_WEIGHT: f64 = 20.0;
/// After the corners are placed, points within this many cracks of one are regressed again
/// with the corner in their window.
const CORNER_REGRESSION_REACH: usize = 12;
/// Tolerance (px) of the pixel-consistency test of a bilevel corner.
const CORNER_PIXEL_SLACK: f64 = 0.2;
/// Largest move (px) of a corner to the intersection of its side lines.
const MAX_CORNER_MOVE: f64 = 1.5;
/// Passes of the [1, 2, 1]/4 filter that pre-smooth bilevel outlines.
const SMOOTHING_PASSES: usize = 4;
/// Bilevel bandwidth σ (px) per √(local diameter), see [`Workspace::choose_bandwidths`].
const BANDWIDTH_PER_SQRT_DIAMETER: f64 = 0.8;
/// Chord length, in cracks, of the curvature estimate behind the bilevel bandwidth.
const BANDWIDTH_CHORD: usize = 8;
/// The bilevel regression fits at every this many points; the points in between are put
/// on the last fitted parabola.
const REGRESSION_STRIDE: usize = 2;
/// The bilevel bandwidth is chosen at every this many points and interpolated between.
const BANDWIDTH_STRIDE: usize = 3;
/// Half-width, in points, of the running mean applied to the bandwidths.
const BANDWIDTH_SMOOTHING: usize = 6;
/// Candidate bandwidths (px) of the bilevel regression, narrowest first.
const BANDWIDTHS: [f64; 6] = [1.5, 2.5, 4.0, 6.0, 9.0, 12.0];
/// Tolerance (px) of the pixel-consistency test of a bilevel regression fit.
const FIT_PIXEL_SLACK: f64 = 0.25;
/// The bilevel regression window ends where the outline has turned by more than 60°, so
/// that a small loop is never fitted as one parabola.
const MIN_WINDOW_TANGENT_COSINE: f64 = 0.5;
/// Window half-width of the bilevel regression, in bandwidths.
const BANDWIDTH_REACH: f64 = 2.5;
/// A crack midpoint is uncertain by ±0.5 px along its own normal, i.e. by
/// ±0.5·|n·ν| across the outline (normal ν): the midpoints of cracks that run across the
/// outline (the risers of a shallow staircase) are precise, those along it are not. Weights
/// are 1 / ((n·ν)² + this floor).
const BILEVEL_PRECISION_FLOOR: f64 = 0.01;
/// Largest distance (px) a bilevel outline point may lie from the nearest pixel-edge
/// midpoint: the midpoints are 1 px apart, and a faithful outline stays within half a pixel
/// of the pixel boundary.
const CRACK_FIDELITY: f64 = 1.25;

/// True when every point of `points` lies within [`CRACK_FIDELITY`] of a pixel-edge midpoint
/// and the enclosed areas agree to within 0.35 px per unit of boundary length: a guard on
/// the bilevel regression, which must never move the outline off its pixels.
pub(super) fn follows_cracks(points: &[Point], cracks: &[Crack]) -> bool {
    if points.len() < 3 || cracks.len() < 3 {
        return false;
    }
    let mids: Vec<Point> = cracks.iter().map(|c| c.mid()).collect();
    let length = mids.len() as f64;
    if (signed_area(points).abs() - signed_area(&mids).abs()).abs() > 0.35 * length {
        return false;
    }
    // The outline runs along its cracks, so a point is mostly within reach of the
    // midpoint that the previous point was near, or of one a few cracks on: those are
    // tried first. Otherwise the midpoints sorted by their cell of a 2 px grid (row, then
    // column), made once when first needed, give the nine cells around the point as
    // three runs of that order, found by binary search.
    let cell = |p: Point| (floor_i64(p.y / 2.0), floor_i64(p.x / 2.0));
    let mut sorted: Vec<((i64, i64), usize)> = Vec::new();
    let mut near = 0;
    points.iter().all(|&p| {
        let mut ahead = (0..WALK_CRACKS).map(|k| (near + k) % mids.len());
        if let Some(k) = ahead.find(|&k| mids[k].distance(p) <= CRACK_FIDELITY) {
            near = k;
            return true;
        }
        if sorted.is_empty() {
            sorted = mids
                .iter()
                .enumerate()
                .map(|(k, &m)| (cell(m), k))
                .collect();
            sorted.sort_unstable();
        }
        let (cy, cx) = cell(p);
        for dy in -1..=1 {
            let row = cy + dy;
            let from = sorted.partition_point(|e| e.0 < (row, cx - 1));
            for &(key, k) in &sorted[from..] {
                if key > (row, cx + 1) {
                    break;
                }
                if mids[k].distance(p) <= CRACK_FIDELITY {
                    near = k;
                    return true;
                }
            }
        }
        false
    })
}

/// Midpoints along the loop (from the one the previous point was near) that
/// [`follows_cracks`] tries before searching them all.
const WALK_CRACKS: usize = 6;

/// Pixel-edge midpoints smoothed by three passes of the closed [1, 2, 1]/4 filter: a robust
/// bilevel outline (corners slightly rounded, later sharpened by the break finder where
/// their sides are straight).
pub(super) fn smoothed_cracks(cracks: &[Crack]) -> Vec<Point> {
    let mut pts: Vec<Point> = cracks.iter().map(|c| c.mid()).collect();
    let n = pts.len();
    if n < 3 {
        return pts;
    }
    let mut next = pts.clone();
    for _ in 0..3 {
        for i in 0..n {
            next[i] = (pts[wrap(i + n - 1, n)] + pts[i] * 2.0 + pts[wrap(i + 1, n)]) * 0.25;
        }
        std::mem::swap(&mut pts, &mut next);
    }
    pts
}

/// Accumulates a weighted least-squares fit of v = a + b·u + c·u².
#[derive(Default)]
pub(super) struct QuadraticFit {
    /// Σw·uᵏ for k = 0..=4.
    moments: [f64; 5],
    /// Σw·v·uᵏ for k = 0..=2.
    rhs: [f64; 3],
    count: usize,
}

impl QuadraticFit {
    #[inline]
    pub(super) fn add(&mut self, u: f64, v: f64, w: f64) {
        let (w1, w2) = (w * u, w * u * u);
        self.moments[0] += w;
        self.moments[1] += w1;
        self.moments[2] += w2;
        self.moments[3] += w2 * u;
        self.moments[4] += w2 * u * u;
        self.rhs[0] += w * v;
        self.rhs[1] += w1 * v;
        self.rhs[2] += w2 * v;
        self.count += 1;
    }

    /// (a, b, c). Falls back to a line, then to the weighted mean, when the points do not
    /// determine the higher terms.
    pub(super) fn solve(&self) -> Option<(f64, f64, f64)> {
        let [m0, m1, m2, m3, m4] = self.moments;
        let [r0, r1, r2] = self.rhs;
        if m0.is_nan() || m0 <= 0.0 {
            return None;
        }
        if self.count >= 4 {
            // Cramer's rule on the moment matrix; c's matrix (third column replaced by
            // the right-hand side) is written transposed, which keeps its determinant.
            let det = det3([[m0, m1, m2], [m1, m2, m3], [m2, m3, m4]]);
            if det.abs() > 1e-9 * m0 * m2 * m4 {
                let a = det3([[r0, m1, m2], [r1, m2, m3], [r2, m3, m4]]) / det;
                let b = det3([[m0, r0, m2], [m1, r1, m3], [m2, r2, m4]]) / det;
                let c = det3([[m0, m1, m2], [m1, m2, m3], [r0, r1, r2]]) / det;
                if a.is_finite() && b.is_finite() && c.is_finite() {
                    return Some((a, b, c));
                }
            }
        }
        self.solve_linear()
    }

    /// (a, b, 0): the weighted least-squares line, or the weighted mean when the points do
    /// not determine a slope.
    fn solve_linear(&self) -> Option<(f64, f64, f64)> {
        let [m0, m1, m2, _, _] = self.moments;
        let [r0, r1, _] = self.rhs;
        if m0.is_nan() || m0 <= 0.0 {
            return None;
        }
        let (det, [a, b]) = cramer2([[m0, m1], [m1, m2]], [r0, r1]);
        if self.count >= 2 && det > 1e-9 * m0 * m2 {
            return Some((a, b, 0.0));
        }
        Some((r0 / m0, 0.0, 0.0))
    }
}

/// The quadratic (or, with `linear`, straight) fit of a window with bandwidth `sigma`
/// (biweight kernel of half-width
/// `BANDWIDTH_REACH · sigma`: smooth and zero at its edge, so that precise points do not
/// jump in and out of the fit as the origin moves).
fn fit_window(window: &[WindowPoint], sigma: f64, linear: bool) -> Option<(f64, f64, f64)> {
    let reach = BANDWIDTH_REACH * sigma;
    let inverse = 1.0 / (reach * reach);
    let mut fit = QuadraticFit::default();
    for w in window {
        let x = w.distance_squared * inverse;
        if x < 1.0 {
            let kernel = (1.0 - x) * (1.0 - x);
            fit.add(w.u, w.v, kernel * w.weight);
        }
    }
    if linear {
        fit.solve_linear()
    } else {
        fit.solve()
    }
}

/// Whether the fitted curve puts no crack's foreground centre outside it, nor its
/// background centre inside, by more than `slack` px (stops at the first that is).
fn respects_cracks(
    window: &[WindowPoint],
    sigma: f64,
    (a, b, c): (f64, f64, f64),
    slack: f64,
) -> bool {
    let reach = BANDWIDTH_REACH * sigma;
    let reach_squared = reach * reach;
    let curve = |u: f64| a + b * u + c * u * u;
    window
        .iter()
        .filter(|w| w.distance_squared < reach_squared)
        .all(|w| {
            let h = w.half_normal;
            let inner = curve(w.u - h.x) - (w.v - h.y);
            let outer = (w.v + h.y) - curve(w.u + h.x);
            // `max` as the fold over the window took it: a NaN side counts as the other.
            inner.max(outer) <= slack || inner.max(outer).is_nan()
        })
}

/// One crack in a bilevel regression window, in the frame of the window's origin.
#[derive(Clone, Copy, Debug)]
struct WindowPoint {
    /// Squared distance of the crack midpoint from the origin.
    distance_squared: f64,
    /// Tangential coordinate of the crack midpoint.
    u: f64,
    /// Normal coordinate of the crack midpoint (positive towards the foreground).
    v: f64,
    /// Run weight × precision weight.
    weight: f64,
    /// Half the crack normal, as (u, v): the background pixel centre is at
    /// (u, v) + this, the foreground centre at (u, v) − this.
    half_normal: Point,
}

impl Workspace {
    /// Bilevel path: crack midpoints smoothed by weighted local regression, with sharp
    /// corners.
    pub(super) fn bilevel_outline(&mut self, cracks: &[Crack], mask: &PaddedMask) -> Vec<Point> {
        self.raw.clear();
        self.raw.extend(cracks.iter().map(|c| c.mid()));
        self.normals.clear();
        self.normals.extend(cracks.iter().map(|c| c.normal()));
        self.points.clear();
        self.points.extend_from_slice(&self.raw);
        let n = self.points.len();
        self.anchors.clear();
        self.anchors.resize(n, false);
        if n >= 2 * CORNER_REACH + 2 {
            if n >= MIN_CORNER_LOOP {
                self.find_corners();
            } else {
                self.corners.clear();
            }
            // A candidate and the cracks next to it (where a digitised corner is cut off by
            // a short chamfer) stay out of the first regression.
            for &c in &self.corners {
                for k in 0..=2 * CORNER_ZONE {
                    self.anchors[(c + n + k - CORNER_ZONE) % n] = true;
                }
            }
            self.smooth();
            self.run_weights();
            let mut window = Vec::new();
            self.update_tangents();
            self.choose_bandwidths(&mut window);
            self.regress(false);
            if !self.corners.is_empty() {
                for &c in &self.corners {
                    for k in 0..=2 * CORNER_ZONE {
                        self.anchors[(c + n + k - CORNER_ZONE) % n] = false;
                    }
                }
                for &c in &self.corners {
                    self.anchors[c] = true;
                }
                self.place_corners(mask);
                self.update_tangents();
                self.regress(true);
            }
        }
        self.update_tangents();
        self.remove_close_and_backsteps();
        self.mark_turns();
        self.resample()
    }

    /// Bilevel corners: local maxima of the angle between the chords to the points
    /// `CORNER_REACH` back and ahead, when above `CORNER_ANGLE_DEG`.
    fn find_corners(&mut self) {
        let pts = &self.points;
        let n = pts.len();
        let chord_angle = |i: usize, k: usize| {
            let back = pts[i] - pts[(i + n - k) % n];
            let ahead = pts[(i + k) % n] - pts[i];
            turn_angle(back, ahead)
        };
        let local_maxima = |angles: &[f64], min: f64, out: &mut Vec<usize>| {
            let k = CORNER_REACH;
            for i in 0..n {
                let a = angles[i];
                if a >= min
                    && (1..=k).all(|j| a > angles[(i + n - j) % n] && a >= angles[(i + j) % n])
                {
                    out.push(i);
                }
            }
        };
        // Short chords see sharp corners...
        self.values.clear();
        self.values
            .extend((0..n).map(|i| chord_angle(i, CORNER_REACH)));
        self.corners.clear();
        local_maxima(
            &self.values,
            CORNER_ANGLE_DEG.to_radians(),
            &mut self.corners,
        );
        // ...long ones also corners that digitisation cut off with a short chamfer, but
        // need a larger angle not to take curves, and would merge corners close together:
        // they only add corners where the short chords found none.
        self.values.clear();
        self.values
            .extend((0..n).map(|i| chord_angle(i, CORNER_LONG_REACH)));
        let mut long = Vec::new();
        local_maxima(&self.values, CORNER_LONG_ANGLE_DEG.to_radians(), &mut long);
        let near = |i: usize, j: usize| {
            let d = (i + n - j) % n;
            d.min(n - d) <= CORNER_LONG_REACH
        };
        let short = self.corners.clone();
        self.corners.extend(
            long.into_iter()
                .filter(|&i| short.iter().all(|&j| !near(i, j))),
        );
        self.corners.sort_unstable();
    }

    /// [1, 2, 1]/4 smoothing, anchors held fixed (cyclic when there is none).
    pub(super) fn smooth(&mut self) {
        let n = self.points.len();
        for _ in 0..SMOOTHING_PASSES {
            self.scratch.clear();
            self.scratch.extend_from_slice(&self.points);
            let src = &self.scratch;
            for i in 0..n {
                if self.anchors[i] {
                    continue;
                }
                let a = src[wrap(i + n - 1, n)];
                let b = src[wrap(i + 1, n)];
                self.points[i] = (a + src[i] * 2.0 + b) * 0.25;
            }
        }
    }

    /// Unit tangents by central differences, one-sided next to anchors.
    fn update_tangents(&mut self) {
        let n = self.points.len();
        self.tangents.clear();
        for i in 0..n {
            let prev = wrap(i + n - 1, n);
            let next = wrap(i + 1, n);
            let a = if self.anchors[prev] && !self.anchors[i] {
                i
            } else {
                prev
            };
            let b = if self.anchors[next] && !self.anchors[i] {
                i
            } else {
                next
            };
            let t = unit(self.points[b] - self.points[a])
                .or_else(|| unit(self.points[next] - self.points[prev]))
                .unwrap_or(Point::ZERO);
            self.tangents.push(t);
        }
    }

    /// Bilevel: each crack's share of its run. A run of equal cracks (a flat stretch of the
    /// staircase) says only that the outline lies within ±0.5 px of it, an error shared by
    /// all its cracks, so together they count as one observation.
    pub(super) fn run_weights(&mut self) {
        let n = self.normals.len();
        self.run_weight.clear();
        self.run_weight.resize(n, 1.0);
        let same = |a: usize, b: usize| self.normals[a] == self.normals[b];
        // Start just after a change of direction, if there is one.
        let Some(start) = (0..n).find(|&i| !same(i, (i + n - 1) % n)) else {
            return;
        };
        let mut i = 0;
        while i < n {
            let first = (start + i) % n;
            let mut len = 1;
            while i + len < n && same(first, (first + len) % n) {
                len += 1;
            }
            for k in 0..len {
                self.run_weight[(first + k) % n] = 1.0 / len as f64;
            }
            i += len;
        }
    }

    /// The cracks around point `i` that a regression window of half-width `reach` may
    /// use, in the frame of the point's current position and tangent. The window stops at
    /// anchors and where the outline has turned by more than 60°. Returns whether an
    /// anchor (a corner) cut it short.
    fn collect_window(&self, i: usize, reach: f64, window: &mut Vec<WindowPoint>) -> bool {
        let origin = self.points[i];
        let tangent = self.tangents[i];
        let normal = tangent.perp();
        let reach_squared = reach * reach;
        window.clear();
        let add = |j: usize| -> bool {
            let d = self.raw[j] - origin;
            let distance_squared = d.length_squared();
            if self.anchors[j]
                || distance_squared > reach_squared
                || self.tangents[j].dot(tangent) < MIN_WINDOW_TANGENT_COSINE
            {
                return false;
            }
            let half_normal = self.normals[j] * 0.5;
            window.push(WindowPoint {
                distance_squared,
                u: d.dot(tangent),
                v: d.dot(normal),
                weight: self.values[j],
                half_normal: Point::new(half_normal.dot(tangent), half_normal.dot(normal)),
            });
            true
        };
        self.walk_window(i, add)
    }

    /// Walks the regression window around point `i`: `i` itself, then backwards and
    /// forwards (at most half the contour each way, never all of it) while `add` accepts
    /// the points. Returns whether an anchor just outside the window cut it short.
    fn walk_window(&self, i: usize, mut add: impl FnMut(usize) -> bool) -> bool {
        let n = self.points.len();
        let half = n / 2;
        add(i);
        let mut back = 0;
        while back < half && add(wrap(i + n - back - 1, n)) {
            back += 1;
        }
        let mut ahead = 0;
        while ahead + back < n - 1 && ahead < half && add(wrap(i + ahead + 1, n)) {
            ahead += 1;
        }
        self.anchors[wrap(i + n - back - 1, n)] || self.anchors[wrap(i + ahead + 1, n)]
    }

    /// Bilevel: the weight of every crack for the current tangents (run weight × precision
    /// weight, see [`BILEVEL_PRECISION_FLOOR`]), into `self.values`.
    fn crack_weights(&mut self) {
        self.values.clear();
        for j in 0..self.raw.len() {
            let across = self.normals[j].cross(self.tangents[j]);
            self.values
                .push(self.run_weight[j] / (across * across + BILEVEL_PRECISION_FLOOR));
        }
    }

    /// Bilevel: the regression bandwidth of every point. Two limits, the smaller wins:
    ///
    /// * *curvature*: the flat run at the top of a digitised circle of radius R is up to
    ///   √(8R) long and the window must reach the risers beyond it, so σ = 0.8·√(2R), with
    ///   R from chords [`BANDWIDTH_CHORD`] cracks long on the current estimate;
    /// * *consistency*: the widest of [`BANDWIDTHS`] whose fit passes between the
    ///   foreground and background centres of every crack in its window, within
    ///   [`FIT_PIXEL_SLACK`]. A window reaching from a straight side into a tight curve
    ///   bulges and fails.
    ///
    /// The result is then averaged along the outline (in log scale, over
    /// ±[`BANDWIDTH_SMOOTHING`] points) so that neighbouring points use similar windows and
    /// the outline has no kinks.
    fn choose_bandwidths(&mut self, window: &mut Vec<WindowPoint>) {
        let n = self.points.len();
        let k = BANDWIDTH_CHORD.min((n - 1) / 2).max(1);
        self.crack_weights();
        // log σ at every BANDWIDTH_STRIDE-th point, into `self.angles`.
        let mut log_sigma = std::mem::take(&mut self.angles);
        log_sigma.clear();
        for i in (0..n).step_by(BANDWIDTH_STRIDE) {
            // The chords stop short of corners; next to one, the curvature is left to the
            // consistency test.
            let reach_back = (1..=k)
                .find(|&j| self.anchors[wrap(i + n - j, n)])
                .unwrap_or(k + 1)
                - 1;
            let reach_ahead = (1..=k)
                .find(|&j| self.anchors[wrap(i + j, n)])
                .unwrap_or(k + 1)
                - 1;
            let (kb, ka) = (reach_back.min(reach_ahead), reach_back.min(reach_ahead));
            let back = self.points[i] - self.points[wrap(i + n - kb, n)];
            let ahead = self.points[wrap(i + ka, n)] - self.points[i];
            let arc = 0.5 * (norm(back) + norm(ahead));
            let curvature = if arc > 0.0 && kb >= 3 {
                turn_angle(back, ahead) / arc
            } else {
                0.0
            };
            let by_curvature = if curvature > 0.0 {
                (BANDWIDTH_PER_SQRT_DIAMETER * (2.0 / curvature).sqrt())
                    .clamp(BANDWIDTHS[0], BANDWIDTHS[BANDWIDTHS.len() - 1])
            } else {
                BANDWIDTHS[BANDWIDTHS.len() - 1]
            };
            let cut = self.collect_window(i, BANDWIDTH_REACH * by_curvature, window);
            // The widest consistent candidate, trying the widest first.
            let candidates = std::iter::once(by_curvature).chain(
                BANDWIDTHS
                    .iter()
                    .rev()
                    .copied()
                    .filter(|&s| s < by_curvature),
            );
            let mut sigma = BANDWIDTHS[0];
            for candidate in candidates {
                let consistent = fit_window(window, candidate, cut)
                    .is_some_and(|fit| respects_cracks(window, candidate, fit, FIT_PIXEL_SLACK));
                if consistent {
                    sigma = candidate;
                    break;
                }
            }
            log_sigma.push(sigma.ln());
        }
        // A running mean of log σ over the sampled points, interpolated in between.
        let m = log_sigma.len();
        let r = (BANDWIDTH_SMOOTHING / BANDWIDTH_STRIDE)
            .max(1)
            .min((m - 1) / 2);
        let mean_at = |s: usize| {
            (0..=2 * r)
                .map(|j| log_sigma[(s + m + j - r) % m])
                .sum::<f64>()
                / (2 * r + 1) as f64
        };
        let means: Vec<f64> = (0..m).map(mean_at).collect();
        self.sigma.clear();
        for i in 0..n {
            let s = i / BANDWIDTH_STRIDE;
            let start = s * BANDWIDTH_STRIDE;
            // The next sample wraps round to the first one.
            let end = if s + 1 < m {
                start + BANDWIDTH_STRIDE
            } else {
                n
            };
            let t = (i - start) as f64 / (end - start) as f64;
            let value = means[s] + (means[(s + 1) % m] - means[s]) * t;
            self.sigma.push(value.exp());
        }
        self.angles = log_sigma;
    }

    /// One round of weighted local quadratic regression of the raw crack midpoints around
    /// the current estimate. In the frame of each point (tangent u, normal v) it fits
    /// v = a + b·u + c·u² with a biweight kernel of the point's bandwidth (see
    /// [`Workspace::choose_bandwidths`]), the run weights and the precision weights of
    /// [`BILEVEL_PRECISION_FLOOR`], and moves the point to v = a. Anchors stay put.
    fn regress(&mut self, near_corners: bool) {
        let n = self.points.len();
        let half = n / 2;
        self.crack_weights();
        self.scratch.clear();
        self.scratch_tangents.clear();
        // With `near_corners`, only the points near a corner are fitted again, and the
        // (placed) corner that ends a window is part of it.
        let mut near = std::mem::take(&mut self.near);
        near.clear();
        near.resize(n, !near_corners);
        if near_corners {
            for &c in &self.corners {
                for k in 0..=2 * CORNER_REGRESSION_REACH.min(half) {
                    near[(c + n + k - CORNER_REGRESSION_REACH.min(half)) % n] = true;
                }
            }
        }
        // The fit of the last fitted point: origin, tangent, (a, b, c).
        let mut last: Option<(Point, Point, (f64, f64, f64))> = None;
        for (i, &fit_here) in near.iter().enumerate() {
            let origin = self.points[i];
            let tangent = self.tangents[i];
            if self.anchors[i] || !fit_here {
                self.scratch.push(origin);
                self.scratch_tangents.push(tangent);
                last = None;
                continue;
            }
            // Every other point lies on the previous point's fitted parabola.
            if let (Some((o, t, (a, b, c))), true) = (last, i % REGRESSION_STRIDE != 0) {
                let nrm = t.perp();
                let u = (origin - o).dot(t);
                self.scratch.push(o + t * u + nrm * (a + b * u + c * u * u));
                self.scratch_tangents
                    .push(unit(t + nrm * (b + 2.0 * c * u)).unwrap_or(tangent));
                continue;
            }
            let normal = tangent.perp();
            let reach = BANDWIDTH_REACH * self.sigma[i];
            let inverse = 1.0 / (reach * reach);
            // The same walk as `collect_window`, fitted on the fly.
            let mut fit = QuadraticFit::default();
            let add = |j: usize| -> bool {
                let corner = self.anchors[j];
                let d = if corner {
                    self.points[j] - origin
                } else {
                    self.raw[j] - origin
                };
                let x = d.length_squared() * inverse;
                if (corner && !near_corners)
                    || x > 1.0
                    || (!corner && self.tangents[j].dot(tangent) < MIN_WINDOW_TANGENT_COSINE)
                {
                    return false;
                }
                let kernel = (1.0 - x) * (1.0 - x);
                let weight = if corner {
                    CORNER_WEIGHT
                } else {
                    self.values[j]
                };
                fit.add(d.dot(tangent), d.dot(normal), kernel * weight);
                // A corner ends the window.
                !corner
            };
            // A window cut short by a corner on one side cannot tell curvature from
            // offset: fit a line there.
            let cut = self.walk_window(i, add);
            let solution = if cut { fit.solve_linear() } else { fit.solve() };
            match solution {
                Some((a, b, c)) => {
                    self.scratch.push(origin + normal * a);
                    self.scratch_tangents
                        .push(unit(tangent + normal * b).unwrap_or(tangent));
                    last = Some((origin, tangent, (a, b, c)));
                }
                None => {
                    self.scratch.push(origin);
                    self.scratch_tangents.push(tangent);
                    last = None;
                }
            }
        }
        std::mem::swap(&mut self.points, &mut self.scratch);
        std::mem::swap(&mut self.tangents, &mut self.scratch_tangents);
        self.near = near;
    }

    /// Places each bilevel corner candidate at the intersection of the lines fitted to the
    /// regressed outline on its two sides, from `CORNER_FIT_SKIP` + 1 to `CORNER_FIT_FAR`
    /// points away (never more than half-way to the neighbouring candidates; near ones fall
    /// back to the nearest points), when that corner is *consistent with the pixels*: the
    /// foreground centres of the cracks around it lie inside the two side lines' wedge and
    /// the background centres outside (within `CORNER_PIXEL_SLACK`), and so do the 5×5
    /// pixels around it. A digitised curve taken for a corner fails this: its extrapolated
    /// corner covers background pixels. Rejected candidates stop being anchors; every
    /// candidate stays in `self.corners` so that its neighbourhood is regressed again.
    fn place_corners(&mut self, mask: &PaddedMask) {
        let n = self.points.len();
        let m = self.corners.len();
        if m == 0 {
            return;
        }
        self.scratch.clear();
        self.scratch.extend_from_slice(&self.points);
        let first = CORNER_FIT_SKIP + 1;
        for ci in 0..m {
            let c = self.corners[ci];
            let prev = self.corners[(ci + m - 1) % m];
            let next = self.corners[(ci + 1) % m];
            // Points strictly between this corner and its neighbours (the whole loop when
            // it is the only corner).
            let gap_back = if m == 1 {
                n - 1
            } else {
                (c + n - prev) % n - 1
            };
            let gap_ahead = if m == 1 {
                n - 1
            } else {
                (next + n - c) % n - 1
            };
            // Straight sides: the raw midpoints all the way to the next corner zone. Curved
            // sides (where the long lines fail the pixel test): the regressed points near
            // the corner. Corners close together: the nearest points.
            let long_back = gap_back.saturating_sub(CORNER_ZONE + 1).min(CORNER_FIT_FAR);
            let long_ahead = gap_ahead
                .saturating_sub(CORNER_ZONE + 1)
                .min(CORNER_FIT_FAR);
            let short_back = gap_back
                .saturating_sub(CORNER_ZONE + 1)
                .min(CORNER_FIT_POINTS);
            let short_ahead = gap_ahead
                .saturating_sub(CORNER_ZONE + 1)
                .min(CORNER_FIT_POINTS);
            let corner = if short_back >= first + 2 && short_ahead >= first + 2 {
                self.corner_from_sides(mask, c, (first, long_back), (first, long_ahead), true)
                    .or_else(|| {
                        self.corner_from_sides(
                            mask,
                            c,
                            (first, short_back),
                            (first, short_ahead),
                            false,
                        )
                    })
            } else {
                let most = CORNER_FIT_POINTS.min(n / 6);
                self.corner_from_sides(
                    mask,
                    c,
                    (1, gap_back.min(most)),
                    (1, gap_ahead.min(most)),
                    false,
                )
            };
            match corner {
                Some(x) => self.points[c] = x,
                None => {
                    // Not a corner after all: the point joins its neighbours.
                    let p = self.scratch[(c + n - 1) % n];
                    let q = self.scratch[(c + 1) % n];
                    self.points[c] = p.lerp(q, 0.5);
                    self.anchors[c] = false;
                }
            }
        }
    }

    /// The line of one side of a bilevel corner: a first guess through the current points
    /// at `indices`, then twice a weighted least-squares line through the raw crack
    /// midpoints with the run and precision weights of the regression (so that the risers
    /// of a shallow staircase decide, not its flat runs).
    pub(super) fn fit_side(&self, indices: impl Iterator<Item = usize> + Clone) -> Option<Line> {
        let (mut line, _) = fit_line(indices.clone().map(|j| self.scratch[j]))?;
        for _ in 0..2 {
            let normal = line.direction.perp();
            let mut fit = QuadraticFit::default();
            for j in indices.clone() {
                let d = self.raw[j] - line.origin;
                let across = self.normals[j].cross(line.direction);
                let weight = self.run_weight[j] / (across * across + BILEVEL_PRECISION_FLOOR);
                fit.add(d.dot(line.direction), d.dot(normal), weight);
            }
            let (a, b, _) = fit.solve_linear()?;
            line = Line {
                origin: line.origin + normal * a,
                direction: unit(line.direction + normal * b)?,
            };
        }
        Some(line)
    }

    /// The corner at `c` from the points `back_first..=back` before and
    /// `ahead_first..=ahead` after it (the raw midpoints by [`Workspace::fit_side`] with
    /// `raw`, else a plain line through the current points `self.scratch`), checked against the cracks in that range and the 5×5 pixels
    /// around the corner (see [`Workspace::place_corners`]).
    fn corner_from_sides(
        &self,
        mask: &PaddedMask,
        c: usize,
        (back_first, back): (usize, usize),
        (ahead_first, ahead): (usize, usize),
        raw: bool,
    ) -> Option<Point> {
        let n = self.scratch.len();
        let pts = &self.scratch;
        let back_indices = (back_first..=back).map(|j| (c + n - j) % n);
        let ahead_indices = (ahead_first..=ahead).map(|j| (c + j) % n);
        let (back_line, ahead_line) = if raw {
            (self.fit_side(back_indices)?, self.fit_side(ahead_indices)?)
        } else {
            (
                fit_line(back_indices.map(|j| pts[j]))?.0,
                fit_line(ahead_indices.map(|j| pts[j]))?.0,
            )
        };
        let x = intersect(back_line, ahead_line)?;
        if norm(x - pts[c]) > MAX_CORNER_MOVE {
            return None;
        }
        // Orient both lines along the walk.
        let orient = |d: Point, along: Point| if d.dot(along) < 0.0 { -d } else { d };
        let da = orient(back_line.direction, pts[c] - pts[(c + n - back) % n]);
        let db = orient(ahead_line.direction, pts[(c + ahead) % n] - pts[c]);
        if turn_angle(da, db) < CORNER_LINE_ANGLE_DEG.to_radians() {
            return None;
        }
        let convex = da.cross(db) > 0.0;
        let slack = CORNER_PIXEL_SLACK;
        let inside = |q: Point| {
            let (a, b) = (da.cross(q - x), db.cross(q - x));
            if convex {
                a > -slack && b > -slack
            } else {
                a > -slack || b > -slack
            }
        };
        let outside = |q: Point| {
            let (a, b) = (da.cross(q - x), db.cross(q - x));
            if convex {
                a < slack || b < slack
            } else {
                a < slack && b < slack
            }
        };
        let cracks_agree = (0..=back + ahead).all(|k| {
            let j = (c + n + k - back) % n;
            let half = self.normals[j] * 0.5;
            inside(self.raw[j] - half) && outside(self.raw[j] + half)
        });
        // The pixels around the corner itself, diagonal neighbours included.
        let (cx, cy) = (floor_i64(x.x), floor_i64(x.y));
        let pixels_agree = (cy - 2..=cy + 2).all(|r| {
            (cx - 2..=cx + 2).all(|col| {
                let q = Point::new(col as f64 + 0.5, r as f64 + 0.5);
                // Image pixel (col, r) is padded pixel (col + 1, r + 1).
                let fg = mask.is_foreground((col + 1, r + 1));
                if fg {
                    inside(q)
                } else {
                    outside(q)
                }
            })
        });
        (cracks_agree && pixels_agree).then_some(x)
    }
}
