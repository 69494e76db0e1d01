//! The tracer as one call: [`Config`] holds every option of a trace and is the only thing
//! that turns them into the options of each stage; [`trace_file`] and [`trace_bitmap`] run
//! the stages in order (extraction, breaks, fit, optional break placement, metaheuristic
//! refit and merging, fidelity check and repair) and return a [`TraceResult`].

use crate::breaks::{find_breaks, BreakOptions, SegmentedContour};
use crate::contour::{self, Contour, ContourOptions};
use crate::error::{Error, ForegroundHint, Result};
use crate::fidelity::{self, Fidelity};
use crate::fit::placement::BreakPlacement;
use crate::fit::refit::Search;
use crate::fit::{self, FittedContour, Method};
use crate::merge;
use crate::merge::outline::MergedCurve;
use crate::optim;
use crate::progress::{NoProgress, Progress, Stage};
use crate::raster::{self, Bitmap, RasterOptions};
use crate::repair;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Every parameter of a trace. `Config::default()` gives the documented defaults.
#[derive(Clone, Debug, Serialize)]
pub struct Config {
    /// Threshold on the 0–255 scale of what is traced: pixels darker than it are the
    /// shape (lighter with `invert`; more opaque when tracing alpha). Default: `None`,
    /// Otsu's threshold of the image.
    pub threshold: Option<u8>,
    /// Whether the alpha channel or the luminance is the shape. Default:
    /// [`raster::AlphaRule::Auto`] (alpha when at least a tenth of the image is transparent).
    pub alpha: raster::AlphaRule,
    /// Which frame of an animation (GIF, APNG, WebP) or page of a TIFF file to trace, from
    /// 0. Default: 0.
    pub frame: u32,
    /// Treat light shapes on a dark background as the foreground. Default: false.
    pub invert: bool,
    /// One threshold for the whole image (`global`), uneven lighting divided out first
    /// (`local`), or local only where the global threshold would paint unevenly lit
    /// paper as ink (`auto`, the default). See [`raster::ThresholdMode`].
    pub threshold_mode: raster::ThresholdMode,
    /// Largest image accepted, in pixels (width × height). Default: 50 000 000, about
    /// 250 MB of working memory at worst.
    pub max_pixels: u64,
    /// Shapes and holes with a smaller area (px²) are dropped as specks. Default: 2.0,
    /// like potrace's turdsize.
    pub min_area: f64,
    /// A turning angle above this (degrees) makes a corner (G0 joint). Default: 50.
    pub corner_angle: f64,
    /// Largest allowed distance (px) from a data point to its fitted curve, for `lsq`.
    /// Default: 0.3.
    pub tolerance: f64,
    /// Widen the tolerance of a contour whose edge is blurred (a soft scan or photo, an
    /// upscaled image) by the square root of the edge's spread over a sharp edge's, up to
    /// 3× (`Contour::edge_scale`); false holds every contour to `tolerance`. Sharp
    /// anti-aliased and bilevel edges are never widened. The report gives each contour's
    /// tolerance. Default: true.
    pub edge_tolerance: bool,
    /// How segments are fitted: [`Method::Lsq`] (separable least squares with
    /// error-driven splitting, the default) or a metaheuristic, which refits the `lsq`
    /// segmentation at fixed centripetal parameters. Reports name it `lsq` or the
    /// algorithm's name.
    pub optimizer: Method,
    /// What a metaheuristic searches: `weights` (default; control points by least squares)
    /// or `full` (the HS paper's C1, C2, w1, w2).
    pub search: Search,
    /// Objective evaluations per segment for a metaheuristic. Default: 5000.
    pub budget: u64,
    /// Scale of the `full` search's control-point box: 1 is the paper's box of Eq. 9 (the
    /// extent of each segment's data), larger values widen it. Default: 1.
    pub search_box_scale: f64,
    /// Keep each segment's best-so-far history (metaheuristics only). Default: false.
    pub history: bool,
    /// Seed of every random choice. Default: 1.
    pub seed: u64,
    /// Record wall times in the result (they are the only non-reproducible numbers).
    /// Default: true.
    pub timings: bool,
    /// After fitting, merge runs of smooth segments into disk Wang–Ball curves within
    /// `tolerance` (`merge::outline`). Default: false.
    pub merge: bool,
    /// Degree of merged curves, 3 to [`merge::MAX_DEGREE`]. Default: 5.
    pub merge_degree: usize,
    /// Where smooth break points go: `curvature` (default) or `optimize`, which keeps the
    /// corners and the segment count of the `lsq` chain and moves its smooth joints to
    /// lower the total Eq. 4 error (`fit::placement`).
    pub breaks: BreakPlacement,
    /// The metaheuristic that places break points with `breaks = optimize`. Default:
    /// [`optim::Algorithm::Fwa`] (fireworks), as in the paper.
    pub break_optimizer: optim::Algorithm,
    /// Objective evaluations per movable smooth joint for `breaks = optimize`. Default:
    /// `fit::placement::DEFAULT_BUDGET`.
    pub break_budget: u64,
    /// Check the drawn outline against the input and repair what it lost or invented
    /// (`fidelity`). Default: true.
    pub check: bool,
}

impl Default for Config {
    fn default() -> Self {
        Config::DEFAULT
    }
}

impl Config {
    /// The documented defaults, in one place: `Config::default()` and the command line's
    /// defaults are these values.
    pub const DEFAULT: Config = Config {
        threshold: None,
        alpha: raster::AlphaRule::Auto,
        frame: 0,
        invert: false,
        threshold_mode: raster::ThresholdMode::Auto,
        max_pixels: 50_000_000,
        min_area: 2.0,
        corner_angle: 50.0,
        tolerance: 0.3,
        edge_tolerance: true,
        optimizer: Method::Lsq,
        search: Search::Weights,
        budget: 5000,
        search_box_scale: 1.0,
        history: false,
        seed: crate::optim::DEFAULT_SEED,
        timings: true,
        merge: false,
        merge_degree: 5,
        breaks: BreakPlacement::Curvature,
        break_optimizer: fit::placement::DEFAULT_OPTIMIZER,
        break_budget: fit::placement::DEFAULT_BUDGET,
        check: true,
    };

    /// The options of the `lsq` fit.
    pub fn lsq_options(&self) -> fit::lsq::LsqOptions {
        fit::lsq::LsqOptions::for_tolerance(self.tolerance, self.timings)
    }

    /// The options of a metaheuristic refit, or `None` when the method is `lsq`.
    pub fn meta_options(&self) -> Option<fit::refit::RefitOptions> {
        Some(fit::refit::RefitOptions {
            optimizer: self.optimizer.algorithm()?,
            search: self.search,
            budget: self.budget,
            seed: self.seed,
            timings: self.timings,
            box_scale: self.search_box_scale,
            history: self.history,
        })
    }

    /// The options of the break placement (`breaks` = optimize).
    pub fn placement_options(&self) -> fit::placement::PlacementOptions {
        fit::placement::PlacementOptions {
            optimizer: self.break_optimizer,
            budget: self.break_budget,
            seed: self.seed,
            lsq: self.lsq_options(),
        }
    }

    /// Checks every value against its domain.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, message: &str| {
            Err(Error::InvalidOption {
                name,
                message: message.to_string(),
            })
        };
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return bad("tolerance", "must be a positive number of pixels");
        }
        if !(self.corner_angle.is_finite() && self.corner_angle > 0.0 && self.corner_angle < 180.0)
        {
            return bad("corner_angle", "must be between 0 and 180 degrees");
        }
        if !(self.min_area.is_finite() && self.min_area >= 0.0) {
            return bad("min_area", "must be a non-negative area in px²");
        }
        if self.max_pixels == 0 {
            return bad("max_pixels", "must be at least 1");
        }
        if !(self.search_box_scale.is_finite() && self.search_box_scale >= 1.0) {
            return bad("search_box_scale", "must be a number ≥ 1");
        }
        if self.budget == 0 {
            return bad("budget", "must be at least 1");
        }
        if self.break_budget == 0 {
            return bad("break_budget", "must be at least 1");
        }
        if !(merge::outline::MIN_OUTLINE_DEGREE..=merge::MAX_DEGREE).contains(&self.merge_degree) {
            return Err(Error::InvalidOption {
                name: "merge_degree",
                message: format!(
                    "must be between {} and {}",
                    merge::outline::MIN_OUTLINE_DEGREE,
                    merge::MAX_DEGREE
                ),
            });
        }
        Ok(())
    }

    /// The raster options this configuration implies.
    pub fn raster_options(&self) -> RasterOptions {
        RasterOptions {
            threshold: self.threshold,
            alpha: self.alpha,
            frame: self.frame,
            invert: self.invert,
            max_pixels: self.max_pixels,
            threshold_mode: self.threshold_mode,
        }
    }
}

/// Facts about the input that the tracer detected.
#[derive(Clone, Debug, Serialize)]
pub struct ImageInfo {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The threshold used, on the 0–255 scale of `threshold_scale` (what `--threshold`
    /// takes).
    pub threshold: f64,
    /// What the threshold was compared with: `luminance` (darker is the shape),
    /// `inverted_luminance`, `alpha` (more opaque is the shape), `inverted_alpha`, or
    /// `coverage` for a bitmap built from coverage values.
    pub threshold_scale: raster::ThresholdScale,
    /// `global` or `local` (uneven lighting divided out before the threshold): what was
    /// used, also when `auto` chose.
    pub threshold_mode: raster::ThresholdMode,
    /// True when the image has (almost) no grey levels at its edges, so the outline was
    /// smoothed instead of refined to sub-pixel positions.
    pub bilevel: bool,
    /// True when the shape came from the alpha channel.
    pub from_alpha: bool,
    /// True when most of the image border is foreground: the polarity is probably wrong.
    pub dark_border: bool,
    /// Share (0–1) of the outermost ring of pixels that is foreground: a shape running
    /// along much of the border is often a scan's dark edge or shadow, not a shape.
    pub border_foreground: f64,
    /// The frame of an animation or page of a TIFF file that was traced, from 0.
    pub frame: u32,
    /// How many frames or pages the file has (1 for a still image).
    pub frames: u32,
}

impl ImageInfo {
    /// What `bitmap` says about its image.
    pub(crate) fn of(bitmap: &Bitmap) -> Self {
        ImageInfo {
            width: bitmap.width(),
            height: bitmap.height(),
            threshold: bitmap.threshold_value(),
            threshold_scale: bitmap.threshold_scale(),
            bilevel: bitmap.is_bilevel(),
            from_alpha: bitmap.from_alpha(),
            threshold_mode: bitmap.threshold_mode(),
            dark_border: bitmap.dark_border(),
            border_foreground: bitmap.border_foreground(),
            frame: bitmap.frame().0,
            frames: bitmap.frame().1,
        }
    }
}

/// The outcome of tracing one image.
#[derive(Clone, Debug, Serialize)]
pub struct TraceResult {
    /// What was detected about the input.
    pub image: ImageInfo,
    /// The fitted contours.
    pub contours: Vec<FittedContour>,
    /// `merged[i]`: the runs of segments of `contours[i]` replaced by disk Wang–Ball curves
    /// (`--merge`), which the SVG draws instead of those segments (the report keeps both).
    /// Empty, or shorter than `contours`, where nothing was merged; see
    /// [`TraceResult::merged_of`].
    pub merged: Vec<Vec<MergedCurve>>,
    /// The end-to-end check of the drawn outline against the input (all zero and
    /// `held = false` when the check was turned off).
    pub fidelity: Fidelity,
    /// Wall time of the whole trace, in seconds (0 when timing is off).
    pub seconds: f64,
}

impl TraceResult {
    /// Total number of segments.
    pub fn segment_count(&self) -> usize {
        self.contours.iter().map(|c| c.segments.len()).sum()
    }

    /// Number of curves the SVG draws: segments not replaced by merged curves, plus the
    /// merged curves (equal to [`TraceResult::segment_count`] without `--merge`).
    pub fn curve_count(&self) -> usize {
        self.contours
            .iter()
            .enumerate()
            .map(|(i, c)| merge::outline::curve_count(c, self.merged_of(i)))
            .sum()
    }

    /// The merged curves of contour `i` (empty without `--merge`).
    pub fn merged_of(&self, i: usize) -> &[MergedCurve] {
        self.merged.get(i).map_or(&[], Vec::as_slice)
    }

    /// Sum of Eq. 4 errors over every segment.
    pub fn sum_sq(&self) -> f64 {
        self.contours.iter().map(FittedContour::sum_sq).sum()
    }

    /// Largest point-to-curve distance over every segment.
    pub fn max_distance(&self) -> f64 {
        self.contours
            .iter()
            .map(FittedContour::max_distance)
            .fold(0.0, f64::max)
    }
}

/// Loads an image file and traces it.
pub fn trace_file(path: &Path, config: &Config) -> Result<TraceResult> {
    config.validate()?;
    let bitmap = raster::load(path, &config.raster_options())?;
    trace_bitmap(&bitmap, config)
}

/// Why an image gave no contour: no foreground at all, or only shapes below `min_area`.
pub(crate) fn nothing_traced(bitmap: &Bitmap, min_area: f64) -> Error {
    let mask = bitmap.mask();
    if mask.pixels().all(|p| p[0] == 0) {
        let transparent = bitmap.transparent_fraction();
        let hint = if !bitmap.from_alpha() && transparent > 0.0 {
            ForegroundHint::TraceAlpha { transparent }
        } else {
            ForegroundHint::InvertOrThreshold
        };
        return Error::NoForeground {
            threshold: bitmap.threshold_scale().describe(bitmap.threshold_value()),
            hint,
        };
    }
    // imageproc's labelling panics on a one-pixel image (its union-find asserts), which
    // can only hold one shape.
    let shapes = if mask.width() * mask.height() == 1 {
        1
    } else {
        let labels = imageproc::region_labelling::connected_components(
            &mask,
            imageproc::region_labelling::Connectivity::Eight,
            image::Luma([0u8]),
        );
        labels.pixels().map(|p| p[0]).max().unwrap_or(0) as usize
    };
    Error::AllBelowMinArea { shapes, min_area }
}

/// Fewest contour points outside the largest contour for which [`trace_bitmap`] fits
/// contours in parallel: about 50 ms of fitting that another thread can take, against
/// well under a millisecond to start a thread pool.
const PARALLEL_FIT_POINTS: usize = 4000;

/// Traces an already loaded bitmap.
///
/// With `config.check` (the default) the drawn outline is checked against the thresholded
/// input and repaired where it lost or invented a part (`fidelity`); the verdict is in
/// [`TraceResult::fidelity`].
pub fn trace_bitmap(bitmap: &Bitmap, config: &Config) -> Result<TraceResult> {
    trace_bitmap_with_progress(bitmap, config, &NoProgress)
}

/// [`trace_bitmap`], reporting its stages and the work done to `progress` (see
/// [`crate::progress`]).
pub fn trace_bitmap_with_progress(
    bitmap: &Bitmap,
    config: &Config,
    progress: &dyn Progress,
) -> Result<TraceResult> {
    config.validate()?;
    let started = Instant::now();
    progress.stage(Stage::Borders, 0);
    let mut extraction = contour::extract_borders(
        bitmap,
        &ContourOptions {
            min_area: config.min_area,
            edge_spread: config.edge_tolerance,
        },
    )?;
    if extraction.contours.is_empty() {
        return Err(nothing_traced(bitmap, config.min_area));
    }
    let break_options =
        BreakOptions::for_image(config.corner_angle, bitmap.width(), bitmap.height());
    let lsq_options = config.lsq_options();
    let placement_options =
        (config.breaks == BreakPlacement::Optimize).then(|| config.placement_options());
    let meta_options = config.meta_options();
    let fit_one = |seg: SegmentedContour, i: usize, tolerance: f64| -> Result<FittedContour> {
        // The drawing bound stays the trace's: a widened contour is drawn as exactly.
        let lsq_options = fit::lsq::LsqOptions {
            tolerance,
            ..lsq_options.clone()
        };
        let mut chain = fit::lsq::fit_contour(&seg, &lsq_options);
        if let Some(opts) = &placement_options {
            chain = fit::placement::optimize_contour(&chain, opts, i)?;
        }
        match &meta_options {
            None => Ok(chain),
            Some(opts) => Ok(fit::refit::refit_contour(&chain, opts, i)),
        }
    };
    // Merged curves come beside their contour (a repaired contour is drawn by its own
    // segments, see `repair`).
    // Each contour is consumed by its fit: the fitted contour keeps the points, and the
    // repair re-traces from the borders, so the extracted copy is not kept (on a page it
    // is as large as the fitted points).
    let fit_indexed = |(i, c): (usize, Contour)| -> Result<(FittedContour, Vec<MergedCurve>)> {
        let tolerance = if config.edge_tolerance {
            config.tolerance * c.edge_scale()
        } else {
            config.tolerance
        };
        let fitted = fit_one(find_breaks(&c, &break_options, Some(bitmap)), i, tolerance)?;
        progress.advance(c.points.len() as u64);
        drop(c);
        let merged = if config.merge {
            let opts = merge::outline::OutlineMergeOptions {
                degree: config.merge_degree,
                tolerance: fitted.tolerance,
            };
            merge::outline::merge_contour(&fitted, &opts)
        } else {
            Vec::new()
        };
        Ok((fitted, merged))
    };
    // Contours are fitted independently (a metaheuristic's generator is seeded by the
    // contour's index), so on a page of text they are fitted in parallel, on the current
    // rayon pool (`batch`'s, or the global one for a single image); images with little
    // work beside their largest contour stay on this thread, where starting the pool
    // would cost more than it saves. The results,
    // and the first error in contour order, are the same on any number of threads.
    let sizes = extraction.contours.iter().map(|c| c.points.len());
    let (points, largest) = sizes.fold((0, 0), |(sum, max), n| (sum + n, max.max(n)));
    progress.stage(Stage::Fitting, points as u64);
    let contours = std::mem::take(&mut extraction.contours);
    let results: Vec<Result<_>> = if points - largest >= PARALLEL_FIT_POINTS {
        use rayon::prelude::*;
        contours
            .into_par_iter()
            .enumerate()
            .map(fit_indexed)
            .collect()
    } else {
        contours.into_iter().enumerate().map(fit_indexed).collect()
    };
    let (mut fitted, mut merged): (Vec<FittedContour>, Vec<Vec<MergedCurve>>) = results
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip();
    let fidelity = if config.check {
        let bound = lsq_options.export_bound;
        let limits = fidelity::Limits {
            deviation: if meta_options.is_none() {
                // The fit's tolerance, the SVG's approximation, and the flattening of the
                // drawn path.
                config.tolerance + bound + fidelity::FLATTEN_ERROR
            } else {
                fidelity::SHAPE_LIMIT.max(config.tolerance)
            },
            tolerance: config.tolerance,
            widening: fitted
                .iter()
                .map(|c| c.tolerance - config.tolerance)
                .fold(0.0, f64::max),
            region: config.min_area.max(2.0),
            bound,
        };
        let input = repair::RepairInput {
            bitmap,
            extraction: &extraction,
            limits,
            min_area: config.min_area,
            break_options: &break_options,
            tolerance: config.tolerance,
            timings: config.timings,
            progress,
        };
        // What each contour was promised: its tolerance before the repair, which may fit
        // it tighter (a restored contour, added at the end, is held to `tolerance`).
        let promised: Vec<f64> = fitted.iter().map(|c| c.tolerance).collect();
        let mut fidelity = repair::check_and_repair(input, &mut fitted, &mut merged)?;
        if meta_options.is_none() {
            let over = fitted
                .iter()
                .enumerate()
                .flat_map(|(i, c)| {
                    let promise = promised.get(i).copied().unwrap_or(config.tolerance);
                    c.segments
                        .iter()
                        .map(move |s| (s.error.max_distance, promise))
                })
                .filter(|&(d, promise)| d > promise)
                .map(|(d, _)| d);
            for d in over {
                fidelity.segments_over_tolerance += 1;
                fidelity.worst_segment_distance = fidelity.worst_segment_distance.max(d);
            }
        }
        fidelity
    } else {
        Fidelity::default()
    };
    let seconds = if config.timings {
        started.elapsed().as_secs_f64()
    } else {
        0.0
    };
    Ok(TraceResult {
        image: ImageInfo::of(bitmap),
        contours: fitted,
        merged,
        fidelity,
        seconds,
    })
}
