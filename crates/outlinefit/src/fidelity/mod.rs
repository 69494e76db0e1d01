//! End-to-end fidelity check: what the SVG draws, measured against the input.
//!
//! Every stage before export can lose a part of the shape without noticing: edge
//! refinement can drop a run of boundary points, a corner can be missed, a short segment
//! that cannot be split can cut across its data, a speck can shrink below `--min-area`
//! during refinement. This module looks only at the result, after the outline has been
//! converted to the polynomial cubics the SVG draws:
//!
//! 1. **Deviation**: the distance from every boundary data point of a contour to the drawn
//!    path of that contour (the path flattened to chords within [`FLATTEN_ERROR`] px of
//!    it, none longer than [`FLATTEN_MAX_CHORD`] px). With the
//!    default `lsq` fit the limit is the tolerance plus the SVG's approximation bound; a
//!    metaheuristic fit promises no tolerance, and is held to [`SHAPE_LIMIT`]. A point
//!    of a polynomial segment, which is drawn as itself, is at most |P(u) − Q| +
//!    [`FLATTEN_ERROR`] from the drawn path (u its fitted parameter); it is measured only
//!    when that bound could make it bad or the contour's worst, which on a page of text
//!    spares most of the distance queries and finds exactly the same.
//! 2. **Disagreement**: the drawn shape is rasterized at the pixel centres (even-odd over
//!    all contours, as the SVG's paths fill) and compared with the thresholded input. A
//!    pixel where they disagree and whose centre lies more than [`SHAPE_LIMIT`] (1 px, or
//!    the deviation limit when a loose tolerance allows more) from the drawn outline is a
//!    *far* pixel: at most a pixel from the outline, a disagreement is only where the edge
//!    crosses the pixel. A pixel within that distance of a crossing of its own row's
//!    centre line (found by the rasterization) is near at once; the others ask a grid of
//!    the drawn edges. Far pixels are grouped into 8-connected
//!    regions; a region larger than max(`--min-area`, 2) px² is a lost or invented part
//!    (smaller ones are specks that `--min-area` drops on purpose).
//! 3. **Dense disagreement** (`dense`): the disagreeing pixels that are not far are
//!    counted per tile of [`dense::TILE`] px; a tile where more than
//!    [`dense::DENSE_SHARE`] of the pixels (times the far distance) disagree is wrong in
//!    bulk, though every pixel lies near an outline (a checkerboard drawn as diagonal
//!    stripes), and its group of such tiles is a region that fails the check.
//!
//! [`crate::trace_bitmap`] repairs what fails (see `repair`) and reports the final check
//! in [`Fidelity`]. The first check of a large image compares the tiles near a border
//! of the mask or an edge of the drawing, where every disagreement starts, and every
//! row only when a disagreement reaches the edge of those tiles (`band_tiles`; the
//! 4096 px horse's outline passes through 6 % of its tiles, a page of text through a
//! fifth); a check after a repair round compares only the tiles around the contours it
//! changed (`dirty`), with a grid of the edges near them (`grid`), and keeps the earlier
//! findings everywhere else, which it would find again: on a scanned page a round costs
//! what its few repaired contours cost.

mod dense;
mod dirty;
mod grid;

use crate::contour::Border;
use crate::curve::CubicBez;
use crate::fit::FittedContour;
use crate::geom::{distance_to_closed_polyline, groups_8, segment_distance, Point};
use crate::merge::outline::{drawing_pieces, MergedCurve};
use crate::raster::Bitmap;
use dense::{dense_regions, UNDECIDED};
use dirty::Dirty;
use grid::{edge_of, Edge, EdgeGrid, Vertex};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashSet;

/// Largest distance (px) between a drawn cubic and its flattening.
pub(crate) const FLATTEN_ERROR: f64 = 0.01;

/// Longest chord (px) of the flattened drawn path, whatever the curvature: a straight
/// piece still becomes several edges, so that no edge spans many cells of the edge grid.
pub(crate) const FLATTEN_MAX_CHORD: f64 = 2.0;

/// Number of equal parameter steps that flatten `cubic` within [`FLATTEN_ERROR`]: linear
/// interpolation over a parameter interval h is within h²/8·max|B''| of the curve (both
/// ways), and |B''| ≤ 6·max(|P0 − 2P1 + P2|, |P1 − 2P2 + P3|), so n steps with
/// n² ≥ 3/4·max(…)/FLATTEN_ERROR are enough. At least enough that no chord is longer
/// than [`FLATTEN_MAX_CHORD`]; at most 4096.
pub(crate) fn flatten_steps(cubic: &CubicBez) -> usize {
    let p = cubic.points;
    let bend = (p[0] - p[1] * 2.0 + p[2])
        .length()
        .max((p[1] - p[2] * 2.0 + p[3]).length());
    let by_error = (0.75 * bend / FLATTEN_ERROR).sqrt();
    // |B'| ≤ 3·(longest control polygon leg), so a step of h is at most that times h long.
    let leg = p[0]
        .distance(p[1])
        .max(p[1].distance(p[2]))
        .max(p[2].distance(p[3]));
    let by_length = 3.0 * leg / FLATTEN_MAX_CHORD;
    let n = by_error.max(by_length).ceil();
    if n.is_nan() {
        1
    } else {
        (n as usize).clamp(1, 4096)
    }
}

/// Distance (px) from the drawn outline beyond which a disagreeing pixel is a lost or
/// invented part, and the deviation limit of fits that promise no tolerance.
pub(crate) const SHAPE_LIMIT: f64 = 1.0;

/// The verdict on one traced image, as reported.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Fidelity {
    /// True when every data point is within its contour's deviation limit of the drawn
    /// outline and no region of disagreement exceeds `region_limit`.
    pub held: bool,
    /// Largest distance (px) from a boundary data point to the drawn outline.
    pub max_deviation: f64,
    /// The deviation the trace promises (px): the tolerance plus the SVG approximation
    /// bound for `lsq`, `SHAPE_LIMIT` for metaheuristic fits; the largest over the
    /// contours, where a blurred edge widened a contour's tolerance (each contour is held
    /// to its own tolerance plus the same bounds).
    pub deviation_limit: f64,
    /// Area (px², counted in pixels) of the largest region where the drawn shape and the
    /// thresholded input disagree farther than `SHAPE_LIMIT` (or the deviation limit, when
    /// larger) from the outline.
    pub largest_region: f64,
    /// Largest region area accepted: max(`--min-area`, 2) px².
    pub region_limit: f64,
    /// Bounding box `[x0, y0, x1, y1]` (pixels, inclusive) of the largest region, if any.
    pub region_box: Option<[u32; 4]>,
    /// Contours traced again by the repair.
    pub repaired_contours: usize,
    /// Shapes or holes the first trace had lost, restored by the repair.
    pub restored_contours: usize,
    /// Segments of an `lsq` fit whose largest data-point distance (`max_distance` in
    /// their report) is above their contour's tolerance: pieces too short to split (under 7 data
    /// points, about 5 px, between two corners). They are within `deviation_limit`, so
    /// the verdict can hold; they are counted here, and the program warns, because the
    /// tolerance was asked for. Always 0 for the metaheuristic fits, which promise none.
    pub segments_over_tolerance: usize,
    /// The largest `max_distance` of those segments (px), 0 when there are none.
    pub worst_segment_distance: f64,
}

/// The findings of one check, with what the repair needs.
#[derive(Debug, Default)]
pub(crate) struct Findings {
    /// Largest data-point deviation over every contour.
    pub(crate) max_deviation: f64,
    /// Per contour: indices of the data points beyond the deviation limit that are local
    /// maxima of the deviation (where a corner or a split is missing).
    pub(crate) bad_points: Vec<Vec<usize>>,
    /// Per contour: the largest deviation of its data points.
    pub(crate) worst: Vec<f64>,
    /// Regions above the limit.
    pub(crate) regions: Vec<Region>,
    /// Area and bounding box of the largest region (above the limit or not).
    pub(crate) largest: (f64, Option<[u32; 4]>),
    /// Pixels far from the drawn outline where it disagrees with the input (excused ones
    /// left out), sorted: a later check keeps those away from what changed.
    far_pixels: Vec<u32>,
    /// Decided pixels near the drawn outline where it disagrees, sorted (likewise).
    near_pixels: Vec<u32>,
    /// Per contour, the box of its drawn path.
    boxes: Vec<Option<[f64; 4]>>,
}

/// A connected region of far pixels.
#[derive(Debug)]
pub(crate) struct Region {
    /// Pixel indices (row × width + column).
    pub(crate) pixels: Vec<u32>,
    /// Contours whose drawn outline passes within [`REGION_REACH`] px beyond the far
    /// limit of the region.
    pub(crate) near_contours: Vec<usize>,
    /// The segments of those contours nearest to the region's pixels, as (contour,
    /// segment), sorted; the segment is `None` where merged curves are drawn.
    pub(crate) near_segments: Vec<(usize, Option<usize>)>,
}

/// How far (px) beyond [`Limits::far`] from a region a contour counts as responsible for
/// it.
const REGION_REACH: f64 = 2.0;

impl Findings {
    /// True when nothing is beyond the limits.
    pub(crate) fn held(&self) -> bool {
        self.regions.is_empty() && self.bad_points.iter().all(Vec::is_empty)
    }
}

/// The limits of a check.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Largest data-point deviation (px) of a contour fitted to the trace's tolerance.
    pub(crate) deviation: f64,
    /// The trace's tolerance (px).
    pub(crate) tolerance: f64,
    /// Largest widening (px) of a contour's tolerance beyond the trace's (a blurred edge,
    /// `Contour::edge_scale`).
    pub(crate) widening: f64,
    /// Largest region area (px²).
    pub(crate) region: f64,
    /// Approximation bound of the SVG's cubics (px).
    pub(crate) bound: f64,
}

impl Limits {
    /// Distance (px) from the drawn outline beyond which a disagreeing pixel is far:
    /// [`SHAPE_LIMIT`], or the deviation limit when a loose tolerance allows more (a fit
    /// that may stray 2 px from its data may leave pixels 2 px from the outline on the
    /// wrong side; it is the tolerance the user asked for, not a lost part), with the
    /// widest contour's widening (one limit for the whole image).
    pub(crate) fn far(&self) -> f64 {
        SHAPE_LIMIT.max(self.deviation + self.widening)
    }

    /// Largest data-point deviation (px) of `contour`: [`Limits::deviation`], plus what
    /// its own tolerance adds to the trace's (a blurred edge's).
    pub(crate) fn deviation_of(&self, contour: &FittedContour) -> f64 {
        self.deviation + (contour.tolerance - self.tolerance).max(0.0)
    }
}

/// The drawn outline of every contour as closed polylines, and for each the segments its
/// points belong to ([`SegmentRuns`]; `u32::MAX` where merged curves are drawn).
fn flatten(
    contours: &[FittedContour],
    merged: &[Vec<MergedCurve>],
    bound: f64,
) -> Vec<(Vec<Vertex>, SegmentRuns)> {
    let parallel = contours.iter().map(|c| c.points.len()).sum::<usize>() >= PARALLEL_POINTS;
    let flatten_one = |(i, c): (usize, &FittedContour)| {
        if c.segments.is_empty() {
            return (Vec::new(), SegmentRuns::default());
        }
        let merged = merged.get(i).map_or(&[][..], Vec::as_slice);
        let pieces = drawing_pieces(c, merged, bound);
        // Without merged curves, piece k is segment k.
        let segment_of = |k: usize| {
            if merged.is_empty() {
                k as u32
            } else {
                u32::MAX
            }
        };
        // Step counts once, so that the polyline is allocated at its exact size.
        let steps: Vec<usize> = pieces
            .iter()
            .flat_map(|(_, cubics)| cubics.iter().map(flatten_steps))
            .collect();
        let size = pieces.len() + steps.iter().sum::<usize>();
        let (mut out, mut segments) = (Vec::with_capacity(size), Vec::with_capacity(size));
        let mut steps = steps.into_iter();
        for (k, (start, cubics)) in pieces.into_iter().enumerate() {
            out.push(Vertex::new(start));
            segments.push(segment_of(k));
            for (cubic, n) in cubics.iter().zip(&mut steps) {
                for j in 1..=n {
                    out.push(Vertex::new(cubic.eval(j as f64 / n as f64)));
                    segments.push(segment_of(k));
                }
            }
        }
        if out.iter().any(|p| !p.is_finite()) {
            let keep: Vec<bool> = out.iter().map(|p| p.is_finite()).collect();
            let mut flags = keep.iter();
            out.retain(|_| *flags.next().unwrap_or(&false));
            let mut flags = keep.iter();
            segments.retain(|_| *flags.next().unwrap_or(&false));
        }
        (out, SegmentRuns::new(&segments))
    };
    if parallel {
        contours.par_iter().enumerate().map(flatten_one).collect()
    } else {
        contours.iter().enumerate().map(flatten_one).collect()
    }
}

/// Which segment each point of a drawn polyline belongs to, as runs: (first point, segment)
/// for each run of points of one segment. A few bytes per segment instead of four per
/// point.
#[derive(Clone, Debug, Default)]
struct SegmentRuns(Vec<(u32, u32)>);

impl SegmentRuns {
    /// The runs of `segments` (one per point).
    fn new(segments: &[u32]) -> SegmentRuns {
        let mut runs: Vec<(u32, u32)> = Vec::new();
        for (k, &s) in segments.iter().enumerate() {
            if runs.last().is_none_or(|r| r.1 != s) {
                runs.push((k as u32, s));
            }
        }
        runs.shrink_to_fit();
        SegmentRuns(runs)
    }

    /// The segment of point `k`.
    fn at(&self, k: u32) -> u32 {
        let run = self.0.partition_point(|r| r.0 <= k);
        self.0[run.saturating_sub(1)].1
    }
}

/// The largest deviation of `deviation` (one per data point of a closed contour) and
/// the points beyond `limit` that are local maxima of it.
fn worst_and_bad(deviation: &[f64], limit: f64) -> (f64, Vec<usize>) {
    let n = deviation.len();
    let mut worst: f64 = 0.0;
    let mut bad = Vec::new();
    for k in 0..n {
        let d = deviation[k];
        worst = worst.max(d);
        if d > limit && d >= deviation[(k + n - 1) % n] && d >= deviation[(k + 1) % n] {
            bad.push(k);
        }
    }
    (worst, bad)
}

/// For every data point of `contour`, a bound of its distance from the contour's drawn
/// path, or infinity: a polynomial segment is drawn as itself, so a point is at most
/// |P(u) − Q| from it (u the point's parameter), plus [`FLATTEN_ERROR`] for the chords
/// that stand for the curve and the single-precision rounding of their ends. A rational
/// segment's drawing is within its bound only as far as samples tell, so its points get
/// no bound and are measured.
fn deviation_bounds(contour: &FittedContour) -> Vec<f64> {
    let n = contour.points.len();
    let mut bound = vec![f64::INFINITY; n];
    for segment in &contour.segments {
        if !segment.curve.is_polynomial() || segment.params.len() != segment.point_count {
            continue;
        }
        for (j, &u) in segment.params.iter().enumerate() {
            let k = (segment.start + j) % n.max(1);
            let q = contour.points[k];
            let p = segment.curve.eval(u);
            // f32 keeps 24 bits: a vertex moves by at most 2⁻²⁴ of its largest coordinate.
            let rounding = 2.0 * f64::from(f32::EPSILON) * (q.x.abs().max(q.y.abs()) + 1.0);
            let b = p.distance(q) + FLATTEN_ERROR + rounding;
            if b.is_finite() {
                bound[k] = bound[k].min(b);
            }
        }
    }
    bound
}

/// The x of every crossing of the drawn paths `lines` (indices into `polylines`, whose
/// boxes are `boxes`) with the centre line y = r + 0.5 of each row r < `h` that `look`
/// looks at: per row, in path and edge order. On a large outline the rows are counted,
/// then filled, in [`CROSSING_BANDS`] bands in parallel, each band visiting the paths
/// whose boxes reach it; the lists are the same. Each row's list is made at its size on
/// the calling thread before it is filled: lists grown by doubling on the worker threads
/// took up to twice the memory, and left it in the workers' heaps when freed, where the
/// rest of the trace cannot reuse it (the 600 dpi scan's peak rose by 2 to 5 MB).
fn row_crossings(
    polylines: &[Vec<Vertex>],
    boxes: &[Option<[f64; 4]>],
    lines: &[usize],
    look: &Dirty,
    h: usize,
    parallel: bool,
) -> Vec<Vec<f64>> {
    let band = if parallel {
        CROSSING_BAND.max(h.div_ceil(CROSSING_BANDS))
    } else {
        h.max(1)
    };
    let visit = |first: usize, end: usize, emit: &mut dyn FnMut(usize, f64)| {
        band_crossings(polylines, boxes, lines, look, first, end, emit);
    };
    let mut count = vec![0usize; h];
    by_band(&mut count, band, parallel, |first, rows| {
        visit(first, first + rows.len(), &mut |r, _| rows[r - first] += 1);
    });
    let mut crossings: Vec<Vec<f64>> = count.into_iter().map(Vec::with_capacity).collect();
    by_band(&mut crossings, band, parallel, |first, rows| {
        visit(first, first + rows.len(), &mut |r, x| {
            rows[r - first].push(x)
        });
    });
    crossings
}

/// Runs `f` on each band of `band` rows of `rows` with the index of its first row: on the
/// thread pool when `parallel`, else one after the other.
fn by_band<T: Send>(
    rows: &mut [T],
    band: usize,
    parallel: bool,
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    if parallel {
        rows.par_chunks_mut(band)
            .enumerate()
            .for_each(|(k, rows)| f(k * band, rows));
    } else {
        rows.chunks_mut(band)
            .enumerate()
            .for_each(|(k, rows)| f(k * band, rows));
    }
}

/// Gives `emit` every crossing (row, x) of the paths `lines` with the centre lines of the
/// rows `first..end` that `look` looks at, in path and edge order (see
/// [`row_crossings`]).
fn band_crossings(
    polylines: &[Vec<Vertex>],
    boxes: &[Option<[f64; 4]>],
    lines: &[usize],
    look: &Dirty,
    first: usize,
    end: usize,
    emit: &mut dyn FnMut(usize, f64),
) {
    let (top, bottom) = (first as f64, end as f64);
    for &i in lines {
        if let Some([_, y0, _, y1]) = boxes[i] {
            if y1 < top || y0 > bottom + 1.0 {
                continue;
            }
        }
        for k in 0..polylines[i].len() as u32 {
            let Edge { a, b, .. } = edge_of(polylines, (i as u32, k));
            if a.y == b.y {
                continue;
            }
            let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
            // An edge wholly above or below the band crosses none of its rows (the same
            // test as the range below, without its two calls to `ceil`): a band visits
            // every edge of a path that reaches it, most of them elsewhere.
            if hi.y - 0.5 <= top || lo.y - 0.5 > bottom - 1.0 {
                continue;
            }
            // Rows whose centre y = r + 0.5 lies in [lo.y, hi.y), within the band.
            let r0 = (lo.y - 0.5).ceil().max(top);
            let r1 = (hi.y - 0.5).ceil().min(bottom);
            let mut r = r0;
            while r < r1 {
                if !look.spans(r as usize).is_empty() {
                    let y = r + 0.5;
                    let x = lo.x + (hi.x - lo.x) * (y - lo.y) / (hi.y - lo.y);
                    emit(r as usize, x);
                }
                r += 1.0;
            }
        }
    }
}

/// The first column after `col` whose centre lies at or beyond the crossing `x` (at most
/// `w`), where `x` lies beyond `col`'s centre.
fn run_end(col: usize, x: f64, w: usize) -> usize {
    let mut end = ((x - 0.5).ceil().max(col as f64 + 1.0) as usize).min(w);
    // Exactly the comparison the pixel loop makes, whatever the rounding above.
    while end > col + 1 && (end - 1) as f64 + 0.5 >= x {
        end -= 1;
    }
    while end < w && (end as f64 + 0.5) < x {
        end += 1;
    }
    end
}

/// Fewest data points of an image (or of one contour) for which the check runs on the
/// thread pool: contours, and the points of a large contour, are measured in parallel,
/// and the rows of the image compared in parallel; the findings are the same on any
/// number of threads.
const PARALLEL_POINTS: usize = 20_000;

/// Most point-to-edge distances (points to measure × edges of their contour's drawn path)
/// taken one by one rather than from the edge grid: building the grid costs about as
/// much per edge of the whole drawing as a few distances, and the first check of a
/// glyph measures two or three points of each contour.
const DIRECT_EDGE_TESTS: usize = 2048;

/// The rows of the image are split into this many bands (of at least
/// [`CROSSING_BAND`] rows) whose crossings with the drawn paths are found in parallel; a
/// path that reaches two bands is visited by both, each keeping its own rows.
const CROSSING_BANDS: usize = 16;

/// Fewest rows of a band of [`CROSSING_BANDS`].
const CROSSING_BAND: usize = 64;

/// `merged[i]` holds the merged curves drawn for `contours[i]` (missing or empty: its
/// segments). Pixels in `excused` (specks dropped on purpose) never count as far.
/// With the borders of the thresholded mask (`borders`), the pixels are compared only in
/// the tiles near a border or a drawn edge, where every disagreement starts (see
/// [`band_tiles`]); without them, on every row.
pub(crate) fn check(
    bitmap: &Bitmap,
    contours: &[FittedContour],
    merged: &[Vec<MergedCurve>],
    limits: Limits,
    excused: &HashSet<u32>,
    borders: Option<&[Border]>,
) -> Findings {
    compare_drawing(bitmap, contours, merged, limits, excused, None, borders)
}

/// [`check`], given the findings of an earlier check of the same contours with
/// `unchanged[i]` true for each contour drawn and fitted as it was then: their data
/// points' deviations (measured from their own drawn path only) are taken from it, and
/// the pixels are compared again only around the contours that changed (see `dirty`):
/// a repair round costs what its repaired contours cost, not a pass over the image.
pub(crate) fn check_again(
    bitmap: &Bitmap,
    contours: &[FittedContour],
    merged: &[Vec<MergedCurve>],
    limits: Limits,
    excused: &HashSet<u32>,
    earlier: Option<(&Findings, &[bool])>,
) -> Findings {
    compare_drawing(bitmap, contours, merged, limits, excused, earlier, None)
}

/// [`check`] and [`check_again`].
fn compare_drawing(
    bitmap: &Bitmap,
    contours: &[FittedContour],
    merged: &[Vec<MergedCurve>],
    limits: Limits,
    excused: &HashSet<u32>,
    earlier: Option<(&Findings, &[bool])>,
    borders: Option<&[Border]>,
) -> Findings {
    let (polylines, segment_of): (Vec<Vec<Vertex>>, Vec<SegmentRuns>) =
        flatten(contours, merged, limits.bound).into_iter().unzip();
    let boxes: Vec<Option<[f64; 4]>> = polylines.iter().map(|line| vertex_box(line)).collect();
    let (w, h) = (bitmap.width() as usize, bitmap.height() as usize);
    let far_limit = limits.far();
    // Reach (px) within which the drawn edges decide what the check finds at a pixel:
    // a region's responsible contours, beyond the far limit, the farthest.
    let reach = REGION_REACH + far_limit + 2.0;
    let whole = [0.0, 0.0, w as f64, h as f64];
    // The tiles to look at again, and a grid of the edges that can matter there.
    let dirty = earlier.map(|(findings, unchanged)| {
        let changed: Vec<[f64; 4]> = (0..contours.len())
            .filter(|&i| unchanged.get(i) != Some(&true))
            .flat_map(|i| [findings.boxes.get(i).copied().flatten(), boxes[i]])
            .flatten()
            .collect();
        Dirty::new(w, h, &changed, reach)
    });
    // Built when first asked on a small drawing: a first check of a glyph often measures
    // a few points only, directly (see `DIRECT_EDGE_TESTS`), and finds no pixel that
    // needs it.
    let grid_cell = std::sync::OnceLock::new();
    let grid = || {
        grid_cell.get_or_init(|| match &dirty {
            None => EdgeGrid::new(&polylines, whole, |_| true),
            Some(d) => {
                // Whole contours away from the tiles first, then edges.
                let near: Vec<bool> = boxes
                    .iter()
                    .map(|b| b.is_some_and(|b| d.near_box(b, reach)))
                    .collect();
                EdgeGrid::new(&polylines, d.bounds(reach).unwrap_or(whole), |e| {
                    near[e.contour as usize] && d.near_box(edge_box(e), reach)
                })
            }
        })
    };
    // Every edge, for what the partial grid cannot answer (rarely needed).
    let full_grid = std::sync::OnceLock::new();
    let full = || full_grid.get_or_init(|| EdgeGrid::new(&polylines, whole, |_| true));

    let parallel = contours.iter().map(|c| c.points.len()).sum::<usize>() >= PARALLEL_POINTS;
    if parallel {
        // Built before the parallel passes: built inside one, on the pool itself, its
        // builder could take up another contour's task that asks for it again. (A large
        // drawing needs it anyway.)
        grid();
    }

    // 1. Deviation of every data point from its own contour's drawn path (the grid holds
    // every edge of a changed contour).
    let deviation_reach = far_limit * 2.0;
    let deviation_of = |(i, c): (usize, &FittedContour)| -> (f64, Vec<usize>) {
        if let Some((findings, unchanged)) = earlier {
            if unchanged.get(i) == Some(&true) && i < findings.worst.len() {
                return (findings.worst[i], findings.bad_points[i].clone());
            }
        }
        if polylines[i].is_empty() {
            return (0.0, Vec::new());
        }
        let limit = limits.deviation_of(c);
        let at = |&p: &Point| match grid().nearest(p, deviation_reach, Some(i as u32)) {
            Some((d, _)) => d,
            None => distance_to_closed_polyline(p, &polylines[i]),
        };
        let big = parallel && c.points.len() >= PARALLEL_POINTS;
        // A bound of every point's distance from the segment it was fitted to, where the
        // fit tells one: only the points whose bound could make them the worst or bad
        // are measured on the drawn path.
        let drawn_as_fitted = merged.get(i).is_none_or(Vec::is_empty);
        let bound = drawn_as_fitted.then(|| deviation_bounds(c));
        let Some(bound) = bound else {
            let deviation: Vec<f64> = if big {
                c.points.par_iter().map(at).collect()
            } else {
                c.points.iter().map(at).collect()
            };
            return worst_and_bad(&deviation, limit);
        };
        // Points without a bound (those of rational segments) are measured whatever the
        // others show, and so is the point of the largest bound: the largest of their
        // distances is a floor of the worst, and a point whose bound lies below both that
        // floor and the limit is neither the worst nor bad. (The distance of one point
        // alone, an unbounded one where there are any, often near 0, made the 4096 px
        // horse, with one rational segment of 48 points, measure 26 500 of its 30 900.)
        let measure_all = |ks: &[usize]| -> Vec<f64> {
            // A few points are measured on the contour's own drawn path edge by edge:
            // the same distances (the nearest edge's, by the same formula), without the
            // grid.
            if ks.len() * polylines[i].len() <= DIRECT_EDGE_TESTS {
                return ks
                    .iter()
                    .map(|&k| distance_to_closed_polyline(c.points[k], &polylines[i]))
                    .collect();
            }
            if big {
                ks.par_iter().map(|&k| at(&c.points[k])).collect()
            } else {
                ks.iter().map(|&k| at(&c.points[k])).collect()
            }
        };
        let largest = (0..bound.len())
            .filter(|&k| bound[k].is_finite())
            .reduce(|m, k| if bound[k] > bound[m] { k } else { m });
        let first: Vec<usize> = (0..bound.len())
            .filter(|&k| !bound[k].is_finite() || Some(k) == largest)
            .collect();
        let mut deviation = bound.clone();
        let mut floor: f64 = 0.0;
        for (&k, d) in first.iter().zip(measure_all(&first)) {
            deviation[k] = d;
            floor = floor.max(d);
        }
        let needed = floor.min(limit);
        // The rest are measured where their bound does not decide; the others keep it:
        // below `needed`, so below every distance that decides.
        let rest: Vec<usize> = (0..bound.len())
            .filter(|&k| bound[k].is_finite() && Some(k) != largest && bound[k] > needed)
            .collect();
        for (&k, d) in rest.iter().zip(measure_all(&rest)) {
            deviation[k] = d;
        }
        worst_and_bad(&deviation, limit)
    };
    let per_contour: Vec<(f64, Vec<usize>)> = if parallel {
        contours.par_iter().enumerate().map(deviation_of).collect()
    } else {
        contours.iter().enumerate().map(deviation_of).collect()
    };
    let max_deviation = per_contour.iter().map(|r| r.0).fold(0.0, f64::max);
    let (worst, bad_points) = per_contour.into_iter().unzip();

    // 2. Disagreement between the drawn shape and the thresholded input, on the rows
    // and columns to look at: after a repair, the tiles it changed; in a first check
    // given the borders, the tiles near a border or a drawn edge (`band`), unless a
    // disagreement reaches the band's edge, when every tile is looked at.
    let everywhere = std::sync::OnceLock::new();
    let everywhere = || everywhere.get_or_init(|| Dirty::all(w, h));
    let band = match (&dirty, borders) {
        (None, Some(borders)) if w * h >= BAND_PIXELS => {
            Some(band_tiles(w, h, borders, &polylines, far_limit, parallel))
        }
        _ => None,
    };
    // A closed path whose box misses the tiles looked at crosses each of their rows
    // left of a pixel an even number of times, or not at all: it cannot change a
    // pixel's side, and is skipped whole.
    let crosses = |i: usize| match &dirty {
        None => true,
        Some(d) => matches!(boxes[i], Some(b) if d.near_box(b, 0.0)),
    };
    let lines: Vec<usize> = (0..polylines.len())
        .filter(|&i| polylines[i].len() >= 2 && crosses(i))
        .collect();
    let threshold = bitmap.threshold();
    // On grey levels, a pixel near the threshold is undecided (an anti-aliased edge
    // pixel); only decided ones count towards dense disagreement. Each pixel is read as
    // a class: FOREGROUND, and DECIDED.
    const FOREGROUND: u8 = 1;
    const DECIDED: u8 = 2;
    let classes = bitmap.level_classes(|v| {
        let decided = bitmap.is_bilevel() || (f64::from(v) - threshold).abs() >= UNDECIDED;
        (u8::from(f64::from(v) >= threshold) * FOREGROUND) | (u8::from(decided) * DECIDED)
    });
    // Set when a disagreeing pixel lies on the edge of the band looked at.
    let overflow = std::sync::atomic::AtomicBool::new(false);
    // The far pixels of one row's spans of `look`, and its near disagreeing ones, given
    // its crossings (sorted here) and a buffer for its pixels' classes.
    let far_in_row = |look: &Dirty,
                      row: usize,
                      xs: &mut [f64],
                      class: &mut [u8],
                      out: &mut (Vec<u32>, Vec<u32>)| {
        let spans = look.spans(row);
        if spans.is_empty() {
            return;
        }
        let banded = band.as_ref().is_some_and(|b| std::ptr::eq(b, look));
        xs.sort_by(f64::total_cmp);
        let (mut next, mut inside) = (0, false);
        for &(from, to) in spans {
            bitmap.read_row_classes(row, from, &classes, &mut class[from..to]);
            let mut col = from;
            while col < to {
                // Crossings at or before this pixel's centre.
                while next < xs.len() && xs[next] <= col as f64 + 0.5 {
                    inside = !inside;
                    next += 1;
                }
                // The run of pixels up to the next crossing, all on one side of the
                // drawn outline: most runs agree with the mask everywhere, which a
                // vectorised count tells before any pixel is looked at alone.
                let end = match xs.get(next) {
                    Some(&x) => run_end(col, x, w).min(to),
                    None => to,
                };
                let run = &class[col..end];
                let side = u8::from(inside);
                let disagree = |c: u8| c & FOREGROUND != side;
                if run.iter().filter(|&&c| disagree(c)).count() > 0 {
                    // The drawn outline crosses this row's centre line at the run's
                    // two crossings: a pixel within the far limit of either along the
                    // row is near the outline without asking the grid.
                    let before = next.checked_sub(1).map(|i| xs[i]);
                    let after = xs.get(next).copied();
                    let reach = far_limit - CROSSING_MARGIN;
                    for (k, &c) in run.iter().enumerate().filter(|&(_, &c)| disagree(c)) {
                        if banded && look.on_edge(col + k, row) {
                            overflow.store(true, std::sync::atomic::Ordering::Relaxed);
                        }
                        let index = (row * w + col + k) as u32;
                        if !excused.contains(&index) {
                            let centre = Point::new((col + k) as f64 + 0.5, row as f64 + 0.5);
                            let on_row = before.is_some_and(|x| centre.x - x < reach)
                                || after.is_some_and(|x| x - centre.x < reach);
                            if !on_row && !grid().any_within(centre, far_limit) {
                                out.0.push(index);
                            } else if c & DECIDED != 0 {
                                out.1.push(index);
                            }
                        }
                    }
                }
                col = end;
            }
        }
    };
    // Every row's far and near disagreeing pixels within the tiles of `look`.
    let compare = |look: &Dirty| -> (Vec<u32>, Vec<u32>) {
        let mut crossings = row_crossings(&polylines, &boxes, &lines, look, h, parallel);
        if parallel {
            let rows: Vec<(Vec<u32>, Vec<u32>)> = crossings
                .par_iter_mut()
                .enumerate()
                .map_init(
                    || vec![0u8; w],
                    |class, (row, xs)| {
                        let mut out = (Vec::new(), Vec::new());
                        far_in_row(look, row, xs, class, &mut out);
                        out
                    },
                )
                .collect();
            let mut all = (Vec::new(), Vec::new());
            for (f, n) in rows {
                all.0.extend(f);
                all.1.extend(n);
            }
            all
        } else {
            let mut class = vec![0u8; w];
            let mut out = (Vec::new(), Vec::new());
            for (row, xs) in crossings.iter_mut().enumerate() {
                far_in_row(look, row, xs, &mut class, &mut out);
            }
            out
        }
    };
    let (mut far_pixels, mut near_pixels) = match (&dirty, &band) {
        (Some(d), _) => compare(d),
        (None, Some(b)) => {
            let found = compare(b);
            // A disagreement on the band's edge may go on outside it: look everywhere.
            if overflow.load(std::sync::atomic::Ordering::Relaxed) {
                compare(everywhere())
            } else {
                found
            }
        }
        (None, None) => compare(everywhere()),
    };
    // Outside the tiles looked at, the earlier findings stand.
    if let (Some(d), Some((findings, _))) = (&dirty, earlier) {
        let kept = |p: &&u32| !d.contains(**p as usize % w, **p as usize / w);
        far_pixels.extend(findings.far_pixels.iter().filter(kept));
        near_pixels.extend(findings.near_pixels.iter().filter(kept));
        far_pixels.sort_unstable();
        near_pixels.sort_unstable();
    }
    let far: HashSet<usize> = far_pixels.iter().map(|&p| p as usize).collect();
    let mut regions = Vec::new();
    let mut largest: (f64, Option<[u32; 4]>) = (0.0, None);
    // The grid that answers for all of `pixels`: the partial one when they lie in or
    // beside the tiles looked at again.
    let grid_for = |pixels: &[u32]| match &dirty {
        Some(d) if !pixels.iter().all(|&p| d.touches(p)) => full(),
        _ => grid(),
    };
    // Records a region of disagreement: the largest one's box, and the contours
    // responsible when it counts.
    let mut record = |mut pixels: Vec<u32>, counts: bool, same: Option<&Region>| {
        let area = pixels.len() as f64;
        if area > largest.0 {
            let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
            for &p in &pixels {
                let (c, r) = (p % w as u32, p / w as u32);
                x0 = x0.min(c);
                y0 = y0.min(r);
                x1 = x1.max(c);
                y1 = y1.max(r);
            }
            largest = (area, Some([x0, y0, x1, y1]));
        }
        if !counts {
            return;
        }
        pixels.sort_unstable();
        if let Some(old) = same.filter(|old| old.pixels == pixels) {
            regions.push(Region {
                pixels,
                near_contours: old.near_contours.clone(),
                near_segments: old.near_segments.clone(),
            });
            return;
        }
        let grid = grid_for(&pixels);
        let mut near: HashSet<(u32, u32)> = HashSet::new();
        for &p in &pixels {
            let centre = Point::new((p as usize % w) as f64 + 0.5, (p as usize / w) as f64 + 0.5);
            if let Some((_, (c, k))) = grid.nearest(centre, REGION_REACH + far_limit, None) {
                near.insert((c, segment_of[c as usize].at(k)));
            }
        }
        let mut near_segments: Vec<(usize, Option<usize>)> = near
            .into_iter()
            .map(|(c, k)| (c as usize, (k != u32::MAX).then_some(k as usize)))
            .collect();
        near_segments.sort_unstable();
        let mut near_contours: Vec<usize> = near_segments.iter().map(|n| n.0).collect();
        near_contours.dedup();
        regions.push(Region {
            pixels,
            near_contours,
            near_segments,
        });
    };
    // An earlier region whose pixels all lie away from the tiles looked at again is
    // found again unchanged (none of its pixels or their neighbours changed).
    let earlier_region = |pixels: &[usize]| -> Option<&Region> {
        let (d, (findings, _)) = (dirty.as_ref()?, earlier?);
        if pixels.iter().any(|&p| d.touches(p as u32)) {
            return None;
        }
        let first = *pixels.iter().min()? as u32;
        findings
            .regions
            .iter()
            .find(|r| r.pixels.first() == Some(&first))
    };
    for group in groups_8(&far, w, h) {
        let same = earlier_region(&group);
        let pixels: Vec<u32> = group.into_iter().map(|p| p as u32).collect();
        let counts = pixels.len() as f64 > limits.region;
        record(pixels, counts, same);
    }
    for pixels in dense_regions(&near_pixels, w, h, far_limit) {
        record(pixels, true, None);
    }
    Findings {
        max_deviation,
        bad_points,
        worst,
        regions,
        largest,
        far_pixels,
        near_pixels,
        boxes,
    }
}

/// How much closer (px) than the far limit a crossing of a pixel's row must lie for the
/// pixel to count as near the outline without a query of the edge grid: the crossing is
/// interpolated on its edge, so the edge lies within round-off of it, far below this.
const CROSSING_MARGIN: f64 = 1e-9;

/// The box `[x0, y0, x1, y1]` of a drawn polyline, if it has a vertex.
fn vertex_box(line: &[Vertex]) -> Option<[f64; 4]> {
    let first = line.first()?.point();
    Some(
        line.iter()
            .fold([first.x, first.y, first.x, first.y], |b, v| {
                let p = v.point();
                [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)]
            }),
    )
}

/// The tiles a first check compares (see [`Dirty`]): those within a margin of a crack of
/// the mask's `borders` or of an edge of the drawn `polylines`, and those along the
/// image's sides. Every region of disagreement between the drawn shape and the mask is
/// bounded by pixels next to a crack (where the mask changes) or to a drawn edge (where
/// the drawing does), or by the image's sides: within the margin, so in these tiles. A
/// region that also reaches outside them has a pixel on their edge, where the check
/// notices it and compares every tile instead. The margin also covers the far limit, so
/// that the near disagreement of a loose tolerance lies inside.
fn band_tiles(
    w: usize,
    h: usize,
    borders: &[Border],
    polylines: &[Vec<Vertex>],
    far_limit: f64,
    parallel: bool,
) -> Dirty {
    // Whole pixels: a corner or a vertex rounded down is within a pixel of the point.
    let margin = (BAND_MARGIN + far_limit).ceil() as i64 + 1;
    // The borders' corners and the drawn paths' vertices (no chord is longer than
    // `FLATTEN_MAX_CHORD`, so its points lie within half that of a vertex), marked in
    // parts on the thread pool and put together.
    let chord = FLATTEN_MAX_CHORD.ceil() as i64;
    let mark_borders = |marks: &mut dirty::Marks, part: &[Border]| {
        for border in part {
            let mut last = [usize::MAX; 4];
            for (x, y) in border.corners() {
                last = marks.mark_near(i64::from(x), i64::from(y), margin, last);
            }
        }
    };
    let mark_lines = |marks: &mut dirty::Marks, part: &[Vec<Vertex>]| {
        for line in part {
            let mut last = [usize::MAX; 4];
            for v in line {
                // Truncated (within a pixel, like rounding down; `floor` is a library
                // call on the baseline x86-64).
                let p = v.point();
                let (x, y) = (p.x as i64, p.y as i64);
                last = marks.mark_near(x, y, margin + chord, last);
            }
        }
    };
    let parts = if parallel { BAND_PARTS } else { 1 };
    let mark_part = |k: usize| {
        let mut marks = dirty::Marks::new(w, h);
        let share = |n: usize| k * n / parts..(k + 1) * n / parts;
        mark_borders(&mut marks, &borders[share(borders.len())]);
        mark_lines(&mut marks, &polylines[share(polylines.len())]);
        marks
    };
    let mut marks = if parallel {
        (0..parts)
            .into_par_iter()
            .map(mark_part)
            .reduce_with(|mut a, b| {
                a.add(&b);
                a
            })
            .unwrap_or_else(|| dirty::Marks::new(w, h))
    } else {
        mark_part(0)
    };
    marks.sides();
    marks.into_dirty()
}

/// Fewest pixels of an image whose first check compares only the tiles of
/// [`band_tiles`]: on a small image, reading every row costs less than marking them.
const BAND_PIXELS: usize = 1 << 20;

/// Parts of the outlines that [`band_tiles`] marks in parallel.
const BAND_PARTS: usize = 8;

/// Margin (px) of [`band_tiles`] beyond the far limit: a crack's midpoint is half a
/// pixel from the centres on either side, and a drawn edge between two pixel centres
/// is within a pixel of both.
const BAND_MARGIN: f64 = 2.0;

/// The box of an edge.
fn edge_box(e: &Edge) -> [f64; 4] {
    [
        e.a.x.min(e.b.x),
        e.a.y.min(e.b.y),
        e.a.x.max(e.b.x),
        e.a.y.max(e.b.y),
    ]
}

/// How far the repair has gone with one contour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Repair {
    /// The normal trace.
    #[default]
    None,
    /// Same data points, corners added where the drawn path left them.
    Corners,
    /// Same data points and corners, fitted again at the `k`-th tighter tolerance of
    /// [`tighter_tolerance`].
    Tighter(u8),
    /// Data points traced again from the thresholded pixels (bilevel regression).
    PixelSmoothed,
    /// The pixel-edge midpoints themselves, cut at the corners of their polygon.
    PixelRaw,
}

impl Repair {
    /// The next trace after this one for a trace at `tolerance`, `None` past the last.
    /// The tighter fits come also for a contour that only sits beside a wrong region:
    /// the fine teeth of an anti-aliased comb are right at 0.15 px from their grey-level
    /// data, and drawn a pixel too thick from the thresholded pixels.
    ///
    /// On a `bilevel` image the first trace is already the pixels' own (the bilevel
    /// regression), so the tighter fits are followed by the pixel polygon directly.
    pub(crate) fn next(self, tolerance: f64, bilevel: bool) -> Option<Repair> {
        let pixels = if bilevel {
            Repair::PixelRaw
        } else {
            Repair::PixelSmoothed
        };
        let tighter = |k: u8| {
            if tighter_tolerance(tolerance, k).is_some() {
                Repair::Tighter(k)
            } else {
                pixels
            }
        };
        match self {
            Repair::None | Repair::Corners => Some(tighter(1)),
            Repair::Tighter(k) => Some(tighter(k + 1)),
            Repair::PixelSmoothed => Some(Repair::PixelRaw),
            Repair::PixelRaw => None,
        }
    }
}

/// Tolerance (px) below which no repair refits: the pixel traces come next.
const TIGHTEST: f64 = 0.15;

/// The `k`-th tolerance (from 1) at which the repair refits a contour that failed at
/// `tolerance`, before it falls back to the pixels: half of it, a quarter, then
/// [`TIGHTEST`] if a quarter was still above it (so that a fit at `--tolerance 10` that
/// fails gets a tight fit, not a pixel polygon). `None` past the last.
pub(crate) fn tighter_tolerance(tolerance: f64, k: u8) -> Option<f64> {
    let mut steps: Vec<f64> = [tolerance / 2.0, tolerance / 4.0]
        .into_iter()
        .filter(|&t| t >= TIGHTEST / 2.0)
        .collect();
    if tolerance / 4.0 > TIGHTEST {
        steps.push(TIGHTEST);
    }
    steps.get(usize::from(k).checked_sub(1)?).copied()
}

/// Indices of the polygon vertices that Douglas–Peucker keeps at `tolerance` px on a
/// closed polyline, always at least two (the first point and the farthest from it).
pub(crate) fn polygon_corners(points: &[Point], tolerance: f64) -> Vec<usize> {
    let n = points.len();
    if n < 3 {
        return (0..n).collect();
    }
    let far = (1..n)
        .max_by(|&a, &b| {
            points[a]
                .distance(points[0])
                .total_cmp(&points[b].distance(points[0]))
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        if b - a < 2 {
            continue;
        }
        let (pa, pb) = (points[a], points[b % n]);
        let mut worst = (0.0, a);
        for (k, &p) in points.iter().enumerate().take(b).skip(a + 1) {
            let d = segment_distance(p, pa, pb);
            if d > worst.0 {
                worst = (d, k);
            }
        }
        if worst.0 > tolerance {
            keep[worst.1] = true;
            stack.push((a, worst.1));
            stack.push((worst.1, b));
        }
    }
    (0..n).filter(|&k| keep[k]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The rows' crossings found band by band on three threads are the lists found in
    /// one pass, bit for bit and in the same order, whether every row is looked at or
    /// only some tiles' rows, and with paths that span several bands.
    #[test]
    fn banded_row_crossings_equal_one_pass() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let (w, h) = (700usize, 1000usize);
        let polylines: Vec<Vec<Vertex>> = (0..400)
            .map(|_| {
                let (cx, cy) = (
                    rng.random_range(0.0..w as f64),
                    rng.random_range(0.0..h as f64),
                );
                let n = rng.random_range(3..60);
                let tall = rng.random_range(1.0..4.0);
                (0..n)
                    .map(|k| {
                        let a = k as f64 / n as f64 * std::f64::consts::TAU;
                        let r = rng.random_range(3.0..40.0);
                        Vertex::new(Point::new(cx + r * a.cos(), cy + tall * r * a.sin()))
                    })
                    .collect()
            })
            .collect();
        let boxes: Vec<Option<[f64; 4]>> = polylines.iter().map(|l| vertex_box(l)).collect();
        let lines: Vec<usize> = (0..polylines.len()).collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let tiles = Dirty::new(
            w,
            h,
            &[[100.0, 130.0, 300.0, 420.0], [0.0, 700.0, 700.0, 760.0]],
            2.0,
        );
        for look in [Dirty::all(w, h), tiles] {
            let one = row_crossings(&polylines, &boxes, &lines, &look, h, false);
            let banded = pool.install(|| row_crossings(&polylines, &boxes, &lines, &look, h, true));
            assert!(one.iter().map(Vec::len).sum::<usize>() > 1000);
            for (r, (a, b)) in one.iter().zip(&banded).enumerate() {
                // Made at their size: no list grew (or shrank) while it was filled.
                assert_eq!((a.capacity(), b.capacity()), (a.len(), b.len()), "row {r}");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(a), bits(b), "row {r}");
            }
        }
    }

    /// A 2 × 2-cell checkerboard checked against the outline of diagonal stripes (what
    /// it was once traced as: every pixel within 1 px of an outline, a quarter of them
    /// on the wrong side) fails as dense disagreement; the stripes checked against
    /// their own image hold.
    #[test]
    fn stripes_drawn_for_a_checkerboard_fail_as_dense_disagreement() {
        let n = 64u32;
        let image = |ink: &dyn Fn(u32, u32) -> bool| {
            let cov = (0..n * n)
                .map(|i| f32::from(u8::from(ink(i % n, i / n))))
                .collect();
            Bitmap::from_coverage(n, n, cov, None).unwrap()
        };
        let board = image(&|x, y| (x / 2 + y / 2) % 2 == 0);
        let stripes = image(&|x, y| (x + 4 * n - y) % 4 < 2);
        let config = crate::Config {
            check: false,
            timings: false,
            ..crate::Config::default()
        };
        let traced = crate::trace_bitmap(&stripes, &config).unwrap();
        let limits = Limits {
            deviation: 0.325,
            tolerance: config.tolerance,
            widening: 0.0,
            region: 2.0,
            bound: config.lsq_options().export_bound,
        };
        let none = HashSet::new();
        let own = check(&stripes, &traced.contours, &[], limits, &none, None);
        assert!(own.regions.is_empty(), "{}", own.largest.0);
        let wrong = check(&board, &traced.contours, &[], limits, &none, None);
        assert!(!wrong.regions.is_empty());
        // Most of the board's wrong pixels, none of them far from an outline.
        assert!(
            wrong.largest.0 > 0.2 * f64::from(n * n),
            "{}",
            wrong.largest.0
        );
    }

    /// Everything a check finds, for comparing two checks.
    fn summary(f: &Findings) -> impl PartialEq + std::fmt::Debug {
        let regions: Vec<_> = f
            .regions
            .iter()
            .map(|r| {
                (
                    r.pixels.clone(),
                    r.near_contours.clone(),
                    r.near_segments.clone(),
                )
            })
            .collect();
        (
            f.max_deviation,
            f.bad_points.clone(),
            f.worst.clone(),
            regions,
            f.largest,
            f.far_pixels.clone(),
            f.near_pixels.clone(),
        )
    }

    /// The contours of `bitmap` traced with the defaults but without the check, and the
    /// default limits of the check.
    fn traced_unchecked(bitmap: &Bitmap) -> (Vec<FittedContour>, Limits) {
        let config = crate::Config {
            check: false,
            timings: false,
            ..crate::Config::default()
        };
        let contours = crate::trace_bitmap(bitmap, &config).unwrap().contours;
        let limits = Limits {
            deviation: 0.325,
            tolerance: config.tolerance,
            widening: 0.0,
            region: 2.0,
            bound: config.lsq_options().export_bound,
        };
        (contours, limits)
    }

    /// Three anti-aliased disks (coverage from 4 × 4 samples per pixel) on a 120 × 64
    /// image, at x = 18, 60 and 100.
    fn three_disks() -> Bitmap {
        let disks = [(18.0, 32.0, 11.0), (60.0, 30.0, 13.0), (100.0, 34.0, 9.5)];
        supersampled(120, 64, |x, y| {
            disks.iter().any(|d| (x - d.0).hypot(y - d.1) <= d.2)
        })
    }

    /// The anti-aliased bitmap of the shape where `inside(x, y)`: coverage from 4 × 4
    /// samples per pixel.
    fn supersampled(w: u32, h: u32, inside: impl Fn(f64, f64) -> bool) -> Bitmap {
        let cov = (0..w * h)
            .map(|i| {
                let (x, y) = (f64::from(i % w), f64::from(i / w));
                let hits = (0..16)
                    .filter(|k| {
                        inside(
                            x + (f64::from(k % 4) + 0.5) / 4.0,
                            y + (f64::from(k / 4) + 0.5) / 4.0,
                        )
                    })
                    .count();
                hits as f32 / 16.0
            })
            .collect();
        Bitmap::from_coverage(w, h, cov, None).unwrap()
    }

    /// A pixel that disagrees with the drawn outline is far exactly when no drawn edge
    /// lies within the far limit of its centre, measured edge by edge: whether the
    /// crossings of its own row tell (most pixels) or the edge grid does. The disks are
    /// drawn 1.4 px to the right and 0.6 px down, so that beside their left and right
    /// sides, where the edges run almost along the columns, pixels lie 0–1.4 px from the
    /// nearest crossing of their row.
    #[test]
    fn far_pixels_are_those_no_drawn_edge_comes_near() {
        let bitmap = three_disks();
        let (mut moved, limits) = traced_unchecked(&bitmap);
        for c in &mut moved {
            for s in &mut c.segments {
                for p in &mut s.curve.points {
                    *p += Point::new(1.4, 0.6);
                }
            }
        }
        let found = check(&bitmap, &moved, &[], limits, &HashSet::new(), None);
        let (polylines, _): (Vec<Vec<Vertex>>, Vec<SegmentRuns>) =
            flatten(&moved, &[], limits.bound).into_iter().unzip();
        let nearest = |p: u32| {
            let w = bitmap.width();
            let centre = Point::new(f64::from(p % w) + 0.5, f64::from(p / w) + 0.5);
            polylines
                .iter()
                .map(|line| distance_to_closed_polyline(centre, line))
                .fold(f64::INFINITY, f64::min)
        };
        let far = limits.far();
        assert!(found.far_pixels.len() > 20, "{}", found.far_pixels.len());
        assert!(found.near_pixels.len() > 20, "{}", found.near_pixels.len());
        for &p in &found.far_pixels {
            assert!(nearest(p) > far, "far pixel {p} at {}", nearest(p));
        }
        for &p in &found.near_pixels {
            assert!(nearest(p) <= far, "near pixel {p} at {}", nearest(p));
        }
        // Far pixels as near as 1.0-1.4 px, which a crossing reach longer than the far
        // limit would have taken for near.
        let close = found
            .far_pixels
            .iter()
            .filter(|&&p| nearest(p) < far + 0.4)
            .count();
        assert!(close > 5, "{close}");
    }

    /// A check after a repair, which looks again only around the changed contours, finds
    /// exactly what a full check of the same contours finds: after a contour is dropped
    /// (a lost shape: a region), and then after another one is moved 3 px (its points
    /// stray: bad points and regions on both sides), with the first region, away from the
    /// second change, carried over.
    #[test]
    fn a_check_after_a_repair_finds_what_a_full_check_finds() {
        let bitmap = three_disks();
        let (base, limits) = traced_unchecked(&bitmap);
        assert_eq!(base.len(), 3);
        let none = HashSet::new();
        let first = check(&bitmap, &base, &[], limits, &none, None);
        assert!(first.held());
        let index_at = |x: f64| {
            (0..3)
                .find(|&i| (base[i].points[0].x - x).abs() < 14.0)
                .unwrap()
        };
        let (left, right) = (index_at(18.0), index_at(100.0));

        let mut dropped = base.clone();
        dropped[right].segments.clear();
        let unchanged: Vec<bool> = (0..3).map(|i| i != right).collect();
        let again = check_again(
            &bitmap,
            &dropped,
            &[],
            limits,
            &none,
            Some((&first, &unchanged)),
        );
        let full = check(&bitmap, &dropped, &[], limits, &none, None);
        assert!(!full.regions.is_empty());
        assert_eq!(summary(&again), summary(&full));

        let mut moved = dropped.clone();
        for s in &mut moved[left].segments {
            for p in &mut s.curve.points {
                p.x += 3.0;
            }
        }
        let unchanged: Vec<bool> = (0..3).map(|i| i != left).collect();
        let again = check_again(
            &bitmap,
            &moved,
            &[],
            limits,
            &none,
            Some((&again, &unchanged)),
        );
        let full = check(&bitmap, &moved, &[], limits, &none, None);
        assert!(!full.bad_points[left].is_empty());
        assert!(full.regions.len() >= 2, "{}", full.regions.len());
        assert_eq!(summary(&again), summary(&full));
    }

    /// The bounds that spare the check most distance queries are bounds: every data
    /// point of a traced shape is no farther from its drawn path than its bound, and the
    /// check finds the same worst deviations and bad points as measuring every point,
    /// also where a contour was moved off its data, on contours with points of both
    /// polynomial and rational segments.
    #[test]
    fn deviation_bounds_hold_and_leave_the_findings_unchanged() {
        let (w, h) = (96u32, 64u32);
        let cov = (0..w * h)
            .map(|i| {
                let (x, y) = (f64::from(i % w) + 0.5, f64::from(i / w) + 0.5);
                // A disk and a rounded square: curved and straight runs, with corners.
                let disk = 12.5 - (x - 24.0).hypot(y - 32.0);
                let square = 11.0 - (x - 68.0).abs().max((y - 30.0).abs());
                (disk.max(square) + 0.5).clamp(0.0, 1.0) as f32
            })
            .collect();
        let bitmap = Bitmap::from_coverage(w, h, cov, None).unwrap();
        let (mut contours, limits) = traced_unchecked(&bitmap);
        assert_eq!(contours.len(), 2);
        // The shapes fit with polynomial cubics alone: one segment of each contour is
        // made rational (a weight nudged, its drawn cubics kept), so that its points have
        // no bound and are measured.
        for c in &mut contours {
            c.segments[0].curve.weights[1] = 1.0 + 1e-9;
        }
        for round in 0..2 {
            if round == 1 {
                // One segment of each contour pushed off its data by 1 px.
                for c in &mut contours {
                    for p in &mut c.segments[1].curve.points {
                        p.x += 1.0;
                        p.y += 1.0;
                    }
                }
            }
            let lines = flatten(&contours, &[], limits.bound);
            let findings = check(&bitmap, &contours, &[], limits, &HashSet::new(), None);
            let (mut polynomial, mut unbounded) = (0, 0);
            for (i, c) in contours.iter().enumerate() {
                let line = &lines[i].0;
                let exact: Vec<f64> = c
                    .points
                    .iter()
                    .map(|&p| distance_to_closed_polyline(p, line))
                    .collect();
                let bounds = deviation_bounds(c);
                for (k, (&d, &b)) in exact.iter().zip(&bounds).enumerate() {
                    assert!(d <= b, "round {round}, contour {i}, point {k}: {d} > {b}");
                    polynomial += usize::from(b.is_finite());
                    unbounded += usize::from(!b.is_finite());
                }
                let (worst, bad) = worst_and_bad(&exact, limits.deviation_of(c));
                assert_eq!(findings.worst[i], worst, "round {round}, contour {i}");
                assert_eq!(findings.bad_points[i], bad, "round {round}, contour {i}");
                assert_eq!(bad.is_empty(), round == 0, "round {round}, contour {i}");
            }
            // Both kinds of point, so that the floor from the unbounded ones is tested.
            assert!(
                polynomial > 0 && unbounded > 0,
                "{polynomial} and {unbounded}"
            );
        }
    }

    /// The flattening of random cubics (straight, gently and sharply bent, up to 400 px
    /// long) stays within `FLATTEN_ERROR` of the curve both ways, with no chord longer than
    /// `FLATTEN_MAX_CHORD`, measured against 2000 samples of each.
    #[test]
    fn flattening_stays_within_its_error_and_chord_length() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for k in 0..300 {
            let span = [2.0, 30.0, 400.0][k % 3];
            let mut pt = || {
                Point::new(
                    rng.random_range(0.0..span),
                    rng.random_range(0.0..span * 0.3),
                )
            };
            let cubic = CubicBez::new(pt(), pt(), pt(), pt());
            let n = flatten_steps(&cubic);
            let line: Vec<Point> = (0..=n).map(|j| cubic.eval(j as f64 / n as f64)).collect();
            for pair in line.windows(2) {
                assert!(pair[0].distance(pair[1]) <= FLATTEN_MAX_CHORD + 1e-9, "{k}");
            }
            let dense: Vec<Point> = (0..=2000).map(|j| cubic.eval(j as f64 / 2000.0)).collect();
            for &q in &dense {
                let d = line
                    .windows(2)
                    .map(|s| segment_distance(q, s[0], s[1]))
                    .fold(f64::INFINITY, f64::min);
                assert!(d <= FLATTEN_ERROR, "{k}: curve {d}");
            }
            for &q in &line {
                let d = dense
                    .windows(2)
                    .map(|s| segment_distance(q, s[0], s[1]))
                    .fold(f64::INFINITY, f64::min);
                assert!(d <= FLATTEN_ERROR + 1e-6, "{k}: polyline {d}");
            }
        }
    }

    /// The runs give every point its segment, merged curves (`u32::MAX`) included.
    #[test]
    fn segment_runs_give_each_point_its_segment() {
        let segments = [0, 0, 1, 1, 1, 2, u32::MAX, u32::MAX, 4];
        let runs = SegmentRuns::new(&segments);
        assert_eq!(runs.0.len(), 5);
        for (k, &s) in segments.iter().enumerate() {
            assert_eq!(runs.at(k as u32), s, "point {k}");
        }
    }

    /// A first check given the borders, which compares the pixels only in the tiles near
    /// a border or a drawn edge, finds exactly what a check of every row finds: on a
    /// faithful trace, with a shape lost (its outline not drawn), with a shape invented
    /// far from any ink, and with a large square lost, whose disagreement reaches far
    /// beyond those tiles (the check must then look everywhere to measure it whole).
    #[test]
    fn a_first_check_in_the_band_finds_what_a_full_check_finds() {
        // Large enough for the band (`BAND_PIXELS`).
        let (w, h) = (1200u32, 900u32);
        assert!((w * h) as usize >= BAND_PIXELS);
        let disks = [(40.0, 40.0, 11.0), (80.0, 44.0, 13.0)];
        let bitmap = supersampled(w, h, |x, y| {
            let square = (200.3..300.3).contains(&x) && (150.6..250.6).contains(&y);
            square || disks.iter().any(|d| (x - d.0).hypot(y - d.1) <= d.2)
        });
        let (base, limits) = traced_unchecked(&bitmap);
        assert_eq!(base.len(), 3);
        let options = crate::contour::ContourOptions {
            min_area: 2.0,
            edge_spread: false,
        };
        let borders = crate::contour::extract_borders(&bitmap, &options)
            .unwrap()
            .borders;
        let none = HashSet::new();
        let both = |contours: &[FittedContour]| {
            let full = check(&bitmap, contours, &[], limits, &none, None);
            let band = check(&bitmap, contours, &[], limits, &none, Some(&borders));
            assert_eq!(summary(&band), summary(&full));
            full
        };
        assert!(both(&base).held());
        // The contour whose points start nearest to x (from the left).
        let index_at = |x: f64| {
            let left = |i: usize| base[i].points.iter().map(|p| p.x).fold(f64::MAX, f64::min);
            (0..3)
                .min_by(|&a, &b| (left(a) - x).abs().total_cmp(&(left(b) - x).abs()))
                .unwrap()
        };
        // A disk lost.
        let mut lost = base.clone();
        lost[index_at(67.0)].segments.clear();
        let found = both(&lost);
        assert!(!found.regions.is_empty());
        // A disk invented 150 px below the first, on blank paper.
        let mut invented = base.clone();
        let mut copy = base[index_at(29.0)].clone();
        for s in &mut copy.segments {
            for p in &mut s.curve.points {
                p.y += 150.0;
            }
        }
        invented.push(copy);
        let found = both(&invented);
        assert!(found.regions.iter().any(|r| r.pixels.len() > 300));
        // The square lost: 10 000 px, most of them far from every crack.
        let mut square = base.clone();
        square[index_at(200.0)].segments.clear();
        let found = both(&square);
        assert!(
            found.regions.iter().any(|r| r.pixels.len() > 9_000),
            "{:?}",
            found.largest
        );
    }
}
