//! `outlinefit trace`: one image in, an outline (SVG, PDF, EPS, DXF, GeoJSON) and optional
//! reports out.

use super::args::FitArgs;
use super::centerline::{centerline_problem, centerline_warnings, ModeArgs};
use super::colour::{colour_problem, colour_warnings, ColourArgs};
use super::format::{is_known_ending, FormatArgs};
use super::interrupt;
use super::messages::{fidelity_problem, trace_warnings};
use super::output::{check_distinct, is_dash, not_regular, resolve_output, write_output};
use super::progress::TerminalProgress;
use anyhow::{bail, Context};
use clap::Args;
use outlinefit::centerline::{self, trace_centerline};
use outlinefit::colour;
use outlinefit::export;
use outlinefit::io::ensure_output_dir_exists;
use outlinefit::{report, trace_bitmap_with_progress, Bitmap};
use outlinefit::{to_overlay_svg, OverlayOptions};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Arguments of `trace`.
#[derive(Args, Debug)]
pub(crate) struct TraceArgs {
    /// The image to trace (`-`: standard input).
    ///
    /// The image to trace (PNG, JPEG, BMP, GIF, TIFF, WebP, PBM/PGM/PPM); `-` reads it from
    /// standard input.
    input: PathBuf,
    /// Where to write the outline (`-`: standard output).
    ///
    /// Its ending chooses the format (.svg, .pdf, .eps, .ps, .dxf, .geojson) unless
    /// --format does. Default: the input's path with the format's ending (standard output
    /// when the input is `-`).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "OUT",
        help_heading = "Output"
    )]
    output: Option<PathBuf>,
    #[command(flatten)]
    output_format: FormatArgs,
    #[command(flatten)]
    colour: ColourArgs,
    /// Write the JSON report here: every segment, its error and joints.
    ///
    /// Write the JSON report here: the configuration, every segment with its control
    /// points, weights and errors, every joint, the fidelity check (`-`: standard
    /// output).
    #[arg(long, value_name = "R.json", help_heading = "Reports")]
    report: Option<PathBuf>,
    /// Write the CSV report (one row per segment) here (`-`: standard output).
    #[arg(
        long,
        value_name = "R.csv",
        help_heading = "Reports",
        hide_short_help = true
    )]
    csv: Option<PathBuf>,
    /// Write a diagnostic SVG: input image, data points, corners, smooth joints, control
    /// polygons.
    #[arg(
        long,
        value_name = "O.svg",
        help_heading = "Reports",
        hide_short_help = true
    )]
    overlay: Option<PathBuf>,
    /// Include every data point's curve parameter in the JSON report.
    #[arg(long, help_heading = "Reports", hide_short_help = true)]
    params: bool,
    /// Write through symbolic links to their targets (without it, an output that is a
    /// link is refused). Devices, FIFOs and folders are always refused.
    #[arg(long, help_heading = "Output", hide_short_help = true)]
    follow_symlinks: bool,
    #[command(flatten)]
    mode: ModeArgs,
    #[command(flatten)]
    fit: FitArgs,
}

/// Refuses a report or overlay whose name ends in another format's ending than what
/// `option` writes (`--report x.csv` would otherwise get JSON under a CSV name). Endings
/// are compared without case; a name without one, or with one no format uses, is taken as
/// it is.
fn check_report_name(option: &str, path: &Path) -> anyhow::Result<()> {
    let writes = match option {
        "--report" => "json",
        "--csv" => "csv",
        _ => "svg",
    };
    let Some(ending) = path.extension().map(|e| e.to_string_lossy().to_lowercase()) else {
        return Ok(());
    };
    if ending != writes && is_known_ending(&ending) {
        bail!(
            "{option} {}: {option} writes {}, not {}; give a name ending in .{writes}",
            path.display(),
            writes.to_uppercase(),
            ending.to_uppercase()
        );
    }
    Ok(())
}

/// Largest input file (bytes) decoded without a thread waiting for Ctrl-C (see
/// `interrupt`): decoding is the one long step before the trace reports progress.
const QUICK_INPUT_BYTES: u64 = 1 << 20;

/// Whether the fit is the default least squares at curvature breaks, whose time follows
/// the image's size.
fn quick_fit(config: &outlinefit::Config) -> bool {
    config.optimizer == outlinefit::Method::Lsq
        && config.breaks == outlinefit::BreakPlacement::Curvature
}

pub(crate) fn run(args: &TraceArgs) -> anyhow::Result<i32> {
    let config = args.fit.config()?;
    config.validate()?;
    let format = args.output_format.format_for(args.output.as_deref())?;
    let export_options = args.output_format.options(config.tolerance, format)?;
    if let Some(note) = args.output_format.note(format) {
        eprintln!("{note}");
    }
    let colour = args.colour.options(&config, format)?;
    let centerline = args
        .mode
        .centerline(&args.fit, &config, format, colour.is_some())?;
    if centerline.is_some() && args.params {
        bail!("--params lists the points of outline segments; leave it out with --mode centerline");
    }
    if colour.is_some() && args.overlay.is_some() {
        bail!("--overlay draws one-colour traces; leave it out with --palette");
    }
    let from_stdin = is_dash(&args.input);
    let out_path = match &args.output {
        Some(p) => p.clone(),
        None if from_stdin => PathBuf::from("-"),
        None => {
            if args.input.starts_with("/dev") || args.input.starts_with("/proc") {
                bail!(
                    "{} names a device or process file; give the output's path with -o (or -o - for standard output)",
                    args.input.display()
                );
            }
            if let Some(kind) = not_regular(&args.input) {
                bail!(
                    "{} is a {kind}; give the output's path with -o (or -o - for standard output)",
                    args.input.display()
                );
            }
            args.input.with_extension(format.extension())
        }
    };
    // Check every output before any work: distinct files, none the input, each a regular
    // file (or a link followed on request) in an existing folder.
    let named = [
        ("-o", Some(out_path.as_path())),
        ("--report", args.report.as_deref()),
        ("--csv", args.csv.as_deref()),
        ("--overlay", args.overlay.as_deref()),
    ];
    let named: Vec<(&str, &Path)> = named
        .iter()
        .filter_map(|(o, p)| p.map(|p| (*o, p)))
        .collect();
    let mut resolved: Vec<PathBuf> = Vec::with_capacity(named.len());
    for (_, p) in &named {
        if is_dash(p) {
            resolved.push(p.to_path_buf());
            continue;
        }
        let target = resolve_output(p, args.follow_symlinks)?;
        ensure_output_dir_exists(target.parent().unwrap_or(Path::new("")))?;
        resolved.push(target);
    }
    let targets: Vec<(&str, &Path)> = named
        .iter()
        .zip(&resolved)
        .map(|((o, _), t)| (*o, t.as_path()))
        .collect();
    check_distinct(&targets, Some(&args.input))?;
    for (option, p) in named.iter().skip(1) {
        check_report_name(option, p)?;
    }

    let name = if from_stdin {
        "<stdin>".to_string()
    } else {
        args.input.display().to_string()
    };
    // A run that may take long gets a thread that ends it as soon as Ctrl-C comes; the
    // others read the signal's flag at each report of progress and before each output,
    // and start the thread once they have run for a while (see `interrupt`).
    let large_file = || std::fs::metadata(&args.input).is_ok_and(|m| m.len() > QUICK_INPUT_BYTES);
    if from_stdin || colour.is_some() || centerline.is_some() || !quick_fit(&config) || large_file()
    {
        interrupt::watch();
    }
    let stdin_bytes = if from_stdin {
        let mut bytes = Vec::new();
        std::io::stdin()
            .lock()
            .read_to_end(&mut bytes)
            .context("cannot read standard input")?;
        Some(bytes)
    } else {
        None
    };
    if let Some(opts) = colour {
        let trace = match &stdin_bytes {
            Some(bytes) => colour::trace_colour_bytes(bytes, Path::new("<stdin>"), &config, &opts)?,
            None => colour::trace_colour_file(&args.input, &config, &opts)?,
        };
        if args.fit.strict {
            if let Some(problem) = colour_problem(&config, &trace) {
                bail!("{name}: {problem}; nothing written (--strict)");
            }
        }
        for w in colour_warnings(&name, &config, &trace) {
            eprintln!("{w}");
        }
        for ((option, _), target) in named.iter().zip(&resolved).skip(1) {
            write_output(target, |w| match *option {
                "--report" => colour::write_json(w, &config, &name, &trace),
                _ => w.write_all(colour::to_csv(&trace).as_bytes()),
            })?;
        }
        let drawing = colour::export_colour(&trace, format, &export_options)?;
        write_output(&resolved[0], |w| w.write_all(&drawing))?;
        return Ok(0);
    }
    if let Some(width) = centerline {
        let bitmap = match &stdin_bytes {
            Some(bytes) => {
                Bitmap::load_bytes(bytes, Path::new("<stdin>"), &config.raster_options())?
            }
            None => Bitmap::load(&args.input, &config.raster_options())?,
        };
        let result = trace_centerline(&bitmap, &config, width)?;
        if args.fit.strict {
            if let Some(problem) = centerline_problem(&config, &result) {
                bail!("{name}: {problem}; nothing written (--strict)");
            }
        }
        for w in centerline_warnings(&name, &config, &result) {
            eprintln!("{w}");
        }
        for ((option, _), target) in named.iter().zip(&resolved).skip(1) {
            write_output(target, |w| match *option {
                "--report" => centerline::write_json(w, &config, &name, &result),
                "--csv" => w.write_all(centerline::to_csv(&result).as_bytes()),
                _ => w.write_all(
                    centerline::centerline_overlay_svg(&result, Some(&bitmap.preview())).as_bytes(),
                ),
            })?;
        }
        let svg = centerline::centerline_svg(&result);
        write_output(&resolved[0], |w| w.write_all(svg.as_bytes()))?;
        return Ok(0);
    }
    let progress = TerminalProgress::new();
    let bitmap = match &stdin_bytes {
        Some(bytes) => Bitmap::load_bytes(bytes, Path::new("<stdin>"), &config.raster_options())?,
        None => Bitmap::load(&args.input, &config.raster_options())?,
    };
    let result = trace_bitmap_with_progress(&bitmap, &config, &progress);
    progress.finish();
    let result = result?;
    if args.fit.strict {
        if let Some(problem) = fidelity_problem(&config, &result) {
            bail!("{name}: {problem}; nothing written (--strict)");
        }
    }
    for w in trace_warnings(&name, &config, &result) {
        eprintln!("{w}");
    }
    // Reports first, the outline last: a finished outline means everything else is there
    // too.
    for ((option, _), target) in named.iter().zip(&resolved).skip(1) {
        let names = [(name.as_str(), &result)];
        write_output(target, |w| match *option {
            "--report" => report::write_json(w, &config, &names, args.params),
            "--csv" => w.write_all(report::to_csv(&config, &names).as_bytes()),
            _ => w.write_all(
                to_overlay_svg(&result, Some(&bitmap.preview()), &OverlayOptions::default())
                    .as_bytes(),
            ),
        })?;
    }
    let outline = export(&result, format, &export_options)?;
    write_output(&resolved[0], |w| w.write_all(&outline))?;
    // Everything is written and the process ends: its memory goes back to the system
    // whole, so the trace's hundred thousand small allocations are not freed one by one
    // (15 ms of a 600 dpi page).
    std::mem::forget((result, bitmap, outline));
    Ok(0)
}
