//! Edge placement on grey levels: each crack midpoint moved along the coverage gradient
//! to the edge by coverage integration, the curvature bias corrected, anti-aliased corners
//! sharpened, and the noise measure that sends noisy grey levels to the bilevel path.

use super::lines::fit_line;
use super::lines::intersect;
use super::lines::lap;
use super::lines::norm;
use super::lines::turn_angle;
use super::lines::unit;
use super::lines::ArcWalk;
use super::mask::Crack;
use super::spikes::{drop_wrapping_edit, mark_edits};
use super::workspace::Workspace;
use crate::geom::distance_to_closed_polyline;
use crate::geom::AngleFloor;
use crate::geom::Point;
use crate::raster::Bitmap;
use crate::raster::Cell;

/// Half-width (px) of the window along the normal over which coverage is integrated.
const HALF_WINDOW: f64 = 2.0;
/// Number of integration steps on each side of the crack midpoint.
const WINDOW_STEPS: usize = 8;
/// A rise (outward) or fall (inward) of coverage by more than this ends the window.
const MONOTONE_SLACK: f64 = 0.02;
/// The gradient normal is used when its cosine with the crack normal is at least this (it
/// may run along the crack, at the tip of a thin sliver, but not back into the foreground).
const MIN_NORMAL_AGREEMENT: f64 = 0.0;
/// Largest accepted move (px) of a refined point from its crack midpoint.
const MAX_SHIFT: f64 = 1.5;
/// Largest distance (px) across its crack that a refined edge point may lie from the crack
/// midpoint: with the threshold near half coverage an edge consistent with the two pixels
/// the crack separates lies within ~0.5 px of it (0.7 px on a diagonal).
const MAX_CRACK_SHIFT: f64 = 0.75;
/// Variance (px²) of the blur between the shape and the integrated profile: the pixel's
/// box filter (1/12) plus bilinear interpolation (1/6).
const EDGE_BLUR_VARIANCE: f64 = 0.25;
/// Largest curvature (1/px) used for the curvature-bias correction.
const MAX_BIAS_CURVATURE: f64 = 0.5;
/// Arc length (px) to the chord ends of the grey-level corner detector.
const GREY_CORNER_REACH: f64 = 2.0;
/// Smallest chord angle (degrees) of a grey-level corner.
const GREY_CORNER_ANGLE_DEG: f64 = 50.0;
/// Arc length (px) on each side of a grey-level corner treated as rounded.
const GREY_CORNER_SKIP: f64 = 1.2;
/// Arc length (px) of each straight side fitted beyond the rounded part.
const GREY_CORNER_SIDE: f64 = 3.0;
/// Largest distance (px) of a side point from its fitted line.
const GREY_CORNER_RESIDUAL: f64 = 0.08;
/// Largest distance (px) from the sharpened corner to the rounded outline.
const GREY_CORNER_MOVE: f64 = 1.0;

/// How the grey-level path places an edge along its normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum EdgeEstimator {
    /// s = −h + ∫ f ds over the clipped window (the default).
    CoverageIntegral,
    /// Where the bilinear coverage crosses the threshold (kept for the comparison test).
    #[cfg_attr(not(test), allow(dead_code))]
    LevelCrossing,
}

/// Noise level (px, [`outline_noise`]) above which a grey-level outline is traced from its
/// thresholded pixels instead: clean anti-aliased edges measure 0.005–0.02 px (glyphs at
/// 64 and 256 px, icons, stress shapes), a bilevel horse saved as a JPEG at quality 30
/// 0.04 px, photos and scans 0.08–0.15 px.
pub(super) const NOISE_LIMIT: f64 = 0.03;

/// Robust noise level (px) of an outline: the median of the fourth difference of the
/// points across the outline (which cancels curves up to cubics), scaled to a standard
/// deviation (for independent noise σ the fourth difference has deviation σ·√70).
pub(super) fn outline_noise(points: &[Point]) -> f64 {
    let n = points.len();
    if n < 8 {
        return 0.0;
    }
    let at = |k: usize| points[k % n];
    let mut r: Vec<f64> = (0..n)
        .filter_map(|i| {
            let (a, b, c, d, e) = (at(i + n - 2), at(i + n - 1), at(i), at(i + 1), at(i + 2));
            let normal = unit(d - b)?.perp();
            let fourth = (a + e) - (b + d) * 4.0 + c * 6.0;
            Some(fourth.dot(normal).abs())
        })
        .collect();
    if r.is_empty() {
        return 0.0;
    }
    median(&mut r) / 0.6745 / 70f64.sqrt()
}

/// The median of `values` (the upper one of an even count); reorders them. Not empty.
fn median(values: &mut [f64]) -> f64 {
    let mid = values.len() / 2;
    *values.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Spread (px) of an edge as the standard deviation of the Gaussian blur that gives its
/// rise: a step blurred by a Gaussian of deviation σ rises from 10 % to 90 % over
/// 2 · 1.2816 σ.
const RISE_PER_SIGMA: f64 = 2.0 * 1.2816;
/// Farthest (px) along the normal that the rise of an edge is followed each way.
const SPREAD_REACH: f64 = 8.0;
/// Cracks sampled per contour for its edge spread (evenly along it).
const SPREAD_SAMPLES: usize = 32;
/// Fewest measured cracks (and at least half of those sampled) for a contour's spread.
const SPREAD_MIN_MEASURED: usize = 6;

/// The walk along an edge's rise ends where the coverage has made no new extreme by more
/// than [`SPREAD_PROGRESS`] for this many steps (1 px): it has levelled out at paper or
/// ink, noise or not.
const SPREAD_LEVEL_STEPS: usize = 4;
/// Least move of the coverage (beyond its extreme so far) that counts as the rise going on.
const SPREAD_PROGRESS: f64 = 0.01;
/// A coverage that turns back by more than this from its extreme ends the measure (a thin
/// stroke, another edge close by); scanner noise stays well below it.
const SPREAD_TURN_BACK: f64 = 0.15;
/// Least rise (coverage) between the two ends of a measured edge.
const SPREAD_MIN_RISE: f64 = 0.25;

/// The coverage walked from `m` along `dir` (falling outwards, rising inwards) into `out`,
/// one sample per step, until it levels out ([`SPREAD_LEVEL_STEPS`]) or at
/// [`SPREAD_REACH`]. `None` if it turns back by more than [`SPREAD_TURN_BACK`] first.
fn rise_walk(
    bitmap: &Bitmap,
    m: Point,
    dir: Point,
    falling: bool,
    out: &mut Vec<f64>,
) -> Option<()> {
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    let steps = (SPREAD_REACH / ds) as usize;
    // Quarter-pixel steps read each cell's pixels once.
    let mut cell = Cell::NONE;
    let mut best = bitmap.sample_in(m, &mut cell);
    let mut idle = 0;
    for j in 1..=steps {
        let f = bitmap.sample_in(m + dir * (j as f64 * ds), &mut cell);
        out.push(f);
        let progress = if falling { best - f } else { f - best };
        if progress > SPREAD_PROGRESS {
            best = f;
            idle = 0;
        } else if -progress > SPREAD_TURN_BACK {
            return None;
        } else {
            idle += 1;
            if idle == SPREAD_LEVEL_STEPS {
                break;
            }
        }
    }
    Some(())
}

/// Spread of the edge at one crack (px, [`RISE_PER_SIGMA`]): the distance along the
/// coverage gradient over which the coverage falls from 90 % to 10 % of the way between
/// the levels it settles at on either side (ink and paper, whatever their coverage;
/// noise smoothed by following the running minimum outwards). `None` where it does not
/// fall by [`SPREAD_MIN_RISE`] within [`SPREAD_REACH`] each way, or turns back.
fn crack_spread(bitmap: &Bitmap, crack: &Crack, profile: &mut Vec<f64>) -> Option<f64> {
    let n = edge_normal(bitmap, crack);
    let m = crack.mid();
    // The profile from its inner end outwards: inward samples reversed, `m`, outward.
    profile.clear();
    rise_walk(bitmap, m, -n, false, profile)?;
    profile.reverse();
    profile.push(bitmap.sample(m));
    rise_walk(bitmap, m, n, true, profile)?;
    let top = (0..profile.len()).fold(0, |k, j| if profile[j] > profile[k] { j } else { k });
    let (hi, lo) = (
        profile[top],
        profile.iter().copied().fold(f64::INFINITY, f64::min),
    );
    if hi - lo < SPREAD_MIN_RISE {
        return None;
    }
    // Steps from the top to where the running minimum first falls below `level`.
    let crossing = |level: f64| {
        let mut low = hi;
        for (k, &f) in profile[top..].iter().enumerate().skip(1) {
            if f < level {
                return Some(k as f64 - (level - f) / (low - f));
            }
            low = low.min(f);
        }
        None
    };
    let inner = crossing(lo + 0.9 * (hi - lo))?;
    let outer = crossing(lo + 0.1 * (hi - lo))?;
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    Some((outer - inner) * ds / RISE_PER_SIGMA)
}

/// The edge spread of a border (px, the median of [`crack_spread`] over up to
/// [`SPREAD_SAMPLES`] cracks evenly along it): 0.3–0.62 px on a sharp anti-aliased edge
/// (the pixel's box filter and bilinear interpolation), about √(σ² + 1/6) on one blurred
/// by a Gaussian of deviation σ up to 3 px (less beyond: the walk's [`SPREAD_REACH`] ends
/// before the coverage levels out). `None` when too few cracks have a measurable rise.
pub(super) fn edge_spread(bitmap: &Bitmap, cracks: &[Crack]) -> Option<f64> {
    let stride = cracks.len().div_ceil(SPREAD_SAMPLES).max(1);
    let sampled = cracks.len().div_ceil(stride);
    let mut profile = Vec::new();
    let mut spreads: Vec<f64> = cracks
        .iter()
        .step_by(stride)
        .filter_map(|c| crack_spread(bitmap, c, &mut profile))
        .collect();
    if spreads.len() < SPREAD_MIN_MEASURED || 2 * spreads.len() < sampled {
        return None;
    }
    Some(median(&mut spreads))
}

/// The direction (unit, towards the background) along which a crack's edge is measured:
/// the coverage gradient ([`gradient_normal`]) where it does not point back into the
/// foreground, else the crack's own normal.
fn edge_normal(bitmap: &Bitmap, crack: &Crack) -> Point {
    gradient_normal(bitmap, crack)
        .filter(|g| g.dot(crack.normal()) >= MIN_NORMAL_AGREEMENT)
        .unwrap_or(crack.normal())
}

/// Unit normal pointing down the coverage gradient (towards the background) at a crack,
/// from a Sobel-like 3×2 stencil on the two pixel rows that the crack separates: the
/// difference across the crack weighted 1-2-1 along it, and the central difference along
/// it summed over both rows. Both are per pixel after dividing by 4, so the common factor
/// is dropped.
fn gradient_normal(bitmap: &Bitmap, crack: &Crack) -> Option<Point> {
    let n = crack.normal();
    let t = n.perp();
    // Pixel indices of the foreground (inside) and background (outside) pixels.
    let (ic, ir) = crack.inside();
    let (nx, ny) = (n.x as i64, n.y as i64);
    let (tx, ty) = (t.x as i64, t.y as i64);
    let at = |c: i64, r: i64| f64::from(bitmap.coverage_at(c, r));
    let (oc, or) = (ic + nx, ir + ny);
    let across = (at(oc - tx, or - ty) + 2.0 * at(oc, or) + at(oc + tx, or + ty))
        - (at(ic - tx, ir - ty) + 2.0 * at(ic, ir) + at(ic + tx, ir + ty));
    let along = (at(ic + tx, ir + ty) + at(oc + tx, or + ty))
        - (at(ic - tx, ir - ty) + at(oc - tx, or - ty));
    let g = n * across + t * along;
    let length = norm(g);
    (length > 0.0 && length.is_finite()).then(|| -g / length)
}

/// How far the coverage integral reaches along the normal and how far from its crack the
/// edge it finds may lie.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Window {
    /// Integration steps of `HALF_WINDOW / WINDOW_STEPS` px each way, at most.
    steps: usize,
    /// Largest distance (px) across the crack from its midpoint.
    crack_shift: f64,
}

impl Window {
    /// Anti-aliased edges, a pixel or two wide: ±2 px, within [`MAX_CRACK_SHIFT`].
    pub(super) const SHARP: Window = Window {
        steps: WINDOW_STEPS,
        crack_shift: MAX_CRACK_SHIFT,
    };
    /// Soft edges (a blurred scan or photo, an upscaled image): the window widens to ±8 px
    /// until the coverage reaches paper and ink, and the edge may lie up to
    /// [`SOFT_CRACK_SHIFT`] across the crack. The narrow window cuts a wide edge off, which
    /// pulls each point towards its crack: the outline follows the pixel staircase, and the
    /// fit follows it in many short pieces.
    pub(super) const SOFT: Window = Window {
        steps: 4 * WINDOW_STEPS,
        crack_shift: SOFT_CRACK_SHIFT,
    };
}

/// Largest distance (px) across its crack of a soft edge: a blur spreads the edge, and the
/// threshold's level, off the middle of the profile, puts the thresholded boundary farther
/// from it than on a sharp edge. Not more than the fidelity check's 1 px, beyond which the
/// drawn outline would disagree with the thresholded pixels.
const SOFT_CRACK_SHIFT: f64 = 1.0;

/// Share of a contour's cracks whose ±2 px window ends short of paper or ink (an edge
/// wider than the window), above which the contour is refined again with
/// [`Window::SOFT`]. Measured on 300 px glyphs: sharp anti-aliased 0–0.3 %, blurred by a
/// Gaussian of σ = 1 px 2–3 %, σ = 2 and 3 px 100 %, the same glyphs upscaled bicubically
/// 4× 72–89 % and 8× 100 %.
pub(super) const SOFT_SHARE: f64 = 0.5;

/// Edge spread (px, [`edge_spread`]) from which an outline is refined with
/// [`Window::SOFT`] at once, without the sharp pass: that pass would find more than
/// [`SOFT_SHARE`] of its windows open and be abandoned, after half of its cracks or more.
/// A Gaussian blur of σ = 2 px spreads an edge by 2.04 px and opens every window; glyphs
/// upscaled 4× (spread about 1.1 px, 72–89 % open) still take the test of the windows.
pub(super) const SOFT_SPREAD: f64 = 2.0;

/// Fewest cracks of a border whose cracks are refined in parallel (the horse upscaled to
/// 4096 px has a border of about 30 000, a glyph of 256 px a few hundred): about a
/// millisecond of work per thousand cracks, well above what the thread pool costs.
const PARALLEL_REFINE_CRACKS: usize = 4_000;

/// Moves a crack midpoint to the edge; returns the point, the normal used, and whether the
/// integration window was open (ended short of paper or ink).
fn refine_crack(
    bitmap: &Bitmap,
    crack: &Crack,
    estimator: EdgeEstimator,
    window: Window,
) -> (Point, Point, bool) {
    let n = edge_normal(bitmap, crack);
    let (s, open) = match estimator {
        EdgeEstimator::CoverageIntegral => {
            let (s, open) = integrate_edge(bitmap, crack.mid(), n, window.steps);
            (Some(s), open)
        }
        EdgeEstimator::LevelCrossing => (level_crossing(bitmap, crack.mid(), n), false),
    };
    let (p, n) = match s {
        // The edge must also stay where the thresholded pixels put it: within the window's
        // shift across the crack (`MAX_CRACK_SHIFT` on sharp edges). Where the coverage is
        // not a clean step from ink to paper (soft gradients, tinted fills, shading), the
        // integral can move the edge a pixel or more into a region the mask calls the other
        // side; the threshold crossing below cannot.
        Some(s)
            if s.is_finite()
                && s.abs() <= MAX_SHIFT
                && (n * s).dot(crack.normal()).abs() <= window.crack_shift =>
        {
            (crack.mid() + n * s, n)
        }
        _ => {
            // Fall back to the threshold crossing between the two pixel centres.
            let half = crack.normal() * 0.5;
            let f_in = bitmap.sample(crack.mid() - half);
            let f_out = bitmap.sample(crack.mid() + half);
            let t = bitmap.threshold();
            let s = if f_in > f_out {
                ((f_in - t) / (f_in - f_out) - 0.5).clamp(-0.5, 0.5)
            } else {
                0.0
            };
            (crack.mid() + crack.normal() * s, crack.normal())
        }
    };
    (p, n, open)
}

/// Signed distance from `m` along `n` to the edge by coverage integration: the edge of a
/// step from 1 to 0 at s = e satisfies ∫₋ₕʰ f ds = e + h.
/// The window reaches `steps` steps each way, and at least [`HALF_WINDOW`] is integrated
/// (coverage taken as 1 past where the inward walk stopped).
/// Also returns whether the window ended before the coverage came within
/// [`OPEN_LEVEL`] of paper outwards or of ink inwards (the edge is wider than the window).
fn integrate_edge(bitmap: &Bitmap, m: Point, n: Point, steps: usize) -> (f64, bool) {
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    // Each walk reads a cell's pixels once for its samples in it.
    let mut cell = Cell::NONE;
    let f0 = bitmap.sample_in(m, &mut cell);

    // Outward: ∫₀ʰ f ds, f taken as 0 past its minimum.
    let mut outward = 0.0;
    let mut prev = f0;
    let mut lowest = f0;
    let mut open = true;
    for j in 1..=steps {
        if prev <= 0.0 {
            break;
        }
        let f = bitmap.sample_in(m + n * (j as f64 * ds), &mut cell);
        if f > lowest + MONOTONE_SLACK {
            open = false;
            break;
        }
        outward += 0.5 * (prev + f) * ds;
        lowest = lowest.min(f);
        prev = f;
    }
    let open_out = open && prev > OPEN_LEVEL;

    // Inward: ∫₋ₕ⁰ f ds, f taken as 1 past its maximum.
    open = true;
    let mut inward = 0.0;
    let mut prev = f0;
    let mut highest = f0;
    let mut reached = 0.0;
    let mut cell = Cell::NONE;
    for j in 1..=steps {
        if prev >= 1.0 {
            break;
        }
        let f = bitmap.sample_in(m - n * (j as f64 * ds), &mut cell);
        if f < highest - MONOTONE_SLACK {
            // Past the ridge of a stroke thinner than the window: its coverage never
            // reaches 1, and "1 past the maximum" would put the edge too far out.
            if let Some(s) = thin_stroke_edge(bitmap, m, n, highest) {
                return (s, false);
            }
            open = false;
            break;
        }
        inward += 0.5 * (prev + f) * ds;
        highest = highest.max(f);
        prev = f;
        reached = j as f64 * ds;
    }
    let open_in = open && prev < 1.0 - OPEN_LEVEL;
    let h = HALF_WINDOW.max(reached);
    inward += h - reached;
    (inward + outward - h, open_out || open_in)
}

/// Coverage short of paper (0) or ink (1) at which a window that ends there is open.
const OPEN_LEVEL: f64 = 0.1;

/// Coverage below which the far side of a thin stroke counts as reached.
const THIN_STROKE_FLOOR: f64 = 0.04;
/// Farthest (px) the far side of a thin stroke is looked for, inwards from the crack.
const THIN_STROKE_REACH: f64 = 3.0;

/// The edge of a stroke too thin for its coverage to reach 1, from its whole profile
/// along `n`: a box-filtered stroke of width w has ∫ f ds = w whatever the blur, and its
/// centre at the centroid c of f, so the edge on the `+n` side is at c + w/2. `None` when
/// the profile does not fall back to paper within `THIN_STROKE_REACH` (a stroke that
/// widens into a shape) or when the stroke is not faint (peak `highest` near 1).
fn thin_stroke_edge(bitmap: &Bitmap, m: Point, n: Point, highest: f64) -> Option<f64> {
    if highest > 0.95 {
        return None;
    }
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    let (mut mass, mut moment) = (0.0, 0.0);
    // Outwards to paper.
    let mut s = 0.0;
    let mut cell = Cell::NONE;
    let mut f = bitmap.sample_in(m, &mut cell);
    let mut closed_out = false;
    while s < HALF_WINDOW {
        let g = bitmap.sample_in(m + n * (s + ds), &mut cell);
        mass += 0.5 * (f + g) * ds;
        moment += 0.5 * (f * s + g * (s + ds)) * ds;
        s += ds;
        f = g;
        if f <= THIN_STROKE_FLOOR {
            closed_out = true;
            break;
        }
    }
    // Inwards across the ridge to paper on the far side.
    let mut s = 0.0;
    let mut cell = Cell::NONE;
    let mut f = bitmap.sample_in(m, &mut cell);
    let mut closed_in = false;
    while s < THIN_STROKE_REACH {
        let g = bitmap.sample_in(m - n * (s + ds), &mut cell);
        mass += 0.5 * (f + g) * ds;
        moment -= 0.5 * (f * s + g * (s + ds)) * ds;
        s += ds;
        f = g;
        if f <= THIN_STROKE_FLOOR {
            closed_in = true;
            break;
        }
    }
    if !(closed_out && closed_in) || mass <= 0.0 {
        return None;
    }
    let centre = moment / mass;
    Some(centre + 0.5 * mass)
}

/// Signed distance from `m` along `n` to where the bilinear coverage crosses the threshold,
/// nearest to `m`.
fn level_crossing(bitmap: &Bitmap, m: Point, n: Point) -> Option<f64> {
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    let t = bitmap.threshold();
    let mut cell = Cell::NONE;
    let f0 = bitmap.sample_in(m, &mut cell);
    // Walk outward while inside, inward while outside.
    let dir = if f0 >= t { 1.0 } else { -1.0 };
    let mut prev = f0;
    for j in 1..=WINDOW_STEPS {
        let s = dir * j as f64 * ds;
        let f = bitmap.sample_in(m + n * s, &mut cell);
        if (f >= t) != (f0 >= t) {
            let frac = (prev - t) / (prev - f);
            return Some(dir * ((j - 1) as f64 + frac) * ds);
        }
        prev = f;
    }
    None
}

impl Workspace {
    /// Grey-level path: every crack midpoint moved to the edge along its normal.
    ///
    /// With `soft_share`, `None` as soon as more than that share of the cracks have open
    /// windows (a soft edge, to be refined with a wider window): the count only grows, so
    /// the rest of the pass could not change the verdict, and is not spent.
    pub(super) fn refined_outline(
        &mut self,
        bitmap: &Bitmap,
        cracks: &[Crack],
        estimator: EdgeEstimator,
        window: Window,
        soft_share: Option<f64>,
    ) -> Option<Vec<Point>> {
        self.points.clear();
        self.tangents.clear();
        self.anchors.clear();
        let soft = soft_share.map(|share| share * cracks.len() as f64);
        if cracks.len() >= PARALLEL_REFINE_CRACKS {
            // Every crack is refined on its own, so a long border's cracks are refined in
            // parallel, in order. The count of open windows only grows, so the verdict of
            // the whole border is the one the serial loop reaches on the way.
            use rayon::prelude::*;
            let refined: Vec<(Point, Point, bool)> = cracks
                .par_iter()
                .map(|crack| refine_crack(bitmap, crack, estimator, window))
                .collect();
            let open_windows = refined.iter().filter(|r| r.2).count();
            if soft.is_some_and(|limit| open_windows as f64 > limit) {
                return None;
            }
            for (p, n, _) in refined {
                self.push_refined(p, n);
            }
        } else {
            let mut open_windows = 0;
            for crack in cracks {
                let (p, n, open) = refine_crack(bitmap, crack, estimator, window);
                open_windows += usize::from(open);
                if soft.is_some_and(|limit| open_windows as f64 > limit) {
                    return None;
                }
                self.push_refined(p, n);
            }
        }
        self.remove_close_and_backsteps();
        self.sharpen_rounded_corners();
        self.correct_curvature_bias();
        self.mark_turns();
        Some(self.resample())
    }

    /// Adds a refined crack: its point, and its walking direction (foreground on the
    /// right: the normal `n` turned by +90°).
    fn push_refined(&mut self, p: Point, n: Point) {
        self.points.push(p);
        self.tangents.push(n.perp());
        self.anchors.push(false);
    }

    /// Grey-level path: on a curved edge the coverage integral is biased towards the
    /// centre of curvature by about v/(2R), v = 1/12 + 1/6 = 1/4 px² being the variance of
    /// the pixel's box filter plus that of bilinear interpolation (0.010 px for R = 12).
    /// Each point is moved back by that amount, with R from the circle through the points
    /// two before and two after it (capped at R ≥ 2 px). Sharpened corners and their
    /// neighbours are left alone.
    fn correct_curvature_bias(&mut self) {
        let n = self.points.len();
        if n < 5 {
            return;
        }
        self.scratch.clear();
        self.scratch.extend_from_slice(&self.points);
        let pts = &self.scratch;
        for i in 0..n {
            // Not across a sharpened corner.
            if (0..5).any(|k| self.anchors[(i + n + k - 2) % n]) {
                continue;
            }
            let (a, b, c) = (pts[(i + n - 2) % n], pts[i], pts[(i + 2) % n]);
            let denominator = norm(b - a) * norm(c - b) * norm(c - a);
            if denominator <= 0.0 {
                continue;
            }
            // Signed curvature, positive where the outline turns towards the foreground
            // (right, on screen); the bias is towards that side.
            let curvature = (2.0 * (b - a).cross(c - b) / denominator)
                .clamp(-MAX_BIAS_CURVATURE, MAX_BIAS_CURVATURE);
            let Some(t) = unit(c - a) else {
                continue;
            };
            // t.perp() points to the foreground side.
            self.points[i] = b - t.perp() * (0.5 * EDGE_BLUR_VARIANCE * curvature);
        }
    }

    /// Grey-level path: anti-aliasing rounds corners off (by up to ~0.6 px for a right
    /// angle). Where the outline turns by more than `GREY_CORNER_ANGLE_DEG` within a few
    /// pixels and both sides are straight (residual below `GREY_CORNER_RESIDUAL`) beyond
    /// the rounded part, the rounded points are replaced by the intersection of the two
    /// side lines, which becomes an anchor.
    fn sharpen_rounded_corners(&mut self) {
        let n = self.points.len();
        if n < 8 {
            return;
        }
        // Cumulative arc length, and arc length at an unrolled index.
        self.values.clear();
        self.values.push(0.0);
        for i in 0..n {
            let step = norm(self.points[(i + 1) % n] - self.points[i]);
            self.values.push(self.values[i] + step);
        }
        let total = self.values[n];
        if total < 4.0 * (GREY_CORNER_SKIP + GREY_CORNER_SIDE) {
            return;
        }
        let nn = n as i64;
        let walk = ArcWalk {
            cumulative: &self.values,
        };
        let arc = |k: i64| walk.arc(k);
        let at = |k: i64| self.points[lap(k, nn).0 as usize];
        let back_by = |i: i64, length: f64| walk.back_by(i, length);
        let ahead_by = |i: i64, length: f64| walk.ahead_by(i, length);
        // Chord angle at every point (two pointers).
        let mut angles = std::mem::take(&mut self.angles);
        angles.clear();
        let mut chord_ends = std::mem::take(&mut self.chord_ends);
        chord_ends.clear();
        let (mut b, mut a) = (
            back_by(0, GREY_CORNER_REACH),
            ahead_by(0, GREY_CORNER_REACH),
        );
        // Only local maxima of at least `min` count: a smaller angle is given as -1 (see
        // `AngleFloor`), which decides every comparison below as its angle would.
        let min = GREY_CORNER_ANGLE_DEG.to_radians();
        let floor = AngleFloor::new(min);
        for i in 0..nn {
            while arc(i) - arc(b + 1) >= GREY_CORNER_REACH {
                b += 1;
            }
            if a <= i {
                a = i + 1;
            }
            while a < i + nn && arc(a) - arc(i) < GREY_CORNER_REACH {
                a += 1;
            }
            let (back, ahead) = (at(i) - at(b), at(a) - at(i));
            angles.push(if floor.certainly_below(back, ahead) {
                -1.0
            } else {
                turn_angle(back, ahead)
            });
            chord_ends.push((b, a));
        }
        let angle_at = |k: i64| angles[lap(k, nn).0 as usize];
        // (first removed unrolled index, removed count, new point)
        let mut edits: Vec<(i64, i64, Point)> = Vec::new();
        let mut last_end = i64::MIN;
        for i in 0..nn {
            let ai = angles[i as usize];
            let (b, a) = chord_ends[i as usize];
            let is_max = ai >= min
                && (b + 1..i).all(|k| ai > angle_at(k))
                && (i + 1..a).all(|k| ai >= angle_at(k));
            if !is_max {
                continue;
            }
            let inner_back = back_by(i, GREY_CORNER_SKIP);
            // A side never reaches into the rounded part of the previous corner.
            let outer_back = back_by(i, GREY_CORNER_SKIP + GREY_CORNER_SIDE).max(last_end);
            let inner_ahead = ahead_by(i, GREY_CORNER_SKIP);
            let outer_ahead = ahead_by(i, GREY_CORNER_SKIP + GREY_CORNER_SIDE);
            if inner_back - outer_back < 2
                || outer_ahead - inner_ahead < 2
                || outer_ahead - outer_back >= nn
            {
                continue;
            }
            let back_line = fit_line((outer_back..=inner_back).map(at));
            let ahead_line = fit_line((inner_ahead..=outer_ahead).map(at));
            let (Some((la, ra)), Some((lb, rb))) = (back_line, ahead_line) else {
                continue;
            };
            if ra > GREY_CORNER_RESIDUAL || rb > GREY_CORNER_RESIDUAL {
                continue;
            }
            let Some(x) = intersect(la, lb) else {
                continue;
            };
            if distance_to_closed_polyline(x, &self.points) > GREY_CORNER_MOVE {
                continue;
            }
            // Replace the points strictly between the two inner side points.
            edits.push((inner_back + 1, inner_ahead - inner_back - 1, x));
            last_end = inner_ahead;
        }
        drop_wrapping_edit(&mut edits, nn);
        self.angles = angles;
        self.chord_ends = chord_ends;
        if edits.is_empty() {
            return;
        }
        let (remove, insert_at) = mark_edits(&edits, n);
        self.scratch.clear();
        self.scratch_tangents.clear();
        let mut anchors = Vec::with_capacity(n);
        for j in 0..n {
            if let Some(x) = insert_at[j] {
                self.scratch.push(x);
                self.scratch_tangents.push(self.tangents[j]);
                anchors.push(true);
            }
            if !remove[j] {
                self.scratch.push(self.points[j]);
                self.scratch_tangents.push(self.tangents[j]);
                anchors.push(self.anchors[j]);
            }
        }
        std::mem::swap(&mut self.points, &mut self.scratch);
        std::mem::swap(&mut self.tangents, &mut self.scratch_tangents);
        self.anchors = anchors;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coverage of a 100 × 12 image whose ink lies left of x = `edge`, blurred by a
    /// Gaussian of `sigma` px (each pixel the mean over 64 columns of the blurred step).
    fn blurred_step(edge: f64, sigma: f64) -> Bitmap {
        let (w, h) = (100usize, 12usize);
        let column = |c: usize| {
            let samples = 64;
            (0..samples)
                .map(|k| {
                    let x = c as f64 + (k as f64 + 0.5) / samples as f64;
                    0.5 * statrs::function::erf::erfc(
                        (x - edge) / (sigma * std::f64::consts::SQRT_2),
                    )
                })
                .sum::<f64>()
                / samples as f64
        };
        let row: Vec<f32> = (0..w).map(|c| column(c) as f32).collect();
        let coverage = (0..h).flat_map(|_| row.iter().copied()).collect();
        Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap()
    }

    /// A disc of radius 18 px centred in a 60 × 60 image, blurred by a Gaussian of `sigma`
    /// px (each pixel the blurred step of its centre's distance from the circle).
    fn blurred_disc(sigma: f64) -> Bitmap {
        let coverage = (0..60 * 60)
            .map(|i| {
                let (x, y) = ((i % 60) as f64 + 0.5, (i / 60) as f64 + 0.5);
                let r = ((x - 30.0).powi(2) + (y - 30.0).powi(2)).sqrt();
                let v = 0.5
                    * statrs::function::erf::erfc((r - 18.0) / (sigma * std::f64::consts::SQRT_2));
                v as f32
            })
            .collect();
        Bitmap::from_coverage(60, 60, coverage, Some(0.5)).unwrap()
    }

    /// The cracks of the one border of a blurred disc.
    fn disc_cracks(b: &Bitmap) -> Vec<Crack> {
        let mask = crate::contour::mask::PaddedMask::new(b).unwrap();
        let mut found = mask.borders();
        assert_eq!(found.len(), 1);
        found.remove(0).cracks
    }

    /// How many of `cracks` have an open window when refined with [`Window::SHARP`].
    fn open_sharp_windows(b: &Bitmap, cracks: &[Crack]) -> usize {
        let estimator = EdgeEstimator::CoverageIntegral;
        cracks
            .iter()
            .filter(|c| refine_crack(b, c, estimator, Window::SHARP).2)
            .count()
    }

    /// The edge spread of a disc blurred by σ is √(σ² + 1/6) within 4 % from σ = 1 to 3 px
    /// (the samples' bilinear interpolation adds the 1/6 px²; beyond 3 px the walk's 8 px
    /// reach ends before the coverage levels out, and the spread comes out short: 3.7 px
    /// for σ = 4), and a sharp edge stays below the spread at which the tolerance is
    /// widened.
    #[test]
    fn the_edge_spread_of_a_blurred_disc_is_its_blur() {
        for sigma in [0.05, 0.3, 1.0, 1.5, 2.0, 3.0] {
            let b = blurred_disc(sigma);
            let spread = edge_spread(&b, &disc_cracks(&b)).unwrap();
            if sigma < 0.5 {
                assert!(
                    spread < crate::contour::SHARP_EDGE_SPREAD,
                    "σ = {sigma}: spread {spread}"
                );
            } else {
                let expected = (sigma * sigma + 1.0 / 6.0).sqrt();
                assert!(
                    (spread / expected - 1.0).abs() < 0.04,
                    "σ = {sigma}: spread {spread}, expected {expected}"
                );
            }
        }
    }

    /// Noise on the paper and the ink (±0.05 of coverage, as a scanner's grain) does not
    /// stop the measure or move it by more than 10 %.
    #[test]
    fn the_edge_spread_is_measured_through_noise() {
        let clean = blurred_disc(1.5);
        let mut state = 12345u64;
        let noisy: Vec<f32> = (0..60 * 60)
            .map(|i| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64;
                let (c, r) = ((i % 60) as i64, (i / 60) as i64);
                (f64::from(clean.coverage_at(c, r)) + 0.1 * (u - 0.5)) as f32
            })
            .collect();
        let b = Bitmap::from_coverage(60, 60, noisy, Some(0.5)).unwrap();
        let mask = crate::contour::mask::PaddedMask::new(&b).unwrap();
        let found = mask.borders();
        let outer = found.iter().max_by_key(|f| f.cracks.len()).unwrap();
        let spread = edge_spread(&b, &outer.cracks).unwrap();
        let expected = (1.5f64 * 1.5 + 1.0 / 6.0).sqrt();
        assert!((spread / expected - 1.0).abs() < 0.1, "spread {spread}");
    }

    /// A border whose spread reaches `SOFT_SPREAD` skips the sharp pass: on every blurred
    /// disc where that happens (σ = 2.5 px and up, and perhaps 2 px), more than
    /// `SOFT_SHARE` of the sharp windows are open, so the pass would have been abandoned
    /// and the soft window used anyway; below it (σ ≤ 1.5 px) the windows decide.
    #[test]
    fn a_spread_that_skips_the_sharp_pass_is_one_whose_windows_are_open() {
        let mut skipped = Vec::new();
        for sigma in [0.4, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5] {
            let b = blurred_disc(sigma);
            let cracks = &disc_cracks(&b);
            let spread = edge_spread(&b, cracks).unwrap();
            if spread < SOFT_SPREAD {
                assert!(sigma < 2.5, "σ = {sigma}: spread {spread}");
                continue;
            }
            assert!(sigma >= 2.0, "σ = {sigma}: spread {spread}");
            let open = open_sharp_windows(&b, cracks);
            assert!(
                open as f64 > SOFT_SHARE * cracks.len() as f64,
                "σ = {sigma}: {open} of {} windows open",
                cracks.len()
            );
            skipped.push(sigma);
        }
        assert!(skipped.contains(&3.0), "{skipped:?}");
    }

    /// The sharp pass gives up on a soft edge as soon as more than `SOFT_SHARE` of its
    /// windows are open, and on a sharp one runs to the end and gives what it gives
    /// without the limit.
    #[test]
    fn the_sharp_pass_stops_once_the_edge_is_known_to_be_soft() {
        let estimator = EdgeEstimator::CoverageIntegral;
        for (sigma, soft) in [(0.4, false), (3.0, true)] {
            let b = blurred_disc(sigma);
            let cracks = &disc_cracks(&b);
            let open = open_sharp_windows(&b, cracks);
            assert_eq!(
                open as f64 > SOFT_SHARE * cracks.len() as f64,
                soft,
                "σ = {sigma}"
            );
            let mut work = Workspace::default();
            let full = work.refined_outline(&b, cracks, estimator, Window::SHARP, None);
            assert!(full.as_ref().is_some_and(|p| p.len() > 50));
            let limited =
                work.refined_outline(&b, cracks, estimator, Window::SHARP, Some(SOFT_SHARE));
            if soft {
                assert!(
                    limited.is_none(),
                    "σ = {sigma}: the soft edge was not noticed"
                );
            } else {
                assert_eq!(limited, full, "σ = {sigma}");
            }
        }
    }

    /// The edge width the refinement estimates, against blurred edges of known σ: the
    /// ±2 px window stays closed on a sharp or slightly blurred edge and finds it; it is
    /// open on edges blurred by 2 and 3 px, whose position it misjudges towards the crack;
    /// the soft window (±8 px) is closed there and finds the edge again.
    #[test]
    fn open_windows_tell_blurred_edges_of_known_width() {
        let edge = 50.3;
        // The thresholded boundary: the crack between columns 49 and 50, facing paper.
        let (m, n) = (Point::new(50.0, 6.5), Point::new(1.0, 0.0));
        let truth = edge - m.x;
        for sigma in [0.3, 0.5, 0.8] {
            let b = blurred_step(edge, sigma);
            let (s, open) = integrate_edge(&b, m, n, Window::SHARP.steps);
            assert!(!open, "σ = {sigma}: the sharp window is open");
            assert!(
                (s - truth).abs() < 0.02,
                "σ = {sigma}: edge at {s}, truth {truth}"
            );
        }
        for sigma in [2.0, 3.0] {
            let b = blurred_step(edge, sigma);
            let (sharp, open) = integrate_edge(&b, m, n, Window::SHARP.steps);
            assert!(open, "σ = {sigma}: the sharp window is closed");
            let (soft, open) = integrate_edge(&b, m, n, Window::SOFT.steps);
            assert!(!open, "σ = {sigma}: the soft window is open");
            assert!(
                (soft - truth).abs() < 0.02,
                "σ = {sigma}: soft edge at {soft}, truth {truth}"
            );
            assert!(
                (sharp - truth).abs() > 2.0 * (soft - truth).abs(),
                "σ = {sigma}: sharp {sharp}, soft {soft}, truth {truth}"
            );
        }
    }
}
