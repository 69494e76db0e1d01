//! Boundary extraction: from a coverage field ([`Bitmap`]) to closed sub-pixel outlines
//! ([`Contour`]), with their nesting (outer borders, holes, islands in holes).
//!
//! The method, in four steps (the full outline of every border is also kept, so that
//! [`crate::fidelity`]'s repairs can trace a border again from its pixels alone):
//!
//! 1. **Topology.** The thresholded mask, padded by one pixel of background on every side
//!    so that shapes touching the image edge get closed borders, is scanned row by row
//!    (`mask::PaddedMask::borders`, the borders of Suzuki and Abe's border following:
//!    8-connected foreground, 4-connected background), giving every border's kind (outer
//!    or hole) and parent in the same order as their algorithm, without its label per
//!    pixel. Before that, ambiguous diagonal pixel pairs are decided by the colour in the
//!    minority around them (`resolve_diagonals`, potrace's "minority" turn policy), so
//!    that a light line thinner than a pixel is not cut into one-pixel holes.
//! 2. **Crack loops.** Each border is a closed loop of pixel edges ("cracks") that
//!    separate its foreground component from the adjacent background component, kept
//!    with the foreground on the right. On screen (y down) outer loops then run
//!    clockwise (`geom::signed_area` > 0) and holes counter-clockwise. Each crack lies
//!    between a foreground and a background pixel; its midpoint is where marching squares
//!    would put the edge of a 0/1 image.
//! 3. **Edge placement.**
//!    * *Grey levels* (`!bitmap.is_bilevel()`): every crack midpoint m is moved along the
//!      outward normal n (down the coverage gradient of the 3×2 pixels around the crack, or
//!      the crack's own normal where that gradient is flat or points back into the
//!      foreground) to the edge, found by **coverage integration**: for an
//!      area-coverage image (what font rasterisers and resvg produce), along the line
//!      m + s·n the coverage falls from 1 to 0 and the edge is at
//!      s = −h + ∫₋ₕʰ f(s) ds, exactly for a straight box-filtered edge, whatever the
//!      threshold. The window (h = 2 px) is clipped where coverage starts rising again
//!      outward or falling again inward, so it never runs across the far side of a thin
//!      stroke or into a neighbouring shape. A test compares this estimator with the
//!      threshold crossing of the interpolated coverage, which is biased by up to ~0.1 px on
//!      curved and oblique edges. The integral assumes interior coverage 1 and background
//!      0; images whose ink and paper are not pure shift the edge by about
//!      h × (impurity), e.g. 0.05 px for 2.5 % grey paper. On a curved edge the integral is
//!      biased towards the centre of curvature by v/(2R) (v = 1/4 px², the box filter plus
//!      bilinear interpolation; 0.01 px at R = 12), which is corrected from the local
//!      curvature of the refined outline.
//!      Anti-aliasing also rounds corners off (by up to ~0.6 px for a right angle):
//!      where the refined outline turns sharply and is straight on both sides beyond the
//!      rounded part, the rounded points are replaced by the intersection of the two side
//!      lines.
//!    * *Bilevel images*: refinement has nothing to work with and the pixel staircase
//!      must not survive (it would be fitted as many tiny corners). From the crack
//!      midpoints:
//!      - *corner candidates* are local maxima of the angle between the chords to the
//!        points 3 cracks back and ahead, above 55° (digital straight lines stay below
//!        ~20°), plus, where those find nothing, of the chords 7 cracks long above 70°
//!        (corners that digitisation cut off with a short chamfer). Loops under 48 cracks
//!        (shapes under ~12 px) get none: there a digitised disk and a polygon look alike;
//!      - a binomial pre-smoothing (four passes of [1, 2, 1]/4) gives first normals and
//!        curvatures;
//!      - every point is then re-estimated by a *weighted local regression* of the crack
//!        midpoints in its own frame (a parabola; a line where a corner cuts the window
//!        short). A midpoint is only known to ±0.5 px along its crack's normal n, i.e.
//!        ±0.5·|n·ν| across the outline (normal ν), so the risers of a shallow staircase
//!        are precise and its long flat runs are not: the weights are 1/((n·ν)² + 0.01),
//!        and a run of equal cracks shares one weight because its error is common to all
//!        of them. The bandwidth grows like √R with the radius of curvature R, since the
//!        flat run at the top of a digitised circle is up to √(8R) long and the window
//!        must reach the risers beyond it, and is cut back where the fitted parabola
//!        would leave the pixel constraints (a window reaching from a straight side into
//!        a tight curve). Plain smoothing of the midpoints leaves ~0.5 px at the top,
//!        bottom and sides of a circle; this leaves ~0.25 px and keeps digital straight
//!        lines straight;
//!      - each candidate corner is then placed at the intersection of its two side lines
//!        (fitted to the raw midpoints with the same weights along straight sides, or to
//!        the regressed points next to it along curved ones) and kept only if it is
//!        *consistent with the pixels*: foreground pixel centres around it inside the
//!        corner's wedge, background centres outside. A digitised curve taken for a
//!        corner fails this and is smoothed instead. The points next to a kept corner are
//!        regressed again with the corner in their windows.
//!    * *Noisy grey levels*: a grey-level outline whose refined points are noisy
//!      (`outline_noise` above `NOISE_LIMIT`: JPEG ringing, scanner grain) is replaced
//!      by the bilevel outline of its pixels, so the fit does not follow the noise.
//!    * *Spikes*: tips that the threshold cut short are extended to the intersection of
//!      their straight sides where the coverage supports it (`extend_spikes`).
//! 4. **Clean-up.** Points closer than 0.3 px to their predecessor are removed, and so
//!    are points that step backwards (at concave corners) by less than 1 px, at most
//!    three in a row, and small self-crossing folds are cut at the crossing (an unbounded
//!    backstep rule once let one bad tangent discard the rest of a contour). Each closed
//!    polyline is then resampled
//!    to about 0.8 px spacing (a little more than one point per pixel of boundary), keeping
//!    corners and sharp turns as exact samples so that they are not cut off. Contours with
//!    fewer than 3 points or an enclosed area below `min_area` are dropped with all the
//!    contours nested inside them, and parent indices are renumbered.
//!
//! Measured (tests in this file, and a benchmark over 10 sub-pixel centres per radius):
//! anti-aliased disks of radius 20 within 0.03 px of the circle (mean 0.006 px), radius
//! 5–80 within 0.06 px; anti-aliased square corners within 0.03 px; bilevel disks of
//! radius 10–80 within 0.23–0.31 px (radius 40: 0.24), radius 2–7 within 0.5 px; bilevel
//! squares exact when axis-aligned, corners within 0.05 px when rotated; the sides of a
//! bilevel rectangle tilted by 4° within 0.06 px.
//!
//! Limits: strokes thinner than about 2 px cannot be placed exactly from one side (the
//! coverage never reaches 1). A bilevel straight edge is only known to the pixel: an
//! axis-aligned one stays up to 0.5 px off, whatever the method. Bilevel shapes under
//! ~12 px across come out rounded.

use crate::error::{Error, Result};
use crate::geom::{distance_to_closed_polyline, floor_i64, signed_area, Point};
use crate::raster::Bitmap;
use mask::{Crack, FoundBorder, PaddedMask};
use serde::Serialize;

mod mask;

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

/// Options of boundary extraction.
#[derive(Clone, Debug)]
pub struct ContourOptions {
    /// Contours enclosing a smaller area (px², after refinement) are dropped as specks,
    /// together with every contour nested inside them. Must be finite and ≥ 0.
    /// Default (in [`crate::Config`]): 2.0.
    pub min_area: f64,
}

/// One closed boundary of a shape, as sub-pixel points in image pixel units.
#[derive(Clone, Debug, Serialize)]
pub struct Contour {
    /// Boundary points in order, closed implicitly (the last connects to the first; the
    /// first point is not repeated). Outer borders run so that `geom::signed_area` is
    /// positive (clockwise on screen), holes so that it is negative.
    pub points: Vec<Point>,
    /// True for the border of a hole.
    pub is_hole: bool,
    /// Index (in the same list) of the enclosing contour: a hole's outer border, or the hole
    /// an island sits in. `None` for top-level outer borders.
    pub parent: Option<usize>,
}

/// How the grey-level path places an edge along its normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum EdgeEstimator {
    /// s = −h + ∫ f ds over the clipped window (the default).
    CoverageIntegral,
    /// Where the bilinear coverage crosses the threshold (kept for the comparison test).
    #[cfg_attr(not(test), allow(dead_code))]
    LevelCrossing,
}

/// Extracts the contours of the foreground of `bitmap`.
///
/// Returns outer borders, holes and islands in the order of their first pixel edge in a
/// raster scan (a parent always comes before its children), with sub-pixel points as described in the
/// module docs. An image with no foreground gives an empty list.
///
/// Errors: [`Error::InvalidOption`] when `min_area` is negative or not finite, or when the
/// bitmap's public `width`/`height` were changed so that they no longer match its
/// coverage, or exceed 2³¹ − 4.
pub fn extract_contours(bitmap: &Bitmap, opts: &ContourOptions) -> Result<Vec<Contour>> {
    Ok(extract_with(bitmap, opts, EdgeEstimator::CoverageIntegral)?.contours)
}

/// The contours together with every border they came from, so that a stretch whose
/// trace does not match the thresholded pixels can be traced again from those pixels
/// alone (see [`crate::fidelity`]).
pub(crate) struct Extraction {
    /// What [`extract_contours`] returns.
    pub(crate) contours: Vec<Contour>,
    /// Every border found, kept or dropped, in raster-scan order.
    pub(crate) borders: Vec<Border>,
    /// Index into `borders` of each contour.
    pub(crate) border_of: Vec<usize>,
    mask: PaddedMask,
}

/// One border of the thresholded mask.
pub(crate) struct Border {
    cracks: Vec<Crack>,
    /// True for the border of a hole.
    pub(crate) is_hole: bool,
    /// Index of the enclosing border.
    pub(crate) parent: Option<usize>,
}

/// How closely a re-trace follows the pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PixelTrace {
    /// The bilevel path (regression of the pixel-edge midpoints with sharp corners),
    /// guarded by [`follows_cracks`].
    Smoothed,
    /// The pixel-edge midpoints themselves: exact to the mask, staircase and all.
    Raw,
}

impl Border {
    /// The pixel-edge midpoints of the border, in walking order (foreground on the right).
    pub(crate) fn midpoints(&self) -> impl Iterator<Item = Point> + '_ {
        self.cracks.iter().map(|c| c.mid())
    }

    /// True when a pixel on either side of the border (index row × `width` + column)
    /// is in `pixels`.
    pub(crate) fn touches(&self, pixels: &std::collections::HashSet<u32>, width: u32) -> bool {
        let index = |(c, r): (i64, i64)| {
            (c >= 0 && r >= 0 && c < i64::from(width))
                .then(|| u32::try_from(r * i64::from(width) + c).ok())
                .flatten()
        };
        self.cracks.iter().any(|k| {
            [k.inside(), k.outside()]
                .into_iter()
                .any(|p| index(p).is_some_and(|i| pixels.contains(&i)))
        })
    }

    /// Area (px²) enclosed by the pixel-edge midpoints.
    pub(crate) fn pixel_area(&self) -> f64 {
        let mids: Vec<Point> = self.midpoints().collect();
        signed_area(&mids).abs()
    }
}

impl Extraction {
    /// The border traced again from the thresholded pixels alone, oriented like a
    /// contour (outer borders clockwise on screen, holes counter-clockwise); `None` when
    /// it has fewer than 3 points or no area.
    pub(crate) fn pixel_contour(
        &self,
        border: usize,
        how: PixelTrace,
        parent: Option<usize>,
    ) -> Option<Contour> {
        let b = self.borders.get(border)?;
        let points = match how {
            PixelTrace::Raw => b.midpoints().collect(),
            PixelTrace::Smoothed => {
                let mut work = Workspace::default();
                let fitted = work.bilevel_outline(&b.cracks, &self.mask);
                if follows_cracks(&fitted, &b.cracks) {
                    fitted
                } else {
                    smoothed_cracks(&b.cracks)
                }
            }
        };
        finish(points, b.is_hole, parent, 0.0)
    }
}

impl Extraction {
    /// The pixels of the shapes and holes dropped on purpose (enclosing less than
    /// `min_area` px²), with their components' pixels (8-connected for shapes, 4-connected
    /// for holes), as row × `width` + column indices: where the drawn outline rightly
    /// disagrees with the mask.
    pub(crate) fn dropped_pixels(
        &self,
        min_area: f64,
        width: u32,
    ) -> std::collections::HashSet<u32> {
        let kept: std::collections::HashSet<usize> = self.border_of.iter().copied().collect();
        let mut out = std::collections::HashSet::new();
        // A component enclosing less than `min_area` has few pixels; the cap only guards
        // against a border that encloses much more than its area says.
        let cap = (4.0 * min_area) as usize + 64;
        for (b, border) in self.borders.iter().enumerate() {
            if kept.contains(&b) || border.pixel_area() >= min_area {
                continue;
            }
            let shape = !border.is_hole;
            let mut stack: Vec<(i64, i64)> = border
                .cracks
                .iter()
                .map(|k| if shape { k.inside() } else { k.outside() })
                .collect();
            let mut seen: std::collections::HashSet<(i64, i64)> = std::collections::HashSet::new();
            while let Some((c, r)) = stack.pop() {
                if seen.len() > cap {
                    break;
                }
                if c < 0 || r < 0 || c >= i64::from(width) || r >= self.mask.height - 2 {
                    continue;
                }
                if self.mask.is_foreground((c + 1, r + 1)) != shape || !seen.insert((c, r)) {
                    continue;
                }
                for (dc, dr) in [
                    (1, 0),
                    (-1, 0),
                    (0, 1),
                    (0, -1),
                    (1, 1),
                    (1, -1),
                    (-1, 1),
                    (-1, -1),
                ] {
                    if shape || dc == 0 || dr == 0 {
                        stack.push((c + dc, r + dr));
                    }
                }
            }
            out.extend(
                seen.into_iter()
                    .filter_map(|(c, r)| u32::try_from(r * i64::from(width) + c).ok()),
            );
        }
        out
    }
}

/// Fewest pixel-edge cracks outside the largest border for which the borders of an image
/// are refined in parallel (a small image would spend more on starting the thread pool).
const PARALLEL_CRACKS: usize = 20_000;

/// [`extract_contours`] keeping the borders.
pub(crate) fn extract_borders(bitmap: &Bitmap, opts: &ContourOptions) -> Result<Extraction> {
    extract_with(bitmap, opts, EdgeEstimator::CoverageIntegral)
}

fn extract_with(
    bitmap: &Bitmap,
    opts: &ContourOptions,
    estimator: EdgeEstimator,
) -> Result<Extraction> {
    if !(opts.min_area.is_finite() && opts.min_area >= 0.0) {
        return Err(Error::InvalidOption {
            name: "min_area",
            message: "must be a non-negative area in px²".to_string(),
        });
    }
    let (w, h) = (bitmap.width() as usize, bitmap.height() as usize);
    let mut mask = PaddedMask::new(bitmap).ok_or_else(|| Error::InvalidOption {
        name: "bitmap",
        message: format!(
            "{w}×{h} is too wide or tall to trace (limit {} px)",
            i32::MAX - 3
        ),
    })?;
    let empty = |mask| Extraction {
        contours: Vec::new(),
        borders: Vec::new(),
        border_of: Vec::new(),
        mask,
    };
    if w == 0 || h == 0 {
        return Ok(empty(mask));
    }
    let found = mask.borders();

    let trace_one = |work: &mut Workspace, border: FoundBorder| -> (Option<Contour>, Border) {
        let (cracks, is_hole) = (border.cracks, border.is_hole);
        let contour = if cracks.is_empty() {
            None
        } else {
            let points = if bitmap.is_bilevel() {
                let fitted = work.bilevel_outline(&cracks, &mask);
                if follows_cracks(&fitted, &cracks) {
                    fitted
                } else {
                    // The regression lost the outline (seen on some diagonal strokes): fall
                    // back to the plainly smoothed pixel-edge midpoints.
                    smoothed_cracks(&cracks)
                }
            } else {
                let refined = work.refined_outline(bitmap, &cracks, estimator);
                if outline_noise(&refined) > NOISE_LIMIT {
                    // The grey levels are noise (JPEG ringing, scanner grain), not
                    // anti-aliasing: refining to them would fit the noise. Trace the
                    // thresholded pixels as a bilevel image is traced.
                    let fitted = work.bilevel_outline(&cracks, &mask);
                    if follows_cracks(&fitted, &cracks) {
                        fitted
                    } else {
                        smoothed_cracks(&cracks)
                    }
                } else {
                    refined
                }
            };
            let mut points = points;
            extend_spikes(&mut points, bitmap);
            finish(points, is_hole, border.parent, opts.min_area)
        };
        let border = Border {
            cracks,
            is_hole,
            parent: border.parent,
        };
        (contour, border)
    };
    // Borders are refined independently: on a large image with many of them (a page of
    // text), in parallel, results in border order.
    let cracks: usize = found.iter().map(|b| b.cracks.len()).sum();
    let largest = found.iter().map(|b| b.cracks.len()).max().unwrap_or(0);
    let results: Vec<(Option<Contour>, Border)> = if cracks - largest >= PARALLEL_CRACKS {
        use rayon::prelude::*;
        found
            .into_par_iter()
            .map_init(Workspace::default, trace_one)
            .collect()
    } else {
        let mut work = Workspace::default();
        found
            .into_iter()
            .map(|border| trace_one(&mut work, border))
            .collect()
    };
    let (traced, borders): (Vec<Option<Contour>>, Vec<Border>) = results.into_iter().unzip();
    let parents = borders.iter().map(|b| b.parent).collect();
    let (contours, border_of) = renumber(traced, parents);
    Ok(Extraction {
        contours,
        borders,
        border_of,
        mask,
    })
}

/// Largest distance (px) a bilevel outline point may lie from the nearest pixel-edge
/// midpoint: the midpoints are 1 px apart, and a faithful outline stays within half a pixel
/// of the pixel boundary.
const CRACK_FIDELITY: f64 = 1.25;

/// True when every point of `points` lies within [`CRACK_FIDELITY`] of a pixel-edge midpoint
/// and the enclosed areas agree to within 0.35 px per unit of boundary length: a guard on
/// the bilevel regression, which must never move the outline off its pixels.
fn follows_cracks(points: &[Point], cracks: &[Crack]) -> bool {
    if points.len() < 3 || cracks.len() < 3 {
        return false;
    }
    let mids: Vec<Point> = cracks.iter().map(|c| c.mid()).collect();
    let length = mids.len() as f64;
    if (signed_area(points).abs() - signed_area(&mids).abs()).abs() > 0.35 * length {
        return false;
    }
    // The midpoints sorted by their cell of a 2 px grid (row, then column): the nine
    // cells around a point are three runs of that order, found by binary search.
    let cell = |p: Point| (floor_i64(p.y / 2.0), floor_i64(p.x / 2.0));
    let mut sorted: Vec<((i64, i64), Point)> = mids.iter().map(|&m| (cell(m), m)).collect();
    sorted.sort_unstable_by_key(|e| e.0);
    points.iter().all(|&p| {
        let (cy, cx) = cell(p);
        let mut best = f64::INFINITY;
        for dy in -1..=1 {
            let row = cy + dy;
            let from = sorted.partition_point(|e| e.0 < (row, cx - 1));
            for &(key, m) in &sorted[from..] {
                if key > (row, cx + 1) {
                    break;
                }
                best = best.min(m.distance(p));
            }
        }
        best <= CRACK_FIDELITY
    })
}

/// Pixel-edge midpoints smoothed by three passes of the closed [1, 2, 1]/4 filter: a robust
/// bilevel outline (corners slightly rounded, later sharpened by the break finder where
/// their sides are straight).
fn smoothed_cracks(cracks: &[Crack]) -> Vec<Point> {
    let mut pts: Vec<Point> = cracks.iter().map(|c| c.mid()).collect();
    let n = pts.len();
    if n < 3 {
        return pts;
    }
    let mut next = pts.clone();
    for _ in 0..3 {
        for i in 0..n {
            next[i] = (pts[(i + n - 1) % n] + pts[i] * 2.0 + pts[(i + 1) % n]) * 0.25;
        }
        std::mem::swap(&mut pts, &mut next);
    }
    pts
}

/// Arc length along a closed polyline at unrolled indices (index k + n is point k one lap
/// later).
struct ArcWalk<'a> {
    /// Cumulative arc length: `cumulative[k]` at point k, the last entry the whole loop.
    cumulative: &'a [f64],
}

impl ArcWalk<'_> {
    /// Arc length at unrolled index `k`.
    fn arc(&self, k: i64) -> f64 {
        let n = self.cumulative.len() as i64 - 1;
        let total = self.cumulative[n as usize];
        self.cumulative[k.rem_euclid(n) as usize] + total * k.div_euclid(n) as f64
    }

    /// The last index at least `length` of arc before `i` (at most one lap back).
    fn back_by(&self, i: i64, length: f64) -> i64 {
        let n = self.cumulative.len() as i64 - 1;
        let mut k = i - 1;
        while k > i - n && self.arc(i) - self.arc(k) < length {
            k -= 1;
        }
        k
    }

    /// The first index at least `length` of arc after `i` (at most one lap ahead).
    fn ahead_by(&self, i: i64, length: f64) -> i64 {
        let n = self.cumulative.len() as i64 - 1;
        let mut k = i + 1;
        while k < i + n && self.arc(k) - self.arc(i) < length {
            k += 1;
        }
        k
    }
}

/// Noise level (px, [`outline_noise`]) above which a grey-level outline is traced from its
/// thresholded pixels instead: clean anti-aliased edges measure 0.005–0.02 px (glyphs at
/// 64 and 256 px, icons, stress shapes), a bilevel horse saved as a JPEG at quality 30
/// 0.04 px, photos and scans 0.08–0.15 px.
const NOISE_LIMIT: f64 = 0.03;

/// Robust noise level (px) of an outline: the median of the fourth difference of the
/// points across the outline (which cancels curves up to cubics), scaled to a standard
/// deviation (for independent noise σ the fourth difference has deviation σ·√70).
fn outline_noise(points: &[Point]) -> f64 {
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
    let mid = r.len() / 2;
    let (_, median, _) = r.select_nth_unstable_by(mid, f64::total_cmp);
    *median / 0.6745 / 70f64.sqrt()
}

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
fn extend_spikes(points: &mut Vec<Point>, bitmap: &Bitmap) {
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
    let at = |k: i64| points[k.rem_euclid(nn) as usize];
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
        let t_at = |k: i64| turn[k.rem_euclid(nn) as usize];
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
    if edits.len() > 1 {
        let (first_start, _, _) = edits[0];
        let (last_start, last_count, _) = edits[edits.len() - 1];
        if last_start + last_count > first_start + nn {
            edits.pop();
        }
    }
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

/// For edits (first replaced unrolled index, count, new point) of a closed outline of `n`
/// points: which points are removed, and the new point inserted before each index.
fn mark_edits(edits: &[(i64, i64, Point)], n: usize) -> (Vec<bool>, Vec<Option<Point>>) {
    let nn = n as i64;
    let mut remove = vec![false; n];
    let mut insert_at = vec![None; n];
    for &(first, count, x) in edits {
        for k in first..first + count {
            remove[k.rem_euclid(nn) as usize] = true;
        }
        insert_at[first.rem_euclid(nn) as usize] = Some(x);
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

/// Orients a finished outline and applies the size rules; `None` when it is dropped.
fn finish(
    mut points: Vec<Point>,
    is_hole: bool,
    parent: Option<usize>,
    min_area: f64,
) -> Option<Contour> {
    if points.len() < 3 {
        return None;
    }
    let area = signed_area(&points);
    if !area.is_finite() || area == 0.0 || area.abs() < min_area {
        return None;
    }
    if (area < 0.0) != is_hole {
        points.reverse();
    }
    Some(Contour {
        points,
        is_hole,
        parent,
    })
}

/// Drops every contour whose ancestor was dropped and renumbers the parents; also gives
/// the border index of every contour kept.
fn renumber(
    traced: Vec<Option<Contour>>,
    parents: Vec<Option<usize>>,
) -> (Vec<Contour>, Vec<usize>) {
    let n = traced.len();
    let alive = |mut i: usize| {
        // A chain longer than n would be a cycle; treat it as dropped.
        for _ in 0..=n {
            if traced[i].is_none() {
                return false;
            }
            match parents[i] {
                Some(p) if p < n => i = p,
                Some(_) => return false,
                None => return true,
            }
        }
        false
    };
    let keep: Vec<bool> = (0..n).map(alive).collect();
    let mut new_index = vec![usize::MAX; n];
    let mut next = 0;
    for (i, &k) in keep.iter().enumerate() {
        if k {
            new_index[i] = next;
            next += 1;
        }
    }
    let mut border_of = Vec::with_capacity(next);
    let contours = traced
        .into_iter()
        .zip(keep)
        .enumerate()
        .filter_map(|(i, (c, k))| if k { c.map(|c| (i, c)) } else { None })
        .map(|(i, mut c)| {
            border_of.push(i);
            c.parent = c.parent.map(|p| new_index[p]);
            c
        })
        .collect();
    (contours, border_of)
}

/// Reusable buffers, so that tracing allocates per contour, not per point.
#[derive(Default)]
struct Workspace {
    /// The outline being built.
    points: Vec<Point>,
    /// Unit walking direction (foreground on the right) at each point.
    tangents: Vec<Point>,
    /// Points that must survive clean-up and resampling exactly (corners, sharp turns).
    anchors: Vec<bool>,
    /// Bilevel: the raw crack midpoints.
    raw: Vec<Point>,
    /// Bilevel: the crack normals.
    normals: Vec<Point>,
    scratch: Vec<Point>,
    scratch_tangents: Vec<Point>,
    values: Vec<f64>,
    /// Grey-level corner detector: chord angle at each point.
    angles: Vec<f64>,
    /// Grey-level corner detector: unrolled chord end indices at each point.
    chord_ends: Vec<(i64, i64)>,
    /// Bilevel: the regression bandwidth at each point.
    sigma: Vec<f64>,
    /// Bilevel: which points the current regression round fits.
    near: Vec<bool>,
    /// Bilevel: the run weight of each crack.
    run_weight: Vec<f64>,
    corners: Vec<usize>,
}

impl Workspace {
    /// Grey-level path: every crack midpoint moved to the edge along its normal.
    fn refined_outline(
        &mut self,
        bitmap: &Bitmap,
        cracks: &[Crack],
        estimator: EdgeEstimator,
    ) -> Vec<Point> {
        self.points.clear();
        self.tangents.clear();
        self.anchors.clear();
        for crack in cracks {
            let (p, n) = refine_crack(bitmap, crack, estimator);
            self.points.push(p);
            // Walking direction, foreground on the right: the normal turned by +90°.
            self.tangents.push(n.perp());
            self.anchors.push(false);
        }
        self.remove_close_and_backsteps();
        self.sharpen_rounded_corners();
        self.correct_curvature_bias();
        self.mark_turns();
        self.resample()
    }

    /// Bilevel path: crack midpoints smoothed by weighted local regression, with sharp
    /// corners.
    fn bilevel_outline(&mut self, cracks: &[Crack], mask: &PaddedMask) -> Vec<Point> {
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
    fn smooth(&mut self) {
        let n = self.points.len();
        for _ in 0..SMOOTHING_PASSES {
            self.scratch.clear();
            self.scratch.extend_from_slice(&self.points);
            let src = &self.scratch;
            for i in 0..n {
                if self.anchors[i] {
                    continue;
                }
                let a = src[(i + n - 1) % n];
                let b = src[(i + 1) % n];
                self.points[i] = (a + src[i] * 2.0 + b) * 0.25;
            }
        }
    }

    /// Unit tangents by central differences, one-sided next to anchors.
    fn update_tangents(&mut self) {
        let n = self.points.len();
        self.tangents.clear();
        for i in 0..n {
            let prev = (i + n - 1) % n;
            let next = (i + 1) % n;
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
    fn run_weights(&mut self) {
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
        let n = self.points.len();
        let half = n / 2;
        let origin = self.points[i];
        let tangent = self.tangents[i];
        let normal = tangent.perp();
        let reach_squared = reach * reach;
        window.clear();
        let mut add = |j: usize| -> bool {
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
        add(i);
        let mut back = 0;
        while back < half && add((i + n - back - 1) % n) {
            back += 1;
        }
        let mut ahead = 0;
        while ahead + back < n - 1 && ahead < half && add((i + ahead + 1) % n) {
            ahead += 1;
        }
        self.anchors[(i + n - back - 1) % n] || self.anchors[(i + ahead + 1) % n]
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
                .find(|&j| self.anchors[(i + n - j) % n])
                .unwrap_or(k + 1)
                - 1;
            let reach_ahead = (1..=k)
                .find(|&j| self.anchors[(i + j) % n])
                .unwrap_or(k + 1)
                - 1;
            let (kb, ka) = (reach_back.min(reach_ahead), reach_back.min(reach_ahead));
            let back = self.points[i] - self.points[(i + n - kb) % n];
            let ahead = self.points[(i + ka) % n] - self.points[i];
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
                    .is_some_and(|fit| fit_violation(window, candidate, fit) <= FIT_PIXEL_SLACK);
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
            let mut add = |j: usize| -> bool {
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
            add(i);
            let mut back = 0;
            while back < half && add((i + n - back - 1) % n) {
                back += 1;
            }
            let mut ahead = 0;
            while ahead + back < n - 1 && ahead < half && add((i + ahead + 1) % n) {
                ahead += 1;
            }
            // A window cut short by a corner on one side cannot tell curvature from
            // offset: fit a line there.
            let cut = self.anchors[(i + n - back - 1) % n] || self.anchors[(i + ahead + 1) % n];
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
    fn fit_side(&self, indices: impl Iterator<Item = usize> + Clone) -> Option<Line> {
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
        let at = |k: i64| self.points[k.rem_euclid(nn) as usize];
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
            angles.push(turn_angle(at(i) - at(b), at(a) - at(i)));
            chord_ends.push((b, a));
        }
        let min = GREY_CORNER_ANGLE_DEG.to_radians();
        let angle_at = |k: i64| angles[k.rem_euclid(nn) as usize];
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
        // The last edit must not overlap the first one across the closing joint.
        if edits.len() > 1 {
            let (first_start, _, _) = edits[0];
            let (last_start, last_count, _) = edits[edits.len() - 1];
            if last_start + last_count > first_start + nn {
                edits.pop();
            }
        }
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
    fn remove_close_and_backsteps(&mut self) {
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
    fn mark_turns(&mut self) {
        let n = self.points.len();
        if n < 3 {
            return;
        }
        let limit = ANCHOR_TURN_DEG.to_radians();
        for i in 0..n {
            let p = self.points[i];
            let turn = turn_angle(
                p - self.points[(i + n - 1) % n],
                self.points[(i + 1) % n] - p,
            );
            if turn > limit {
                self.anchors[i] = true;
            }
        }
    }

    /// Resamples the closed polyline to about `TARGET_SPACING`, keeping anchors exactly.
    fn resample(&self) -> Vec<Point> {
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
        out
    }
}

/// Accumulates a weighted least-squares fit of v = a + b·u + c·u².
#[derive(Default)]
struct QuadraticFit {
    /// Σw·uᵏ for k = 0..=4.
    moments: [f64; 5],
    /// Σw·v·uᵏ for k = 0..=2.
    rhs: [f64; 3],
    count: usize,
}

impl QuadraticFit {
    #[inline]
    fn add(&mut self, u: f64, v: f64, w: f64) {
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
    fn solve(&self) -> Option<(f64, f64, f64)> {
        let [m0, m1, m2, m3, m4] = self.moments;
        let [r0, r1, r2] = self.rhs;
        if m0.is_nan() || m0 <= 0.0 {
            return None;
        }
        if self.count >= 4 {
            let det =
                m0 * (m2 * m4 - m3 * m3) - m1 * (m1 * m4 - m3 * m2) + m2 * (m1 * m3 - m2 * m2);
            if det.abs() > 1e-9 * m0 * m2 * m4 {
                let a = (r0 * (m2 * m4 - m3 * m3) - m1 * (r1 * m4 - m3 * r2)
                    + m2 * (r1 * m3 - m2 * r2))
                    / det;
                let b = (m0 * (r1 * m4 - m3 * r2) - r0 * (m1 * m4 - m3 * m2)
                    + m2 * (m1 * r2 - r1 * m2))
                    / det;
                let c = (m0 * (m2 * r2 - m3 * r1) - m1 * (m1 * r2 - m3 * r0)
                    + m2 * (m1 * r1 - m2 * r0))
                    / det;
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
        let det = m0 * m2 - m1 * m1;
        if self.count >= 2 && det > 1e-9 * m0 * m2 {
            let a = (r0 * m2 - m1 * r1) / det;
            let b = (m0 * r1 - m1 * r0) / det;
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

/// How far (px) the fitted curve puts a crack's foreground centre outside, or its
/// background centre inside; 0 when every crack in the window is respected.
fn fit_violation(window: &[WindowPoint], sigma: f64, (a, b, c): (f64, f64, f64)) -> f64 {
    let reach = BANDWIDTH_REACH * sigma;
    let reach_squared = reach * reach;
    let curve = |u: f64| a + b * u + c * u * u;
    window
        .iter()
        .filter(|w| w.distance_squared < reach_squared)
        .map(|w| {
            let h = w.half_normal;
            let inner = curve(w.u - h.x) - (w.v - h.y);
            let outer = (w.v + h.y) - curve(w.u + h.x);
            inner.max(outer)
        })
        .fold(0.0, f64::max)
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

/// Euclidean length without `hypot` (which is several times slower and whose extra
/// range is not needed for pixel coordinates).
#[inline]
fn norm(p: Point) -> f64 {
    p.length_squared().sqrt()
}

/// The vector scaled to unit length, or `None` if it is zero or not finite.
#[inline]
fn unit(p: Point) -> Option<Point> {
    let length = norm(p);
    (length > 0.0 && length.is_finite()).then(|| p / length)
}

/// Angle in [0, π] between two vectors; 0 when either is zero.
#[inline]
fn turn_angle(a: Point, b: Point) -> f64 {
    a.cross(b).abs().atan2(a.dot(b))
}

/// A line through `origin` along the unit vector `direction`.
#[derive(Clone, Copy, Debug)]
struct Line {
    origin: Point,
    direction: Point,
}

/// The crossing point of segments ab and cd when they properly intersect.
fn segment_crossing(a: Point, b: Point, c: Point, d: Point) -> Option<Point> {
    let r = b - a;
    let q = d - c;
    let denom = r.cross(q);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (c - a).cross(q) / denom;
    let u = (c - a).cross(r) / denom;
    (t > 0.0 && t < 1.0 && u > 0.0 && u < 1.0).then(|| a + r * t)
}

/// Total least-squares line through at least two distinct points, with the largest
/// distance of a point from it.
fn fit_line(points: impl Iterator<Item = Point> + Clone) -> Option<(Line, f64)> {
    let mut count = 0.0;
    let mut sum = Point::ZERO;
    for p in points.clone() {
        count += 1.0;
        sum += p;
    }
    if count < 2.0 {
        return None;
    }
    let mean = sum / count;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points.clone() {
        let d = p - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    if sxx + syy < 1e-12 {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let direction = Point::new(angle.cos(), angle.sin());
    let residual = points
        .map(|p| (p - mean).cross(direction).abs())
        .fold(0.0, f64::max);
    Some((
        Line {
            origin: mean,
            direction,
        },
        residual,
    ))
}

/// Intersection of two lines that cross at more than 25°.
fn intersect(a: Line, b: Line) -> Option<Point> {
    let cross = a.direction.cross(b.direction);
    if cross.abs() < 25f64.to_radians().sin() {
        return None;
    }
    let s = (b.origin - a.origin).cross(b.direction) / cross;
    let x = a.origin + a.direction * s;
    x.is_finite().then_some(x)
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

/// Moves a crack midpoint to the edge; returns the point and the normal used.
fn refine_crack(bitmap: &Bitmap, crack: &Crack, estimator: EdgeEstimator) -> (Point, Point) {
    let n = gradient_normal(bitmap, crack)
        .filter(|g| g.dot(crack.normal()) >= MIN_NORMAL_AGREEMENT)
        .unwrap_or(crack.normal());
    let s = match estimator {
        EdgeEstimator::CoverageIntegral => Some(integrate_edge(bitmap, crack.mid(), n)),
        EdgeEstimator::LevelCrossing => level_crossing(bitmap, crack.mid(), n),
    };
    match s {
        // The edge must also stay where the thresholded pixels put it: within
        // `MAX_CRACK_SHIFT` of the crack midpoint across the crack. Where the coverage is
        // not a clean step from ink to paper (soft gradients, tinted fills, shading), the
        // integral can move the edge a pixel or more into a region the mask calls the other
        // side; the threshold crossing below cannot.
        Some(s)
            if s.is_finite()
                && s.abs() <= MAX_SHIFT
                && (n * s).dot(crack.normal()).abs() <= MAX_CRACK_SHIFT =>
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
    }
}

/// Signed distance from `m` along `n` to the edge by coverage integration: the edge of a
/// step from 1 to 0 at s = e satisfies ∫₋ₕʰ f ds = e + h.
fn integrate_edge(bitmap: &Bitmap, m: Point, n: Point) -> f64 {
    let ds = HALF_WINDOW / WINDOW_STEPS as f64;
    let f0 = bitmap.sample(m);

    // Outward: ∫₀ʰ f ds, f taken as 0 past its minimum.
    let mut outward = 0.0;
    let mut prev = f0;
    let mut lowest = f0;
    for j in 1..=WINDOW_STEPS {
        if prev <= 0.0 {
            break;
        }
        let f = bitmap.sample(m + n * (j as f64 * ds));
        if f > lowest + MONOTONE_SLACK {
            break;
        }
        outward += 0.5 * (prev + f) * ds;
        lowest = lowest.min(f);
        prev = f;
    }

    // Inward: ∫₋ₕ⁰ f ds, f taken as 1 past its maximum.
    let mut inward = 0.0;
    let mut prev = f0;
    let mut highest = f0;
    let mut reached = 0.0;
    for j in 1..=WINDOW_STEPS {
        if prev >= 1.0 {
            break;
        }
        let f = bitmap.sample(m - n * (j as f64 * ds));
        if f < highest - MONOTONE_SLACK {
            // Past the ridge of a stroke thinner than the window: its coverage never
            // reaches 1, and "1 past the maximum" would put the edge too far out.
            if let Some(s) = thin_stroke_edge(bitmap, m, n, highest) {
                return s;
            }
            break;
        }
        inward += 0.5 * (prev + f) * ds;
        highest = highest.max(f);
        prev = f;
        reached = j as f64 * ds;
    }
    inward += HALF_WINDOW - reached;
    inward + outward - HALF_WINDOW
}

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
    let mut f = bitmap.sample(m);
    let mut closed_out = false;
    while s < HALF_WINDOW {
        let g = bitmap.sample(m + n * (s + ds));
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
    let mut f = bitmap.sample(m);
    let mut closed_in = false;
    while s < THIN_STROKE_REACH {
        let g = bitmap.sample(m - n * (s + ds));
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
    let f0 = bitmap.sample(m);
    // Walk outward while inside, inward while outside.
    let dir = if f0 >= t { 1.0 } else { -1.0 };
    let mut prev = f0;
    for j in 1..=WINDOW_STEPS {
        let s = dir * j as f64 * ds;
        let f = bitmap.sample(m + n * s);
        if (f >= t) != (f0 >= t) {
            let frac = (prev - t) / (prev - f);
            return Some(dir * ((j - 1) as f64 + frac) * ds);
        }
        prev = f;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::angle_between;

    /// Coverage of a shape by `ss`×`ss` supersampling of each pixel.
    fn supersample(w: u32, h: u32, ss: u32, inside: impl Fn(f64, f64) -> bool) -> Vec<f32> {
        let mut cov = Vec::with_capacity((w * h) as usize);
        for r in 0..h {
            for c in 0..w {
                let mut hits = 0;
                for j in 0..ss {
                    for i in 0..ss {
                        let x = c as f64 + (i as f64 + 0.5) / ss as f64;
                        let y = r as f64 + (j as f64 + 0.5) / ss as f64;
                        hits += u32::from(inside(x, y));
                    }
                }
                cov.push(hits as f32 / (ss * ss) as f32);
            }
        }
        cov
    }

    /// A 0/1 image of a shape sampled at pixel centres.
    fn binary(w: u32, h: u32, inside: impl Fn(f64, f64) -> bool) -> Vec<f32> {
        supersample(w, h, 1, inside)
    }

    fn opts(min_area: f64) -> ContourOptions {
        ContourOptions { min_area }
    }

    /// Distance from `p` to the closed polyline.
    fn distance_to_polyline(p: Point, pts: &[Point]) -> f64 {
        let n = pts.len();
        (0..n)
            .map(|i| {
                let (a, b) = (pts[i], pts[(i + 1) % n]);
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                p.distance(a + ab * t)
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn disk_bitmap(ss: u32) -> (Bitmap, Point, f64) {
        let centre = Point::new(24.37, 25.81);
        let radius = 20.0;
        let cov = supersample(50, 52, ss, |x, y| {
            Point::new(x, y).distance(centre) < radius
        });
        (
            Bitmap::from_coverage(50, 52, cov, None).unwrap(),
            centre,
            radius,
        )
    }

    /// (max, mean) of |distance to centre − radius|.
    fn circle_errors(pts: &[Point], centre: Point, radius: f64) -> (f64, f64) {
        let errs: Vec<f64> = pts
            .iter()
            .map(|p| (p.distance(centre) - radius).abs())
            .collect();
        let max = errs.iter().cloned().fold(0.0, f64::max);
        (max, errs.iter().sum::<f64>() / errs.len() as f64)
    }

    #[test]
    fn antialiased_disk_is_refined_to_a_twentieth_of_a_pixel() {
        let (bm, centre, radius) = disk_bitmap(16);
        assert!(!bm.is_bilevel());
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        assert_eq!(cs.len(), 1);
        let c = &cs[0];
        assert!(!c.is_hole && c.parent.is_none());
        let (max, mean) = circle_errors(&c.points, centre, radius);
        eprintln!("integral: max {max:.4} mean {mean:.4} n {}", c.points.len());
        assert!(max < 0.05, "max |r − R| = {max}");
        assert!(mean < 0.02, "mean |r − R| = {mean}");
        // About one point per 0.8 px of the 125.7 px circumference.
        let n = c.points.len() as f64;
        assert!((140.0..180.0).contains(&n), "{n} points");
        let area = signed_area(&c.points);
        let true_area = std::f64::consts::PI * radius * radius;
        assert!((area - true_area).abs() < 0.01 * true_area, "{area}");
    }

    #[test]
    fn coverage_integration_beats_the_threshold_crossing() {
        let (bm, centre, radius) = disk_bitmap(16);
        let integral = extract_with(&bm, &opts(2.0), EdgeEstimator::CoverageIntegral)
            .unwrap()
            .contours;
        let crossing = extract_with(&bm, &opts(2.0), EdgeEstimator::LevelCrossing)
            .unwrap()
            .contours;
        let (imax, imean) = circle_errors(&integral[0].points, centre, radius);
        let (cmax, cmean) = circle_errors(&crossing[0].points, centre, radius);
        eprintln!("integral {imax:.4}/{imean:.4}, crossing {cmax:.4}/{cmean:.4}");
        assert!(imax < cmax && imean < cmean);
    }

    /// Turning angle (degrees) at every point of a closed polyline.
    fn turning_degrees(pts: &[Point]) -> Vec<f64> {
        let n = pts.len();
        (0..n)
            .map(|i| {
                let p = pts[i];
                angle_between(p - pts[(i + n - 1) % n], pts[(i + 1) % n] - p).to_degrees()
            })
            .collect()
    }

    /// Corners of a square of side `side` centred at `centre`, rotated by `deg`.
    fn square_corners(centre: Point, side: f64, deg: f64) -> [Point; 4] {
        let (s, c) = deg.to_radians().sin_cos();
        let u = Point::new(c, s) * (side / 2.0);
        let v = Point::new(-s, c) * (side / 2.0);
        [
            centre - u - v,
            centre + u - v,
            centre + u + v,
            centre - u + v,
        ]
    }

    /// Inside test for a convex polygon given clockwise on screen.
    fn inside_convex(poly: &[Point], p: Point) -> bool {
        let n = poly.len();
        (0..n).all(|i| (poly[(i + 1) % n] - poly[i]).cross(p - poly[i]) > 0.0)
    }

    #[test]
    fn antialiased_rotated_square_keeps_its_corners() {
        let corners = square_corners(Point::new(20.3, 19.6), 24.0, 30.0);
        let cov = supersample(40, 40, 16, |x, y| inside_convex(&corners, Point::new(x, y)));
        let bm = Bitmap::from_coverage(40, 40, cov, None).unwrap();
        assert!(!bm.is_bilevel());
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        assert_eq!(cs.len(), 1);
        let pts = &cs[0].points;
        for corner in corners {
            let d = distance_to_polyline(corner, pts);
            eprintln!("AA corner distance {d:.3}");
            assert!(d < 0.3, "corner {corner:?} is {d} px from the outline");
        }
        // Away from the corners the points lie on the sides.
        let mut worst: f64 = 0.0;
        for p in pts {
            if corners.iter().all(|c| c.distance(*p) > 1.5) {
                let d = (0..4)
                    .map(|i| {
                        let (a, b) = (corners[i], corners[(i + 1) % 4]);
                        ((*p - a).cross(b - a) / (b - a).length()).abs()
                    })
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
        eprintln!("AA square side error {worst:.4}");
        assert!(worst < 0.05, "side error {worst}");
    }

    #[test]
    fn bilevel_disk_is_smooth_and_close() {
        // Three sub-pixel centres: the first puts the top of the circle 0.4 px above the
        // first row of crack midpoints, where plain smoothing of the midpoints is 0.40 px
        // off.
        for centre in [
            Point::new(50.3, 49.6),
            Point::new(50.03, 50.0),
            Point::new(50.73, 50.59),
        ] {
            let radius = 40.0;
            let cov = binary(101, 100, |x, y| Point::new(x, y).distance(centre) < radius);
            let bm = Bitmap::from_coverage(101, 100, cov, None).unwrap();
            assert!(bm.is_bilevel());
            let cs = extract_contours(&bm, &opts(2.0)).unwrap();
            assert_eq!(cs.len(), 1);
            let pts = &cs[0].points;
            let (max, mean) = circle_errors(pts, centre, radius);
            let turn = turning_degrees(pts).into_iter().fold(0.0, f64::max);
            eprintln!("bilevel disk {centre:?}: max {max:.3} mean {mean:.3} turn {turn:.1}°");
            // Measured: max 0.11–0.15 px, mean ≤ 0.053 px, turn ≤ 4°.
            assert!(max < 0.3, "max |r − R| = {max}");
            assert!(mean < 0.08, "mean |r − R| = {mean}");
            assert!(turn < 15.0, "turn {turn}°");
        }
    }

    #[test]
    fn bilevel_square_stays_square() {
        // Pixels 5..=24 in both directions: the square [5, 25]².
        let cov = binary(30, 30, |x, y| {
            (5.0..25.0).contains(&x) && (5.0..25.0).contains(&y)
        });
        let bm = Bitmap::from_coverage(30, 30, cov, None).unwrap();
        assert!(bm.is_bilevel());
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        assert_eq!(cs.len(), 1);
        let pts = &cs[0].points;
        for corner in [(5.0, 5.0), (25.0, 5.0), (25.0, 25.0), (5.0, 25.0)] {
            let corner = Point::new(corner.0, corner.1);
            let d = pts
                .iter()
                .map(|p| p.distance(corner))
                .fold(f64::INFINITY, f64::min);
            assert!(d < 0.05, "corner {corner:?} at {d}");
        }
        // Every point on a side: the straight runs stay straight.
        for p in pts {
            let d = [p.x - 5.0, 25.0 - p.x, p.y - 5.0, 25.0 - p.y]
                .into_iter()
                .map(f64::abs)
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-9, "{p:?}");
        }
        assert!((signed_area(pts) - 400.0).abs() < 1e-6);
        // 80 px of boundary at 0.8 px spacing.
        assert_eq!(pts.len(), 100);
    }

    #[test]
    fn bilevel_rotated_square_has_sharp_corners() {
        let corners = square_corners(Point::new(30.3, 29.6), 36.0, 20.0);
        let cov = binary(60, 60, |x, y| inside_convex(&corners, Point::new(x, y)));
        let bm = Bitmap::from_coverage(60, 60, cov, None).unwrap();
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        let pts = &cs[0].points;
        for corner in corners {
            let d = distance_to_polyline(corner, pts);
            eprintln!("bilevel rotated corner {d:.3}");
            assert!(d < 0.7, "corner {corner:?} is {d} px away");
        }
    }

    /// Checks the invariants every result must satisfy: at least 3 finite points, outer
    /// borders with positive area, holes negative, parents earlier in the list and of the
    /// opposite kind.
    fn check_invariants(cs: &[Contour]) {
        for (i, c) in cs.iter().enumerate() {
            assert!(
                c.points.len() >= 3,
                "contour {i} has {} points",
                c.points.len()
            );
            assert!(c.points.iter().all(|p| p.is_finite()));
            let area = signed_area(&c.points);
            assert_eq!(
                area < 0.0,
                c.is_hole,
                "contour {i}: area {area}, hole {}",
                c.is_hole
            );
            assert!(area != 0.0);
            match c.parent {
                Some(p) => {
                    assert!(p < i, "contour {i} has parent {p}");
                    assert_ne!(cs[p].is_hole, c.is_hole, "contour {i} and its parent {p}");
                }
                None => assert!(!c.is_hole, "hole {i} without parent"),
            }
        }
    }

    /// A disk of radius `outer` with a hole of radius `inner` and, if `island` > 0, a disk
    /// of that radius in the hole.
    fn rings(ss: u32, outer: f64, inner: f64, island: f64) -> Bitmap {
        let centre = Point::new(30.4, 29.7);
        let cov = supersample(61, 60, ss, |x, y| {
            let d = Point::new(x, y).distance(centre);
            (d < outer && d >= inner) || d < island
        });
        Bitmap::from_coverage(61, 60, cov, None).unwrap()
    }

    #[test]
    fn ring_gives_an_outer_border_and_its_hole() {
        for ss in [16, 1] {
            let bm = rings(ss, 25.0, 12.0, 0.0);
            let cs = extract_contours(&bm, &opts(2.0)).unwrap();
            check_invariants(&cs);
            assert_eq!(cs.len(), 2, "supersampling {ss}");
            assert!(!cs[0].is_hole && cs[0].parent.is_none());
            assert!(cs[1].is_hole);
            assert_eq!(cs[1].parent, Some(0));
            let pi = std::f64::consts::PI;
            let tolerance = if ss == 1 { 0.02 } else { 0.002 };
            let outer = signed_area(&cs[0].points);
            let hole = signed_area(&cs[1].points);
            assert!(
                (outer / (pi * 625.0) - 1.0).abs() < tolerance,
                "outer area {outer}"
            );
            assert!(
                (hole / (-pi * 144.0) - 1.0).abs() < tolerance,
                "hole area {hole}"
            );
        }
    }

    #[test]
    fn island_in_a_hole_has_the_hole_as_parent() {
        for ss in [16, 1] {
            let bm = rings(ss, 25.0, 15.0, 7.0);
            let cs = extract_contours(&bm, &opts(2.0)).unwrap();
            check_invariants(&cs);
            assert_eq!(cs.len(), 3, "supersampling {ss}");
            let hole = cs.iter().position(|c| c.is_hole).unwrap();
            let island = cs
                .iter()
                .position(|c| !c.is_hole && c.parent.is_some())
                .unwrap();
            assert_eq!(cs[hole].parent, Some(0));
            assert_eq!(cs[island].parent, Some(hole));
            let area = signed_area(&cs[island].points);
            let expected = std::f64::consts::PI * 49.0;
            assert!((area / expected - 1.0).abs() < 0.03, "island area {area}");
        }
    }

    #[test]
    fn specks_and_everything_inside_them_are_dropped() {
        // A 20×20 square with a one-pixel hole, a one-pixel speck outside, and a 3×3 hole
        // holding a one-pixel island.
        let cov = binary(40, 30, |x, y| {
            let square = (5.0..25.0).contains(&x) && (5.0..25.0).contains(&y);
            let pinhole = (10.0..11.0).contains(&x) && (10.0..11.0).contains(&y);
            let big_hole = (15.0..18.0).contains(&x) && (15.0..18.0).contains(&y);
            let island = (16.0..17.0).contains(&x) && (16.0..17.0).contains(&y);
            let speck = (32.0..33.0).contains(&x) && (8.0..9.0).contains(&y);
            (square && !pinhole && !big_hole) || island || speck
        });
        let bm = Bitmap::from_coverage(40, 30, cov, Some(0.5)).unwrap();
        let all = extract_contours(&bm, &opts(0.0)).unwrap();
        check_invariants(&all);
        assert_eq!(all.len(), 5);
        // Speck area 0.5 (a diamond through the crack midpoints), pinhole 0.5, the big
        // hole about 8.5: min_area 2 keeps the square and the big hole; the island goes.
        let kept = extract_contours(&bm, &opts(2.0)).unwrap();
        check_invariants(&kept);
        assert_eq!(kept.len(), 2, "{kept:#?}");
        assert!(!kept[0].is_hole && kept[1].is_hole);
        assert_eq!(kept[1].parent, Some(0));
        assert!((signed_area(&kept[0].points) - 400.0).abs() < 1e-6);
        // Dropping the outer border drops its holes too.
        let none = extract_contours(&bm, &opts(500.0)).unwrap();
        assert!(none.is_empty());
    }

    #[test]
    fn shapes_touching_the_edge_are_closed_along_it() {
        // A bar over the full width, rows 4..10 of a 30×14 image, and the same bar
        // anti-aliased (edges at y = 3.625 and 10.3125, exact under 16×16 supersampling).
        for ss in [1, 16] {
            let cov = supersample(30, 14, ss, |_, y| (3.625..10.3125).contains(&y));
            let bm = Bitmap::from_coverage(30, 14, cov, None).unwrap();
            let cs = extract_contours(&bm, &opts(2.0)).unwrap();
            check_invariants(&cs);
            assert_eq!(cs.len(), 1);
            let pts = &cs[0].points;
            let min_x = pts.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let max_x = pts.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            assert!(min_x.abs() < 1e-9, "min x {min_x}");
            assert!((max_x - 30.0).abs() < 1e-9, "max x {max_x}");
            assert!(pts.iter().filter(|p| p.x.abs() < 1e-9).count() >= 2);
            if ss == 16 {
                // The long sides are refined to the true edges.
                for p in pts.iter().filter(|p| (3.0..27.0).contains(&p.x)) {
                    let d = (p.y - 3.625).abs().min((p.y - 10.3125).abs());
                    assert!(d < 0.02, "{p:?}");
                }
            }
        }
    }

    #[test]
    fn full_and_empty_images() {
        let full = Bitmap::from_coverage(30, 20, vec![1.0; 600], Some(0.5)).unwrap();
        let grey = Bitmap::from_coverage(30, 20, vec![0.9; 600], None).unwrap();
        for bm in [full, grey] {
            let cs = extract_contours(&bm, &opts(2.0)).unwrap();
            check_invariants(&cs);
            assert_eq!(cs.len(), 1);
            // One outer border along the image border, square corners kept.
            let area = signed_area(&cs[0].points);
            assert!((area - 600.0).abs() < 1e-9, "area {area}");
        }
        // Too small for corners (under 40 cracks of boundary): rounded, but traced.
        let small = Bitmap::from_coverage(7, 5, vec![1.0; 35], Some(0.5)).unwrap();
        let cs = extract_contours(&small, &opts(2.0)).unwrap();
        check_invariants(&cs);
        let area = signed_area(&cs[0].points);
        assert!(area > 33.0 && area < 35.0, "area {area}");
        let empty = Bitmap::from_coverage(7, 5, vec![0.0; 35], Some(0.5)).unwrap();
        assert!(extract_contours(&empty, &opts(0.0)).unwrap().is_empty());
    }

    #[test]
    fn degenerate_shapes_do_not_break_anything() {
        let cases: Vec<(&str, u32, u32, Vec<f32>)> = vec![
            (
                "one pixel",
                5,
                5,
                binary(5, 5, |x, y| x > 2.0 && x < 3.0 && y > 2.0 && y < 3.0),
            ),
            (
                "one-pixel line",
                20,
                5,
                binary(20, 5, |x, y| x > 2.0 && y > 2.0 && y < 3.0),
            ),
            (
                "diagonal line",
                12,
                12,
                binary(12, 12, |x, y| (x - y).abs() < 0.5),
            ),
            (
                "checkerboard",
                9,
                8,
                binary(9, 8, |x, y| (x as i64 + y as i64) % 2 == 0),
            ),
            (
                "all four edges",
                9,
                9,
                binary(9, 9, |x, y| x < 1.0 || y < 1.0 || x > 8.0 || y > 8.0),
            ),
            (
                "thin grey line",
                20,
                6,
                (0..120)
                    .map(|i| {
                        if i / 20 == 2 {
                            0.6
                        } else if i / 20 == 3 {
                            0.4
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            ),
            (
                "noise",
                16,
                16,
                (0..256u32)
                    .map(|i| ((i.wrapping_mul(2_654_435_761) >> 7) % 256) as f32 / 255.0)
                    .collect(),
            ),
        ];
        for (name, w, h, cov) in cases {
            for threshold in [None, Some(0.5)] {
                let bm = Bitmap::from_coverage(w, h, cov.clone(), threshold).unwrap();
                for min_area in [0.0, 2.0] {
                    let cs = extract_contours(&bm, &opts(min_area))
                        .unwrap_or_else(|e| panic!("{name}: {e}"));
                    check_invariants(&cs);
                    for c in &cs {
                        assert!(signed_area(&c.points).abs() >= min_area, "{name}");
                        for p in &c.points {
                            // Everything stays within a pixel of the image.
                            assert!(p.x >= -1.0 && p.y >= -1.0, "{name}: {p:?}");
                            assert!(p.x <= w as f64 + 1.0 && p.y <= h as f64 + 1.0, "{name}");
                        }
                    }
                }
            }
        }
        // The single pixel survives only without a speck limit, as a small diamond.
        let bm = Bitmap::from_coverage(
            5,
            5,
            binary(5, 5, |x, y| x > 2.0 && x < 3.0 && y > 2.0 && y < 3.0),
            Some(0.5),
        )
        .unwrap();
        let cs = extract_contours(&bm, &opts(0.0)).unwrap();
        assert_eq!(cs.len(), 1);
        assert!((signed_area(&cs[0].points) - 0.5).abs() < 1e-9);
        assert!(extract_contours(&bm, &opts(2.0)).unwrap().is_empty());
    }

    #[test]
    fn invalid_min_area_is_an_error() {
        let bm = Bitmap::from_coverage(2, 2, vec![1.0; 4], Some(0.5)).unwrap();
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                extract_contours(&bm, &opts(bad)),
                Err(Error::InvalidOption {
                    name: "min_area",
                    ..
                })
            ));
        }
    }

    #[test]
    fn edge_placement_does_not_depend_on_the_threshold() {
        let (bm, centre, radius) = disk_bitmap(16);
        for t in [0.3, 0.7] {
            let moved =
                Bitmap::from_coverage(bm.width(), bm.height(), bm.to_coverage(), Some(t)).unwrap();
            let cs = extract_contours(&moved, &opts(2.0)).unwrap();
            let (max, _) = circle_errors(&cs[0].points, centre, radius);
            assert!(max < 0.05, "threshold {t}: {max}");
        }
    }

    #[test]
    fn bilevel_shallow_straight_edges_stay_straight() {
        // A 60×40 rectangle rotated by 4°: its long sides are digital lines with long flat
        // runs; away from the corners the outline must follow the true sides.
        let corners = {
            let (s, c) = 4f64.to_radians().sin_cos();
            let centre = Point::new(40.3, 30.6);
            let u = Point::new(c, s) * 30.0;
            let v = Point::new(-s, c) * 20.0;
            [
                centre - u - v,
                centre + u - v,
                centre + u + v,
                centre - u + v,
            ]
        };
        let cov = binary(80, 62, |x, y| inside_convex(&corners, Point::new(x, y)));
        let bm = Bitmap::from_coverage(80, 62, cov, None).unwrap();
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        let pts = &cs[0].points;
        let mut worst: f64 = 0.0;
        for p in pts
            .iter()
            .filter(|p| corners.iter().all(|c| c.distance(**p) > 3.0))
        {
            let d = (0..4)
                .map(|i| {
                    let (a, b) = (corners[i], corners[(i + 1) % 4]);
                    ((*p - a).cross(b - a) / (b - a).length()).abs()
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        eprintln!("shallow sides: worst {worst:.3}");
        assert!(worst < 0.3, "worst side distance {worst}");
        let turn = turning_degrees(pts)
            .into_iter()
            .zip(pts)
            .filter(|(_, p)| corners.iter().all(|c| c.distance(**p) > 3.0))
            .map(|(t, _)| t)
            .fold(0.0, f64::max);
        assert!(turn < 10.0, "turn {turn}° on a straight side");
    }

    #[test]
    fn quadratic_fit_recovers_a_parabola() {
        let mut fit = QuadraticFit::default();
        for k in -5..=5 {
            let u = k as f64 * 0.7;
            fit.add(u, 0.3 - 0.2 * u + 0.05 * u * u, 1.0 + (k * k) as f64);
        }
        let (a, b, c) = fit.solve().unwrap();
        assert!((a - 0.3).abs() < 1e-12 && (b + 0.2).abs() < 1e-12 && (c - 0.05).abs() < 1e-12);
        // Two points determine a line, one a constant.
        let mut line = QuadraticFit::default();
        line.add(0.0, 1.0, 1.0);
        line.add(2.0, 2.0, 1.0);
        let (a, b, c) = line.solve().unwrap();
        assert!((a - 1.0).abs() < 1e-12 && (b - 0.5).abs() < 1e-12 && c == 0.0);
    }

    #[test]
    fn weighted_side_fit_follows_the_risers() {
        // The half-plane below y = 10.3 + tan(4°)·x, cut to a box: its top side is a
        // digital line with flat runs of about 14 px.
        let m = 4f64.to_radians().tan();
        let cov = binary(60, 30, |x, y| {
            y > 10.3 + m * x && x > 5.0 && x < 55.0 && y < 25.0
        });
        let bm = Bitmap::from_coverage(60, 30, cov, Some(0.5)).unwrap();
        let cracks = PaddedMask::new(&bm)
            .unwrap()
            .borders()
            .swap_remove(0)
            .cracks;
        let mut w = Workspace::default();
        w.raw.extend(cracks.iter().map(|c| c.mid()));
        w.normals.extend(cracks.iter().map(|c| c.normal()));
        w.run_weights();
        w.scratch = w.raw.clone();
        let top: Vec<usize> = (0..w.raw.len())
            .filter(|&j| (15.0..45.0).contains(&w.raw[j].x) && w.raw[j].y < 15.0)
            .collect();
        let weighted = w.fit_side(top.iter().copied()).unwrap();
        let (plain, _) = fit_line(top.iter().map(|&j| w.raw[j])).unwrap();
        let error = |l: Line| {
            let at = |x: f64| l.origin.y + (x - l.origin.x) / l.direction.x * l.direction.y;
            (at(20.0) - (10.3 + 20.0 * m))
                .abs()
                .max((at(40.0) - (10.3 + 40.0 * m)).abs())
        };
        let (we, pe) = (error(weighted), error(plain));
        // Measured: 0.041 px weighted, 0.071 px plain.
        assert!(we < 0.05, "weighted side line off by {we}");
        assert!(we < pe, "weighted {we} vs plain {pe}");
    }

    /// Bilevel diagonal strokes (a "V"): the outline keeps the shape's area.
    #[test]
    fn bilevel_diagonal_strokes_keep_their_area() {
        let poly = [
            Point::new(20.0, 10.0),
            Point::new(40.0, 10.0),
            Point::new(60.0, 70.0),
            Point::new(80.0, 10.0),
            Point::new(100.0, 10.0),
            Point::new(70.0, 100.0),
            Point::new(50.0, 100.0),
        ];
        let inside = |p: Point| {
            let mut c = false;
            for k in 0..poly.len() {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x)
                {
                    c = !c;
                }
            }
            c
        };
        let (w, h) = (120u32, 110u32);
        let cov: Vec<f32> = (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .map(|(c, r)| {
                if inside(Point::new(c as f64 + 0.5, r as f64 + 0.5)) {
                    1.0
                } else {
                    0.0
                }
            })
            .collect();
        let pixels = cov.iter().filter(|&&v| v > 0.5).count() as f64;
        let bm = Bitmap::from_coverage(w, h, cov, Some(0.5)).unwrap();
        assert!(bm.is_bilevel());
        let cs = extract_contours(&bm, &ContourOptions { min_area: 2.0 }).unwrap();
        assert_eq!(cs.len(), 1);
        let area = signed_area(&cs[0].points);
        assert!(
            (area - pixels).abs() < 0.01 * pixels,
            "area {area} vs {pixels} pixels"
        );
    }

    /// The guard of the bilevel regression accepts outlines on the pixel boundary and
    /// rejects ones that leave it (shifted, or cutting a corner off).
    #[test]
    fn crack_guard_rejects_outlines_off_the_pixels() {
        // Pixel-edge midpoints of a 10 × 10 square of pixels at (5, 5).
        let cov = binary(20, 20, |x, y| {
            (5.0..15.0).contains(&x) && (5.0..15.0).contains(&y)
        });
        let bm = Bitmap::from_coverage(20, 20, cov, Some(0.5)).unwrap();
        let cracks = PaddedMask::new(&bm)
            .unwrap()
            .borders()
            .swap_remove(0)
            .cracks;
        assert_eq!(cracks.len(), 40);
        let smooth = smoothed_cracks(&cracks);
        assert!(follows_cracks(&smooth, &cracks));
        let shifted: Vec<Point> = smooth.iter().map(|&p| p + Point::new(2.0, 0.0)).collect();
        assert!(!follows_cracks(&shifted, &cracks));
        // A chord across a quarter of the square keeps every point near a midpoint of
        // the far sides but loses a large area.
        let cut: Vec<Point> = cracks
            .iter()
            .map(|c| c.mid())
            .filter(|m| m.x + m.y > 15.0)
            .collect();
        assert!(!follows_cracks(&cut, &cracks));
    }
}
