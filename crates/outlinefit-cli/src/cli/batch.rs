//! `outlinefit batch`: every image of a folder, in parallel.

use super::args::{whole, FitArgs};
use super::centerline::{centerline_problem, centerline_warnings, ModeArgs};
use super::colour::{colour_problem, colour_warnings, ColourArgs};
use super::format::FormatArgs;
use super::messages::{error_line, fidelity_problem, panic_message, trace_warnings};
use super::output::resolve_output;
use anyhow::{bail, Context};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use outlinefit::centerline::{self, trace_centerline, CenterlineResult, StrokeWidth};
use outlinefit::colour::{self, ColourOptions, ColourTrace};
use outlinefit::io::{remove_stale_temporaries, write_atomic, write_atomic_with};
use outlinefit::{export, report, trace_file, Bitmap, Config, ExportOptions, Format, TraceResult};
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};
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
    /// Output folder: <name>.svg (or the --format's ending), <name>.json, summary.csv.
    ///
    /// Output folder (created if missing); receives <name>.svg (or the --format's ending),
    /// <name>.json and summary.csv.
    #[arg(short = 'o', long = "output", value_name = "OUTDIR")]
    output: PathBuf,
    /// Worker threads [default: all cores].
    ///
    /// Worker threads (default: all cores; at most 8 per core). Results do not depend on
    /// it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..), allow_negative_numbers = true)]
    jobs: Option<u16>,
    /// Also trace images in sub-folders.
    ///
    /// Also trace images in sub-folders (their outputs mirror the folder structure). Links
    /// to folders are not followed unless --follow-symlinks is given; no folder is visited
    /// twice.
    #[arg(long)]
    recursive: bool,
    /// Follow symbolic links to folders with --recursive, and write through outputs that
    /// are links (to their targets).
    #[arg(long, hide_short_help = true)]
    follow_symlinks: bool,
    /// Skip images whose outline (in the --format) already exists in OUTDIR.
    #[arg(long)]
    skip_existing: bool,
    /// Process only shard K of N (1-based), for array jobs.
    ///
    /// Process only shard K of N (1-based): the files whose position in the sorted list is
    /// K−1 modulo N, for splitting a huge folder over array jobs (docs/cluster.md;
    /// `outlinefit summary merge` joins their summaries).
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    /// The shard as a 0-based index, with --shard-count: `--shard-index I --shard-count
    /// N` is `--shard I+1/N` (for schedulers that hand out 0-based indices, such as a
    /// Kubernetes Indexed Job's JOB_COMPLETION_INDEX).
    #[arg(long, value_name = "I", requires = "shard_count", conflicts_with = "shard", value_parser = whole::<usize>, hide_short_help = true)]
    shard_index: Option<usize>,
    /// Number of shards, with --shard-index.
    #[arg(long, value_name = "N", requires = "shard_index", value_parser = whole::<usize>, hide_short_help = true)]
    shard_count: Option<usize>,
    /// Write only the outlines (no per-image JSON report).
    ///
    /// Write only the outlines (no per-image JSON report); the name is older than
    /// --format and holds for every format.
    #[arg(long, visible_alias = "outline-only")]
    svg_only: bool,
    #[command(flatten)]
    output_format: FormatArgs,
    #[command(flatten)]
    colour: ColourArgs,
    #[command(flatten)]
    mode: ModeArgs,
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
    let format = args.output_format.format_for(None)?;
    let export_options = args.output_format.options(config.tolerance, format)?;
    if let Some(note) = args.output_format.note(format) {
        eprintln!("{note}");
    }
    let writing = Writing {
        format,
        options: export_options,
        colour: args.colour.options(&config, format)?,
        centerline: None,
    };
    let writing = Writing {
        centerline: args
            .mode
            .centerline(&args.fit, &config, format, writing.colour.is_some())?,
        ..writing
    };
    if !args.input.is_dir() {
        bail!("{} is not a folder", args.input.display());
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = match args.jobs {
        Some(j) if usize::from(j) > MAX_JOBS_PER_CORE * cores => bail!(
            "--jobs {j} is more than {MAX_JOBS_PER_CORE} per core ({cores} cores: at most {})",
            MAX_JOBS_PER_CORE * cores
        ),
        Some(j) => usize::from(j),
        None => 0,
    };
    let files = list_images(&args.input, args.recursive, args.follow_symlinks)
        .with_context(|| format!("cannot list {}", args.input.display()))?;
    let mut jobs = assign_stems(&args.input, files);
    let shard = match (args.shard, args.shard_index, args.shard_count) {
        (Some(shard), _, _) => Some(shard),
        (None, Some(i), Some(n)) if i < n => Some((i + 1, n)),
        (None, Some(i), Some(n)) => {
            bail!("--shard-index {i} is not below --shard-count {n} (indices count from 0)")
        }
        _ => None,
    };
    if let Some((k, n)) = shard {
        jobs = jobs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k - 1)
            .map(|(_, j)| j)
            .collect();
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    // Debris of an earlier run that was killed mid-write.
    let mut folders: Vec<PathBuf> = jobs
        .iter()
        .filter_map(|j| args.output.join(&j.stem).parent().map(Path::to_path_buf))
        .collect();
    folders.push(args.output.clone());
    folders.sort();
    folders.dedup();
    let stale: usize = folders.iter().map(|d| remove_stale_temporaries(d)).sum();
    if stale > 0 {
        eprintln!("removed {stale} temporary files left by an interrupted run");
    }
    // Until the run finishes, summary.csv says that it has not: an interrupted run never
    // leaves the summary of an earlier one behind.
    let summary_path = resolve_output(&args.output.join("summary.csv"), args.follow_symlinks)?;
    write_summary(&summary_path, &[], false)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let bar = ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} eta {eta} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let rows: Vec<Row> = pool.install(|| {
        // One task per file: a run of files handed to a thread as one task cannot be
        // shared once it starts, and files that take long sort together (the stress
        // shapes, whose checks repair), so the last such run kept one core busy alone.
        jobs.par_iter()
            .with_max_len(1)
            .map(|job| {
                let row = process(job, args, &config, &writing);
                bar.inc(1);
                if row.status == "failed" {
                    // Decoding errors already name the file.
                    let line = if row.message.starts_with(&row.file) {
                        row.message.clone()
                    } else {
                        format!("{}: {}", row.file, row.message)
                    };
                    bar.suspend(|| eprintln!("error: {line}"));
                }
                for w in &row.warnings {
                    bar.suspend(|| eprintln!("{w}"));
                }
                row
            })
            .collect()
    });
    bar.finish_and_clear();
    let failed = rows.iter().filter(|r| r.status == "failed").count();
    write_summary(&summary_path, &rows, true)?;
    let done = rows.iter().filter(|r| r.status == "ok").count();
    let skipped = rows.iter().filter(|r| r.status == "skipped").count();
    eprintln!(
        "{done} traced, {skipped} skipped, {failed} failed; summary in {}",
        args.output.join("summary.csv").display()
    );
    Ok(if failed > 0 { 1 } else { 0 })
}

/// Largest --jobs per core: more threads only add memory (each holds a whole image).
const MAX_JOBS_PER_CORE: usize = 8;

/// The images `batch` traces in `dir`, sorted: the order of the jobs, of the summary's
/// rows and of `--shard`'s split.
pub(crate) fn list_images(
    dir: &Path,
    recursive: bool,
    follow_symlinks: bool,
) -> std::io::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut visited = HashSet::new();
    collect_images(dir, recursive, follow_symlinks, &mut visited, &mut files)?;
    files.sort();
    Ok(files)
}

/// The images of `dir` (and its sub-folders with --recursive): links to folders only with
/// --follow-symlinks, and each folder once (by its canonical path), so a link loop ends.
fn collect_images(
    dir: &Path,
    recursive: bool,
    follow_symlinks: bool,
    visited: &mut HashSet<PathBuf>,
    out: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    if !visited.insert(dir.canonicalize()?) {
        return Ok(());
    }
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let path = entry.path();
        let link = entry.file_type()?.is_symlink();
        if path.is_dir() {
            if recursive && (!link || follow_symlinks) {
                collect_images(&path, recursive, follow_symlinks, visited, out)?;
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

/// Output stems relative to OUTDIR, unique whatever the names (files sorted first, so
/// the choice is deterministic): the input's relative path without its extension; for
/// inputs that share it, the path with the extension (`a.png` → `a.png.svg`); where that
/// still meets another stem (`a.png` beside `a.png.jpg`), `~2`, `~3`, … appended in
/// sorted order. Stems are compared ignoring case, for case-insensitive file systems.
fn assign_stems(root: &Path, files: Vec<PathBuf>) -> Vec<Job> {
    let rel = |p: &Path| p.strip_prefix(root).unwrap_or(p).to_path_buf();
    let key = |p: &Path| p.to_string_lossy().to_lowercase();
    let mut count: HashMap<String, usize> = HashMap::new();
    for f in &files {
        *count.entry(key(&rel(f).with_extension(""))).or_default() += 1;
    }
    let mut taken: HashSet<String> = HashSet::new();
    files
        .into_iter()
        .map(|input| {
            let r = rel(&input);
            let plain = r.with_extension("");
            let mut stem = if count.get(&key(&plain)).copied().unwrap_or(0) > 1 {
                r
            } else {
                plain
            };
            let base = stem.clone();
            let mut k = 2;
            while !taken.insert(key(&stem)) {
                stem = with_suffix(&base, &format!("~{k}"));
                k += 1;
            }
            Job { input, stem }
        })
        .collect()
}

fn with_suffix(base: &Path, suffix: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

/// The outline's format and how it is written.
struct Writing {
    format: Format,
    options: ExportOptions,
    /// Colour tracing (`--palette`), or `None` for one shape.
    colour: Option<ColourOptions>,
    /// The stroke width of centre-line tracing (`--mode centerline`), or `None`.
    centerline: Option<StrokeWidth>,
}

/// What one file's trace gave, for its summary row.
enum Traced {
    Shape(TraceResult),
    Centerline(CenterlineResult),
    Colour(ColourTrace),
}

fn process(job: &Job, args: &BatchArgs, config: &Config, writing: &Writing) -> Row {
    let file = job.input.display().to_string();
    let base = args.output.join(&job.stem);
    let out_path = with_suffix(&base, &format!(".{}", writing.format.extension()));
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
    if args.skip_existing && out_path.exists() {
        row.status = "skipped";
        return row;
    }
    let started = Instant::now();
    // Each file is traced in isolation: a panic anywhere in its pipeline (a bug, which the
    // panic message on standard error reports) fails this file's row, and the batch goes on.
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
        || -> anyhow::Result<Traced> {
            if let Some(parent) = out_path.parent() {
                std::fs::create_dir_all(parent)
                    .with_context(|| format!("cannot create {}", parent.display()))?;
            }
            if let Some(opts) = &writing.colour {
                let trace = colour::trace_colour_file(&job.input, config, opts)?;
                if args.fit.strict {
                    if let Some(problem) = colour_problem(config, &trace) {
                        bail!("{problem}; nothing written (--strict)");
                    }
                }
                if !args.svg_only {
                    let target =
                        resolve_output(&with_suffix(&base, ".json"), args.follow_symlinks)?;
                    write_atomic_with(&target, |w| {
                        colour::write_json(w, config, &row.file, &trace)
                    })?;
                }
                let target = resolve_output(&out_path, args.follow_symlinks)?;
                write_atomic(
                    &target,
                    &colour::export_colour(&trace, writing.format, &writing.options)?,
                )?;
                return Ok(Traced::Colour(trace));
            }
            if let Some(width) = writing.centerline {
                let bitmap = Bitmap::load(&job.input, &config.raster_options())?;
                let result = trace_centerline(&bitmap, config, width)?;
                if args.fit.strict {
                    if let Some(problem) = centerline_problem(config, &result) {
                        bail!("{problem}; nothing written (--strict)");
                    }
                }
                if !args.svg_only {
                    let target =
                        resolve_output(&with_suffix(&base, ".json"), args.follow_symlinks)?;
                    write_atomic_with(&target, |w| {
                        centerline::write_json(w, config, &row.file, &result)
                    })?;
                }
                let target = resolve_output(&out_path, args.follow_symlinks)?;
                write_atomic(&target, centerline::centerline_svg(&result).as_bytes())?;
                return Ok(Traced::Centerline(result));
            }
            let result = trace_file(&job.input, config)?;
            if args.fit.strict {
                if let Some(problem) = fidelity_problem(config, &result) {
                    bail!("{problem}; nothing written (--strict)");
                }
            }
            if !args.svg_only {
                let target = resolve_output(&with_suffix(&base, ".json"), args.follow_symlinks)?;
                write_atomic_with(&target, |w| {
                    report::write_json(w, config, &[(&row.file, &result)], false)
                })?;
            }
            let target = resolve_output(&out_path, args.follow_symlinks)?;
            write_atomic(&target, &export(&result, writing.format, &writing.options)?)?;
            Ok(Traced::Shape(result))
        },
    ))
    .unwrap_or_else(|panic| {
        Err(anyhow::anyhow!(
            "internal error while tracing this file ({}); please report it with the file",
            panic_message(panic.as_ref())
        ))
    });
    match &outcome {
        Ok(Traced::Colour(trace)) => {
            let f = &trace.fidelity;
            row.checked(config, f.held, f.max_deviation, f.largest_region);
            row.segments = trace.segment_count();
            row.curves = row.segments;
            row.max_distance = f.max_deviation;
            row.warnings = colour_warnings(&row.file, config, trace);
        }
        Ok(Traced::Centerline(result)) => {
            let c = &result.check;
            row.checked(config, c.held, 0.0, c.largest_region as f64);
            row.segments = result.segment_count();
            row.curves = result.strokes.len();
            row.max_distance = result
                .strokes
                .iter()
                .map(|s| s.centre_max)
                .fold(0.0, f64::max);
            row.warnings = centerline_warnings(&row.file, config, result);
        }
        Ok(Traced::Shape(result)) => {
            let f = &result.fidelity;
            row.checked(config, f.held, f.max_deviation, f.largest_region);
            row.segments = result.segment_count();
            row.curves = result.curve_count();
            row.sum_sq = result.sum_sq();
            row.max_distance = result.max_distance();
            row.warnings = trace_warnings(&row.file, config, result);
        }
        Err(e) => {
            row.status = "failed";
            row.message = error_line(e.as_ref());
        }
    }
    if outcome.is_ok() && config.timings {
        row.seconds = started.elapsed().as_secs_f64();
    }
    row
}

impl Row {
    /// Records the check's verdict (held, largest deviation, largest region) when it ran.
    fn checked(&mut self, config: &Config, held: bool, deviation: f64, region: f64) {
        if config.check {
            self.held = if held { "yes" } else { "no" };
            self.max_deviation = deviation;
            self.largest_region = region;
        }
    }
}

/// Writes summary.csv: one row per input, or, before the run has finished, a single row
/// saying so (status `unfinished`).
fn write_summary(path: &Path, rows: &[Row], finished: bool) -> anyhow::Result<()> {
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
    if !finished {
        w.write_record([
            "",
            "unfinished",
            "",
            "",
            "",
            "",
            "",
            "",
            "",
            "",
            "the run that writes this summary has not finished (or was interrupted)",
        ])?;
    }
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
