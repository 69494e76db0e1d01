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
//!    that a light line thinner than a pixel is not cut into one-pixel holes. On a large
//!    image the borders are refined (steps 2 and 3) on the thread pool as the scan finds
//!    them, in batches, while it goes on looking for more.
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
//!    * *Soft edges*: a boundary where more than `SOFT_SHARE` of the ±2 px integration
//!      windows end short of paper or ink (a blurred or upscaled edge) is refined again
//!      with `Window::SOFT` (±8 px, up to 1 px across the crack); a border whose
//!      measured spread is at least `SOFT_SPREAD` (2 px) is refined with it at once.
//!    * *Edge spread*: on a grey-level image every border's spread is measured (the
//!      10–90 % rise of the coverage along its gradient at up to 32 cracks, as a
//!      Gaussian's σ, `grey::edge_spread`); a blurred edge widens its outline's
//!      tolerance (`Contour::edge_scale`).
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
//! Measured (`contour/tests.rs`, and a benchmark over 10 sub-pixel centres per radius):
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
//!
//! One file per step: `mask` (the thresholded bit mask, the diagonal decisions and the
//! border scan), `grey` (edge placement on grey levels), `bilevel` (the regression and
//! corners of bilevel outlines), `spikes`, `cleanup` (spacing, folds, resampling), with
//! `lines` (small line geometry) and `workspace` (the buffers a thread reuses) below them;
//! this file holds the types and runs the steps.

mod bilevel;
mod cleanup;
mod grey;
mod lines;
mod mask;
mod spikes;
mod workspace;

use crate::error::{Error, Result};
use crate::geom::{signed_area, Point};
use crate::raster::Bitmap;
use bilevel::{follows_cracks, smoothed_cracks};
use grey::{
    edge_spread, outline_noise, EdgeEstimator, Window, NOISE_LIMIT, SOFT_SHARE, SOFT_SPREAD,
};
use mask::{Crack, CrackLoop, PaddedMask};
use serde::Serialize;
use spikes::extend_spikes;
use workspace::Workspace;

/// Options of boundary extraction.
#[derive(Clone, Debug)]
pub(crate) struct ContourOptions {
    /// Contours enclosing a smaller area (px², after refinement) are dropped as specks,
    /// together with every contour nested inside them. Must be finite and ≥ 0.
    /// Default (in [`crate::Config`]): 2.0.
    pub min_area: f64,
    /// Measure each grey-level border's edge spread ([`Contour::edge_spread`]); only a
    /// trace that widens its tolerance on blurred edges needs it.
    pub edge_spread: bool,
}

/// One closed boundary of a shape, as sub-pixel points in image pixel units.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct Contour {
    /// Boundary points in order, closed implicitly (the last connects to the first; the
    /// first point is not repeated). Outer borders run so that `geom::signed_area` is
    /// positive (clockwise on screen), holes so that it is negative.
    pub points: Vec<Point>,
    /// True for the border of a hole.
    pub is_hole: bool,
    /// Index (in the same list) of the enclosing contour: a hole's outer border, or the hole
    /// an island sits in. `None` for top-level outer borders.
    pub parent: Option<usize>,
    /// Spread (px) of the grey-level edge along the border: the deviation of the Gaussian
    /// blur that gives its rise from paper to ink, the median over cracks sampled along
    /// it (`grey::edge_spread`). `None` on a bilevel image and where too few cracks show
    /// a clean rise (thin strokes, crowded edges).
    pub edge_spread: Option<f64>,
}

/// Largest edge spread (px) of a sharp anti-aliased edge: the pixel's box filter and
/// bilinear interpolation give 0.29–0.62 px (on the development corpus's glyphs, icons and
/// stress shapes every contour measures 0.53–0.624 px).
pub(crate) const SHARP_EDGE_SPREAD: f64 = 0.65;
/// Largest widening of the tolerance on a blurred edge, for a spread of 5.85 px. The
/// measure's 8 px reach keeps the spreads it finds below about 4 px (a widening of 2.5),
/// so this is a guard, not a limit met in practice.
pub(crate) const MAX_EDGE_SCALE: f64 = 3.0;

impl Contour {
    /// How many times the tolerance is widened on this contour's edge: the square root of
    /// its spread in units of a sharp edge's ([`SHARP_EDGE_SPREAD`]), at least 1 and at
    /// most [`MAX_EDGE_SCALE`]. An edge blurred over σ px shows the shape only to the
    /// scale of that blur: upscaling by F leaves ripples of about F/4 px where the pixel
    /// steps were (with σ ≈ 0.28·F), and a fit held to 0.3 px follows them in short
    /// pieces. The square root is the geometric mean of holding the tolerance in image
    /// pixels and in units of the blur, measured on the corpus's glyphs upscaled 4× and
    /// 8× and blurred by 2 px (`bench/soft_edges.py`, against the truth): in units of the
    /// blur the pieces fell to 0.37–0.56× potrace's but the area error rose to
    /// 0.83–0.95× potrace's; the square root keeps 0.57–0.83× (0.43–0.79× in image
    /// pixels) with 0.66–0.86× potrace's pieces (0.98–1.48× in image pixels).
    pub(crate) fn edge_scale(&self) -> f64 {
        self.edge_spread.map_or(1.0, |s| {
            (s / SHARP_EDGE_SPREAD).sqrt().clamp(1.0, MAX_EDGE_SCALE)
        })
    }
}

/// Extracts the contours of the foreground of `bitmap`.
///
/// Returns outer borders, holes and islands in the order of their first pixel edge in a
/// raster scan (a parent always comes before its children), with sub-pixel points as described in the
/// module docs. An image with no foreground gives an empty list.
///
/// Errors: [`Error::InvalidOption`] when `min_area` is negative or not finite, or when the
/// bitmap's public `width`/`height` were changed so that they no longer match its
/// coverage, or exceed 2³¹ − 4. (The trace uses [`extract_with`], which keeps the borders
/// for the repair stage; this is the contours alone, for the tests.)
#[cfg(test)]
pub(crate) fn extract_contours(bitmap: &Bitmap, opts: &ContourOptions) -> Result<Vec<Contour>> {
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
    cracks: CrackLoop,
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
    /// The pixel corners the border passes, in walking order, in image coordinates.
    pub(crate) fn corners(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.cracks.vertices()
    }

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
            PixelTrace::Raw => {
                // The pinches (pixels touching only at a corner) are points of their own,
                // so that the outline is held at them and the pixels on either side stay
                // apart (a checkerboard is cells, not diagonal stripes).
                let mut points = Vec::with_capacity(b.cracks.len());
                for c in b.cracks.iter() {
                    if self.mask.leaves_pinch(c) {
                        points.push(c.start());
                    }
                    points.push(c.mid());
                }
                points
            }
            PixelTrace::Smoothed => {
                let cracks = b.cracks.to_vec();
                let mut work = Workspace::default();
                let fitted = work.bilevel_outline(&cracks, &self.mask);
                if follows_cracks(&fitted, &cracks) {
                    fitted
                } else {
                    smoothed_cracks(&cracks)
                }
            }
        };
        finish(points, b.is_hole, parent, 0.0, None)
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

/// Fewest pixels of an image whose borders are refined while the raster scan still looks
/// for more ([`refine_while_scanning`]).
const PIPELINE_PIXELS: usize = 1 << 22;

/// Cracks per task of [`refine_while_scanning`]: enough that a task costs far more than
/// handing it to the thread pool.
const BATCH_CRACKS: usize = 8_192;

/// Scans the mask for its borders and refines them on the thread pool as they are found,
/// in batches of consecutive borders, so that the scan (one thread, about 30 ms on a
/// 600 dpi page) no longer runs while the other threads wait. Returns each border's
/// result in border order, and the parents from the scan.
fn refine_while_scanning<R, F>(mask: &PaddedMask, trace_one: &F) -> (Vec<R>, Vec<Option<usize>>)
where
    R: Send,
    F: Fn(&mut Workspace, Vec<Crack>, bool) -> R + Sync,
{
    let done: std::sync::Mutex<Vec<(usize, Vec<R>)>> = std::sync::Mutex::new(Vec::new());
    let parents = rayon::scope(|scope| {
        let done = &done;
        let mut batch: Vec<(Vec<Crack>, bool)> = Vec::new();
        let (mut first, mut next, mut cracks) = (0, 0, 0);
        let send = |batch: Vec<(Vec<Crack>, bool)>, first: usize| {
            scope.spawn(move |_| {
                let mut work = Workspace::default();
                let out: Vec<R> = batch
                    .into_iter()
                    .map(|(c, is_hole)| trace_one(&mut work, c, is_hole))
                    .collect();
                done.lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .push((first, out));
            });
        };
        let parents = mask.scan_borders(|c, is_hole| {
            cracks += c.len();
            batch.push((c, is_hole));
            next += 1;
            if cracks >= BATCH_CRACKS {
                send(std::mem::take(&mut batch), first);
                (first, cracks) = (next, 0);
            }
        });
        if !batch.is_empty() {
            send(batch, first);
        }
        parents
    });
    let mut done = done
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    done.sort_unstable_by_key(|&(first, _)| first);
    let results = done.into_iter().flat_map(|(_, out)| out).collect();
    (results, parents)
}

/// [`extract_contours`] keeping the borders.
pub(crate) fn extract_borders(bitmap: &Bitmap, opts: &ContourOptions) -> Result<Extraction> {
    extract_with(bitmap, opts, EdgeEstimator::CoverageIntegral)
}

fn extract_with(
    bitmap: &Bitmap,
    opts: &ContourOptions,
    estimator: EdgeEstimator,
) -> Result<Extraction> {
    let pixels = bitmap.width() as usize * bitmap.height() as usize;
    extract_scheduled(bitmap, opts, estimator, pixels >= PIPELINE_PIXELS)
}

/// [`extract_with`], refining the borders while the scan looks for more when `pipelined`
/// (same results either way).
fn extract_scheduled(
    bitmap: &Bitmap,
    opts: &ContourOptions,
    estimator: EdgeEstimator,
    pipelined: bool,
) -> Result<Extraction> {
    if !(opts.min_area.is_finite() && opts.min_area >= 0.0) {
        return Err(Error::InvalidOption {
            name: "min_area",
            message: "must be a non-negative area in px²".to_string(),
        });
    }
    let (w, h) = (bitmap.width() as usize, bitmap.height() as usize);
    let mask = PaddedMask::new(bitmap).ok_or_else(|| Error::InvalidOption {
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
    // A border's contour and kept border, without their parent (set once the scan ends).
    let trace_one = |work: &mut Workspace, cracks: Vec<Crack>, is_hole: bool| {
        let contour = if cracks.is_empty() {
            None
        } else {
            let bilevel = |work: &mut Workspace| {
                let fitted = work.bilevel_outline(&cracks, &mask);
                if follows_cracks(&fitted, &cracks) {
                    fitted
                } else {
                    // The regression lost the outline (seen on some diagonal strokes): fall
                    // back to the plainly smoothed pixel-edge midpoints.
                    smoothed_cracks(&cracks)
                }
            };
            let measure = opts.edge_spread && !bitmap.is_bilevel();
            let spread = measure.then(|| edge_spread(bitmap, &cracks));
            let points = if bitmap.is_bilevel() {
                bilevel(work)
            } else {
                // A soft edge is refined with the window that spans it: at once when its
                // measured spread says so, else once the sharp window has found it open.
                let soft = |work: &mut Workspace| {
                    let all = work.refined_outline(bitmap, &cracks, estimator, Window::SOFT, None);
                    all.unwrap_or_default()
                };
                let refined = if spread.flatten().is_some_and(|s| s >= SOFT_SPREAD) {
                    soft(work)
                } else {
                    let sharp = Window::SHARP;
                    work.refined_outline(bitmap, &cracks, estimator, sharp, Some(SOFT_SHARE))
                        .unwrap_or_else(|| soft(work))
                };
                if outline_noise(&refined) > NOISE_LIMIT {
                    // The grey levels are noise (JPEG ringing, scanner grain), not
                    // anti-aliasing: refining to them would fit the noise. Trace the
                    // thresholded pixels as a bilevel image is traced.
                    bilevel(work)
                } else {
                    refined
                }
            };
            let mut points = points;
            extend_spikes(&mut points, bitmap);
            finish(points, is_hole, None, opts.min_area, spread.flatten())
        };
        let border = Border {
            cracks: CrackLoop::new(&cracks),
            is_hole,
            parent: None,
        };
        (contour, border)
    };
    // Borders are refined independently, so on a large image with many of them (a page
    // of text) in parallel, results in border order.
    let (results, parents) = if pipelined {
        refine_while_scanning(&mask, &trace_one)
    } else {
        let found = mask.borders();
        let parents: Vec<Option<usize>> = found.iter().map(|b| b.parent).collect();
        let cracks: usize = found.iter().map(|b| b.cracks.len()).sum();
        let largest = found.iter().map(|b| b.cracks.len()).max().unwrap_or(0);
        let results: Vec<(Option<Contour>, Border)> = if cracks - largest >= PARALLEL_CRACKS {
            use rayon::prelude::*;
            found
                .into_par_iter()
                .map_init(Workspace::default, |work, b| {
                    trace_one(work, b.cracks, b.is_hole)
                })
                .collect()
        } else {
            let mut work = Workspace::default();
            found
                .into_iter()
                .map(|b| trace_one(&mut work, b.cracks, b.is_hole))
                .collect()
        };
        (results, parents)
    };
    let (mut traced, mut borders): (Vec<Option<Contour>>, Vec<Border>) =
        results.into_iter().unzip();
    for ((contour, border), &parent) in traced.iter_mut().zip(&mut borders).zip(&parents) {
        border.parent = parent;
        if let Some(contour) = contour {
            contour.parent = parent;
        }
    }
    let (contours, border_of) = renumber(traced, parents);
    Ok(Extraction {
        contours,
        borders,
        border_of,
        mask,
    })
}

/// Orients a finished outline and applies the size rules; `None` when it is dropped.
fn finish(
    mut points: Vec<Point>,
    is_hole: bool,
    parent: Option<usize>,
    min_area: f64,
    edge_spread: Option<f64>,
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
        edge_spread,
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

#[cfg(test)]
mod tests;
