//! `outlinefit reduce`: degree reduction of an (SG-)Bézier curve, printed as JSON.

use super::args::whole;
use anyhow::Context;
use clap::builder::PossibleValuesParser;
use clap::{Args, ValueEnum};
use outlinefit_lab::reduce::sg_bezier::SgShape;
use outlinefit_lab::reduce::{read_curve_json, reduce, reduction_svg, Constraint, ReduceOptions};
use serde::Serialize;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `reduce`.
#[derive(Args, Debug)]
pub(crate) struct ReduceArgs {
    /// JSON file with the ORIGINAL curve of degree n:
    /// {"control_points": [[x, y], …], "omega": ω, "lambda": […], "mu": […]}. Only
    /// control_points is required; without omega the curve is a plain Bézier curve
    /// (ω = 0); a missing lambda/mu is C(n+1, j)/2 (ignored at ω = 0). lambda has ⌊n/2⌋
    /// entries (⌊n/2⌋ + 1 for odd n), mu ⌊n/2⌋.
    #[arg(value_name = "INPUT.json")]
    input: PathBuf,
    /// Degree m of the reduced curve: 1 ≤ m < n (m ≥ 3 with --constraint c1).
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = whole::<usize>)]
    degree: usize,
    /// End conditions: `none`; `c0` keeps the end points; `c1` keeps the end points and the
    /// end derivatives (first derivatives, with their lengths).
    #[arg(long, value_enum, default_value_t = ConstraintArg::None)]
    constraint: ConstraintArg,
    /// `exact`: least squares for the reduced curve's fixed shape (default ω = 0, a plain
    /// Bézier curve: the classical L2-optimal reduction; see --omega). Any other name is a
    /// metaheuristic that searches the reduced curve's shape (ω, λ, μ in the paper's box)
    /// with control points by least squares, never worse than `exact` at ω = 0: gwo (grey
    /// wolf, the paper's method), hs, ga, pso, cs, ics, fwa, so, beeso, de.
    #[arg(long, default_value = "exact", value_name = "NAME", value_parser = method_names())]
    method: String,
    /// Objective evaluations (least-squares solves) of a metaheuristic, one of them spent
    /// on the ω = 0 comparison. The default is the paper's 20 wolves × 300 iterations.
    #[arg(long, default_value_t = outlinefit_lab::reduce::DEFAULT_BUDGET, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Seed of a metaheuristic's random choices; the same seed gives the same output.
    #[arg(long, default_value_t = outlinefit::optim::DEFAULT_SEED, value_name = "S", allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// With `exact`: the reduced curve's global shape parameter ω (the paper uses
    /// 0 ≤ ω ≤ 1). Default 0 (plain Bézier).
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    omega: Option<f64>,
    /// With `exact`: the reduced curve's λ_1, λ_2, … comma-separated (⌊m/2⌋ values,
    /// ⌊m/2⌋ + 1 for odd m). Default C(m+1, j)/2.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "L1,L2,…",
        allow_negative_numbers = true
    )]
    lambda: Option<Vec<f64>>,
    /// With `exact`: the reduced curve's μ_1, μ_2, … comma-separated (⌊m/2⌋ values).
    /// Default C(m+1, j)/2.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "M1,M2,…",
        allow_negative_numbers = true
    )]
    mu: Option<Vec<f64>>,
    /// Also draw the original curve (blue), the reduced one (red, dashed) and both control
    /// polygons into this SVG file (written atomically).
    #[arg(long, value_name = "PICTURE.svg")]
    svg: Option<PathBuf>,
}

/// `--constraint` values.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum ConstraintArg {
    /// No end conditions.
    None,
    /// Keep the end points.
    C0,
    /// Keep the end points and end derivatives.
    C1,
}

impl From<ConstraintArg> for Constraint {
    fn from(c: ConstraintArg) -> Constraint {
        match c {
            ConstraintArg::None => Constraint::None,
            ConstraintArg::C0 => Constraint::C0,
            ConstraintArg::C1 => Constraint::C1,
        }
    }
}

/// `exact` and every metaheuristic's name, for `--method`.
fn method_names() -> PossibleValuesParser {
    PossibleValuesParser::new(
        std::iter::once("exact").chain(outlinefit::optim::NAMES.iter().copied()),
    )
}

/// What `reduce` prints.
#[derive(Serialize)]
struct Output {
    error: f64,
    degree: usize,
    constraint: Constraint,
    method: String,
    omega: f64,
    lambda: Vec<f64>,
    mu: Vec<f64>,
    control_points: Vec<[f64; 2]>,
    evaluations: u64,
}

pub(crate) fn run(args: &ReduceArgs) -> anyhow::Result<i32> {
    let original = read_curve_json(&args.input)?;
    let m = args.degree;
    let shape = if args.omega.is_some() || args.lambda.is_some() || args.mu.is_some() {
        let default = SgShape::bezier(m);
        Some(SgShape {
            omega: args.omega.unwrap_or(0.0),
            lambda: args.lambda.clone().unwrap_or(default.lambda),
            mu: args.mu.clone().unwrap_or(default.mu),
        })
    } else {
        None
    };
    if let Some(path) = &args.svg {
        // Fail before the work if the picture could not be written.
        outlinefit::io::ensure_output_dir_exists(path.parent().unwrap_or(path.as_path()))?;
    }
    let options = ReduceOptions {
        degree: m,
        constraint: args.constraint.into(),
        method: args.method.clone(),
        shape,
        budget: args.budget,
        seed: args.seed,
    };
    let reduced = reduce(&original, &options)?;
    if let Some(path) = &args.svg {
        let svg = reduction_svg(&original, &reduced)?;
        outlinefit::io::write_atomic(path, svg.as_bytes())?;
    }
    let out = Output {
        error: reduced.error,
        degree: reduced.curve.degree(),
        constraint: reduced.constraint,
        method: reduced.method.clone(),
        omega: reduced.curve.shape.omega,
        lambda: reduced.curve.shape.lambda.clone(),
        mu: reduced.curve.shape.mu.clone(),
        control_points: reduced.curve.points.iter().map(|p| [p.x, p.y]).collect(),
        evaluations: reduced.evaluations,
    };
    // Not println!, which panics when standard output is closed early (`| head`).
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string_pretty(&out)?)
        .and_then(|()| stdout.flush())
        .context("cannot write to standard output")?;
    Ok(0)
}
