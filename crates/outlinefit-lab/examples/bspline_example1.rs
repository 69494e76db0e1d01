//! Example 1 of the fireworks paper (the quartic parametric curve converted to a cubic
//! B-spline) for every optimizer and the uniform-knot baseline: prints, per fit target,
//! budget and method, seed 1's RMSE and largest error and the dense RMSE of every seed.
//! Not a check (the tests hold those); a table for looking at.
//!
//! `cargo run --release --example bspline_example1`, narrowed by environment variables:
//! `EX1_METHODS=hs,uniform` (default: all optimizers and `uniform`), `EX1_SEEDS=5`,
//! `EX1_FIT=curve|samples` (default both), `EX1_BUDGETS=3000,10000` (default 3000).

use outlinefit::optim;
use outlinefit_lab::bspline::{convert, ConvertOptions, FitTarget, ParametricCurve, UNIFORM};

fn main() {
    let curve = ParametricCurve::parse(
        "-26*u^4+64*u^3-52*u^2+16*u-1",
        "-112/3*u^4+224/3*u^3-48*u^2+32/3*u",
    )
    .unwrap();
    let mut names: Vec<&str> = optim::NAMES.to_vec();
    names.push(UNIFORM);
    let only = std::env::var("EX1_METHODS").unwrap_or_default();
    if !only.is_empty() {
        names = only.split(',').collect();
    }
    let seeds: u64 = std::env::var("EX1_SEEDS").map_or(5, |s| s.parse().unwrap());
    let fits: Vec<FitTarget> = match std::env::var("EX1_FIT").as_deref() {
        Ok("curve") => vec![FitTarget::Curve],
        Ok("samples") => vec![FitTarget::Samples],
        _ => FitTarget::ALL.to_vec(),
    };
    let budgets: Vec<u64> = std::env::var("EX1_BUDGETS")
        .unwrap_or_else(|_| "3000".into())
        .split(',')
        .map(|b| b.parse().unwrap())
        .collect();
    for &fit in &fits {
        for &budget in &budgets {
            for name in &names {
                let mut dense = Vec::new();
                let t = std::time::Instant::now();
                for seed in 1u64..=seeds {
                    let c = convert(
                        &curve,
                        &ConvertOptions {
                            method: name.to_string(),
                            budget,
                            seed,
                            fit,
                            ..Default::default()
                        },
                    )
                    .unwrap();
                    dense.push(c.rmse_dense);
                    if seed == 1 {
                        print!(
                            "{:7} {budget:6} {name:7} seed 1: rmse {:.6} max {:.6} | dense seeds 1-{seeds}:",
                            fit.name(),
                            c.rmse,
                            c.max_error_dense
                        );
                    }
                }
                for d in &dense {
                    print!(" {d:.7}");
                }
                let worst = dense.iter().cloned().fold(0.0, f64::max);
                println!(
                    " worst {worst:.7} ({:.3}s/run)",
                    t.elapsed().as_secs_f64() / seeds as f64
                );
            }
        }
    }
}
