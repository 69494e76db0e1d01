//! The arguments the subcommands share (how outlines are found and fitted, what a
//! metaheuristic searches) and the parsers of their values.

use clap::builder::PossibleValuesParser;
use clap::{Args, ValueEnum};
use outlinefit::optim::Algorithm;
use outlinefit::{AlphaRule, ThresholdMode};
use outlinefit::{Config, Search};

/// What a metaheuristic searches, as named on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SearchArg {
    /// The HS paper's formulation: C1, C2, w1, w2 (odd segments free, even ones
    /// constrained for G1).
    Full,
    /// Only the weights w1, w2; control points by least squares (separable, exact G1).
    Weights,
}

impl From<Search> for SearchArg {
    fn from(s: Search) -> SearchArg {
        match s {
            Search::Full => SearchArg::Full,
            Search::Weights => SearchArg::Weights,
        }
    }
}

impl From<SearchArg> for Search {
    fn from(s: SearchArg) -> Search {
        match s {
            SearchArg::Full => Search::Full,
            SearchArg::Weights => Search::Weights,
        }
    }
}

/// How an image is thresholded, as named on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum ThresholdModeArg {
    /// One threshold for the whole image.
    Global,
    /// Uneven lighting (a page darker on one side, a shadow) divided out first: the
    /// paper's level is estimated in blocks across the image.
    Local,
    /// Local when the global threshold would paint large areas of unevenly lit paper as
    /// ink, global otherwise.
    Auto,
}

impl From<ThresholdModeArg> for ThresholdMode {
    fn from(m: ThresholdModeArg) -> ThresholdMode {
        match m {
            ThresholdModeArg::Global => ThresholdMode::Global,
            ThresholdModeArg::Local => ThresholdMode::Local,
            ThresholdModeArg::Auto => ThresholdMode::Auto,
        }
    }
}

/// Parses a whole number for an unsigned option, so that a negative or fractional value is
/// refused with its range rather than clap's "unexpected argument" or "invalid digit".
pub(crate) fn whole<T: TryFrom<i128>>(s: &str) -> Result<T, String> {
    let n: i128 = s
        .trim()
        .parse()
        .map_err(|_| "must be a whole number".to_string())?;
    if n < 0 {
        return Err("must be 0 or more".into());
    }
    T::try_from(n).map_err(|_| {
        let max = (0..128)
            .rev()
            .map(|b| (1i128 << b) - 1)
            .find(|&m| T::try_from(m).is_ok())
            .unwrap_or(0);
        format!("must be at most {max}")
    })
}

/// `lsq` and every metaheuristic's name, for `--optimizer`.
pub(crate) fn optimizer_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        std::iter::once("lsq").chain(outlinefit::optim::NAMES.iter().copied()),
    )
}

/// How outlines are found and segmented: options shared by `trace`, `batch` and
/// `compare`.
#[derive(Args, Debug, Clone)]
pub(crate) struct ShapeArgs {
    /// Largest distance (px) allowed between a data point and its curve (lsq).
    /// 0.3 px sits well above the ~0.05 px noise of sub-pixel edges, and on the development
    /// corpus it beats potrace's area error by 2.8× (64 px glyphs) to 3.3× (256 px) with
    /// fewer segments; 0.4 saves ~10% of segments but misses the 64 px area target.
    #[arg(
        long,
        default_value_t = Config::DEFAULT.tolerance,
        value_name = "PX",
        allow_negative_numbers = true
    )]
    pub(crate) tolerance: f64,
    /// Turning angle (degrees) above which a point is a corner (G0 joint).
    #[arg(
        long,
        default_value_t = Config::DEFAULT.corner_angle,
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    pub(crate) corner_angle: f64,
    /// Drop shapes and holes smaller than this area (px²), like potrace's turdsize.
    #[arg(
        long,
        default_value_t = Config::DEFAULT.min_area,
        value_name = "PX2",
        allow_negative_numbers = true
    )]
    pub(crate) min_area: f64,
    /// Foreground threshold, 0–255: pixels darker than this are the shape (lighter with
    /// --invert; more opaque when an image with transparency traces its alpha). Default:
    /// Otsu's level; the report's "threshold" gives the one used, on the same scale.
    #[arg(long, value_name = "0-255", allow_negative_numbers = true, value_parser = whole::<u8>)]
    pub(crate) threshold: Option<u8>,
    /// How the threshold applies: one for the whole image (global), or after the paper's
    /// uneven lighting is divided out (local; for scans and photos of pages). auto
    /// chooses local only when the global threshold would paint large areas of unevenly
    /// lit paper as ink; the report's "threshold_mode" says which was used. Images traced
    /// from their alpha channel always use global.
    #[arg(long, value_enum, default_value = "auto", value_name = "MODE")]
    pub(crate) threshold_mode: ThresholdModeArg,
    /// Trace the luminance (transparent pixels count as white paper) even when at least a
    /// tenth of the image is transparent, which otherwise traces its alpha channel.
    #[arg(long)]
    pub(crate) luminance: bool,
    /// Trace the alpha channel (opaque is the shape) even when less than a tenth of the
    /// image is transparent, which otherwise traces the luminance.
    #[arg(long, conflicts_with = "luminance")]
    pub(crate) alpha: bool,
    /// Light shapes on a dark background (or inverted alpha) are the foreground.
    #[arg(long)]
    pub(crate) invert: bool,
    /// Which frame of an animated GIF, PNG or WebP, or page of a TIFF file, to trace,
    /// from 0. A file with several gets a note saying which was traced.
    #[arg(long, default_value_t = Config::DEFAULT.frame, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>)]
    pub(crate) frame: u32,
    /// Refuse images with more pixels than this (protects memory).
    #[arg(long, default_value_t = Config::DEFAULT.max_pixels, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    pub(crate) max_pixels: u64,
}

impl ShapeArgs {
    /// The default configuration with these tracing settings.
    pub(crate) fn config(&self) -> Config {
        Config {
            threshold: self.threshold,
            alpha: match (self.alpha, self.luminance) {
                (true, _) => AlphaRule::Alpha,
                (_, true) => AlphaRule::Luminance,
                _ => AlphaRule::Auto,
            },
            invert: self.invert,
            threshold_mode: self.threshold_mode.into(),
            max_pixels: self.max_pixels,
            frame: self.frame,
            min_area: self.min_area,
            corner_angle: self.corner_angle,
            tolerance: self.tolerance,
            ..Config::default()
        }
    }
}

/// Options shared by `trace` and `batch`: every parameter of the pipeline.
#[derive(Args, Debug, Clone)]
pub(crate) struct FitArgs {
    #[command(flatten)]
    pub(crate) shape: ShapeArgs,
    /// Fitting method. `lsq` (default): separable least squares with error-driven
    /// splitting. Any other name refits the lsq segmentation with that metaheuristic at
    /// fixed centripetal parameters: hs (harmony search), ga (genetic algorithm), pso
    /// (particle swarm), gwo (grey wolf), cs / ics (cuckoo search, improved), fwa
    /// (fireworks), so / beeso (snake optimizer, enhanced), de (differential evolution).
    #[arg(long, default_value = Config::DEFAULT.optimizer.name(), value_name = "NAME", value_parser = optimizer_names())]
    pub(crate) optimizer: String,
    /// What a metaheuristic searches: `weights` (w1, w2; control points by least squares,
    /// reaches the optimum) or `full` (the HS paper's C1, C2, w1, w2).
    #[arg(long, value_enum, default_value_t = Config::DEFAULT.search.into())]
    pub(crate) search: SearchArg,
    /// Objective evaluations per segment for a metaheuristic.
    #[arg(long, default_value_t = Config::DEFAULT.budget, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    pub(crate) budget: u64,
    /// Widen the `full` search's control-point box by this factor (1 = the paper's box of
    /// Eq. 9, the extent of each segment's data, which can exclude the optimum).
    #[arg(
        long,
        default_value_t = Config::DEFAULT.search_box_scale,
        value_name = "S",
        allow_negative_numbers = true
    )]
    pub(crate) search_box_scale: f64,
    /// Record each segment's best-so-far error after every evaluation in the JSON report
    /// (metaheuristics only; large).
    #[arg(long)]
    pub(crate) history: bool,
    /// Seed of every random choice; the same seed gives the same output on any number of
    /// threads.
    #[arg(long, default_value_t = Config::DEFAULT.seed, allow_negative_numbers = true, value_parser = whole::<u64>)]
    pub(crate) seed: u64,
    /// Write 0 for every time in reports, so reports are byte-identical across runs.
    #[arg(long)]
    pub(crate) no_timings: bool,
    /// After fitting, merge runs of smooth segments into single disk Wang–Ball curves whose
    /// center line stays within --tolerance of the data; the disk radii carry the fit-error
    /// band. The SVG draws merged curves (as cubics), the report lists them, --overlay
    /// shows their bands.
    #[arg(long)]
    pub(crate) merge: bool,
    /// Degree of merged curves (3–20).
    #[arg(long, default_value_t = Config::DEFAULT.merge_degree, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    pub(crate) merge_degree: usize,
    /// Where smooth break points go: `curvature` (curvature analysis and error-driven
    /// splitting) or `optimize` (same corners and segment count, smooth joints moved by
    /// --break-optimizer to lower the total error; never worse, typically a few times
    /// slower than curvature).
    #[arg(long, default_value = Config::DEFAULT.breaks.name(), value_name = "MODE")]
    pub(crate) breaks: String,
    /// The metaheuristic that places break points with --breaks optimize (fwa: fireworks,
    /// as in the paper; any name of --optimizer except lsq).
    #[arg(long, default_value = Config::DEFAULT.break_optimizer.name(), value_name = "NAME")]
    pub(crate) break_optimizer: String,
    /// Objective evaluations per movable smooth joint with --breaks optimize.
    #[arg(long, default_value_t = Config::DEFAULT.break_budget, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    pub(crate) break_budget: u64,
    /// Fail (exit 1, no SVG written) when the drawn outline does not match the input after
    /// repair: a data point farther from the drawn path than the tolerance allows, or a
    /// lost or invented region. Without it such an image gets a warning line and
    /// `"held": false` in the report.
    #[arg(long)]
    pub(crate) strict: bool,
    /// Skip the end-to-end check of the drawn outline against the input and its repairs
    /// (faster; nothing then notices a lost or invented part).
    #[arg(long, conflicts_with = "strict")]
    pub(crate) no_check: bool,
}

impl FitArgs {
    /// The configuration; fails on an unknown `--breaks` mode or `--break-optimizer` (the
    /// other values are checked by [`Config::validate`]).
    pub(crate) fn config(&self) -> outlinefit::Result<Config> {
        Ok(Config {
            optimizer: self.optimizer.parse()?,
            search: self.search.into(),
            budget: self.budget,
            search_box_scale: self.search_box_scale,
            history: self.history,
            seed: self.seed,
            timings: !self.no_timings,
            merge: self.merge,
            merge_degree: self.merge_degree,
            breaks: self.breaks.parse()?,
            break_optimizer: Algorithm::from_name(&self.break_optimizer).ok_or_else(|| {
                outlinefit::Error::InvalidOption {
                    name: "break_optimizer",
                    message: format!(
                        "unknown optimizer `{}` (expected one of {})",
                        self.break_optimizer,
                        outlinefit::optim::NAMES.join(", ")
                    ),
                }
            })?,
            break_budget: self.break_budget,
            check: !self.no_check,
            ..self.shape.config()
        })
    }
}
