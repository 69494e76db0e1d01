//! `outlinefit bspline`: a parametric curve given by two expressions in u, converted into a
//! B-spline by the hybrid fireworks algorithm; JSON on stdout, optional SVG picture.

use super::args::whole;
use anyhow::Context;
use clap::{Args, ValueEnum};
use outlinefit::io::write_atomic;
use outlinefit::Error;
use outlinefit_lab::bspline::{
    self as bs, convert, svg, ConvertOptions, FitTarget, ParametricCurve,
};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `bspline`.
#[derive(Args, Debug)]
pub(crate) struct BsplineArgs {
    /// x(u): numbers, u, pi, + - * / ^ (or **), parentheses, sin cos tan asin acos atan
    /// sinh cosh tanh exp ln log sqrt. Example: '-26*u^4+64*u^3-52*u^2+16*u-1'.
    #[arg(long = "x", value_name = "EXPR", allow_hyphen_values = true)]
    x: String,
    /// y(u), same syntax as --x.
    #[arg(long = "y", value_name = "EXPR", allow_hyphen_values = true)]
    y: String,
    /// Parameter range A,B with A < B (e.g. 0,1 for the paper's examples).
    #[arg(long, value_name = "A,B", allow_hyphen_values = true)]
    range: String,
    /// Number of samples: the two ends, every feature point, and auxiliary samples placed
    /// by --method.
    #[arg(long, default_value_t = bs::DEFAULT_SAMPLES, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    samples: usize,
    /// Number of control points of the B-spline (at least --order, at most --samples).
    #[arg(long, default_value_t = bs::DEFAULT_CONTROL_POINTS, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    control_points: usize,
    /// Order of the B-spline (degree + 1; 4 is cubic).
    #[arg(long, default_value_t = bs::DEFAULT_ORDER, value_name = "K", allow_negative_numbers = true, value_parser = whole::<usize>)]
    order: usize,
    /// How the auxiliary samples are placed: fwa (fireworks, the paper's), any other
    /// optimizer (hs, ga, pso, gwo, cs, ics, so, beeso, de), or uniform (evenly spaced,
    /// no search). Optimizers minimise the spline's dense RMSE against the curve.
    #[arg(long, default_value = bs::DEFAULT_METHOD, value_name = "NAME")]
    method: String,
    /// What the control points are fitted to: curve (least squares against the true curve
    /// at the 1000 dense parameters, minimising the dense error for the samples' knots) or
    /// samples (least squares on the samples, the paper's Eq. 1). The knots come from the
    /// samples either way.
    #[arg(long, value_enum, default_value_t = FitArg::Curve, value_name = "TARGET")]
    fit: FitArg,
    /// Objective evaluations for the optimizer.
    #[arg(long, default_value_t = bs::DEFAULT_BUDGET, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>)]
    budget: u64,
    /// Seed of the optimizer; the same seed gives the same output.
    #[arg(long, default_value_t = outlinefit::optim::DEFAULT_SEED, allow_negative_numbers = true, value_parser = whole::<u64>)]
    seed: u64,
    /// Grid intervals of the curvature scan that finds the feature points.
    #[arg(long, default_value_t = bs::features::DEFAULT_GRID, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>)]
    grid: usize,
    /// Also write a picture: the curve, the samples (feature points marked), the spline
    /// and its control polygon.
    #[arg(long, value_name = "PICTURE.svg")]
    svg: Option<PathBuf>,
}

/// `--fit` values.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum FitArg {
    /// Least squares against the true curve at the dense parameters.
    Curve,
    /// Least squares on the samples (Eq. 1).
    Samples,
}

impl From<FitArg> for FitTarget {
    fn from(arg: FitArg) -> FitTarget {
        match arg {
            FitArg::Curve => FitTarget::Curve,
            FitArg::Samples => FitTarget::Samples,
        }
    }
}

/// Parses `A,B` into two numbers (their order is checked by `ConvertOptions::validate`).
fn parse_range(text: &str) -> Result<(f64, f64), Error> {
    let bad = || Error::InvalidOption {
        name: "range",
        message: format!("expected two numbers A,B (e.g. 0,1), got '{text}'"),
    };
    let (a, b) = text.split_once(',').ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    Ok((a, b))
}

pub(crate) fn run(args: &BsplineArgs) -> anyhow::Result<i32> {
    let options = ConvertOptions {
        range: parse_range(&args.range)?,
        samples: args.samples,
        control_points: args.control_points,
        order: args.order,
        method: args.method.clone(),
        budget: args.budget,
        seed: args.seed,
        feature_grid: args.grid,
        fit: args.fit.into(),
    };
    // Options first, so that a bad option is reported before a bad expression is parsed.
    options.validate()?;
    let curve = ParametricCurve::parse(&args.x, &args.y)?;
    let conversion = convert(&curve, &options)?;
    if let Some(path) = &args.svg {
        write_atomic(path, svg::picture(&curve, &conversion).as_bytes())?;
    }
    let json = serde_json::to_string_pretty(&conversion).context("cannot encode the JSON")?;
    let mut out = std::io::stdout().lock();
    writeln!(out, "{json}").context("cannot write to standard output")?;
    Ok(0)
}
