//! Objective evaluations per second on a 100-point segment, for both search spaces:
//! `full` (the HS paper's C1, C2, w1, w2: one rational evaluation per point) and `weights`
//! (w1, w2: a least-squares solve of the control points per evaluation), plus a whole
//! harmony-search run of 5 000 evaluations in each space.
//!
//! `cargo bench --bench objective`; criterion reports the time per evaluation and the
//! throughput in evaluations per second ("elem/s").

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use outlinefit::fit::solve::{
    centripetal_parameters, EndCondition, SegmentProblem, WeightsProblem,
};
use outlinefit::optim::{HarmonySearch, Optimizer, Problem, SeededRng};
use outlinefit::{Point, RationalCubic};
use rand::SeedableRng;
use std::hint::black_box;

/// 100 points on a rational cubic arc with a small deterministic ripple.
fn segment() -> Vec<Point> {
    let c = RationalCubic::new(
        [
            Point::new(0.0, 0.0),
            Point::new(20.0, 40.0),
            Point::new(70.0, 45.0),
            Point::new(90.0, 5.0),
        ],
        [1.4, 0.7],
    );
    (0..100)
        .map(|i| {
            let u = i as f64 / 99.0;
            c.eval(u) + Point::new(0.0, 0.05 * (i as f64 * 1.7).sin())
        })
        .collect()
}

fn objective(c: &mut Criterion) {
    let points = segment();
    let params = centripetal_parameters(&points);
    let full = SegmentProblem::free(&points, &params);
    let tangent = |d: Point| EndCondition::Tangent(d.normalized().unwrap_or(Point::new(1.0, 0.0)));
    let weights = WeightsProblem::new(
        &points,
        &params,
        tangent(points[1] - points[0]),
        tangent(points[99] - points[98]),
    );
    let x_full = [20.0, 40.0, 70.0, 45.0, 1.4, 0.7];
    let x_weights = WeightsProblem::point_of([1.4, 0.7]);

    let mut g = c.benchmark_group("objective_100_points");
    g.throughput(Throughput::Elements(1));
    g.bench_function("full", |b| b.iter(|| full.evaluate(black_box(&x_full))));
    g.bench_function("weights", |b| {
        b.iter(|| weights.evaluate(black_box(&x_weights)))
    });
    g.finish();

    let mut g = c.benchmark_group("hs_5000_evaluations_100_points");
    g.throughput(Throughput::Elements(5000));
    g.sample_size(20);
    let hs = HarmonySearch::default();
    for (name, problem) in [("full", &full as &dyn Problem), ("weights", &weights)] {
        g.bench_function(name, |b| {
            b.iter_batched(
                || SeededRng::seed_from_u64(1),
                |mut rng| hs.minimize(problem, 5000, &mut rng, false).value,
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, objective);
criterion_main!(benches);
