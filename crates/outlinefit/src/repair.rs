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
//!
//! The work is bounded and goes where the trouble is:
//! - The corners step refits only the runs (corner to corner) that its new corners cut;
//!   a tighter fit of a contour of [`LOCAL_POINTS`] or more only the runs beside what went
//!   wrong. The other runs keep their segments (`fit::lsq::refit_runs`).
//! - At most [`LADDER_CONTOURS`] contours take the steps between the corners and the
//!   pixel polygon, and those steps refit at most [`LADDER_WORK`] times the data points
//!   the trace fitted. An ordinary image never meets either bound; on noise or a speck
//!   field, where thousands of contours fail at once, the rest go straight to the pixel
//!   polygon, which is exact to the mask.
//! - On a bilevel image the first trace already follows the pixels (the bilevel
//!   regression), so the pixel trace of step 3 is skipped.
//! - The check after a round measures again only the data points of the contours it
//!   changed, and compares the pixels only around them (`fidelity::check_again`).
//! - A round's refits run in parallel: each contour's step is decided first, in order,
//!   against the work budget as it stood when the round began, and the refitted contours
//!   are put back in order, so the result does not depend on the number of threads.

use crate::breaks::{find_breaks, Break, BreakOptions, BreakReason, SegmentedContour};
use crate::contour::{Extraction, PixelTrace};
use crate::error::Result;
use crate::fidelity::{
    check, check_again, polygon_corners, tighter_tolerance, Fidelity, Limits, Repair,
};
use crate::fit::lsq::{fit_contour, refit_runs, LsqOptions};
use crate::fit::{FittedContour, JointKind};
use crate::merge::outline::MergedCurve;
use crate::progress::{Progress, Stage, CHECK_ROUNDS};
use crate::raster::Bitmap;
use std::collections::{BTreeSet, HashMap, HashSet};

/// Rounds of check and repair before giving up (enough for every step of [`Repair`]
/// with corners added before each).
const MAX_ROUNDS: usize = CHECK_ROUNDS as usize - 1;

/// Data points the steps before the pixel polygon may refit, in all, as a multiple of the
/// points the trace fitted (see the module's documentation).
const LADDER_WORK: f64 = 3.0;

/// Contours that may take the steps between the corners and the pixel polygon: an
/// ordinary image has a few dozen to repair at most (a 600 dpi page of text: none of
/// 2 932), noise or a speck field thousands, whose pixel-scale detail only the pixel
/// polygon follows.
const LADDER_CONTOURS: usize = 256;

/// Data points of a contour from which a tighter fit refits only the runs (corner to
/// corner) where something went wrong; a smaller contour is refitted whole, which also
/// tightens what was nearly wrong (an anti-aliased comb's teeth come out closer to the
/// true outline than when each is refitted alone).
const LOCAL_POINTS: usize = 50_000;

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
    /// Record wall times in the refitted segments.
    pub(crate) timings: bool,
    /// Told of each round of the check.
    pub(crate) progress: &'a dyn Progress,
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
        timings,
        progress,
    } = input;
    let mut level = vec![Repair::None; contours.len()];
    // Each contour's tolerance before repair (widened on a blurred edge), from which its
    // tighter fits are derived.
    let mut base: Vec<f64> = contours.iter().map(|c| c.tolerance).collect();
    let mut corners_tried = vec![false; contours.len()];
    let mut border_of = extraction.border_of.clone();
    let mut repaired: HashSet<usize> = HashSet::new();
    let mut restored = 0usize;
    let excused = extraction.dropped_pixels(min_area, bitmap.width());
    let traced_points: usize = contours.iter().map(|c| c.points.len()).sum();
    let mut ladder_left = LADDER_WORK * traced_points as f64;
    let mut slots_left = LADDER_CONTOURS;
    // One list of merged curves per contour: a contour refitted here is drawn by its own
    // segments.
    merged.resize_with(contours.len(), Vec::new);
    // The round under way is counted as it starts.
    progress.stage(Stage::Checking, CHECK_ROUNDS);
    progress.advance(1);
    let mut findings = check(
        bitmap,
        contours,
        merged,
        limits,
        &excused,
        Some(&extraction.borders),
    );
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
        // Per target contour, the data points where something went wrong: its bad
        // points and the starts of the segments nearest to a region (`None`: all of it).
        let mut trouble: HashMap<usize, Option<Vec<usize>>> = HashMap::new();
        for region in &findings.regions {
            for &(i, segment) in &region.near_segments {
                let entry = trouble.entry(i).or_insert_with(|| Some(Vec::new()));
                match (
                    segment.and_then(|k| contours[i].segments.get(k)),
                    entry.as_mut(),
                ) {
                    (Some(s), Some(list)) => list.push(s.start),
                    _ => *entry = None,
                }
            }
        }
        let mut progressed = false;
        // Contours refitted or added in this round.
        let mut changed: HashSet<usize> = HashSet::new();
        // The round in three passes: each target's step is decided in order (the work
        // budget as it stood when the round began), the refits run in parallel (each reads
        // only its own contour), and their results are applied in order: the same on any
        // number of threads.
        let spent_at_start = ladder_left <= 0.0;
        let mut jobs: Vec<Job> = Vec::new();
        for i in targets {
            let bad = &findings.bad_points[i];
            // Where the path left its data, first add corners there (repeatable on the
            // last step); otherwise trace the contour again, closer to the pixels.
            // Once the ladder's work is spent, what still fails goes to the last step.
            let spent = spent_at_start || (level[i] == Repair::None && slots_left == 0);
            let step = if !bad.is_empty()
                && ((!corners_tried[i] && !spent) || level[i] == Repair::PixelRaw)
            {
                Repair::Corners
            } else {
                match level[i].next(base[i], bitmap.is_bilevel()) {
                    Some(_) if spent => Repair::PixelRaw,
                    Some(next) => next,
                    None => continue,
                }
            };
            // The runs between corners where something went wrong: a bad point belongs
            // to the runs on both sides of it.
            let n = contours[i].points.len();
            let mut at: Option<Vec<usize>> = trouble.get(&i).cloned().unwrap_or_default();
            if let Some(list) = at.as_mut() {
                list.extend(bad.iter().flat_map(|&k| [k, (k + n - 1) % n]));
                list.sort_unstable();
            }
            let pixels = match step {
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
                    Some(if step == Repair::PixelRaw {
                        polygon_segmented(c.points, c.is_hole, c.parent)
                    } else {
                        find_breaks(&c, break_options, Some(bitmap))
                    })
                }
                _ => None,
            };
            if level[i] == Repair::None && step != Repair::Corners && step != Repair::PixelRaw {
                slots_left = slots_left.saturating_sub(1);
            }
            jobs.push(Job {
                index: i,
                step,
                at,
                pixels,
            });
        }
        let run = |job: &Job| -> (FittedContour, f64) {
            let i = job.index;
            // True when the run from corner a to corner b is to be fitted tighter: every
            // run of a contour below LOCAL_POINTS, otherwise a run with a point of
            // trouble in [a, b) (cyclically).
            let whole_tighter = contours[i].points.len() < LOCAL_POINTS;
            let dirty = |a: usize, b: usize| {
                whole_tighter
                    || job.at.as_ref().is_none_or(|list| {
                        let from = list.partition_point(|&t| t < a);
                        if a < b {
                            list.get(from).is_some_and(|&t| t < b)
                        } else {
                            from < list.len() || list.first().is_some_and(|&t| t < b)
                        }
                    })
            };
            let options = |tolerance: f64| lsq_options(tolerance, limits.bound, timings);
            // A contour's own tolerance: the repair's tighter one once it has reached it.
            let own = contours[i].tolerance;
            match (job.step, &job.pixels) {
                (Repair::Corners, _) => {
                    // Only the runs that the new corners cut are fitted again.
                    let seg = with_corners(&contours[i], &findings.bad_points[i]);
                    let (refit, work) =
                        refit_runs(&contours[i], &seg, &|_, _| false, &options(own));
                    let counted = if level[i] == Repair::PixelRaw {
                        0
                    } else {
                        work
                    };
                    (refit, counted as f64)
                }
                (Repair::Tighter(k), _) => {
                    // Only the runs where something went wrong are fitted tighter.
                    let tighter = tighter_tolerance(base[i], k).unwrap_or(base[i]);
                    let seg = corners_kept(&contours[i]);
                    let (refit, work) = refit_runs(&contours[i], &seg, &dirty, &options(tighter));
                    (refit, work as f64)
                }
                (step, Some(seg)) => {
                    let work = if step == Repair::PixelSmoothed {
                        seg.points.len() as f64
                    } else {
                        0.0
                    };
                    (fit_contour(seg, &options(tolerance)), work)
                }
                (_, None) => (contours[i].clone(), 0.0),
            }
        };
        let refits: Vec<(FittedContour, f64)> = if jobs.len() > 1 {
            use rayon::prelude::*;
            jobs.par_iter().map(run).collect()
        } else {
            jobs.iter().map(run).collect()
        };
        for (job, (refit, work)) in jobs.into_iter().zip(refits) {
            let (i, step) = (job.index, job.step);
            contours[i] = refit;
            ladder_left -= work;
            if step == Repair::Corners {
                corners_tried[i] = true;
            } else {
                level[i] = step;
                corners_tried[i] = false;
            }
            merged[i].clear();
            repaired.insert(i);
            changed.insert(i);
            progressed = true;
        }
        // Shapes and holes lost altogether: borders that touch a region and have no
        // contour.
        let mut lost: BTreeSet<usize> = BTreeSet::new();
        if !findings.regions.is_empty() {
            let kept: HashSet<usize> = border_of.iter().copied().collect();
            let pixels: HashSet<u32> = findings
                .regions
                .iter()
                .flat_map(|r| r.pixels.iter().copied())
                .collect();
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
                let options = lsq_options(tolerance, limits.bound, timings);
                contours.push(fit_contour(
                    &find_breaks(&c, break_options, Some(bitmap)),
                    &options,
                ));
                merged.push(Vec::new());
                changed.insert(contours.len() - 1);
                border_of.push(b);
                base.push(tolerance);
                level.push(Repair::PixelSmoothed);
                corners_tried.push(false);
                restored += 1;
                progressed = true;
            }
        }
        if !progressed {
            break;
        }
        progress.advance(1);
        let unchanged: Vec<bool> = (0..contours.len()).map(|i| !changed.contains(&i)).collect();
        findings = check_again(
            bitmap,
            contours,
            merged,
            limits,
            &excused,
            Some((&findings, &unchanged)),
        );
    }
    Ok(Fidelity {
        held: findings.held(),
        max_deviation: findings.max_deviation,
        deviation_limit: limits.deviation + limits.widening,
        largest_region: findings.largest.0,
        region_limit: limits.region,
        region_box: findings.largest.1,
        repaired_contours: repaired.len(),
        restored_contours: restored,
        segments_over_tolerance: 0,
        worst_segment_distance: 0.0,
    })
}

/// One contour's step in a round of repair.
struct Job {
    /// The contour.
    index: usize,
    /// The step it takes.
    step: Repair,
    /// Its data points where something went wrong, sorted (`None`: all of it).
    at: Option<Vec<usize>>,
    /// The pixel steps' newly traced and segmented contour.
    pixels: Option<SegmentedContour>,
}

/// The options of a repair's fit at `tolerance`: drawn within the trace's `bound`, as
/// the SVG draws every segment, so that its pieces are counted and its cubics made once.
fn lsq_options(tolerance: f64, bound: f64, timings: bool) -> LsqOptions {
    LsqOptions {
        export_bound: bound,
        ..LsqOptions::for_tolerance(tolerance, timings)
    }
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
    let at: HashMap<usize, usize> = breaks
        .iter()
        .enumerate()
        .map(|(k, b)| (b.index, k))
        .collect();
    for &k in bad {
        match at.get(&k).map(|&j| &mut breaks[j]) {
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
/// fit that places its smooth splits anew. A contour with fewer than two corners (an
/// "o") keeps all its joints: a closed chain needs two, and without them the fit would
/// have nothing to draw.
fn corners_kept(contour: &FittedContour) -> SegmentedContour {
    let mut seg = with_corners(contour, &[]);
    let corners = seg.breaks.iter().filter(|b| b.kind == JointKind::Corner);
    if corners.count() >= 2 {
        seg.breaks.retain(|b| b.kind == JointKind::Corner);
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contour::Contour;
    use crate::geom::Point;

    /// The tighter refit of a contour without corners (an "o") keeps its joints: with the
    /// corners alone it had none, and the refit drew nothing (an upscaled "o" whose first
    /// check failed at its widened tolerance came out empty).
    #[test]
    fn a_tighter_refit_of_a_contour_without_corners_draws_it() {
        let points: Vec<Point> = (0..300)
            .map(|i| {
                let a = i as f64 / 300.0 * std::f64::consts::TAU;
                Point::new(60.0 + 40.0 * a.cos(), 60.0 + 30.0 * a.sin())
            })
            .collect();
        let contour = Contour {
            points,
            is_hole: false,
            parent: None,
            edge_spread: None,
        };
        let options = LsqOptions::for_tolerance(0.6, false);
        let seg = find_breaks(&contour, &BreakOptions::for_image(50.0, 120, 120), None);
        let fitted = fit_contour(&seg, &options);
        assert!(fitted.joints.iter().all(|j| j.kind == JointKind::Smooth));
        let kept = corners_kept(&fitted);
        assert_eq!(kept.breaks.len(), fitted.joints.len());
        let tighter = fit_contour(&kept, &LsqOptions::for_tolerance(0.3, false));
        assert!(tighter.segments.len() >= fitted.segments.len());
        assert!(tighter.max_distance() <= 0.3);
    }
}
