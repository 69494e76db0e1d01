//! Repair of what the fidelity check ([`crate::fidelity`]) finds: each contour that leaves
//! its data or sits beside a lost or invented region goes one step further along
//! [`Repair`], and borders whose shape or hole was lost altogether are traced again from
//! the pixels, until the check holds or nothing is left to try.
//!
//! The steps, per contour:
//! 1. *Corners*: the same data points, with a corner (G0 joint) at every point where the
//!    drawn path left them, so that a short run that could not be split, or a corner the
//!    curvature analysis missed, is fitted on both sides of it.
//! 2. *Tighter fits*: the same data points and corners, fitted again at half the
//!    tolerance, a quarter, then 0.15 px (`fidelity::tighter_tolerance`): a loose
//!    `--tolerance` that fails is tightened before anything falls back to the pixels.
//! 3. *Pixel trace*: the data points traced again from the thresholded pixels alone (the
//!    bilevel regression), when grey-level refinement moved them off the pixels.
//! 4. *Pixel polygon*: the pixel-edge midpoints themselves, cut at the vertices of their
//!    Douglas–Peucker polygon and held at every pinch (a pixel corner where two
//!    foreground pixels touch diagonally, a point of its own): exact to the mask, at the
//!    cost of more segments.

use crate::breaks::{find_breaks, Break, BreakOptions, BreakReason, SegmentedContour};
use crate::contour::{Extraction, PixelTrace};
use crate::error::Result;
use crate::fidelity::{check, polygon_corners, tighter_tolerance, Fidelity, Limits, Repair};
use crate::fit::{FittedContour, JointKind};
use crate::merge::outline::MergedCurve;
use crate::raster::Bitmap;
use std::collections::{BTreeSet, HashSet};

/// Rounds of check and repair before giving up (enough for every step of [`Repair`]
/// with corners added before each).
const MAX_ROUNDS: usize = 12;

/// Tolerance (px) of the pixel polygon's corners: the midpoints of a digital straight line
/// lie within half a pixel of it.
const POLYGON_TOLERANCE: f64 = 0.45;

/// What the check and its repairs work from: the input, the limits, and how the trace
/// segments and fits a contour.
#[derive(Clone, Copy)]
pub(crate) struct RepairInput<'a> {
    /// The thresholded input the outline must match.
    pub(crate) bitmap: &'a Bitmap,
    /// The contours the trace extracted from it.
    pub(crate) extraction: &'a Extraction,
    /// How far the drawn outline may stray, and the smallest region that counts.
    pub(crate) limits: Limits,
    /// The trace's `min_area`: shapes below it were dropped on purpose.
    pub(crate) min_area: f64,
    /// How the trace finds break points.
    pub(crate) break_options: &'a BreakOptions,
    /// The trace's `--tolerance` (px).
    pub(crate) tolerance: f64,
    /// Fits one segmented contour as the trace does (its second argument is the
    /// contour's index, its third the tolerance of a repair, which the trace fits by
    /// `lsq` alone; `None` for the trace's own fit).
    pub(crate) fit: &'a dyn Fn(SegmentedContour, usize, Option<f64>) -> Result<FittedContour>,
}

/// Checks `contours` (drawn with their `merged` curves, one list per contour) against
/// `input` and repairs them in place; returns the final verdict. A repaired or restored
/// contour is drawn by its own segments, without merged curves.
pub(crate) fn check_and_repair(
    input: RepairInput<'_>,
    contours: &mut Vec<FittedContour>,
    merged: &mut Vec<Vec<MergedCurve>>,
) -> Result<Fidelity> {
    let RepairInput {
        bitmap,
        extraction,
        limits,
        min_area,
        break_options,
        tolerance,
        fit,
    } = input;
    let mut level = vec![Repair::None; contours.len()];
    let mut corners_tried = vec![false; contours.len()];
    let mut border_of = extraction.border_of.clone();
    let mut repaired: HashSet<usize> = HashSet::new();
    let mut restored = 0usize;
    let excused = extraction.dropped_pixels(min_area, bitmap.width());
    // One list of merged curves per contour: a contour refitted here is drawn by its own
    // segments.
    merged.resize_with(contours.len(), Vec::new);
    let mut findings = check(bitmap, contours, merged, limits, &excused);
    for _ in 0..MAX_ROUNDS {
        if findings.held() {
            break;
        }
        let mut targets: BTreeSet<usize> = BTreeSet::new();
        for (i, bad) in findings.bad_points.iter().enumerate() {
            if !bad.is_empty() {
                targets.insert(i);
            }
        }
        for region in &findings.regions {
            targets.extend(region.near_contours.iter().copied());
        }
        let mut progressed = false;
        for i in targets {
            let bad = &findings.bad_points[i];
            // Where the path left its data, first add corners there (repeatable on the
            // last step); otherwise trace the contour again, closer to the pixels.
            let step = if !bad.is_empty() && (!corners_tried[i] || level[i] == Repair::PixelRaw) {
                Repair::Corners
            } else {
                match level[i].next(tolerance) {
                    Some(next) => next,
                    None => continue,
                }
            };
            let mut fit_tolerance = tolerance;
            let seg = match step {
                Repair::None => continue,
                Repair::Corners => with_corners(&contours[i], bad),
                Repair::Tighter(k) => {
                    fit_tolerance = tighter_tolerance(tolerance, k).unwrap_or(tolerance);
                    corners_kept(&contours[i])
                }
                Repair::PixelSmoothed | Repair::PixelRaw => {
                    let how = if step == Repair::PixelRaw {
                        PixelTrace::Raw
                    } else {
                        PixelTrace::Smoothed
                    };
                    let Some(c) = extraction.pixel_contour(border_of[i], how, contours[i].parent)
                    else {
                        continue;
                    };
                    if step == Repair::PixelRaw {
                        polygon_segmented(c.points, c.is_hole, c.parent)
                    } else {
                        find_breaks(&c, break_options)
                    }
                }
            };
            if step == Repair::Corners {
                corners_tried[i] = true;
            } else {
                level[i] = step;
                corners_tried[i] = false;
            }
            contours[i] = fit(seg, i, Some(fit_tolerance))?;
            merged[i].clear();
            repaired.insert(i);
            progressed = true;
        }
        // Shapes and holes lost altogether: borders that touch a region and have no
        // contour.
        let mut lost: BTreeSet<usize> = BTreeSet::new();
        let kept: HashSet<usize> = border_of.iter().copied().collect();
        for region in &findings.regions {
            let pixels: HashSet<u32> = region.pixels.iter().copied().collect();
            for (b, border) in extraction.borders.iter().enumerate() {
                if !kept.contains(&b)
                    && border.pixel_area() >= min_area
                    && border.touches(&pixels, bitmap.width())
                {
                    lost.insert(b);
                }
            }
        }
        for b in lost {
            // Restore the enclosing borders first, so the parent index exists.
            let mut chain = vec![b];
            while let Some(p) = extraction.borders[*chain.last().unwrap_or(&b)].parent {
                if border_of.contains(&p) || chain.contains(&p) {
                    break;
                }
                chain.push(p);
            }
            for &b in chain.iter().rev() {
                if border_of.contains(&b) {
                    continue;
                }
                let parent = extraction.borders[b]
                    .parent
                    .and_then(|p| border_of.iter().position(|&x| x == p));
                let Some(c) = extraction.pixel_contour(b, PixelTrace::Smoothed, parent) else {
                    continue;
                };
                let index = contours.len();
                contours.push(fit(find_breaks(&c, break_options), index, Some(tolerance))?);
                merged.push(Vec::new());
                border_of.push(b);
                level.push(Repair::PixelSmoothed);
                corners_tried.push(false);
                restored += 1;
                progressed = true;
            }
        }
        if !progressed {
            break;
        }
        findings = check(bitmap, contours, merged, limits, &excused);
    }
    Ok(Fidelity {
        held: findings.held(),
        max_deviation: findings.max_deviation,
        deviation_limit: limits.deviation,
        largest_region: findings.largest.0,
        region_limit: limits.region,
        region_box: findings.largest.1,
        repaired_contours: repaired.len(),
        restored_contours: restored,
        segments_over_tolerance: 0,
        worst_segment_distance: 0.0,
    })
}

/// The contour's own points and joints, with a corner added at each of `bad`.
fn with_corners(contour: &FittedContour, bad: &[usize]) -> SegmentedContour {
    let mut breaks: Vec<Break> = contour
        .joints
        .iter()
        .map(|j| Break {
            index: j.index,
            kind: j.kind,
            reason: match j.kind {
                JointKind::Corner => BreakReason::Corner,
                JointKind::Smooth => BreakReason::Split,
            },
        })
        .collect();
    for &k in bad {
        match breaks.iter_mut().find(|b| b.index == k) {
            Some(b) => {
                b.kind = JointKind::Corner;
                b.reason = BreakReason::Repair;
            }
            None => breaks.push(Break {
                index: k,
                kind: JointKind::Corner,
                reason: BreakReason::Repair,
            }),
        }
    }
    breaks.sort_by_key(|b| b.index);
    SegmentedContour {
        points: contour.points.clone(),
        is_hole: contour.is_hole,
        parent: contour.parent,
        breaks,
    }
}

/// The contour's own points with its corners (given and added by the repair), for a
/// fit that places its smooth splits anew.
fn corners_kept(contour: &FittedContour) -> SegmentedContour {
    let mut seg = with_corners(contour, &[]);
    seg.breaks.retain(|b| b.kind == JointKind::Corner);
    seg
}

/// Indices of the pinches among pixel-edge midpoints (see `contour::PixelTrace::Raw`):
/// the points on a pixel corner (both coordinates whole; a midpoint has one half) where
/// the outline turns sharply.
fn pinches(points: &[crate::geom::Point]) -> Vec<usize> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    (0..n)
        .filter(|&k| {
            let p = points[k];
            if p.x.fract() != 0.0 || p.y.fract() != 0.0 {
                return false;
            }
            let (a, b) = (p - points[(k + n - 1) % n], points[(k + 1) % n] - p);
            // A turn of more than 45°.
            a.dot(b) < std::f64::consts::FRAC_1_SQRT_2 * a.length() * b.length()
        })
        .collect()
}

/// Pixel-edge midpoints cut into straight runs at the corners of their polygon.
fn polygon_segmented(
    points: Vec<crate::geom::Point>,
    is_hole: bool,
    parent: Option<usize>,
) -> SegmentedContour {
    let mut corners = polygon_corners(&points, POLYGON_TOLERANCE);
    corners.extend(pinches(&points));
    corners.sort_unstable();
    corners.dedup();
    let breaks = corners
        .into_iter()
        .map(|index| Break {
            index,
            kind: JointKind::Corner,
            reason: BreakReason::Repair,
        })
        .collect();
    SegmentedContour {
        points,
        is_hole,
        parent,
        breaks,
    }
}
