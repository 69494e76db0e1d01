//! `outlinefit batch`: every image of a folder, in parallel.

use super::{fidelity_problem, trace_warnings, FitArgs};
use anyhow::{bail, Context};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use outlinefit::export::svg::{to_svg, SvgOptions};
use outlinefit::io::write_atomic;
use outlinefit::{report, trace_file, Config, TraceResult};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// File extensions (lower case) that batch picks up.
const IMAGE_EXTENSIONS: &[&str] = &[
    "png", "jpg", "jpeg", "bmp", "gif", "tif", "tiff", "webp", "pbm", "pgm", "ppm", "pnm",
];

/// Arguments of `batch`.
#[derive(Args, Debug)]
pub(crate) struct BatchArgs {
    /// Folder of images.
    input: PathBuf,
    /// Output folder (created if missing); receives <name>.svg, <name>.json and summary.csv.
    #[arg(short = 'o', long = "output", value_name = "OUTDIR")]
    output: PathBuf,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Also trace images in sub-folders (their outputs mirror the folder structure).
    #[arg(long)]
    recursive: bool,
    /// Skip images whose SVG already exists in OUTDIR.
    #[arg(long)]
    skip_existing: bool,
    /// Process only shard K of N (1-based): the files whose position in the sorted list is
    /// K−1 modulo N, for splitting a huge folder over array jobs.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    /// Write only the SVGs (no per-image JSON report).
    #[arg(long)]
    svg_only: bool,
    #[command(flatten)]
    fit: FitArgs,
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("expected K/N, got {s:?}"))?;
    let k: usize = k
        .trim()
        .parse()
        .map_err(|_| format!("bad shard index in {s:?}"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("bad shard count in {s:?}"))?;
    if n == 0 || k == 0 || k > n {
        return Err(format!("shard must satisfy 1 ≤ K ≤ N, got {k}/{n}"));
    }
    Ok((k, n))
}

/// One input and where its outputs go (relative stem inside OUTDIR).
struct Job {
    input: PathBuf,
    stem: PathBuf,
}

/// The outcome of one file, for summary.csv.
struct Row {
    file: String,
    status: &'static str,
    message: String,
    segments: usize,
    curves: usize,
    sum_sq: f64,
    max_distance: f64,
    /// The fidelity check: "yes", "no", or empty when it did not run.
    held: &'static str,
    max_deviation: f64,
    largest_region: f64,
    warnings: Vec<String>,
    seconds: f64,
}

pub(crate) fn run(args: &BatchArgs) -> anyhow::Result<i32> {
    let config = args.fit.config()?;
    config.validate()?;
    if !args.input.is_dir() {
        bail!("{} is not a folder", args.input.display());
    }
    let mut files = Vec::new();
    collect_images(&args.input, args.recursive, &mut files)
        .with_context(|| format!("cannot list {}", args.input.display()))?;
    files.sort();
    let mut jobs = assign_stems(&args.input, files);
    if let Some((k, n)) = args.shard {
        jobs = jobs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k - 1)
            .map(|(_, j)| j)
            .collect();
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()?;
    let bar = ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} eta {eta} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let rows: Vec<Row> = pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let row = process(job, args, &config);
                bar.inc(1);
                if row.status == "failed" {
                    bar.suspend(|| eprintln!("error: {}: {}", row.file, row.message));
                }
                for w in &row.warnings {
                    bar.suspend(|| eprintln!("warning: {w}"));
                }
                row
            })
            .collect()
    });
    bar.finish_and_clear();
    let failed = rows.iter().filter(|r| r.status == "failed").count();
    write_summary(&args.output.join("summary.csv"), &rows)?;
    let done = rows.iter().filter(|r| r.status == "ok").count();
    let skipped = rows.iter().filter(|r| r.status == "skipped").count();
    eprintln!(
        "{done} traced, {skipped} skipped, {failed} failed; summary in {}",
        args.output.join("summary.csv").display()
    );
    Ok(if failed > 0 { 1 } else { 0 })
}

fn collect_images(dir: &Path, recursive: bool, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            if recursive {
                collect_images(&path, recursive, out)?;
            }
        } else if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| IMAGE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
        {
            out.push(path);
        }
    }
    Ok(())
}

/// Output stems relative to OUTDIR: the input's relative path without extension, or with
/// it (`a.png` → `a.png`) when two inputs of one folder share a stem.
fn assign_stems(root: &Path, files: Vec<PathBuf>) -> Vec<Job> {
    let rel = |p: &Path| p.strip_prefix(root).unwrap_or(p).to_path_buf();
    let mut count: HashMap<PathBuf, usize> = HashMap::new();
    for f in &files {
        *count.entry(rel(f).with_extension("")).or_default() += 1;
    }
    files
        .into_iter()
        .map(|input| {
            let r = rel(&input);
            let plain = r.with_extension("");
            let stem = if count.get(&plain).copied().unwrap_or(0) > 1 {
                r
            } else {
                plain
            };
            Job { input, stem }
        })
        .collect()
}

fn with_suffix(base: &Path, suffix: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

fn process(job: &Job, args: &BatchArgs, config: &Config) -> Row {
    let file = job.input.display().to_string();
    let base = args.output.join(&job.stem);
    let svg_path = with_suffix(&base, ".svg");
    let mut row = Row {
        file,
        status: "ok",
        message: String::new(),
        segments: 0,
        curves: 0,
        sum_sq: 0.0,
        max_distance: 0.0,
        held: "",
        max_deviation: 0.0,
        largest_region: 0.0,
        warnings: Vec::new(),
        seconds: 0.0,
    };
    if args.skip_existing && svg_path.exists() {
        row.status = "skipped";
        return row;
    }
    let started = Instant::now();
    let outcome = (|| -> anyhow::Result<TraceResult> {
        if let Some(parent) = svg_path.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create {}", parent.display()))?;
        }
        let result = trace_file(&job.input, config)?;
        if args.fit.strict {
            if let Some(problem) = fidelity_problem(config, &result) {
                bail!("{problem}; nothing written (--strict)");
            }
        }
        if !args.svg_only {
            let json = report::to_json(config, &[(&row.file, &result)], false);
            write_atomic(&with_suffix(&base, ".json"), json.as_bytes())?;
        }
        write_atomic(
            &svg_path,
            to_svg(&result, &SvgOptions::for_tolerance(config.tolerance)).as_bytes(),
        )?;
        Ok(result)
    })();
    match outcome {
        Ok(result) => {
            row.segments = result.segment_count();
            row.curves = result.curve_count();
            row.sum_sq = result.sum_sq();
            row.max_distance = result.max_distance();
            if config.check {
                row.held = if result.fidelity.held { "yes" } else { "no" };
                row.max_deviation = result.fidelity.max_deviation;
                row.largest_region = result.fidelity.largest_region;
            }
            row.warnings = trace_warnings(&row.file, config, &result);
            row.seconds = if config.timings {
                started.elapsed().as_secs_f64()
            } else {
                0.0
            };
        }
        Err(e) => {
            row.status = "failed";
            let mut msg = e.to_string();
            let mut src = e.source();
            while let Some(s) = src {
                let t = s.to_string();
                if !msg.contains(&t) {
                    msg.push_str(": ");
                    msg.push_str(&t);
                }
                src = s.source();
            }
            row.message = msg;
        }
    }
    row
}

fn write_summary(path: &Path, rows: &[Row]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "file",
        "status",
        "segments",
        "curves",
        "sum_sq",
        "max_distance",
        "fidelity_held",
        "max_deviation",
        "largest_region",
        "seconds",
        "error",
    ])?;
    for r in rows {
        w.write_record([
            r.file.clone(),
            r.status.to_string(),
            r.segments.to_string(),
            r.curves.to_string(),
            r.sum_sq.to_string(),
            r.max_distance.to_string(),
            r.held.to_string(),
            r.max_deviation.to_string(),
            r.largest_region.to_string(),
            r.seconds.to_string(),
            r.message.clone(),
        ])?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot build summary: {e}"))?;
    write_atomic(path, &bytes)?;
    Ok(())
}
