//! `outlinefit surface`: a Bézier surface fitted to a cloud of 3-D points (the surface
//! paper), one of its example clouds, or the rerun of its experiment.

use super::args::whole;
use super::output::{check_distinct, is_dash, resolve_output, write_output};
use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use outlinefit_lab::surface::examples::Example;
use outlinefit_lab::surface::experiment::{self, ExperimentOptions};
use outlinefit_lab::surface::{self as surf, ParamMethod, PointCloud, SurfaceFit, SurfaceOptions};
use outlinefit_lab::Error;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `surface`.
#[derive(Args, Debug)]
pub(crate) struct SurfaceArgs {
    /// Points to fit: one "x y z" per line, separated by spaces, tabs, commas or semicolons
    /// (a CSV header line and lines starting with # are skipped); - reads standard input.
    #[arg(value_name = "POINTS", required_unless_present_any = ["example", "rerun"], conflicts_with_all = ["example", "rerun"])]
    points: Option<PathBuf>,
    /// Fit one of the paper's example clouds instead (I, II or III; Table 1), drawn with
    /// --seed; its degree is the paper's unless --degree is given.
    #[arg(long, value_name = "NAME", value_parser = example_name, conflicts_with = "rerun")]
    example: Option<Example>,
    /// Output name: writes OUT.json (poles, parameters, errors), OUT.obj (the surface as
    /// a mesh) and OUT.svg (points and wireframe); a .json, .obj or .svg ending is dropped
    /// first. Default: POINTS without its extension, or example-NAME. With --rerun: the
    /// Markdown tables' file (default: standard output).
    #[arg(short, long, value_name = "OUT")]
    output: Option<PathBuf>,
    /// The points form an organized grid of M rows and N columns, in row order (one τ per
    /// row, one ζ per column); otherwise they are unorganized (one (τ, ζ) per point).
    #[arg(long, value_name = "MxN", value_parser = grid_size)]
    grid: Option<(usize, usize)>,
    /// Degree η,σ of the surface (η along the rows' parameter τ); one number for both.
    #[arg(long, value_name = "η,σ", value_parser = degree)]
    degree: Option<(usize, usize)>,
    /// How the data parameters are chosen: uniform, chordal, centripetal (§5.2), cs (the
    /// paper's cuckoo search), ics (improved cuckoo search) or correct (parameter
    /// correction from centripetal: alternating least squares and Newton foot points).
    #[arg(long, value_enum, default_value_t = MethodArg::Correct, value_name = "METHOD")]
    param: MethodArg,
    /// Objective evaluations per search run (cs, ics); the default is the paper's 2000
    /// generations of 100 nests.
    #[arg(long, default_value_t = surf::DEFAULT_BUDGET, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Independent runs: a search keeps the best of N seeded runs (the others' Y are in the
    /// report). With --rerun: runs per example and method (the paper: 50).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    runs: Option<usize>,
    /// Seed of the searches and of --example's noise; the same seed gives the same output
    /// on any number of threads.
    #[arg(long, default_value_t = outlinefit::optim::DEFAULT_SEED, allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// Samples per parameter of the OBJ mesh (at least 2).
    #[arg(long, default_value_t = 50, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    mesh_res: usize,
    /// Rerun the paper's experiment: the three examples, 50 runs each (new noise every
    /// run), uniform, chordal, centripetal, cs, ics and correct; prints Tables 3, 4 and 5
    /// beside the paper's. --param limits it to one method plus cs.
    #[arg(long)]
    rerun: bool,
    /// With --rerun: the examples to run, e.g. I,III (default: all three).
    #[arg(long, value_name = "NAMES", value_delimiter = ',', value_parser = example_name, requires = "rerun")]
    examples: Vec<Example>,
    /// With --rerun: the methods to run (default: all six).
    #[arg(
        long,
        value_name = "METHODS",
        value_delimiter = ',',
        value_enum,
        requires = "rerun"
    )]
    methods: Vec<MethodArg>,
    /// Threads for --rerun and --runs (default: one per core).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    jobs: Option<usize>,
    /// Let an output that is a symbolic link be written through to its target.
    #[arg(long)]
    follow_symlinks: bool,
}

/// `--param` values.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum MethodArg {
    /// Equal steps (Eq. 11).
    Uniform,
    /// Accumulated chord lengths (Eq. 12).
    Chordal,
    /// Accumulated square roots of chord lengths (Eq. 13).
    Centripetal,
    /// Cuckoo search with Lévy flights over the parameters (the paper's CSA).
    Cs,
    /// Improved cuckoo search: p_a from 0.5 to 0.1.
    Ics,
    /// Parameter correction from the centripetal parameters.
    Correct,
}

impl From<MethodArg> for ParamMethod {
    fn from(m: MethodArg) -> ParamMethod {
        match m {
            MethodArg::Uniform => ParamMethod::Uniform,
            MethodArg::Chordal => ParamMethod::Chordal,
            MethodArg::Centripetal => ParamMethod::Centripetal,
            MethodArg::Cs => ParamMethod::Cs,
            MethodArg::Ics => ParamMethod::Ics,
            MethodArg::Correct => ParamMethod::Correct,
        }
    }
}

fn example_name(s: &str) -> Result<Example, String> {
    Example::from_name(s.trim()).ok_or_else(|| format!("'{s}' is not an example (I, II or III)"))
}

fn positive(s: &str, what: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!(
            "'{s}': {what} must be a whole number of at least 1"
        )),
    }
}

/// `MxN` (also `M×N`, `M,N`).
fn grid_size(s: &str) -> Result<(usize, usize), String> {
    let (m, n) = s
        .split_once(['x', 'X', '×', ','])
        .ok_or_else(|| format!("'{s}': expected rows×columns, e.g. 29x29"))?;
    Ok((positive(m, "rows")?, positive(n, "columns")?))
}

/// `η,σ` or one number for both.
fn degree(s: &str) -> Result<(usize, usize), String> {
    match s.split_once(',') {
        Some((a, b)) => Ok((positive(a, "a degree")?, positive(b, "a degree")?)),
        None => {
            let d = positive(s, "a degree")?;
            Ok((d, d))
        }
    }
}

/// The JSON report of a fit.
#[derive(Serialize)]
struct Report<'a> {
    input: String,
    points: usize,
    grid: Option<(usize, usize)>,
    options: &'a SurfaceOptions,
    /// Y of every run (one for the deterministic methods).
    runs: Vec<f64>,
    fit: &'a SurfaceFit,
}

fn pool(jobs: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()?)
}

pub(crate) fn run(args: &SurfaceArgs) -> anyhow::Result<i32> {
    if args.rerun {
        return rerun(args);
    }
    if args.mesh_res < 2 {
        return Err(Error::InvalidOption {
            name: "mesh_res",
            message: "must be at least 2".into(),
        }
        .into());
    }
    let runs = args.runs.unwrap_or(1);
    if runs == 0 {
        bail!("invalid option --runs: must be at least 1");
    }
    let (cloud, input, default_stem) = match (&args.points, args.example) {
        (_, Some(example)) => {
            let mut cloud = example.generate(args.seed);
            if let Some(g) = args.grid {
                cloud.grid = Some(g);
            }
            (
                cloud,
                format!("example {}", example.name()),
                PathBuf::from(format!("example-{}", example.name())),
            )
        }
        (Some(path), None) => {
            let points = surf::points::read(path)?;
            let stem = if is_dash(path) {
                None
            } else {
                Some(path.with_extension(""))
            };
            (
                PointCloud {
                    points,
                    grid: args.grid,
                },
                path.display().to_string(),
                stem.unwrap_or_default(),
            )
        }
        (None, None) => bail!("give POINTS, --example or --rerun"),
    };
    let degree = args
        .degree
        .or(args.example.map(Example::degree))
        .unwrap_or((5, 5));
    let options = SurfaceOptions {
        degree,
        method: args.param.into(),
        budget: args.budget,
        seed: args.seed,
    };
    surf::validate(&cloud, &options)?;
    let stem = match &args.output {
        Some(o) if is_dash(o) => {
            bail!("-o needs a file name: surface writes three files (OUT.json, OUT.obj, OUT.svg)")
        }
        Some(o) => strip_known_extension(o),
        None if default_stem.as_os_str().is_empty() => {
            bail!("reading standard input needs -o OUT (surface writes OUT.json, OUT.obj, OUT.svg)")
        }
        None => default_stem,
    };
    let paths = ["json", "obj", "svg"].map(|ext| with_suffix(&stem, ext));
    check_distinct(
        &[
            ("-o (json)", &paths[0]),
            ("-o (obj)", &paths[1]),
            ("-o (svg)", &paths[2]),
        ],
        args.points.as_deref(),
    )?;
    let targets: Vec<PathBuf> = paths
        .iter()
        .map(|p| resolve_output(p, args.follow_symlinks))
        .collect::<anyhow::Result<_>>()?;

    // Deterministic methods run once; a search runs `runs` times with derived seeds.
    let seeds: Vec<u64> = if options.method.is_search() {
        (0..runs as u64)
            .map(|r| args.seed.wrapping_add(r))
            .collect()
    } else {
        vec![args.seed]
    };
    let fits: Vec<SurfaceFit> = pool(args.jobs)?.install(|| {
        use rayon::prelude::*;
        seeds
            .par_iter()
            .map(|&seed| surf::fit(&cloud, &SurfaceOptions { seed, ..options }))
            .collect::<Result<_, Error>>()
    })?;
    let all: Vec<f64> = fits.iter().map(|f| f.error).collect();
    let best = fits
        .into_iter()
        .min_by(|a, b| a.error.total_cmp(&b.error))
        .context("no run")?;
    let best_options = SurfaceOptions {
        seed: options.seed,
        ..options
    };
    let report = Report {
        input: input.clone(),
        points: cloud.points.len(),
        grid: cloud.grid,
        options: &best_options,
        runs: all,
        fit: &best,
    };
    let json = serde_json::to_string_pretty(&report).context("cannot encode the JSON")?;
    let comment = [
        format!("outlinefit surface: {input}, {} points", cloud.points.len()),
        format!(
            "method {}, degree ({}, {}), Y = {:e}, RMSE = {:e}",
            best.method.name(),
            degree.0,
            degree.1,
            best.error,
            best.rmse
        ),
    ];
    let obj = surf::obj::to_obj(&best.surface, args.mesh_res, &comment);
    let title = format!(
        "{input}: degree ({}, {}), {}, Y = {:.4e}",
        degree.0,
        degree.1,
        best.method.name(),
        best.error
    );
    let svg = surf::picture::to_svg(&title, &cloud.points, Some(&best.surface)).map_err(|e| {
        Error::Plot {
            what: paths[2].display().to_string(),
            message: e.to_string(),
        }
    })?;
    for (target, text) in targets.iter().zip([json + "\n", obj, svg]) {
        write_output(target, |w| w.write_all(text.as_bytes()))?;
    }
    eprintln!(
        "{}: {} points, degree ({}, {}), {}: Y = {:.6e}, RMSE = {:.6e}, max distance {:.4e}; wrote {}",
        input,
        cloud.points.len(),
        degree.0,
        degree.1,
        best.method.name(),
        best.error,
        best.rmse,
        best.max_distance,
        paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    );
    Ok(0)
}

/// `OUT` without a trailing .json, .obj or .svg.
fn strip_known_extension(p: &Path) -> PathBuf {
    match p.extension().and_then(|e| e.to_str()) {
        Some("json" | "obj" | "svg") => p.with_extension(""),
        _ => p.to_path_buf(),
    }
}

/// `stem.ext`, keeping any dots already in the stem's name.
fn with_suffix(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn rerun(args: &SurfaceArgs) -> anyhow::Result<i32> {
    let runs = args.runs.unwrap_or(50);
    if runs < 2 {
        bail!("invalid option --runs: the rerun's statistics need at least 2 runs");
    }
    if args.budget == 0 {
        bail!("invalid option --budget: a search needs at least one evaluation");
    }
    let examples = if args.examples.is_empty() {
        Example::ALL.to_vec()
    } else {
        args.examples.clone()
    };
    let methods: Vec<ParamMethod> = if args.methods.is_empty() {
        ParamMethod::ALL.to_vec()
    } else {
        let mut m: Vec<ParamMethod> = args.methods.iter().map(|&m| m.into()).collect();
        m.sort_by_key(|&x| ParamMethod::ALL.iter().position(|&y| y == x));
        m.dedup();
        m
    };
    let target = match &args.output {
        Some(o) if !is_dash(o) => Some(resolve_output(o, args.follow_symlinks)?),
        _ => None,
    };
    let options = ExperimentOptions {
        runs,
        budget: args.budget,
        seed: args.seed,
        examples,
        methods,
    };
    let bar =
        ProgressBar::new((options.runs * options.examples.len() * options.methods.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} fits {elapsed_precise} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let tick = || bar.inc(1);
    let results = pool(args.jobs)?.install(|| experiment::run(&options, &tick))?;
    bar.finish_and_clear();
    let text = experiment::report(&results, &options);
    match target {
        Some(t) => write_output(&t, |w| w.write_all(text.as_bytes()))?,
        None => write_output(Path::new("-"), |w| w.write_all(text.as_bytes()))?,
    }
    Ok(0)
}
