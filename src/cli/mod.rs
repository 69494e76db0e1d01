//! Command definitions (clap derive) and dispatch.

mod batch;
mod trace;

use clap::{Args, Parser, Subcommand, ValueEnum};
use outlinefit::{Config, Strategy};
use std::path::PathBuf;

/// Trace bitmap outlines into G1-continuous rational cubic Bézier curves, with a
/// per-segment error report.
#[derive(Parser, Debug)]
#[command(name = "outlinefit", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Trace one image into an SVG outline (and optional JSON/CSV reports and overlay).
    Trace(trace::TraceArgs),
    /// Trace every image of a folder in parallel into OUTDIR/<name>.svg and <name>.json,
    /// with OUTDIR/summary.csv.
    Batch(batch::BatchArgs),
}

/// The fitting strategy, as named on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum OptimizerName {
    /// Separable least squares with exact G1 joints (default).
    Lsq,
    /// Harmony search over C1, C2, w1, w2 as in the HS paper.
    Hs,
}

/// Options shared by `trace` and `batch`: every parameter of the pipeline.
#[derive(Args, Debug, Clone)]
struct FitArgs {
    /// Largest distance (px) allowed between a data point and its curve (lsq).
    /// 0.3 px sits well above the ~0.05 px noise of sub-pixel edges, and on the development
    /// corpus it beats potrace's area error by 2.8× (64 px glyphs) to 3.3× (256 px) with
    /// fewer segments; 0.4 saves ~10% of segments but misses the 64 px area target.
    #[arg(long, default_value_t = 0.3, value_name = "PX")]
    tolerance: f64,
    /// Turning angle (degrees) above which a point is a corner (G0 joint).
    #[arg(long, default_value_t = 50.0, value_name = "DEG")]
    corner_angle: f64,
    /// Drop shapes and holes smaller than this area (px²), like potrace's turdsize.
    #[arg(long, default_value_t = 2.0, value_name = "PX2")]
    min_area: f64,
    /// Foreground threshold on the 0–255 coverage scale (default: Otsu's level).
    #[arg(long, value_name = "0-255")]
    threshold: Option<u8>,
    /// Light shapes on a dark background (or inverted alpha) are the foreground.
    #[arg(long)]
    invert: bool,
    /// Refuse images with more pixels than this (protects memory).
    #[arg(long, default_value_t = 50_000_000, value_name = "N")]
    max_pixels: u64,
    /// Fitting method: lsq (default) or hs (the harmony-search paper's scheme).
    #[arg(long, value_enum, default_value_t = OptimizerName::Lsq)]
    optimizer: OptimizerName,
    /// Objective evaluations per segment for metaheuristic optimizers (hs).
    #[arg(long, default_value_t = 5000, value_name = "N")]
    budget: u64,
    /// Widen the hs control-point search box by this factor (1 = the paper's box of Eq. 9,
    /// the extent of each segment's data, which can exclude the optimum).
    #[arg(long, default_value_t = 1.0, value_name = "S")]
    search_box_scale: f64,
    /// Seed of every random choice; the same seed gives the same output on any number of
    /// threads.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write 0 for every time in reports, so reports are byte-identical across runs.
    #[arg(long)]
    no_timings: bool,
}

impl FitArgs {
    fn config(&self) -> Config {
        Config {
            threshold: self.threshold,
            invert: self.invert,
            max_pixels: self.max_pixels,
            min_area: self.min_area,
            corner_angle: self.corner_angle,
            tolerance: self.tolerance,
            strategy: match self.optimizer {
                OptimizerName::Lsq => Strategy::Lsq,
                OptimizerName::Hs => Strategy::Hs,
            },
            budget: self.budget,
            search_box_scale: self.search_box_scale,
            seed: self.seed,
            timings: !self.no_timings,
        }
    }
}

/// Parses the command line and runs it; returns the exit code.
pub(crate) fn run() -> anyhow::Result<i32> {
    let cli = Cli::parse();
    match cli.command {
        Command::Trace(args) => trace::run(&args),
        Command::Batch(args) => batch::run(&args),
    }
}

/// True when `p` means standard output.
fn is_stdout(p: &std::path::Path) -> bool {
    p.as_os_str() == "-"
}

/// The default SVG path for an input: the input's name with `.svg`, in the same folder.
fn default_svg_path(input: &std::path::Path) -> PathBuf {
    input.with_extension("svg")
}
