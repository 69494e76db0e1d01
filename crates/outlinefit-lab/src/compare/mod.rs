//! Comparing optimizers on the same outlines: the experiment behind `outlinefit compare`.
//!
//! Each image is traced once with `lsq`; its segmentation is then refitted by every
//! optimizer `runs` times with independent seeds ([`run_seed`]), in parallel. A run's
//! result is the total Eq. 4 error over all segments (the HS paper's Table 2 quantity),
//! the error of every segment, and the total best-so-far error after each evaluation per
//! segment (every segment gets the same budget, so histories add index by index). The
//! separable least-squares optimum of the same segments is the reference row.
//!
//! [`statistics`] turns the runs into the paper's tables (descriptive statistics,
//! normality, F-tests, Welch t-tests, one-way ANOVA), and [`output`] writes them.

pub mod output;
pub mod plot;

use crate::stats::{self, Anova, Describe, FTest, Normality, TTest};
use crate::{Error, Result};
use outlinefit::fit::Method;
use outlinefit::fit::{reference_errors, refit_contour, RefitOptions, Search};
use outlinefit::optim::Algorithm;
use outlinefit::{trace_file, Config};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Independent runs per optimizer unless told otherwise (the HS paper used 30).
pub const DEFAULT_RUNS: usize = 30;

/// Points kept per convergence history unless told otherwise.
pub const DEFAULT_HISTORY_POINTS: usize = 200;

/// What to compare and how.
#[derive(Clone, Debug, Serialize)]
pub struct CompareOptions {
    /// The metaheuristics compared, in report order.
    pub optimizers: Vec<Algorithm>,
    /// Independent runs per optimizer.
    pub runs: usize,
    /// Objective evaluations per segment and run.
    pub budget: u64,
    /// Search space.
    pub search: Search,
    /// Base seed: run r of every optimizer uses [`run_seed`]`(seed, r)`.
    pub seed: u64,
    /// `full` search only: scale of the control-point box (1 = the paper's Eq. 9 box).
    pub search_box_scale: f64,
    /// Points kept per convergence history (evenly spaced evaluation counts, the last
    /// evaluation included); the full history of every run would be budget × segments.
    pub history_points: usize,
    /// Tracing settings (threshold, tolerance, corner angle, …) for the base segmentation.
    pub trace: Config,
}

impl CompareOptions {
    /// Checks the options; an error names the offending field.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, message: String| Err(Error::InvalidOption { name, message });
        if self.optimizers.is_empty() {
            return bad("optimizers", "name at least one optimizer".into());
        }
        if self.runs == 0 {
            return bad("runs", "must be at least 1".into());
        }
        if self.budget == 0 {
            return bad("budget", "must be at least 1".into());
        }
        if self.history_points < 2 {
            return bad("history_points", "must be at least 2".into());
        }
        if !(self.search_box_scale.is_finite() && self.search_box_scale >= 1.0) {
            return bad("search_box_scale", "must be a number ≥ 1".into());
        }
        Ok(self.trace.validate()?)
    }
}

/// One run of one optimizer on one image.
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    /// The run's seed.
    pub seed: u64,
    /// Total Eq. 4 error over all segments.
    pub total: f64,
    /// Eq. 4 error of every segment, contours in order.
    pub segments: Vec<f64>,
    /// Objective evaluations used over all segments.
    pub evaluations: u64,
    /// Wall time of the run, in seconds (runs share the machine's cores).
    pub seconds: f64,
    /// Total best-so-far error after the evaluation counts of [`ImageComparison::history_at`].
    pub history: Vec<f64>,
}

/// All runs of one optimizer on one image.
#[derive(Clone, Debug, Serialize)]
pub struct OptimizerRuns {
    /// The optimizer's name.
    pub name: String,
    /// Its runs, in run order.
    pub runs: Vec<RunResult>,
}

impl OptimizerRuns {
    /// Every run's total error.
    pub fn totals(&self) -> Vec<f64> {
        self.runs.iter().map(|r| r.total).collect()
    }

    /// The smallest error each segment reached over all runs (the paper's Fig. 9).
    pub fn segment_minima(&self) -> Vec<f64> {
        let n = self.runs.first().map_or(0, |r| r.segments.len());
        (0..n)
            .map(|s| {
                self.runs
                    .iter()
                    .map(|r| r.segments[s])
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    /// Mean wall time per run.
    pub fn seconds_per_run(&self) -> f64 {
        self.runs.iter().map(|r| r.seconds).sum::<f64>() / self.runs.len().max(1) as f64
    }
}

/// One segment of the base segmentation.
#[derive(Clone, Debug, Serialize)]
pub struct SegmentInfo {
    /// Contour index.
    pub contour: usize,
    /// Segment index within the contour.
    pub segment: usize,
    /// Data points fitted.
    pub points: usize,
    /// The separable least-squares optimum of its Eq. 4 error (the reference).
    pub reference: f64,
}

/// Everything measured on one image.
#[derive(Clone, Debug, Serialize)]
pub struct ImageComparison {
    /// The image as given.
    pub path: String,
    /// Segments of the base (`lsq`) segmentation.
    pub segments: Vec<SegmentInfo>,
    /// Sum of the reference errors.
    pub reference_total: f64,
    /// Evaluation counts (per segment) at which histories are sampled.
    pub history_at: Vec<u64>,
    /// Every optimizer's runs, in the order requested.
    pub optimizers: Vec<OptimizerRuns>,
}

/// A statistic that may be undefined for the data (e.g. zero variance).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum Outcome<T> {
    /// The statistic.
    Value(T),
    /// Why it is undefined.
    Undefined {
        /// The reason.
        undefined: String,
    },
}

impl<T> From<std::result::Result<T, stats::StatsError>> for Outcome<T> {
    fn from(r: std::result::Result<T, stats::StatsError>) -> Self {
        match r {
            Ok(v) => Outcome::Value(v),
            Err(e) => Outcome::Undefined {
                undefined: e.to_string(),
            },
        }
    }
}

impl<T> Outcome<T> {
    /// The value, if defined.
    pub fn value(&self) -> Option<&T> {
        match self {
            Outcome::Value(v) => Some(v),
            Outcome::Undefined { .. } => None,
        }
    }
}

/// Statistics of one optimizer's totals.
#[derive(Clone, Debug, Serialize)]
pub struct OptimizerStats {
    /// The optimizer.
    pub name: String,
    /// Best, worst, mean, median, variance, standard deviation (Table 2).
    pub describe: Outcome<Describe>,
    /// Shapiro–Wilk (Table 3).
    pub shapiro_wilk: Outcome<Normality>,
    /// Kolmogorov–Smirnov with Lilliefors' correction (Table 3).
    pub lilliefors: Outcome<Normality>,
    /// Mean wall time per run, in seconds.
    pub seconds_per_run: f64,
    /// Gap of the mean total to the reference, in percent.
    pub mean_gap_percent: f64,
    /// Gap of the best total to the reference, in percent.
    pub best_gap_percent: f64,
}

/// Tests between two optimizers' totals.
#[derive(Clone, Debug, Serialize)]
pub struct PairStats {
    /// First optimizer.
    pub a: String,
    /// Second optimizer.
    pub b: String,
    /// F-test of equal variances (Table 4).
    pub f_test: Outcome<FTest>,
    /// Welch's two-sample t-test (Table 5).
    pub t_test: Outcome<TTest>,
}

/// All statistics of one image.
#[derive(Clone, Debug, Serialize)]
pub struct ImageStats {
    /// The image.
    pub path: String,
    /// Per optimizer.
    pub optimizers: Vec<OptimizerStats>,
    /// Every pair of optimizers.
    pub pairs: Vec<PairStats>,
    /// One-way ANOVA over all optimizers (Table 6).
    pub anova: Outcome<Anova>,
}

/// The seed of run `run`: a SplitMix64 step from the base seed, so runs are independent
/// streams and run r is the same whatever else is compared.
pub fn run_seed(seed: u64, run: usize) -> u64 {
    outlinefit::fit::segment_seed(seed ^ 0xC0FF_EE00_D15E_A5E5, usize::MAX, run)
}

/// Evaluation counts at which histories are sampled: `points` values from 1 to `budget`,
/// evenly spaced, each at most once.
pub fn history_points(budget: u64, points: usize) -> Vec<u64> {
    let points = points.max(2) as u64;
    let mut at: Vec<u64> = (0..points)
        .map(|i| 1 + i * (budget - 1) / (points - 1))
        .collect();
    at.dedup();
    at
}

/// Traces `path` with `lsq` and runs every optimizer on its segmentation.
/// `progress` is called once per finished run.
pub fn compare_image(
    path: &Path,
    opts: &CompareOptions,
    progress: &(dyn Fn() + Sync),
) -> Result<ImageComparison> {
    opts.validate()?;
    let trace_config = Config {
        optimizer: Method::Lsq,
        ..opts.trace.clone()
    };
    let base = trace_file(path, &trace_config)?;
    let mut segments = Vec::new();
    for (ci, c) in base.contours.iter().enumerate() {
        for (k, reference) in reference_errors(c).into_iter().enumerate() {
            segments.push(SegmentInfo {
                contour: ci,
                segment: k,
                points: c.segments[k].point_count,
                reference,
            });
        }
    }
    let history_at = history_points(opts.budget, opts.history_points);
    let tasks: Vec<(usize, usize)> = (0..opts.optimizers.len())
        .flat_map(|o| (0..opts.runs).map(move |r| (o, r)))
        .collect();
    let results: Vec<RunResult> = tasks
        .par_iter()
        .map(|&(o, r)| {
            let meta = RefitOptions {
                optimizer: opts.optimizers[o],
                search: opts.search,
                budget: opts.budget,
                seed: run_seed(opts.seed, r),
                timings: false,
                box_scale: opts.search_box_scale,
                history: true,
            };
            let started = Instant::now();
            let mut run = RunResult {
                seed: meta.seed,
                total: 0.0,
                segments: Vec::with_capacity(segments.len()),
                evaluations: 0,
                seconds: 0.0,
                history: vec![0.0; history_at.len()],
            };
            for (ci, c) in base.contours.iter().enumerate() {
                let fitted = refit_contour(c, &meta, ci);
                for s in &fitted.segments {
                    run.segments.push(s.error.sum_sq);
                    run.total += s.error.sum_sq;
                    run.evaluations += s.evaluations;
                    // A segment too short to search keeps its error from the start.
                    for (h, &at) in run.history.iter_mut().zip(&history_at) {
                        let idx = (at as usize).min(s.history.len());
                        *h += if idx == 0 {
                            s.error.sum_sq
                        } else {
                            s.history[idx - 1]
                        };
                    }
                }
            }
            run.seconds = started.elapsed().as_secs_f64();
            progress();
            run
        })
        .collect();
    let mut optimizers: Vec<OptimizerRuns> = opts
        .optimizers
        .iter()
        .map(|name| OptimizerRuns {
            name: name.name().to_string(),
            runs: Vec::with_capacity(opts.runs),
        })
        .collect();
    for (&(o, _), result) in tasks.iter().zip(results) {
        optimizers[o].runs.push(result);
    }
    Ok(ImageComparison {
        path: path.display().to_string(),
        reference_total: segments.iter().map(|s| s.reference).sum(),
        segments,
        history_at,
        optimizers,
    })
}

/// The statistics of one image's comparison.
pub fn statistics(image: &ImageComparison) -> ImageStats {
    let gap = |v: f64| {
        if image.reference_total > 0.0 {
            100.0 * (v - image.reference_total) / image.reference_total
        } else {
            0.0
        }
    };
    let totals: Vec<Vec<f64>> = image.optimizers.iter().map(|o| o.totals()).collect();
    let optimizers = image
        .optimizers
        .iter()
        .zip(&totals)
        .map(|(o, t)| {
            let describe = stats::describe(t);
            let (mean, best) = describe
                .as_ref()
                .map_or((f64::NAN, f64::NAN), |d| (d.mean, d.best));
            OptimizerStats {
                name: o.name.clone(),
                describe: describe.into(),
                shapiro_wilk: stats::shapiro_wilk(t).into(),
                lilliefors: stats::lilliefors(t).into(),
                seconds_per_run: o.seconds_per_run(),
                mean_gap_percent: gap(mean),
                best_gap_percent: gap(best),
            }
        })
        .collect();
    let mut pairs = Vec::new();
    for i in 0..totals.len() {
        for j in i + 1..totals.len() {
            pairs.push(PairStats {
                a: image.optimizers[i].name.clone(),
                b: image.optimizers[j].name.clone(),
                f_test: stats::f_test(&totals[i], &totals[j]).into(),
                t_test: stats::welch_t(&totals[i], &totals[j]).into(),
            });
        }
    }
    let groups: Vec<&[f64]> = totals.iter().map(Vec::as_slice).collect();
    ImageStats {
        path: image.path.clone(),
        optimizers,
        pairs,
        anova: stats::anova_oneway(&groups).into(),
    }
}

/// File-name stems for the images' charts: the file stem, made unique with a numeric
/// suffix when two images share one.
pub fn image_stems(paths: &[PathBuf]) -> Vec<String> {
    let mut seen = std::collections::HashMap::<String, usize>::new();
    paths
        .iter()
        .map(|p| {
            let stem = p
                .file_stem()
                .map_or_else(|| "image".to_string(), |s| s.to_string_lossy().into_owned());
            let n = seen.entry(stem.clone()).or_insert(0);
            *n += 1;
            if *n == 1 {
                stem
            } else {
                format!("{stem}-{n}")
            }
        })
        .collect()
}
