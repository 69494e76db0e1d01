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
/// `compare`. Everyday options show under `-h`; `--help` adds the rest under their
/// headings. potrace's names for the same settings are accepted (see the README's table).
#[derive(Args, Debug, Clone)]
pub(crate) struct ShapeArgs {
    /// Largest distance (px) allowed between an edge point and its curve.
    ///
    /// Largest distance (px) allowed between an edge point and its curve. 0.3 px sits
    /// well above the ~0.05 px noise of sub-pixel edges, and on the development corpus it
    /// beats potrace's area error by 2.8× (64 px glyphs) to 3.3× (256 px) with fewer
    /// segments; 0.4 saves ~10% of segments but misses the 64 px area target.
    /// [potrace: -O/--opttolerance, same number: both bound how far a curve may stray,
    /// potrace's from its polygon, ours from the edge points]
    #[arg(
        long,
        short = 'O',
        visible_alias = "opttolerance",
        default_value_t = Config::DEFAULT.tolerance,
        value_name = "PX",
        allow_negative_numbers = true,
        help_heading = "Tracing"
    )]
    pub(crate) tolerance: f64,
    /// Hold every outline to --tolerance, also where its edge is blurred.
    ///
    /// Hold every outline to --tolerance, also where its edge is blurred. By default an
    /// outline whose grey levels rise from paper to ink over more than a sharp
    /// anti-aliased edge's 0.65 px (a soft scan or photo, an upscaled image) is fitted to
    /// --tolerance times the square root of that spread over 0.65 px, at most 3 times:
    /// such an edge shows the shape only to the scale of its blur, and a tight fit
    /// follows the ripples that blurring or upscaling leave (an image upscaled 4× has a
    /// spread of about 1.1 px, and is fitted to 0.39 px). Sharp anti-aliased and bilevel
    /// edges are never widened. The report gives each contour's tolerance and the
    /// summary the widened contours.
    #[arg(long, help_heading = "Tracing", hide_short_help = true)]
    pub(crate) fixed_tolerance: bool,
    /// Turning angle (degrees) above which a point is a corner, a joint where the outline
    /// may turn sharply [G0 joint]; smaller angles are smooth joints [G1].
    #[arg(
        long,
        default_value_t = Config::DEFAULT.corner_angle,
        value_name = "DEG",
        allow_negative_numbers = true,
        help_heading = "Tracing",
        hide_short_help = true
    )]
    pub(crate) corner_angle: f64,
    /// potrace's corner threshold, 0 < A < 4/3 (larger: fewer corners): the same as
    /// --corner-angle 135·A (monotone, and equal to potrace's at both ends: near 0 every
    /// bend is a corner, near 4/3 none is; potrace's own test also depends on its
    /// polygon's edge lengths, so no formula matches it everywhere).
    #[arg(
        long = "alphamax",
        short = 'a',
        value_name = "A",
        allow_negative_numbers = true,
        conflicts_with = "corner_angle",
        help_heading = "Tracing",
        hide_short_help = true
    )]
    pub(crate) alphamax: Option<f64>,
    /// Drop shapes and holes smaller than this area (px²).
    ///
    /// Drop shapes and holes smaller than this area (px²): specks of dust, noise.
    #[arg(
        long,
        default_value_t = Config::DEFAULT.min_area,
        value_name = "PX2",
        allow_negative_numbers = true,
        help_heading = "Tracing"
    )]
    pub(crate) min_area: f64,
    /// potrace's speck size: drop shapes and holes of at most N pixels, the same as
    /// --min-area N+1 (areas of pixel outlines are whole numbers).
    #[arg(
        long = "turdsize",
        short = 't',
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = whole::<u32>,
        conflicts_with = "min_area",
        help_heading = "Tracing",
        hide_short_help = true
    )]
    pub(crate) turdsize: Option<u32>,
    /// Pixels darker than this (0–255) are the shape [default: Otsu's level].
    ///
    /// Foreground threshold, 0–255: pixels darker than this are the shape (lighter with
    /// --invert; more opaque when an image with transparency traces its alpha). Default:
    /// Otsu's level; the report's "threshold" gives the one used, on the same scale.
    #[arg(
        long,
        value_name = "0-255",
        allow_negative_numbers = true,
        value_parser = whole::<u8>,
        help_heading = "Input"
    )]
    pub(crate) threshold: Option<u8>,
    /// potrace's threshold, 0–1: pixels darker than L × 255 are the shape, the same as
    /// --threshold ⌈255·L⌉.
    #[arg(
        long = "blacklevel",
        short = 'k',
        value_name = "L",
        allow_negative_numbers = true,
        conflicts_with = "threshold",
        help_heading = "Input",
        hide_short_help = true
    )]
    pub(crate) blacklevel: Option<f64>,
    /// How the threshold applies: one for the whole image (global), or after the paper's
    /// uneven lighting is divided out (local; for scans and photos of pages). auto
    /// chooses local only when the global threshold would paint large areas of unevenly
    /// lit paper as ink; the report's "threshold_mode" says which was used. Images traced
    /// from their alpha channel always use global.
    #[arg(
        long,
        value_enum,
        default_value = "auto",
        value_name = "MODE",
        help_heading = "Input",
        hide_short_help = true
    )]
    pub(crate) threshold_mode: ThresholdModeArg,
    /// Trace the luminance (transparent pixels count as white paper) even when at least a
    /// tenth of the image is transparent, which otherwise traces its alpha channel.
    #[arg(long, help_heading = "Input", hide_short_help = true)]
    pub(crate) luminance: bool,
    /// Trace the alpha channel (opaque is the shape) even when less than a tenth of the
    /// image is transparent, which otherwise traces the luminance.
    #[arg(
        long,
        conflicts_with = "luminance",
        help_heading = "Input",
        hide_short_help = true
    )]
    pub(crate) alpha: bool,
    /// Trace light shapes on a dark background.
    ///
    /// Light shapes on a dark background (or inverted alpha) are the foreground.
    /// [potrace: -i/--invert]
    #[arg(long, short = 'i', help_heading = "Input")]
    pub(crate) invert: bool,
    /// Which frame of an animated GIF, PNG or WebP, or page of a TIFF file, to trace,
    /// from 0. A file with several gets a note saying which was traced.
    #[arg(long, default_value_t = Config::DEFAULT.frame, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>, help_heading = "Input", hide_short_help = true)]
    pub(crate) frame: u32,
    /// Refuse images with more pixels than this (protects memory).
    #[arg(long, default_value_t = Config::DEFAULT.max_pixels, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>, help_heading = "Input", hide_short_help = true)]
    pub(crate) max_pixels: u64,
}

impl ShapeArgs {
    /// The default configuration with these tracing settings; fails on a potrace-named
    /// value outside its range.
    pub(crate) fn config(&self) -> outlinefit::Result<Config> {
        let bad = |name: &'static str, message: String| outlinefit::Error::InvalidOption {
            name,
            message,
        };
        let threshold = match self.blacklevel {
            None => self.threshold,
            Some(l) if (0.0..=1.0).contains(&l) => Some((255.0 * l).ceil() as u8),
            Some(l) => {
                return Err(bad(
                    "blacklevel",
                    format!("must be between 0 and 1, not {l}"),
                ))
            }
        };
        let corner_angle = match self.alphamax {
            None => self.corner_angle,
            Some(a) if a > 0.0 && a < 4.0 / 3.0 => 135.0 * a,
            Some(a) => {
                return Err(bad(
                    "alphamax",
                    format!(
                        "must be above 0 and below 4/3 (every joint a corner, or none), not {a}"
                    ),
                ))
            }
        };
        let min_area = self.turdsize.map_or(self.min_area, |t| f64::from(t) + 1.0);
        Ok(Config {
            threshold,
            alpha: match (self.alpha, self.luminance) {
                (true, _) => AlphaRule::Alpha,
                (_, true) => AlphaRule::Luminance,
                _ => AlphaRule::Auto,
            },
            invert: self.invert,
            threshold_mode: self.threshold_mode.into(),
            max_pixels: self.max_pixels,
            frame: self.frame,
            min_area,
            corner_angle,
            tolerance: self.tolerance,
            edge_tolerance: !self.fixed_tolerance,
            ..Config::default()
        })
    }
}

/// Options shared by `trace` and `batch`: every parameter of the pipeline.
#[derive(Args, Debug, Clone)]
pub(crate) struct FitArgs {
    #[command(flatten)]
    pub(crate) shape: ShapeArgs,
    /// How each piece is fitted. `lsq` (default): least squares, split where the error
    /// is too large [separable least squares with error-driven splitting]. Any other name
    /// refits lsq's pieces with that search method from the papers, at fixed centripetal
    /// parameters: hs (harmony search), ga (genetic algorithm), pso (particle swarm), gwo
    /// (grey wolf), cs / ics (cuckoo search, improved), fwa (fireworks), so / beeso (snake
    /// optimizer, enhanced), de (differential evolution).
    #[arg(long, default_value = Config::DEFAULT.optimizer.name(), value_name = "NAME", value_parser = optimizer_names(), help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) optimizer: String,
    /// What a search method varies: `weights` (the two inner weights, control points by
    /// least squares; reaches the optimum) or `full` (control points and weights, as the
    /// harmony-search paper does [C1, C2, w1, w2]).
    #[arg(long, value_enum, default_value_t = Config::DEFAULT.search.into(), help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) search: SearchArg,
    /// Evaluations of the error per piece for a search method [objective evaluations].
    #[arg(long, default_value_t = Config::DEFAULT.budget, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) budget: u64,
    /// Widen the region where `full` looks for control points by this factor (1: the
    /// extent of each piece's data, which can exclude the best curve [the paper's Eq. 9
    /// box]).
    #[arg(
        long,
        default_value_t = Config::DEFAULT.search_box_scale,
        value_name = "S",
        allow_negative_numbers = true,
        help_heading = "Fitting (research)",
        hide_short_help = true
    )]
    pub(crate) search_box_scale: f64,
    /// Record each piece's best error so far after every evaluation in the JSON report
    /// (search methods only; large) [convergence history].
    #[arg(long, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) history: bool,
    /// Seed of every random choice; the same seed gives the same output on any number of
    /// threads.
    #[arg(long, default_value_t = Config::DEFAULT.seed, allow_negative_numbers = true, value_parser = whole::<u64>, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) seed: u64,
    /// Write 0 for every time in reports, so reports are byte-identical across runs.
    #[arg(long, help_heading = "Reports", hide_short_help = true)]
    pub(crate) no_timings: bool,
    /// After fitting, join runs of smooth pieces into single curves of higher degree whose
    /// centre line stays within --tolerance of the data, with a band of the fit's error
    /// around it [disk Wang–Ball curves]. The outline draws them (as cubics), the report
    /// lists them, --overlay shows their bands.
    #[arg(long, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) merge: bool,
    /// Degree of joined curves with --merge (3–20).
    #[arg(long, default_value_t = Config::DEFAULT.merge_degree, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) merge_degree: usize,
    /// Where smooth joints between pieces go: `curvature` (where the outline bends, then
    /// split where the error is too large) or `optimize` (same corners and number of
    /// pieces, smooth joints moved by --break-optimizer to lower the total error; never
    /// worse, typically a few times slower) [break points].
    #[arg(long, default_value = Config::DEFAULT.breaks.name(), value_name = "MODE", help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) breaks: String,
    /// The search method that places joints with --breaks optimize (fwa: fireworks, as in
    /// the paper; any name of --optimizer except lsq).
    #[arg(long, default_value = Config::DEFAULT.break_optimizer.name(), value_name = "NAME", help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) break_optimizer: String,
    /// Evaluations of the error per movable smooth joint with --breaks optimize.
    #[arg(long, default_value_t = Config::DEFAULT.break_budget, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>, help_heading = "Fitting (research)", hide_short_help = true)]
    pub(crate) break_budget: u64,
    /// Fail (exit 1, no outline written) when the drawn outline does not match the input
    /// after repair: an edge point farther from the drawn path than the tolerance allows,
    /// or a lost or invented region. Without it such an image gets a warning line and
    /// `"held": false` in the report.
    #[arg(long, help_heading = "Checking", hide_short_help = true)]
    pub(crate) strict: bool,
    /// Skip the end-to-end check of the drawn outline against the input and its repairs
    /// (faster; nothing then notices a lost or invented part).
    #[arg(
        long,
        conflicts_with = "strict",
        help_heading = "Checking",
        hide_short_help = true
    )]
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
            ..self.shape.config()?
        })
    }
}
