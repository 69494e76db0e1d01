//! Command definitions (clap derive) and dispatch.

mod batch;
mod bspline;
mod compare;
mod merge;
mod output;
mod reduce;
mod surface;
mod trace;

use clap::builder::PossibleValuesParser;
use clap::{Args, Parser, Subcommand, ValueEnum};
use outlinefit::raster::AlphaRule;
use outlinefit::{Config, Search, TraceResult};
use std::path::PathBuf;

/// Trace bitmap outlines into G1-continuous rational cubic Bézier curves, with a
/// per-segment error report.
#[derive(Parser, Debug)]
#[command(name = "outlinefit", version, about, long_about = None, after_help = EXIT_STATUS)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The exit statuses, shown under every command's `--help` (the README has the same table).
const EXIT_STATUS: &str = "\
Exit status:
  0    everything done
  1    an input, an output or an option's value was refused (batch: at least one
       file failed; the others are still done)
  2    the command line does not parse: unknown option, missing or malformed value
       (a negative or fractional count included)
  130  interrupted (SIGINT, SIGTERM); outputs not yet written are missing";

#[derive(Subcommand, Debug)]
enum Command {
    /// Trace one image into an SVG outline (and optional JSON/CSV reports and overlay).
    #[command(after_help = EXIT_STATUS)]
    Trace(trace::TraceArgs),
    /// Trace every image of a folder in parallel into OUTDIR/<name>.svg and <name>.json,
    /// with OUTDIR/summary.csv.
    #[command(after_help = EXIT_STATUS)]
    Batch(batch::BatchArgs),
    /// Compare optimizers on the same segmentation of one or more images: many seeded runs
    /// each, descriptive statistics, normality, F-, t-tests and ANOVA, charts.
    #[command(after_help = EXIT_STATUS)]
    Compare(compare::CompareArgs),
    /// Convert a parametric curve x(u), y(u) into a B-spline: curvature feature points plus
    /// auxiliary samples placed by the fireworks algorithm (or another optimizer); JSON on
    /// stdout.
    #[command(after_help = EXIT_STATUS)]
    Bspline(bspline::BsplineArgs),
    /// Merge two adjacent disk Wang–Ball curves into one of a given degree, exactly (least
    /// squares) or by a metaheuristic; prints the control disks and merging error as JSON.
    #[command(after_help = EXIT_STATUS)]
    Merge(merge::MergeArgs),
    /// Reduce the degree of an (SG-)Bézier curve from n to m < n (unconstrained, C0 or C1
    /// ends), exactly (least squares) or with a metaheuristic searching the shape
    /// parameters; prints the reduced control points and the L2 error as JSON.
    #[command(after_help = EXIT_STATUS)]
    Reduce(reduce::ReduceArgs),
    /// Fit a Bézier surface to a cloud of 3-D points (a grid or unorganized): parameters by
    /// correction (default), the classical rules or cuckoo search, poles by least squares;
    /// writes the poles and errors (JSON), a mesh (OBJ) and a picture (SVG). --rerun
    /// repeats the surface paper's experiment.
    #[command(after_help = EXIT_STATUS)]
    Surface(surface::SurfaceArgs),
}

/// What a metaheuristic searches, as named on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum SearchArg {
    /// The HS paper's formulation: C1, C2, w1, w2 (odd segments free, even ones
    /// constrained for G1).
    Full,
    /// Only the weights w1, w2; control points by least squares (separable, exact G1).
    Weights,
}

impl From<SearchArg> for Search {
    fn from(s: SearchArg) -> Search {
        match s {
            SearchArg::Full => Search::Full,
            SearchArg::Weights => Search::Weights,
        }
    }
}

/// Parses a whole number for an unsigned option, so that a negative or fractional value is
/// refused with its range rather than clap's "unexpected argument" or "invalid digit".
fn whole<T: TryFrom<i128>>(s: &str) -> Result<T, String> {
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
fn optimizer_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        std::iter::once("lsq").chain(outlinefit::optim::NAMES.iter().copied()),
    )
}

/// How outlines are found and segmented: options shared by `trace`, `batch` and
/// `compare`.
#[derive(Args, Debug, Clone)]
struct ShapeArgs {
    /// Largest distance (px) allowed between a data point and its curve (lsq).
    /// 0.3 px sits well above the ~0.05 px noise of sub-pixel edges, and on the development
    /// corpus it beats potrace's area error by 2.8× (64 px glyphs) to 3.3× (256 px) with
    /// fewer segments; 0.4 saves ~10% of segments but misses the 64 px area target.
    #[arg(
        long,
        default_value_t = 0.3,
        value_name = "PX",
        allow_negative_numbers = true
    )]
    tolerance: f64,
    /// Turning angle (degrees) above which a point is a corner (G0 joint).
    #[arg(
        long,
        default_value_t = 50.0,
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    corner_angle: f64,
    /// Drop shapes and holes smaller than this area (px²), like potrace's turdsize.
    #[arg(
        long,
        default_value_t = 2.0,
        value_name = "PX2",
        allow_negative_numbers = true
    )]
    min_area: f64,
    /// Foreground threshold, 0–255: pixels darker than this are the shape (lighter with
    /// --invert; more opaque when an image with transparency traces its alpha). Default:
    /// Otsu's level; the report's "threshold" gives the one used, on the same scale.
    #[arg(long, value_name = "0-255", allow_negative_numbers = true, value_parser = whole::<u8>)]
    threshold: Option<u8>,
    /// Trace the luminance (transparent pixels count as white paper) even when at least a
    /// tenth of the image is transparent, which otherwise traces its alpha channel.
    #[arg(long)]
    luminance: bool,
    /// Trace the alpha channel (opaque is the shape) even when less than a tenth of the
    /// image is transparent, which otherwise traces the luminance.
    #[arg(long, conflicts_with = "luminance")]
    alpha: bool,
    /// Light shapes on a dark background (or inverted alpha) are the foreground.
    #[arg(long)]
    invert: bool,
    /// Which frame of an animated GIF, PNG or WebP, or page of a TIFF file, to trace,
    /// from 0. A file with several gets a note saying which was traced.
    #[arg(long, default_value_t = 0, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>)]
    frame: u32,
    /// Refuse images with more pixels than this (protects memory).
    #[arg(long, default_value_t = 50_000_000, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    max_pixels: u64,
}

impl ShapeArgs {
    /// The default configuration with these tracing settings.
    fn config(&self) -> Config {
        Config {
            threshold: self.threshold,
            alpha: match (self.alpha, self.luminance) {
                (true, _) => AlphaRule::Alpha,
                (_, true) => AlphaRule::Luminance,
                _ => AlphaRule::Auto,
            },
            invert: self.invert,
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
struct FitArgs {
    #[command(flatten)]
    shape: ShapeArgs,
    /// Fitting method. `lsq` (default): separable least squares with error-driven
    /// splitting. Any other name refits the lsq segmentation with that metaheuristic at
    /// fixed centripetal parameters: hs (harmony search), ga (genetic algorithm), pso
    /// (particle swarm), gwo (grey wolf), cs / ics (cuckoo search, improved), fwa
    /// (fireworks), so / beeso (snake optimizer, enhanced), de (differential evolution).
    #[arg(long, default_value = "lsq", value_name = "NAME", value_parser = optimizer_names())]
    optimizer: String,
    /// What a metaheuristic searches: `weights` (w1, w2; control points by least squares,
    /// reaches the optimum) or `full` (the HS paper's C1, C2, w1, w2).
    #[arg(long, value_enum, default_value_t = SearchArg::Weights)]
    search: SearchArg,
    /// Objective evaluations per segment for a metaheuristic.
    #[arg(long, default_value_t = 5000, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Widen the `full` search's control-point box by this factor (1 = the paper's box of
    /// Eq. 9, the extent of each segment's data, which can exclude the optimum).
    #[arg(
        long,
        default_value_t = 1.0,
        value_name = "S",
        allow_negative_numbers = true
    )]
    search_box_scale: f64,
    /// Record each segment's best-so-far error after every evaluation in the JSON report
    /// (metaheuristics only; large).
    #[arg(long)]
    history: bool,
    /// Seed of every random choice; the same seed gives the same output on any number of
    /// threads.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// Write 0 for every time in reports, so reports are byte-identical across runs.
    #[arg(long)]
    no_timings: bool,
    /// After fitting, merge runs of smooth segments into single disk Wang–Ball curves whose
    /// center line stays within --tolerance of the data; the disk radii carry the fit-error
    /// band. The SVG draws merged curves (as cubics), the report lists them, --overlay
    /// shows their bands.
    #[arg(long)]
    merge: bool,
    /// Degree of merged curves (3–20).
    #[arg(long, default_value_t = 5, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    merge_degree: usize,
    /// Where smooth break points go: `curvature` (curvature analysis and error-driven
    /// splitting) or `optimize` (same corners and segment count, smooth joints moved by
    /// --break-optimizer to lower the total error; never worse, typically a few times
    /// slower than curvature).
    #[arg(long, default_value = "curvature", value_name = "MODE")]
    breaks: String,
    /// The metaheuristic that places break points with --breaks optimize (fwa: fireworks,
    /// as in the paper; any name of --optimizer except lsq).
    #[arg(long, default_value = outlinefit::fit::break_placement::DEFAULT_OPTIMIZER, value_name = "NAME")]
    break_optimizer: String,
    /// Objective evaluations per movable smooth joint with --breaks optimize.
    #[arg(long, default_value_t = outlinefit::fit::break_placement::DEFAULT_BUDGET, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    break_budget: u64,
    /// Fail (exit 1, no SVG written) when the drawn outline does not match the input after
    /// repair: a data point farther from the drawn path than the tolerance allows, or a
    /// lost or invented region. Without it such an image gets a warning line and
    /// `"held": false` in the report.
    #[arg(long)]
    strict: bool,
    /// Skip the end-to-end check of the drawn outline against the input and its repairs
    /// (faster; nothing then notices a lost or invented part).
    #[arg(long, conflicts_with = "strict")]
    no_check: bool,
}

impl FitArgs {
    /// The configuration; fails on an unknown `--breaks` mode (the other values are
    /// checked by [`Config::validate`]).
    fn config(&self) -> outlinefit::Result<Config> {
        Ok(Config {
            optimizer: self.optimizer.clone(),
            search: self.search.into(),
            budget: self.budget,
            search_box_scale: self.search_box_scale,
            history: self.history,
            seed: self.seed,
            timings: !self.no_timings,
            merge: self.merge,
            merge_degree: self.merge_degree,
            breaks: self.breaks.parse()?,
            break_optimizer: self.break_optimizer.clone(),
            break_budget: self.break_budget,
            check: !self.no_check,
            ..self.shape.config()
        })
    }
}

/// The warnings and notes a trace deserves, one line each with its `warning: ` or `note: `
/// prefix: a polarity that looks wrong, a drawn outline that does not match the input, and
/// which frame of a file with several was traced.
pub(crate) fn trace_warnings(name: &str, config: &Config, result: &TraceResult) -> Vec<String> {
    let mut out = Vec::new();
    let (frame, frames) = (result.image.frame, result.image.frames);
    if frames > 1 {
        out.push(format!(
            "note: {name}: traced frame {frame} of {frames} (counted from 0; --frame N picks another)"
        ));
    }
    if result.image.dark_border {
        out.push(if config.invert {
            format!(
                "warning: {name}: most of the image border is foreground with --invert; if the shapes are dark on a light background, leave --invert out"
            )
        } else {
            format!(
                "warning: {name}: most of the image border is foreground; if the shapes are light on a dark background, use --invert"
            )
        });
    }
    if let Some(problem) = fidelity_problem(config, result) {
        out.push(format!("warning: {name}: {problem}"));
    }
    out
}

/// What is wrong with the trace's fidelity, if the check ran and did not hold.
pub(crate) fn fidelity_problem(config: &Config, result: &TraceResult) -> Option<String> {
    let f = &result.fidelity;
    if !config.check || f.held {
        return None;
    }
    let mut parts = Vec::new();
    if f.max_deviation > f.deviation_limit {
        parts.push(format!(
            "a data point lies {:.2} px from the drawn outline (limit {:.2} px)",
            f.max_deviation, f.deviation_limit
        ));
    }
    if f.largest_region > f.region_limit {
        let at = f.region_box.map_or(String::new(), |[x0, y0, x1, y1]| {
            format!(" at pixels ({x0},{y0})-({x1},{y1})")
        });
        parts.push(format!(
            "a region of {:.0} px² is lost or invented{at}",
            f.largest_region
        ));
    }
    Some(format!(
        "the drawn outline does not match the input: {} (see \"fidelity\" in the report)",
        parts.join("; ")
    ))
}

/// Parses the command line and runs it; returns the exit code.
pub(crate) fn run() -> anyhow::Result<i32> {
    let cli = Cli::parse();
    match cli.command {
        Command::Trace(args) => trace::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Reduce(args) => reduce::run(&args),
        Command::Bspline(args) => bspline::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Surface(args) => surface::run(&args),
    }
}

/// The default SVG path for an input: the input's name with `.svg`, in the same folder.
fn default_svg_path(input: &std::path::Path) -> PathBuf {
    input.with_extension("svg")
}
