use super::*;
use crate::curve::rational::RationalCubic;
use crate::geom::Point;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn sample_curve(c: &RationalCubic, n: usize) -> Vec<Point> {
    (0..n).map(|i| c.eval(i as f64 / (n - 1) as f64)).collect()
}

fn max_dist_to(c: &RationalCubic, pts: &[Point]) -> f64 {
    pts.iter().map(|q| c.nearest(*q, 64).1).fold(0.0, f64::max)
}

#[test]
fn random_rational_cubics_are_recovered_with_free_ends() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for trial in 0..50 {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(rng.random_range(5.0..25.0), rng.random_range(10.0..40.0)),
            Point::new(rng.random_range(35.0..55.0), rng.random_range(10.0..40.0)),
            Point::new(60.0, rng.random_range(-5.0..5.0)),
        ];
        let w = [rng.random_range(0.2..2.5), rng.random_range(0.2..2.5)];
        let truth = RationalCubic::new(pts, w);
        let data = sample_curve(&truth, 200);
        let sol = fit_segment(
            &data,
            EndCondition::Free,
            EndCondition::Free,
            &FitSettings::thorough(),
        );
        let err = max_dist_to(&sol.curve, &data);
        assert!(
            err < 1e-6,
            "trial {trial}: weights {w:?} → {:?}, max distance {err}",
            sol.curve.weights
        );
    }
}

#[test]
fn tangent_constraints_are_exact_and_recover_the_curve() {
    let truth = RationalCubic::new(
        [
            Point::new(0.0, 0.0),
            Point::new(10.0, 20.0),
            Point::new(40.0, 25.0),
            Point::new(50.0, 0.0),
        ],
        [1.7, 0.45],
    );
    let t0 = truth.start_tangent().unwrap();
    let t3 = truth.end_tangent().unwrap();
    let data = sample_curve(&truth, 120);
    let sol = fit_segment(
        &data,
        EndCondition::Tangent(t0),
        EndCondition::Tangent(t3),
        &FitSettings::thorough(),
    );
    let got0 = sol.curve.start_tangent().unwrap();
    let got3 = sol.curve.end_tangent().unwrap();
    assert!(crate::geom::angle_between(got0, t0) < 1e-12);
    assert!(crate::geom::angle_between(got3, t3) < 1e-12);
    assert!(max_dist_to(&sol.curve, &data) < 1e-6);
    assert!(
        (sol.curve.weights[0] - 1.7).abs() < 1e-5,
        "{:?}",
        sol.curve.weights
    );
}

#[test]
fn linear_solve_is_exact_at_true_parameters_and_weights() {
    let truth = RationalCubic::new(
        [
            Point::new(1.0, 2.0),
            Point::new(3.0, 9.0),
            Point::new(8.0, 7.5),
            Point::new(11.0, 1.0),
        ],
        [0.3, 2.1],
    );
    let params: Vec<f64> = (0..30).map(|i| (i as f64 / 29.0).powf(1.3)).collect();
    let data: Vec<Point> = params.iter().map(|&u| truth.eval(u)).collect();
    let (c, e) = solve_control_points(
        &data,
        &params,
        EndCondition::Free,
        EndCondition::Free,
        [0.3, 2.1],
    );
    assert!(e < 1e-20);
    assert!(c.points[1].distance(truth.points[1]) < 1e-9);
    assert!(c.points[2].distance(truth.points[2]) < 1e-9);
}

/// Three points between two corners (a serif's short flat end) used to give an
/// arbitrary solution of a singular system: a loop 2.4 px out from the points.
#[test]
fn three_points_with_a_free_end_give_a_curve_through_them_without_a_loop() {
    let points = [
        Point::new(32.986_531, 38.173_453),
        Point::new(33.011_039, 37.447_736),
        Point::new(33.113_380, 35.928_570),
    ];
    let tangent = Point::new(1.0, 0.0);
    for (start, end) in [
        (EndCondition::Free, EndCondition::Free),
        (EndCondition::Free, EndCondition::Tangent(tangent)),
        (
            EndCondition::Tangent(Point::new(0.0, -1.0)),
            EndCondition::Free,
        ),
    ] {
        let sol = fit_segment(&points, start, end, &FitSettings::polynomial());
        let c = sol.curve;
        assert!(
            c.eval(sol.params[1]).distance(points[1]) < 1e-9,
            "{start:?} {end:?}"
        );
        assert_eq!((c.eval(0.0), c.eval(1.0)), (points[0], points[2]));
        if let EndCondition::Tangent(t) = end {
            let arrival = (c.points[3] - c.points[2]).normalized().unwrap();
            assert!(arrival.cross(t).abs() < 1e-12, "{start:?} {end:?}");
        }
        if let EndCondition::Tangent(t) = start {
            let leaving = (c.points[1] - c.points[0]).normalized().unwrap();
            assert!(leaving.cross(t).abs() < 1e-12, "{start:?} {end:?}");
        }
        // Nothing of the curve strays from the points by more than the chord's length.
        let chord = points[0].distance(points[2]);
        let far = (0..=100)
            .map(|i| {
                let p = c.eval(i as f64 / 100.0);
                crate::geom::segment_distance(p, points[0], points[1])
                    .min(crate::geom::segment_distance(p, points[1], points[2]))
            })
            .fold(0.0, f64::max);
        assert!(far < 0.5 * chord, "{start:?} {end:?}: {far}");
    }
}

/// Three periods of a sine: no cubic comes within a pixel of it.
fn wave() -> Vec<Point> {
    (0..=90)
        .map(|i| {
            let x = i as f64;
            Point::new(x, 6.0 * (x * 3.0 * std::f64::consts::TAU / 90.0).sin())
        })
        .collect()
}

#[test]
fn a_fit_that_gives_up_stops_after_its_first_round_of_correction() {
    let data = wave();
    let (start, end) = (EndCondition::Free, EndCondition::Free);
    let base = FitSettings {
        reparam_rounds: 2,
        polish_iterations: 0,
        ..FitSettings::default()
    };
    // Far off after the first round: the result is exactly that round's curve, with the
    // parameters at its feet, as if only one round had been asked for.
    let gave_up = fit_segment(
        &data,
        start,
        end,
        &FitSettings {
            give_up: Some(0.5),
            ..base
        },
    );
    let one_round = fit_segment(
        &data,
        start,
        end,
        &FitSettings {
            reparam_rounds: 0,
            ..base
        },
    );
    let full = fit_segment(&data, start, end, &base);
    assert_eq!(gave_up.curve, one_round.curve);
    assert_eq!(gave_up.params, one_round.params);
    assert_eq!(gave_up.evaluations, one_round.evaluations);
    assert!(gave_up.evaluations < full.evaluations);
    // The curve really is that far off, so giving up was right.
    assert!(max_dist_to(&gave_up.curve, &data) > 0.5);
    // A bound the fit never exceeds changes nothing.
    let never = fit_segment(
        &data,
        start,
        end,
        &FitSettings {
            give_up: Some(1e6),
            ..base
        },
    );
    assert_eq!(never.curve, full.curve);
    assert_eq!(never.params, full.params);
}

/// The largest distance between a point and the curve at its parameter.
fn farthest_at_params(sol: &SegmentSolution, pts: &[Point]) -> f64 {
    pts.iter()
        .zip(&sol.params)
        .map(|(q, &u)| sol.curve.eval(u).distance(*q))
        .fold(0.0, f64::max)
}

#[test]
fn the_give_up_bound_tightens_with_each_round() {
    // After round k the fit stops when a point is farther than give_up / k: a bound that
    // the first round passes and the second misses (at half the bound) stops the fit
    // after its second round, with that round's curve and the parameters at its feet.
    let data = wave();
    let (start, end) = (EndCondition::Free, EndCondition::Free);
    let rounds = |reparam_rounds| FitSettings {
        reparam_rounds,
        polish_iterations: 0,
        ..FitSettings::polynomial()
    };
    // A fit with r rounds leaves its parameters where round r + 1's check measures them.
    let after_first = farthest_at_params(&fit_segment(&data, start, end, &rounds(0)), &data);
    let one_round = fit_segment(&data, start, end, &rounds(1));
    let after_second = farthest_at_params(&one_round, &data);
    assert!(
        after_first < 2.0 * after_second,
        "{after_first} {after_second}"
    );
    let limit = 0.5 * (after_first + 2.0 * after_second);
    let stopped = fit_segment(
        &data,
        start,
        end,
        &FitSettings {
            give_up: Some(limit),
            ..rounds(4)
        },
    );
    assert_eq!(stopped.curve, one_round.curve);
    assert_eq!(stopped.params, one_round.params);
    let full = fit_segment(&data, start, end, &rounds(4));
    assert_ne!(stopped.curve, full.curve);
    // A bound above twice the second round's distance lets the second round pass.
    let passed = fit_segment(
        &data,
        start,
        end,
        &FitSettings {
            give_up: Some(2.0 * after_second * 1.001),
            ..rounds(4)
        },
    );
    assert_ne!(passed.curve, one_round.curve);
}

/// Half a period of a sine with a little wobble: a polynomial cubic comes within a few
/// hundredths of a pixel, and its rounds of parameter correction still move it.
fn wobbly_arc() -> Vec<Point> {
    (0..=40)
        .map(|i| {
            let x = i as f64;
            let wobble = 0.03 * (x * 1.7).sin();
            Point::new(x, 8.0 * (x * std::f64::consts::PI / 40.0).sin() + wobble)
        })
        .collect()
}

#[test]
fn a_stopped_polynomial_fit_resumes_to_the_uninterrupted_fit() {
    let data = wobbly_arc();
    let start = EndCondition::Tangent(Point::new(1.0, 0.6).normalized().unwrap());
    let end = EndCondition::Tangent(Point::new(1.0, -0.6).normalized().unwrap());
    let settings = FitSettings {
        reparam_rounds: 4,
        polish_iterations: 0,
        give_up: Some(10.0),
        ..FitSettings::polynomial()
    };
    let full = fit_segment(&data, start, end, &settings);
    // Never stopped: exactly `fit_segment`'s fit.
    let (unstopped, none) = fit_polynomial_until(&data, start, end, &settings, |_, _, _| false);
    assert_eq!(none, None);
    assert_eq!(unstopped.curve, full.curve);
    assert_eq!(unstopped.params, full.params);
    assert_eq!(unstopped.evaluations, full.evaluations);
    for stop_at in 1..4 {
        let mut asked = 0;
        let mut farthest = Vec::new();
        let (early, stopped) = fit_polynomial_until(&data, start, end, &settings, |c, u, far| {
            asked += 1;
            farthest.push((far, max_dist_at_params(c, &data, u)));
            asked == stop_at
        });
        assert_eq!(stopped, Some(Stopped { rounds: stop_at }));
        // The farthest foot it is told is the curve's farthest at the feet it is given.
        for (far, at_params) in farthest {
            assert!((far - at_params).abs() < 1e-12, "{far} {at_params}");
        }
        assert!(early.evaluations < full.evaluations);
        assert_ne!(early.curve, full.curve, "round {stop_at} is not the last");
        let resumed = resume_polynomial(
            &data,
            start,
            end,
            &settings,
            early,
            Stopped { rounds: stop_at },
        );
        assert_eq!(resumed.curve, full.curve, "stopped after round {stop_at}");
        assert_eq!(resumed.params, full.params);
        assert_eq!(resumed.evaluations, full.evaluations);
    }
    // The last round is never offered: it would save nothing.
    let mut asked = 0;
    let _ = fit_polynomial_until(&data, start, end, &settings, |_, _, _| {
        asked += 1;
        false
    });
    assert_eq!(asked, 3);
}

/// Largest |P(uᵢ) − Qᵢ| at the given parameters.
fn max_dist_at_params(curve: &RationalCubic, data: &[Point], params: &[f64]) -> f64 {
    data.iter()
        .zip(params)
        .map(|(q, &u)| curve.eval(u).distance(*q))
        .fold(0.0, f64::max)
}
