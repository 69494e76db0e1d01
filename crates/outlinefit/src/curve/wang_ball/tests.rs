use super::basis::wang_ball_basis_derivative;
use super::convert::{
    bernstein_to_wang_ball, invert_exact, wang_ball_to_bernstein, wang_ball_to_bernstein_exact,
};
use super::*;
use crate::curve::basis::binomial_exact;
use crate::geom::Point;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_points(rng: &mut ChaCha8Rng, count: usize) -> Vec<Point> {
    (0..count)
        .map(|_| Point::new(rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0)))
        .collect()
}

fn bezier_eval(points: &[Point], t: f64) -> Point {
    let mut w = points.to_vec();
    for level in 1..w.len() {
        for k in 0..w.len() - level {
            w[k] = w[k].lerp(w[k + 1], t);
        }
    }
    w[0]
}

fn ts(count: usize) -> impl Iterator<Item = f64> {
    (0..=count).map(move |k| k as f64 / count as f64)
}

#[test]
fn basis_is_a_partition_of_unity() {
    for n in 1..=12 {
        let mut w = vec![0.0; n + 1];
        for t in ts(200) {
            wang_ball_basis(n, t, &mut w);
            let s: f64 = w.iter().sum();
            assert!((s - 1.0).abs() < 1e-14, "n={n} t={t} sum={s}");
            assert!(w.iter().all(|&x| x >= 0.0));
        }
    }
}

#[test]
fn cubic_basis_is_the_ball_basis() {
    let mut w = [0.0; 4];
    for t in ts(100) {
        wang_ball_basis(3, t, &mut w);
        let s = 1.0 - t;
        let expect = [s * s, 2.0 * t * s * s, 2.0 * t * t * s, t * t];
        for i in 0..4 {
            assert!((w[i] - expect[i]).abs() < 1e-15, "i={i} t={t}");
        }
    }
}

#[test]
fn quadratic_and_linear_bases_are_bernstein() {
    let mut w2 = [0.0; 3];
    let mut w1 = [0.0; 2];
    for t in ts(50) {
        wang_ball_basis(2, t, &mut w2);
        wang_ball_basis(1, t, &mut w1);
        let s = 1.0 - t;
        assert!((w2[0] - s * s).abs() < 1e-15);
        assert!((w2[1] - 2.0 * s * t).abs() < 1e-15);
        assert!((w2[2] - t * t).abs() < 1e-15);
        assert!((w1[0] - s).abs() < 1e-15 && (w1[1] - t).abs() < 1e-15);
    }
}

#[test]
fn conversion_matrices_are_inverse_and_match_the_basis() {
    for n in 1..=12 {
        let t_mat = wang_ball_to_bernstein(n);
        let s_mat = bernstein_to_wang_ball(n);
        for i in 0..=n {
            for j in 0..=n {
                let p: f64 = (0..=n).map(|k| t_mat[i][k] * s_mat[k][j]).sum();
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((p - e).abs() < 1e-12, "n={n} ({i},{j}) {p}");
            }
        }
        // W_i = Σ_j T[j][i] B_j at sample points.
        let mut w = vec![0.0; n + 1];
        for t in ts(37) {
            wang_ball_basis(n, t, &mut w);
            for i in 0..=n {
                let b: f64 = (0..=n)
                    .map(|j| {
                        t_mat[j][i]
                            * binomial_exact(n, j).unwrap() as f64
                            * t.powi(j as i32)
                            * (1.0 - t).powi((n - j) as i32)
                    })
                    .sum();
                assert!((b - w[i]).abs() < 1e-13, "n={n} i={i} t={t}");
            }
        }
    }
}

#[test]
fn exact_inverse_is_available_to_high_degree() {
    for n in 1..=30 {
        let m = wang_ball_to_bernstein_exact(n).expect("forward overflow");
        assert!(
            invert_exact(&m).is_some(),
            "exact inverse overflowed at n={n}"
        );
    }
}

#[test]
fn round_trip_through_bezier() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for n in 1..=12 {
        for _ in 0..5 {
            let p = random_points(&mut rng, n + 1);
            let wb = WangBall::new(p.clone());
            let back = WangBall::from_bezier(&wb.to_bezier());
            assert_eq!(back.degree(), n);
            for (a, b) in p.iter().zip(&back.points) {
                assert!(a.distance(*b) < 1e-12, "n={n}: {a:?} vs {b:?}");
            }
        }
    }
}

#[test]
fn curve_equals_its_bezier_conversion() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for n in 1..=12 {
        let wb = WangBall::new(random_points(&mut rng, n + 1));
        let bez = wb.to_bezier();
        for t in ts(100) {
            let d = wb.eval(t).distance(bezier_eval(&bez, t));
            assert!(d < 1e-12, "n={n} t={t} d={d}");
        }
    }
}

#[test]
fn curve_interpolates_end_points() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for n in 1..=12 {
        let p = random_points(&mut rng, n + 1);
        let wb = WangBall::new(p.clone());
        assert!(wb.eval(0.0).distance(p[0]) < 1e-14);
        assert!(wb.eval(1.0).distance(p[n]) < 1e-14);
    }
}

#[test]
fn derivative_matches_central_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let h = 1e-6;
    for n in 1..=12 {
        let wb = WangBall::new(random_points(&mut rng, n + 1));
        for t in ts(40).map(|t| 0.01 + 0.98 * t) {
            let fd = (wb.eval(t + h) - wb.eval(t - h)) / (2.0 * h);
            let d = wb.derivative(t);
            assert!(
                (fd - d).length() < 1e-6 * (1.0 + d.length()),
                "n={n} t={t}: {d:?} vs {fd:?}"
            );
        }
        // Basis derivatives at the ends, compared with one-sided differences.
        let mut d0 = vec![0.0; n + 1];
        let (mut a, mut b) = (vec![0.0; n + 1], vec![0.0; n + 1]);
        wang_ball_basis_derivative(n, 0.0, &mut d0);
        wang_ball_basis(n, 0.0, &mut a);
        wang_ball_basis(n, h, &mut b);
        for i in 0..=n {
            assert!((d0[i] - (b[i] - a[i]) / h).abs() < 1e-4, "n={n} i={i}");
        }
    }
}

#[test]
fn split_halves_reproduce_the_curve() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    for n in 1..=12 {
        let wb = WangBall::new(random_points(&mut rng, n + 1));
        for &s in &[0.3, 0.5, 0.81] {
            let (l, r) = wb.split(s);
            assert_eq!((l.degree(), r.degree()), (n, n));
            for u in ts(50) {
                assert!(l.eval(u).distance(wb.eval(s * u)) < 1e-11, "n={n} left");
                let tr = s + (1.0 - s) * u;
                assert!(r.eval(u).distance(wb.eval(tr)) < 1e-11, "n={n} right");
            }
        }
    }
}

fn line_dwb(n: usize, a: Point, b: Point) -> DiskWangBall {
    // Bézier points evenly spaced on the segment give a uniformly parametrised line.
    let bez: Vec<Point> = (0..=n).map(|k| a.lerp(b, k as f64 / n as f64)).collect();
    let wb = WangBall::from_bezier(&bez);
    DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 1.0)).collect())
}

#[test]
fn dwb_evaluates_center_and_radius_with_the_same_basis() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    for n in 1..=8 {
        let pts = random_points(&mut rng, n + 1);
        let radii: Vec<f64> = (0..=n).map(|_| rng.random_range(0.1..2.0)).collect();
        let dwb = DiskWangBall::new(
            pts.iter()
                .zip(&radii)
                .map(|(&p, &r)| Disk::new(p, r))
                .collect(),
        );
        let center = WangBall::new(pts.clone());
        let mut w = vec![0.0; n + 1];
        for t in ts(30) {
            let d = dwb.eval(t);
            wang_ball_basis(n, t, &mut w);
            let r: f64 = w.iter().zip(&radii).map(|(a, b)| a * b).sum();
            assert!(d.center.distance(center.eval(t)) < 1e-13);
            assert!((d.radius - r).abs() < 1e-13);
            assert!((dwb.radius(t) - r).abs() < 1e-13);
        }
        assert!((dwb.radius(0.0) - radii[0]).abs() < 1e-14);
        assert!((dwb.radius(1.0) - radii[n]).abs() < 1e-14);
        let h = 1e-6;
        let fd = (dwb.radius(0.4 + h) - dwb.radius(0.4 - h)) / (2.0 * h);
        assert!((dwb.radius_derivative(0.4) - fd).abs() < 1e-6);
    }
}

#[test]
fn straight_line_arc_length_is_the_chord() {
    for n in 1..=12 {
        let (a, b) = (Point::new(1.0, -2.0), Point::new(4.0, 2.0));
        let dwb = line_dwb(n, a, b);
        let l = dwb.center_arc_length();
        assert!((l - 5.0).abs() < 1e-12, "n={n} l={l}");
    }
    // A non-uniformly parametrised line (still straight): length is still the chord.
    let wb = WangBall::new(vec![
        Point::new(0.0, 0.0),
        Point::new(0.5, 0.0),
        Point::new(2.5, 0.0),
        Point::new(3.0, 0.0),
    ]);
    let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.5)).collect());
    assert!((dwb.center_arc_length() - 3.0).abs() < 1e-12);
}

#[test]
fn quarter_circle_arc_length() {
    // Standard cubic Bézier approximation of the unit quarter circle (radial error
    // ≤ 2.7e-4), converted to Wang–Ball form.
    let k = 4.0 / 3.0 * (2f64.sqrt() - 1.0);
    let bez = [
        Point::new(1.0, 0.0),
        Point::new(1.0, k),
        Point::new(k, 1.0),
        Point::new(0.0, 1.0),
    ];
    let wb = WangBall::from_bezier(&bez);
    let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.1)).collect());
    let l = dwb.center_arc_length();
    let quarter = std::f64::consts::FRAC_PI_2;
    assert!((l - quarter).abs() < 2e-4 * quarter, "l={l}");
    // And against a fine polyline of the curve itself.
    let m = 200_000;
    let poly: f64 = (0..m)
        .map(|i| {
            let (a, b) = (i as f64 / m as f64, (i + 1) as f64 / m as f64);
            bezier_eval(&bez, a).distance(bezier_eval(&bez, b))
        })
        .sum();
    assert!((l - poly).abs() < 1e-10, "l={l} poly={poly}");
}

#[test]
fn arc_length_handles_a_cusp() {
    // Bézier cubic with C'(0.5) = 0 (a cusp): x = 3t² − 2t³ style symmetric curve.
    let bez = [
        Point::new(0.0, 0.0),
        Point::new(2.0, 1.0),
        Point::new(0.0, 1.0),
        Point::new(2.0, 0.0),
    ];
    let wb = WangBall::from_bezier(&bez);
    let dwb = DiskWangBall::new(wb.points.iter().map(|&p| Disk::new(p, 0.1)).collect());
    let l = dwb.center_arc_length();
    let m = 400_000;
    let poly: f64 = (0..m)
        .map(|i| {
            let (a, b) = (i as f64 / m as f64, (i + 1) as f64 / m as f64);
            bezier_eval(&bez, a).distance(bezier_eval(&bez, b))
        })
        .sum();
    assert!((l - poly).abs() < 1e-8, "l={l} poly={poly}");
}

#[test]
fn merge_lambda_is_the_arc_length_share() {
    let a = line_dwb(3, Point::new(0.0, 0.0), Point::new(3.0, 4.0));
    let b = line_dwb(4, Point::new(3.0, 4.0), Point::new(3.0, 9.0));
    assert!((merge_lambda(&a, &b) - 0.5).abs() < 1e-14);
    let c = line_dwb(2, Point::new(3.0, 4.0), Point::new(3.0, 19.0));
    assert!((merge_lambda(&a, &c) - 0.25).abs() < 1e-14);
    assert!((merge_lambda(&c, &a) - 0.75).abs() < 1e-14);
    let p = DiskWangBall::new(vec![Disk::new(Point::new(1.0, 1.0), 0.5); 3]);
    assert_eq!(merge_lambda(&p, &p), 0.5);
}
