//! Reruns the merging experiments of the BEESO paper (Examples 1 and 3, §3.3) with every
//! optimizer of the suite and with `exact`, and prints a markdown table for
//! docs/experiments.md.
//!
//! `cargo run --release --example merge_paper [-- RUNS [BUDGET]]` (default 30 seeds, the
//! paper's 25 000 evaluations = population 50 × 500 iterations).

use outlinefit::merge::{MergeMethod as Method, MergeOptions, MergeProblem};
use outlinefit::optim;
use outlinefit_lab::merge::examples;
use rayon::prelude::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let runs: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(30);
    let budget: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(25_000);
    let example1 = examples::example1();
    let example3 = examples::example3();
    // (name, curves, degree, preserve, the paper's BEESO error and best other method)
    let cases = [
        (
            "Example 1, n = 6, free ends (Table 2)",
            &example1,
            6,
            false,
            "7.256e-4 (BEESO)",
        ),
        (
            "Example 1, n = 6, ends kept (Table 3)",
            &example1,
            6,
            true,
            "5.777e-4 (BEESO)",
        ),
        (
            "Example 3, n = 4, free ends (Table 8)",
            &example3,
            4,
            false,
            "8.957e-2 (BEESO)",
        ),
        (
            "Example 3, n = 4, ends kept (Table 9)",
            &example3,
            4,
            true,
            "1.467e-1 (BEESO, SO, WSO)",
        ),
    ];
    println!("{runs} seeds, {budget} evaluations per run; ε = merging error of Eq. 10.\n");
    for (title, (a, b), degree, preserve, paper) in cases {
        let mut o = MergeOptions::new(degree);
        o.preserve_endpoints = preserve;
        let problem = match MergeProblem::new(a, b, o) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("{title}: {e}");
                std::process::exit(1);
            }
        };
        let exact = match problem.solve(Method::Exact) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{title}: {e}");
                std::process::exit(1);
            }
        };
        println!("### {title}\n");
        println!("Paper's best: {paper}. λ = {:.6}.\n", exact.lambda);
        println!("| method | best ε | mean ε | worst ε | mean / exact | s per run |");
        println!("|---|---|---|---|---|---|");
        println!(
            "| exact | {:.4e} | {:.4e} | {:.4e} | 1 | {:.4} |",
            exact.error,
            exact.error,
            exact.error,
            {
                let t = Instant::now();
                let _ = problem.solve(Method::Exact);
                t.elapsed().as_secs_f64()
            }
        );
        for name in optim::NAMES {
            let started = Instant::now();
            let errors: Vec<f64> = (0..runs)
                .into_par_iter()
                .map(|seed| {
                    let opt = optim::by_name(name).expect("a name of optim::NAMES");
                    problem
                        .solve(Method::Optimizer {
                            optimizer: opt.as_ref(),
                            budget,
                            seed: 1000 + seed,
                        })
                        .map(|m| m.error)
                        .unwrap_or(f64::NAN)
                })
                .collect();
            let secs =
                started.elapsed().as_secs_f64() / runs as f64 * rayon::current_num_threads() as f64;
            let best = errors.iter().copied().fold(f64::INFINITY, f64::min);
            let worst = errors.iter().copied().fold(0.0, f64::max);
            let mean = errors.iter().sum::<f64>() / errors.len() as f64;
            println!(
                "| {name} | {best:.4e} | {mean:.4e} | {worst:.4e} | {:.3} | {secs:.3} |",
                mean / exact.error
            );
        }
        println!();
    }
}
