//! Objective evaluation must not allocate: both search spaces, and the optimizer's
//! evaluation path through the tracker, are counted with a counting global allocator.

use outlinefit::fit::solve::{
    centripetal_parameters, EndCondition, SegmentProblem, WeightsProblem,
};
use outlinefit::optim::{Problem, Tracker};
use outlinefit::Point;

fn points() -> Vec<Point> {
    (0..100)
        .map(|i| {
            let a = i as f64 / 99.0 * 2.0;
            Point::new(40.0 * a.cos(), 30.0 * a.sin())
        })
        .collect()
}

#[test]
fn objective_evaluations_do_not_allocate() {
    let pts = points();
    let params = centripetal_parameters(&pts);
    let full = SegmentProblem::free(&pts, &params);
    let weights = WeightsProblem::new(
        &pts,
        &params,
        EndCondition::Tangent(Point::new(0.0, 1.0)),
        EndCondition::Free,
    );
    let x_full = [35.0, 20.0, 10.0, 35.0, 1.1, 0.9];
    let x_weights = WeightsProblem::point_of([1.1, 0.9]);
    let mut tracker = Tracker::new(&weights, 2000, false);
    let mut sink = 0.0;
    let counts = allocation_counter::measure(|| {
        for _ in 0..1000 {
            sink += full.evaluate(&x_full);
            sink += weights.evaluate(&x_weights);
            sink += tracker.evaluate(&x_weights).unwrap_or(0.0);
        }
    });
    assert!(sink.is_finite() && sink > 0.0);
    assert_eq!(counts.count_total, 0, "{counts:?}");
    // The counter itself works (a vacuous zero would hide a regression).
    let one = allocation_counter::measure(|| {
        std::hint::black_box(vec![1u8; 10]);
    });
    assert_eq!(one.count_total, 1);
}
