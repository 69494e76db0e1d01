//! `outlinefit compare`: optimizers side by side on the same segmentation, with statistics.

use super::args::{whole, SearchArg, ShapeArgs};
use anyhow::{bail, Context};
use clap::builder::PossibleValuesParser;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use outlinefit::optim::Algorithm;
use outlinefit::Config;
use outlinefit_lab::compare::{compare_image, image_stems, output, statistics, CompareOptions};
use std::path::PathBuf;

/// Arguments of `compare`.
#[derive(Args, Debug)]
pub(crate) struct CompareArgs {
    /// Images to compare on; each is traced once with lsq and its segments are refitted by
    /// every optimizer.
    #[arg(required = true, value_name = "IMAGE")]
    images: Vec<PathBuf>,
    /// Output folder (created if missing): summary.md, summary.csv, segments.csv,
    /// stats.json and <image>-{convergence,boxplot,segments}.svg.
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    output: PathBuf,
    /// Optimizers to compare, comma-separated (default: all). The separable least-squares
    /// optimum (lsq) is always the reference row.
    #[arg(long, value_delimiter = ',', value_name = "NAMES", value_parser = optimizer_list())]
    optimizers: Vec<String>,
    /// Independent runs per optimizer (the HS paper used 30).
    #[arg(long, default_value_t = outlinefit_lab::compare::DEFAULT_RUNS, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    runs: usize,
    /// Objective evaluations per segment and run, the same for every optimizer.
    #[arg(long, default_value_t = Config::DEFAULT.budget, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Search space: `weights` (w1, w2 with control points by least squares) or `full`
    /// (the HS paper's C1, C2, w1, w2, as in its experiments).
    #[arg(long, value_enum, default_value_t = Config::DEFAULT.search.into())]
    search: SearchArg,
    /// Widen the `full` search's control-point box by this factor (1 = the paper's Eq. 9).
    #[arg(
        long,
        default_value_t = Config::DEFAULT.search_box_scale,
        value_name = "S",
        allow_negative_numbers = true
    )]
    search_box_scale: f64,
    /// Base seed; run r of every optimizer uses the same seed derived from it, so the same
    /// seed gives the same numbers on any number of threads.
    #[arg(long, default_value_t = Config::DEFAULT.seed, allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// Points kept per convergence curve (evenly spaced evaluation counts).
    #[arg(long, default_value_t = outlinefit_lab::compare::DEFAULT_HISTORY_POINTS, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    history_points: usize,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    jobs: Option<usize>,
    #[command(flatten)]
    shape: ShapeArgs,
}

/// The metaheuristics' names and `lsq` (accepted and ignored: it is always the reference).
fn optimizer_list() -> PossibleValuesParser {
    PossibleValuesParser::new(
        std::iter::once("lsq").chain(outlinefit::optim::NAMES.iter().copied()),
    )
}

pub(crate) fn run(args: &CompareArgs) -> anyhow::Result<i32> {
    let mut optimizers: Vec<Algorithm> = Vec::new();
    let requested: Vec<&str> = if args.optimizers.is_empty() {
        outlinefit::optim::NAMES.to_vec()
    } else {
        args.optimizers.iter().map(String::as_str).collect()
    };
    // `lsq` (not a metaheuristic) is the reference every comparison has anyway.
    for a in requested.into_iter().filter_map(Algorithm::from_name) {
        if !optimizers.contains(&a) {
            optimizers.push(a);
        }
    }
    let opts = CompareOptions {
        optimizers,
        runs: args.runs,
        budget: args.budget,
        search: args.search.into(),
        seed: args.seed,
        search_box_scale: args.search_box_scale,
        history_points: args.history_points,
        trace: outlinefit::Config {
            timings: false,
            ..args.shape.config()?
        },
    };
    opts.validate()?;
    for image in &args.images {
        if !image.is_file() {
            bail!("{} is not a file", image.display());
        }
    }
    if args.output.exists() && !args.output.is_dir() {
        bail!("{} exists and is not a folder", args.output.display());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()?;
    let total = (args.images.len() * opts.optimizers.len() * opts.runs) as u64;
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs {elapsed_precise} eta {eta} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut images = Vec::with_capacity(args.images.len());
    for path in &args.images {
        bar.set_message(path.display().to_string());
        let tick = || bar.inc(1);
        // Library errors name the file already.
        let image = pool.install(|| compare_image(path, &opts, &tick))?;
        images.push(image);
    }
    bar.finish_and_clear();
    // The folder is made only now, so a failed comparison leaves nothing behind.
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    let stats: Vec<_> = images.iter().map(statistics).collect();
    let stems = image_stems(&args.images);
    output::write_all(&args.output, &opts, &images, &stats, &stems)?;
    eprintln!(
        "{} optimizers × {} runs on {} image(s); report in {}",
        opts.optimizers.len(),
        opts.runs,
        images.len(),
        args.output.join("summary.md").display()
    );
    Ok(0)
}
