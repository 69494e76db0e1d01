//! `outlinefit trace`: one image in, an SVG and optional reports out.

use super::{default_svg_path, fidelity_problem, is_stdout, trace_warnings, FitArgs};
use anyhow::bail;
use clap::Args;
use outlinefit::export::overlay::{to_overlay_svg, OverlayOptions};
use outlinefit::export::svg::{to_svg, SvgOptions};
use outlinefit::io::{ensure_output_dir_exists, write_atomic};
use outlinefit::{raster, report, trace_bitmap};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `trace`.
#[derive(Args, Debug)]
pub(crate) struct TraceArgs {
    /// The image to trace (PNG, JPEG, BMP, GIF, TIFF, WebP, PBM/PGM/PPM).
    input: PathBuf,
    /// Where to write the SVG; `-` for standard output. Default: the input's path with
    /// the extension `.svg`.
    #[arg(short = 'o', long = "output", value_name = "OUT.svg")]
    output: Option<PathBuf>,
    /// Write the JSON report (configuration, every segment, every joint) here.
    #[arg(long, value_name = "R.json")]
    report: Option<PathBuf>,
    /// Write the CSV report (one row per segment) here.
    #[arg(long, value_name = "R.csv")]
    csv: Option<PathBuf>,
    /// Write a diagnostic SVG: input image, data points, corners, smooth joints, control
    /// polygons.
    #[arg(long, value_name = "O.svg")]
    overlay: Option<PathBuf>,
    /// Include every data point's curve parameter in the JSON report.
    #[arg(long)]
    params: bool,
    #[command(flatten)]
    fit: FitArgs,
}

pub(crate) fn run(args: &TraceArgs) -> anyhow::Result<i32> {
    let config = args.fit.config()?;
    config.validate()?;
    let svg_path = args
        .output
        .clone()
        .unwrap_or_else(|| default_svg_path(&args.input));
    // Refuse to overwrite the input, and check every output folder before any work.
    let outputs: Vec<&Path> = [
        Some(svg_path.as_path()),
        args.report.as_deref(),
        args.csv.as_deref(),
        args.overlay.as_deref(),
    ]
    .into_iter()
    .flatten()
    .filter(|p| !is_stdout(p))
    .collect();
    for p in &outputs {
        if same_file(p, &args.input) {
            bail!("output {} would overwrite the input", p.display());
        }
        ensure_output_dir_exists(p.parent().unwrap_or(Path::new("")))?;
    }
    let bitmap = raster::load(&args.input, &config.raster_options())?;
    let result = trace_bitmap(&bitmap, &config)?;
    let name = args.input.display().to_string();
    if args.fit.strict {
        if let Some(problem) = fidelity_problem(&config, &result) {
            bail!("{name}: {problem}; nothing written (--strict)");
        }
    }
    for w in trace_warnings(&name, &config, &result) {
        eprintln!("warning: {w}");
    }
    let svg = to_svg(&result, &SvgOptions::for_tolerance(config.tolerance));
    // Reports first, the SVG last: a finished SVG means everything else is there too.
    if let Some(p) = &args.report {
        write_atomic(
            p,
            report::to_json(&config, &[(&name, &result)], args.params).as_bytes(),
        )?;
    }
    if let Some(p) = &args.csv {
        write_atomic(p, report::to_csv(&config, &[(&name, &result)]).as_bytes())?;
    }
    if let Some(p) = &args.overlay {
        let preview = bitmap.preview();
        write_atomic(
            p,
            to_overlay_svg(&result, Some(&preview), &OverlayOptions::default()).as_bytes(),
        )?;
    }
    if is_stdout(&svg_path) {
        let mut out = std::io::stdout().lock();
        out.write_all(svg.as_bytes())?;
        out.flush()?;
    } else {
        write_atomic(&svg_path, svg.as_bytes())?;
    }
    Ok(0)
}

/// True when two paths name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
