use super::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn quintic() -> Vec<Point> {
    vec![
        Point::new(0.0, 0.0),
        Point::new(10.0, 20.0),
        Point::new(30.0, 25.0),
        Point::new(45.0, -5.0),
        Point::new(60.0, 10.0),
        Point::new(70.0, 30.0),
    ]
}

#[test]
fn split_halves_are_the_curve_on_sub_ranges() {
    let b = quintic();
    let (l, r) = split(&b, 0.3);
    for i in 0..=10 {
        let t = i as f64 / 10.0;
        assert!(de_casteljau(&l, t).distance(de_casteljau(&b, 0.3 * t)) < 1e-12);
        assert!(de_casteljau(&r, t).distance(de_casteljau(&b, 0.3 + 0.7 * t)) < 1e-12);
    }
}

#[test]
fn c1_cubic_of_an_elevated_cubic_is_that_cubic() {
    // Elevate a cubic to degree 5 twice; the C1 reduction must give it back.
    let c = [
        Point::new(0.0, 0.0),
        Point::new(1.0, 3.0),
        Point::new(4.0, -1.0),
        Point::new(5.0, 2.0),
    ];
    let elevate = crate::curve::basis::elevate;
    let quint = elevate(&elevate(&c));
    let got = c1_cubic(&quint);
    for (g, w) in got.points.iter().zip(&c) {
        assert!(g.distance(*w) < 1e-12, "{g:?} vs {w:?}");
    }
}

#[test]
fn center_cubics_stay_within_the_bound_and_meet_g1() {
    let b = quintic();
    let centers = bezier_points_to_wang_ball(&b);
    let m = MergedCurve {
        first_segment: 0,
        segment_count: 2,
        degree: 5,
        disks: centers
            .iter()
            .map(|c| DiskReport {
                x: c.x,
                y: c.y,
                r: 0.1,
            })
            .collect(),
        point_count: 0,
        max_distance: 0.0,
        rms_distance: 0.0,
        merging_error: 0.0,
    };
    for bound in [1.0, 0.1, 0.01] {
        let cubics = m.center_cubics(bound);
        assert!(cubics.len() >= 2, "this curve needs subdivision at {bound}");
        // Each piece covers an equal-halving range; check against the curve densely.
        let k = cubics.len();
        let mut ranges = Vec::new();
        fn ranges_of(
            b: &[Point],
            bound: f64,
            a: f64,
            z: f64,
            depth: u32,
            out: &mut Vec<(f64, f64)>,
        ) {
            let c = c1_cubic(b);
            let worst = (1..32)
                .map(|i| de_casteljau(b, i as f64 / 32.0).distance(c.eval(i as f64 / 32.0)))
                .fold(0.0, f64::max);
            let g1_ok = g1_cubic(b).is_some_and(|g| parametric_distance(b, &g) <= bound);
            if worst <= bound || depth >= MAX_CUBIC_DEPTH || g1_ok {
                out.push((a, z));
                return;
            }
            let (l, r) = split(b, 0.5);
            let mid = 0.5 * (a + z);
            ranges_of(&l, bound, a, mid, depth + 1, out);
            ranges_of(&r, bound, mid, z, depth + 1, out);
        }
        ranges_of(&b, bound, 0.0, 1.0, 0, &mut ranges);
        assert_eq!(ranges.len(), k);
        for (c, &(a, z)) in cubics.iter().zip(&ranges) {
            for i in 0..=200 {
                let s = i as f64 / 200.0;
                let d = c.eval(s).distance(de_casteljau(&b, a + (z - a) * s));
                assert!(d <= bound * 1.05, "bound {bound}: {d}");
            }
        }
        for w in cubics.windows(2) {
            let (p, q) = (w[0].points, w[1].points);
            assert!(p[3].distance(q[0]) < 1e-12);
            // G1: the pieces keep their sub-curves' end tangent directions.
            let (u, v) = (p[3] - p[2], q[1] - q[0]);
            assert!(u.cross(v).abs() < 1e-9 * u.length() * v.length() && u.dot(v) > 0.0);
        }
    }
}

#[test]
fn solve_center_recovers_an_exact_quintic() {
    let b = quintic();
    let params: Vec<f64> = (0..60).map(|i| i as f64 / 59.0).collect();
    let points: Vec<Point> = params.iter().map(|&t| de_casteljau(&b, t)).collect();
    let t0 = (b[1] - b[0]).normalized();
    let t1 = (b[5] - b[4]).normalized();
    for (a, z) in [(None, None), (t0, None), (None, t1), (t0, t1)] {
        let got = solve_center(&points, &params, 5, b[0], b[5], a, z).unwrap();
        for (g, w) in got.iter().zip(&b) {
            assert!(g.distance(*w) < 1e-9, "{g:?} vs {w:?}");
        }
    }
    // A reversed tangent constraint is refused.
    let reversed = t0.map(|t| -t);
    assert!(solve_center(&points, &params, 5, b[0], b[5], reversed, t1).is_none());
}

#[test]
fn envelope_radii_cover_every_distance() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for n in [3, 5, 8] {
        let params: Vec<f64> = (0..80).map(|i| i as f64 / 79.0).collect();
        let distances: Vec<f64> = params
            .iter()
            .map(|&t| 0.1 + 0.1 * (6.0 * t).sin().abs() + rng.random_range(0.0..0.05))
            .collect();
        let r = envelope_radii(&params, &distances, n).unwrap();
        assert!(r.iter().all(|&v| v >= 0.0));
        let mut w = vec![0.0; n + 1];
        let mut slack: f64 = f64::INFINITY;
        for (&t, &d) in params.iter().zip(&distances) {
            wang_ball_basis(n, t, &mut w);
            let radius: f64 = w.iter().zip(&r).map(|(a, b)| a * b).sum();
            assert!(radius >= d, "n {n}: R {radius} < {d}");
            slack = slack.min(radius - d);
        }
        // Tight: the lift makes the band touch at least one point.
        assert!(slack < 1e-9, "n {n}: slack {slack}");
    }
}

#[test]
fn covers_counts_cyclically() {
    let m = MergedCurve {
        first_segment: 4,
        segment_count: 3,
        degree: 5,
        disks: Vec::new(),
        point_count: 0,
        max_distance: 0.0,
        rms_distance: 0.0,
        merging_error: 0.0,
    };
    let covered: Vec<usize> = (0..6).filter(|&k| m.covers(k, 6)).collect();
    assert_eq!(covered, vec![0, 4, 5]);
}

#[test]
fn c1_cubic_keeps_the_end_points_and_end_derivatives() {
    // A cubic under C1 end conditions has nothing left free: its end points are the
    // quintic's and its end derivatives 3 (c1 − c0), 3 (c3 − c2) are the quintic's
    // 5 (b1 − b0), 5 (b5 − b4).
    let b = quintic();
    let c = c1_cubic(&b).points;
    assert!(c[0].distance(b[0]) < 1e-12 && c[3].distance(b[5]) < 1e-12);
    assert!(((c[1] - c[0]) * 3.0).distance((b[1] - b[0]) * 5.0) < 1e-9);
    assert!(((c[3] - c[2]) * 3.0).distance((b[5] - b[4]) * 5.0) < 1e-9);
}
