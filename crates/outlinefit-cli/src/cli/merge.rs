//! `outlinefit merge`: two adjacent disk Wang–Ball curves into one.

use super::args::whole;
use anyhow::Context;
use clap::builder::PossibleValuesParser;
use clap::Args;
use outlinefit::merge::{MergeMethod as Method, MergeOptions, MergeProblem, Merged};
use outlinefit_lab::merge::input::parse_curves;
use outlinefit_lab::merge::picture::{to_svg, Layer};
use serde::Serialize;
use std::io::Write as _;
use std::path::PathBuf;

/// Arguments of `merge`.
#[derive(Args, Debug)]
pub(crate) struct MergeArgs {
    /// JSON file with two adjacent curves:
    /// {"curves": [{"centers": [[x, y], …], "radii": [r, …]}, {…}]}; the first curve's last
    /// disk must equal the second one's first.
    #[arg(value_name = "INPUT.json")]
    input: PathBuf,
    /// Degree n of the merged curve, at least the higher input degree, at most 20.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    degree: usize,
    /// Keep the outer end disks of the inputs as the merged curve's end disks (Eq. 11–12).
    #[arg(long)]
    preserve_endpoints: bool,
    /// `exact` (least squares; the minimum merging error) or a metaheuristic searching the
    /// control disks within a box: hs, ga, pso, gwo, cs, ics, fwa, so, beeso (the paper's
    /// method), de.
    #[arg(long, default_value = "exact", value_name = "NAME", value_parser = method_names())]
    method: String,
    /// Lower bound of every computed radius (the paper's results stop at 0.001).
    #[arg(long, default_value_t = outlinefit::merge::DEFAULT_MIN_RADIUS, value_name = "R", allow_negative_numbers = true)]
    min_radius: f64,
    /// Objective evaluations of a metaheuristic (the paper: population 50 × 500 iterations).
    #[arg(long, default_value_t = outlinefit::merge::DEFAULT_BUDGET, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Seed of a metaheuristic's random choices.
    #[arg(long, default_value_t = outlinefit::optim::DEFAULT_SEED, allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// Metaheuristics search centers within this many times the input's extent around it.
    #[arg(
        long,
        default_value_t = outlinefit::merge::DEFAULT_BOX_SCALE,
        value_name = "S",
        allow_negative_numbers = true
    )]
    box_scale: f64,
    /// Also draw both input curves and the merged one (center lines, disk envelopes,
    /// control disks) into this SVG file.
    #[arg(long, value_name = "PICTURE.svg")]
    svg: Option<PathBuf>,
}

fn method_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        std::iter::once("exact").chain(outlinefit::optim::NAMES.iter().copied()),
    )
}

#[derive(Serialize)]
struct DiskJson {
    x: f64,
    y: f64,
    r: f64,
}

#[derive(Serialize)]
struct Output<'a> {
    #[serde(flatten)]
    merged: &'a Merged,
    preserve_endpoints: bool,
    disks: Vec<DiskJson>,
}

pub(crate) fn run(args: &MergeArgs) -> anyhow::Result<i32> {
    let text = std::fs::read_to_string(&args.input)
        .with_context(|| format!("cannot read {}", args.input.display()))?;
    let (a, b) = parse_curves(&text, &args.input.display().to_string())?;
    let options = MergeOptions {
        degree: args.degree,
        preserve_endpoints: args.preserve_endpoints,
        min_radius: args.min_radius,
        box_scale: args.box_scale,
    };
    let problem = MergeProblem::new(&a, &b, options)?;
    let optimizer = outlinefit::optim::by_name(&args.method);
    let method = match &optimizer {
        None => Method::Exact,
        Some(o) => Method::Optimizer {
            optimizer: o.as_ref(),
            budget: args.budget,
            seed: args.seed,
        },
    };
    let merged = problem.solve(method)?;
    if let Some(path) = &args.svg {
        let label = format!("merged, degree {} ({})", merged.degree, merged.method);
        let svg = to_svg(&[
            Layer {
                curve: &merged.curve,
                colour: "#2ca02c",
                label: &label,
            },
            Layer {
                curve: &a,
                colour: "#1f77b4",
                label: "first input curve",
            },
            Layer {
                curve: &b,
                colour: "#ff7f0e",
                label: "second input curve",
            },
        ]);
        outlinefit::io::write_atomic(path, svg.as_bytes())?;
    }
    let out = Output {
        merged: &merged,
        preserve_endpoints: args.preserve_endpoints,
        disks: merged
            .curve
            .disks
            .iter()
            .map(|d| DiskJson {
                x: d.center.x,
                y: d.center.y,
                r: d.radius,
            })
            .collect(),
    };
    // Not println!, which panics when standard output is closed early (`| head`).
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)
        .and_then(|()| stdout.flush())
        .context("cannot write to standard output")?;
    Ok(0)
}
