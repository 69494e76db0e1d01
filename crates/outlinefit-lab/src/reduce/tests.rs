use super::*;
use outlinefit::curve::basis::elevate;

/// Example 1 of the paper (§5): a plain Bézier curve of degree 6 (ω* = 0), polygon
/// symmetric about x = 0.3.
fn example1() -> SgBezier {
    let pts = [
        (0.1, 0.0),
        (0.0, 0.1),
        (0.05, 0.2),
        (0.3, 0.3),
        (0.55, 0.2),
        (0.6, 0.1),
        (0.5, 0.0),
    ];
    SgBezier::from_bezier(pts.iter().map(|&(x, y)| Point::new(x, y)).collect()).unwrap()
}

/// The reduced (degree 4) shape of Tables 2 and 3: ω with λ_1, λ_2, μ_1, μ_2.
fn shape4(omega: f64, lambda: [f64; 2], mu: [f64; 2]) -> SgShape {
    SgShape::new(4, omega, lambda.to_vec(), mu.to_vec()).unwrap()
}

/// Deterministic test inputs from the project's seeded generator.
struct Rng(rand_chacha::ChaCha8Rng);
impl Rng {
    fn seeded(seed: u64) -> Self {
        Rng(rand::SeedableRng::seed_from_u64(seed))
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * rand::RngExt::random::<f64>(&mut self.0)
    }
    fn points(&mut self, count: usize) -> Vec<Point> {
        (0..count)
            .map(|_| Point::new(self.range(-5.0, 5.0), self.range(-5.0, 5.0)))
            .collect()
    }
    /// A shape for degree n in the paper's box.
    fn shape(&mut self, n: usize) -> SgShape {
        let omega = self.range(0.0, 1.0);
        let lambda = (1..=SgShape::lambda_len(n))
            .map(|j| self.range(0.0, binomial(n + 1, j)))
            .collect();
        let mu = (1..=SgShape::mu_len(n))
            .map(|j| self.range(0.0, binomial(n + 1, j)))
            .collect();
        SgShape::new(n, omega, lambda, mu).unwrap()
    }
}

/// P(0), P(1), P'(0), P'(1) of a curve, from its exact Bernstein form of degree n + 1
/// (`SgBezier::to_bernstein`, independent of this module's end-derivative rows).
fn ends(c: &SgBezier) -> [Point; 4] {
    let b = c.to_bernstein().unwrap();
    let k = b.len() - 1;
    [
        b[0],
        b[k],
        (b[1] - b[0]) * k as f64,
        (b[k] - b[k - 1]) * k as f64,
    ]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn example1_c1_reproduces_table_2() {
    // Table 2, C1 row (ω = 0, 0.2, 0.3, 0.5; λ_j = μ_j = 3). With two fixed points at each
    // end only Q_2 is free, so the paper's search reached the optimum and `exact` gives its
    // numbers: 9.10962e-3, 9.18883e-3, 9.19349e-3, 9.10962e-3 (0.2e-4 or better).
    let p = example1();
    for (omega, paper) in [
        (0.0, 9.1096e-3),
        (0.2, 9.1890e-3),
        (0.3, 9.1935e-3),
        (0.5, 9.1096e-3),
    ] {
        let r = reduce_exact(&p, 4, Constraint::C1, &shape4(omega, [3.0; 2], [3.0; 2])).unwrap();
        assert!(
            rel(r.error, paper) < 1e-4,
            "ω = {omega}: {:e} vs paper {paper:e}",
            r.error
        );
    }
    // Table 3's C1 column: every row has ω = 0, where λ, μ do not matter; the paper prints
    // 9.1097e-3 (ours 9.10962e-3: equal to 3 significant digits).
    for (l, m) in [
        ([2.0, 3.0], [3.0, 3.0]),
        ([3.0, 4.0], [3.0, 3.0]),
        ([3.0, 3.0], [2.0, 3.0]),
        ([2.0, 3.0], [3.0, 2.0]),
    ] {
        let r = reduce_exact(&p, 4, Constraint::C1, &shape4(0.0, l, m)).unwrap();
        assert!(rel(r.error, 9.1097e-3) < 5e-4, "{:e}", r.error);
    }
    // The classical C1 points at ω = 0: Q_1 = P_0 + (6/4)(P_1 − P_0) = (−0.05, 0.15).
    let r = reduce_bezier(&p.points, 4, Constraint::C1).unwrap();
    assert!(r.0[1].distance(Point::new(-0.05, 0.15)) < 1e-15);
    assert!(r.0[3].distance(Point::new(0.65, 0.15)) < 1e-15);
}

#[test]
fn example1_paper_unconstrained_and_c0_values_lie_above_the_optimum() {
    // The paper's GWO searched control points and did not reach the least-squares optimum
    // for 4 (unrestricted) or 2 (C0) free points: each of its values is at or above the
    // exact optimum for the same shape. The closest is Table 3's C0 row 1, 2.6558e-3
    // against our 2.64693e-3 (0.3 % above); the unrestricted values are 2.2× (4.0165e-3)
    // to 5.5× above ours. The exact ω = 0 numbers are this implementation's (checked by
    // brute-force integration below): unrestricted 1.83050e-3, C0 2.64693e-3.
    let p = example1();
    let exact = |c, omega, l, m| reduce_exact(&p, 4, c, &shape4(omega, l, m)).unwrap().error;
    assert!(rel(exact(Constraint::None, 0.0, [3.0; 2], [3.0; 2]), 1.83050e-3) < 1e-5);
    assert!(rel(exact(Constraint::C0, 0.0, [3.0; 2], [3.0; 2]), 2.64693e-3) < 1e-5);
    // Table 2.
    for (omega, none, c0) in [
        (0.0, 4.9914e-3, 4.1972e-3),
        (0.2, 8.6669e-3, 2.7182e-3),
        (0.3, 7.4429e-3, 3.1251e-3),
        (0.5, 9.5617e-3, 2.6399e-3),
    ] {
        let e_none = exact(Constraint::None, omega, [3.0; 2], [3.0; 2]);
        let e_c0 = exact(Constraint::C0, omega, [3.0; 2], [3.0; 2]);
        assert!(
            e_none <= none && e_c0 <= c0,
            "ω = {omega}: {e_none:e}, {e_c0:e}"
        );
        assert!(e_none <= e_c0 * (1.0 + 1e-12));
    }
    // Table 3 (ω = 0 in every row).
    for (l, m, none, c0) in [
        ([2.0, 3.0], [3.0, 3.0], 1.0108e-2, 2.6558e-3),
        ([3.0, 4.0], [3.0, 3.0], 4.4997e-3, 2.6803e-3),
        ([3.0, 3.0], [2.0, 3.0], 4.0165e-3, 1.0576e-2),
        ([2.0, 3.0], [3.0, 2.0], 7.3299e-3, 1.0956e-2),
    ] {
        assert!(exact(Constraint::None, 0.0, l, m) <= none);
        assert!(exact(Constraint::C0, 0.0, l, m) <= c0);
    }
}

#[test]
fn example1_reduction_keeps_the_symmetry() {
    // The polygon is mirror-symmetric about x = 0.3 and the reduced shape λ = μ is too, so
    // the L2-optimal reduced polygon must be: Q_i.x + Q_{4−i}.x = 0.6, Q_i.y = Q_{4−i}.y.
    let p = example1();
    for c in [Constraint::None, Constraint::C0, Constraint::C1] {
        for omega in [0.0, 0.5] {
            let q = reduce_exact(&p, 4, c, &shape4(omega, [3.0; 2], [3.0; 2]))
                .unwrap()
                .curve
                .points;
            for i in 0..=4 {
                assert!((q[i].x + q[4 - i].x - 0.6).abs() < 1e-12, "{c} ω={omega}");
                assert!((q[i].y - q[4 - i].y).abs() < 1e-12, "{c} ω={omega}");
            }
        }
    }
}

#[test]
fn example1_gwo_beats_exact_and_the_paper() {
    // GWO (20 wolves, 6000 evaluations) over the reduced curve's shape with least-squares
    // control points. On seeds 1–5 it reaches 3.6019e-4 / 4.9212e-4 / 1.3477e-3
    // (unrestricted / C0 / C1), the same values DE finds with 60,000 evaluations. The
    // paper's best GWO values for Example 1 over Tables 2–3 are 4.0165e-3, 2.6399e-3 and
    // 9.1096e-3: ours are 11×, 5.4× and 6.8× smaller.
    let p = example1();
    for (c, ours, paper_best) in [
        (Constraint::None, 3.6019e-4, 4.0165e-3),
        (Constraint::C0, 4.9212e-4, 2.6399e-3),
        (Constraint::C1, 1.3477e-3, 9.1096e-3),
    ] {
        let options = ReduceOptions {
            constraint: c,
            method: "gwo".to_string(),
            ..ReduceOptions::new(4)
        };
        let r = reduce(&p, &options).unwrap();
        let exact = reduce(
            &p,
            &ReduceOptions {
                constraint: c,
                ..ReduceOptions::new(4)
            },
        )
        .unwrap();
        assert!(
            r.error <= exact.error,
            "{c}: {:e} > {:e}",
            r.error,
            exact.error
        );
        assert!(rel(r.error, ours) < 1e-3, "{c}: {:e}", r.error);
        assert!(r.error < 0.2 * paper_best);
        assert_eq!(r.method, "gwo");
        assert_eq!(r.evaluations, 6000);
        assert!(r.curve.shape.within_paper_bounds(4));
        // The reported error is the error of the reported curve.
        assert!(rel(l2_distance(&p, &r.curve).unwrap(), r.error) < 1e-9);
        // Same seed, same result.
        assert_eq!(reduce(&p, &options).unwrap(), r);
    }
}

#[test]
fn optimizer_is_never_worse_than_exact() {
    // ω = 0 lies in the paper's box; the ω = 0 solution is compared with the optimizer's,
    // so even a starved optimizer cannot return worse than `exact`.
    let p = example1();
    let mut rng = Rng::seeded(11);
    let other = SgBezier::from_bezier(rng.points(8)).unwrap();
    for curve in [&p, &other] {
        for c in [Constraint::None, Constraint::C0, Constraint::C1] {
            let exact = reduce(
                curve,
                &ReduceOptions {
                    constraint: c,
                    ..ReduceOptions::new(4)
                },
            )
            .unwrap();
            for name in ["gwo", "hs", "pso", "de"] {
                for budget in [1, 2, 7, 40] {
                    let r = reduce(
                        curve,
                        &ReduceOptions {
                            constraint: c,
                            method: name.to_string(),
                            budget,
                            seed: 3,
                            ..ReduceOptions::new(4)
                        },
                    )
                    .unwrap();
                    assert!(r.error <= exact.error, "{name} {budget} {c}");
                    assert_eq!(r.evaluations, budget);
                    if budget == 1 {
                        assert_eq!(r.curve.points, exact.curve.points);
                        assert_eq!(r.curve.shape.omega, 0.0);
                    }
                }
            }
        }
    }
}

#[test]
fn degree_elevated_curves_are_recovered() {
    let mut rng = Rng::seeded(21);
    for m in 1..=6 {
        for extra in 1..=3 {
            // A plain Bézier curve of degree m elevated to m + extra.
            let q = rng.points(m + 1);
            let mut p = q.clone();
            for _ in 0..extra {
                p = elevate(&p);
            }
            for c in [Constraint::None, Constraint::C0, Constraint::C1] {
                if m < c.min_degree() {
                    continue;
                }
                let (got, err) = reduce_bezier(&p, m, c).unwrap();
                assert!(err < 1e-9, "m={m} +{extra} {c}: {err:e}");
                for (a, b) in got.iter().zip(&q) {
                    assert!(a.distance(*b) < 1e-9, "m={m} +{extra} {c}");
                }
            }
            // An SG-Bézier curve of degree m (a polynomial of degree m + 1), written as a
            // plain Bézier curve of degree m + extra, comes back with its shape.
            let shape = rng.shape(m);
            let sg = SgBezier::new(rng.points(m + 1), shape.clone()).unwrap();
            let mut b = sg.to_bernstein().unwrap();
            for _ in 1..extra {
                b = elevate(&b);
            }
            let original = SgBezier::from_bezier(b).unwrap();
            if original.degree() <= m {
                continue;
            }
            for c in [Constraint::None, Constraint::C0, Constraint::C1] {
                if m < c.min_degree() {
                    continue;
                }
                let r = reduce_exact(&original, m, c, &shape).unwrap();
                assert!(r.error < 1e-9, "SG m={m} +{extra} {c}: {:e}", r.error);
                for (a, b) in r.curve.points.iter().zip(&sg.points) {
                    assert!(a.distance(*b) < 1e-9, "SG m={m} +{extra} {c}");
                }
            }
        }
    }
}

#[test]
fn constraints_hold_for_sg_shapes() {
    // Random originals (plain and SG), random reduced shapes with ω > 0, where Bernstein's
    // end-derivative rule would be wrong.
    let mut rng = Rng::seeded(31);
    for n in 4..=9 {
        for m in 3..n {
            let original = if n % 2 == 0 {
                SgBezier::from_bezier(rng.points(n + 1)).unwrap()
            } else {
                let s = rng.shape(n);
                SgBezier::new(rng.points(n + 1), s).unwrap()
            };
            let [p0, p1, dp0, dp1] = ends(&original);
            let shape = rng.shape(m);
            let c0 = reduce_exact(&original, m, Constraint::C0, &shape).unwrap();
            let [q0, q1, _, _] = ends(&c0.curve);
            assert!(q0.distance(p0) < 1e-12 && q1.distance(p1) < 1e-12);
            assert!(c0.curve.points[0] == original.points[0]);
            assert!(c0.curve.points[m] == original.points[n]);
            let c1 = reduce_exact(&original, m, Constraint::C1, &shape).unwrap();
            let [q0, q1, dq0, dq1] = ends(&c1.curve);
            let scale = dp0.length().max(dp1.length());
            assert!(q0.distance(p0) < 1e-12 && q1.distance(p1) < 1e-12);
            assert!(dq0.distance(dp0) < 1e-12 * scale, "n={n} m={m}");
            assert!(dq1.distance(dp1) < 1e-12 * scale, "n={n} m={m}");
            // And by central differences on the curves themselves (polynomials, so t may
            // leave [0, 1]).
            let fd = |c: &SgBezier, t: f64| (c.eval(t + 1e-5) - c.eval(t - 1e-5)) / 2e-5;
            assert!(fd(&c1.curve, 0.0).distance(fd(&original, 0.0)) < 1e-6 * scale);
            assert!(fd(&c1.curve, 1.0).distance(fd(&original, 1.0)) < 1e-6 * scale);
            // Constraints cost accuracy, never gain it.
            let free = reduce_exact(&original, m, Constraint::None, &shape).unwrap();
            assert!(free.error <= c0.error * (1.0 + 1e-12));
            assert!(c0.error <= c1.error * (1.0 + 1e-12));
        }
    }
}

/// ∫₀¹ ‖a − b‖² by composite Simpson on 20,000 intervals, square-rooted.
fn dense_l2(a: &SgBezier, b: &SgBezier) -> f64 {
    let k = 20_000;
    let h = 1.0 / k as f64;
    let f = |t: f64| (a.eval(t) - b.eval(t)).length_squared();
    let mut s = f(0.0) + f(1.0);
    for i in 1..k {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    (s * h / 3.0).sqrt()
}

#[test]
fn error_matches_dense_integration() {
    let p = example1();
    let mut rng = Rng::seeded(41);
    let sg = SgBezier::new(rng.points(8), rng.shape(7)).unwrap();
    for original in [&p, &sg] {
        for c in [Constraint::None, Constraint::C0, Constraint::C1] {
            for shape in [SgShape::bezier(4), rng.shape(4)] {
                let r = reduce_exact(original, 4, c, &shape).unwrap();
                let dense = dense_l2(original, &r.curve);
                assert!(
                    rel(r.error, dense) < 1e-9,
                    "{c}: {:e} vs {dense:e}",
                    r.error
                );
                assert!(rel(l2_distance(original, &r.curve).unwrap(), dense) < 1e-9);
            }
        }
    }
}

#[test]
fn least_squares_is_a_minimum() {
    // Moving any free control point in any direction raises the error.
    let mut rng = Rng::seeded(51);
    let original = SgBezier::new(rng.points(7), rng.shape(6)).unwrap();
    for c in [Constraint::None, Constraint::C0, Constraint::C1] {
        let shape = rng.shape(4);
        let r = reduce_exact(&original, 4, c, &shape).unwrap();
        let fixed: &[usize] = match c {
            Constraint::None => &[],
            Constraint::C0 => &[0, 4],
            Constraint::C1 => &[0, 1, 3, 4],
        };
        for i in (0..=4).filter(|i| !fixed.contains(i)) {
            for d in [Point::new(1e-4, 0.0), Point::new(0.0, -1e-4)] {
                let mut moved = r.curve.clone();
                moved.points[i] += d;
                assert!(l2_distance(&original, &moved).unwrap() > r.error, "{c} {i}");
            }
        }
    }
}

#[test]
fn reduce_bezier_five_to_three_with_c1() {
    let mut rng = Rng::seeded(61);
    let p = rng.points(6);
    let (q, err) = reduce_bezier(&p, 3, Constraint::C1).unwrap();
    // Cubic with end points and end derivatives 5(P1 − P0) = 3(Q1 − Q0): nothing is free.
    assert_eq!(q.len(), 4);
    assert!(q[0] == p[0] && q[3] == p[5]);
    assert!(q[1].distance(p[0] + (p[1] - p[0]) * (5.0 / 3.0)) < 1e-12);
    assert!(q[2].distance(p[5] + (p[4] - p[5]) * (5.0 / 3.0)) < 1e-12);
    let original = SgBezier::from_bezier(p.clone()).unwrap();
    let cubic = SgBezier::from_bezier(q).unwrap();
    assert!(rel(err, dense_l2(&original, &cubic)) < 1e-9);
    let (_, free) = reduce_bezier(&p, 3, Constraint::None).unwrap();
    assert!(free < err);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let p = example1();
    let opt = |m: usize| ReduceOptions::new(m);
    let is_option = |r: Result<Reduction>, name: &str| match r {
        Err(Error::InvalidOption { name: n, .. }) => assert_eq!(n, name),
        other => panic!("expected an {name} error, got {other:?}"),
    };
    is_option(reduce(&p, &opt(0)), "degree");
    is_option(reduce(&p, &opt(6)), "degree");
    is_option(reduce(&p, &opt(9)), "degree");
    let c1 = |m| ReduceOptions {
        constraint: Constraint::C1,
        ..opt(m)
    };
    is_option(reduce(&p, &c1(2)), "degree");
    let short = SgBezier::from_bezier(p.points[..4].to_vec()).unwrap();
    let err = reduce(&short, &c1(3)).unwrap_err().to_string();
    assert!(err.contains("needs degree at least 4"), "{err}");
    is_option(
        reduce(
            &p,
            &ReduceOptions {
                method: "nope".into(),
                ..opt(4)
            },
        ),
        "method",
    );
    is_option(
        reduce(
            &p,
            &ReduceOptions {
                method: "gwo".into(),
                budget: 0,
                ..opt(4)
            },
        ),
        "budget",
    );
    is_option(
        reduce(
            &p,
            &ReduceOptions {
                method: "gwo".into(),
                shape: Some(SgShape::bezier(4)),
                ..opt(4)
            },
        ),
        "shape",
    );
    is_option(
        reduce(
            &p,
            &ReduceOptions {
                shape: Some(SgShape::bezier(5)),
                ..opt(4)
            },
        ),
        "shape",
    );
    let nan_shape = SgShape {
        omega: f64::NAN,
        ..SgShape::bezier(4)
    };
    is_option(
        reduce(
            &p,
            &ReduceOptions {
                shape: Some(nan_shape),
                ..opt(4)
            },
        ),
        "shape",
    );
    // Non-finite or inconsistent curves.
    let mut bad = p.clone();
    bad.points[2].x = f64::INFINITY;
    assert!(matches!(
        reduce(&bad, &opt(4)),
        Err(Error::InvalidInput { .. })
    ));
    let mut bad = p.clone();
    bad.points.pop();
    assert!(matches!(
        reduce(&bad, &opt(4)),
        Err(Error::InvalidInput { .. })
    ));
    let huge = SgBezier::from_bezier(vec![Point::new(1e308, -1e308); 7]).unwrap();
    assert!(reduce(&huge, &opt(4)).is_err());
    assert!(reduce_bezier(&[], 1, Constraint::None).is_err());
    // Singular: ω = 1, λ_1 = 5, λ_2 = 0 makes l_{1,4} ≡ 0.
    let singular = shape4(1.0, [5.0, 0.0], [2.0, 2.0]);
    let err = reduce_exact(&p, 4, Constraint::None, &singular)
        .unwrap_err()
        .to_string();
    assert!(err.contains("singular"), "{err}");
    // C1 impossible: ω = 1, λ_1 = m + 1 makes Q'(0) = 0 for every Q.
    let flat = shape4(1.0, [5.0, 3.0], [2.0, 2.0]);
    let err = reduce_exact(&p, 4, Constraint::C1, &flat)
        .unwrap_err()
        .to_string();
    assert!(err.contains("C1 is impossible"), "{err}");
    // An optimizer steps over such shapes (the box contains them) without failing.
    for c in [Constraint::None, Constraint::C1] {
        let r = reduce(
            &p,
            &ReduceOptions {
                constraint: c,
                method: "gwo".into(),
                budget: 300,
                ..opt(4)
            },
        )
        .unwrap();
        assert!(r.error.is_finite());
    }
}

#[test]
fn curve_files() {
    let c = parse_curve_json(r#"{"control_points": [[0, 0], [1, 2], [3, 1]]}"#, "f").unwrap();
    assert_eq!(c.degree(), 2);
    assert_eq!(c.shape, SgShape::bezier(2));
    let c = parse_curve_json(
        r#"{"control_points": [[0,0],[1,2],[3,1],[4,0]], "omega": 0.5, "lambda": [1, 2], "mu": [3]}"#,
        "f",
    )
    .unwrap();
    assert_eq!(
        c.shape,
        SgShape::new(3, 0.5, vec![1.0, 2.0], vec![3.0]).unwrap()
    );
    for (text, expect) in [
        ("{", "not a valid curve file"),
        (r#"{"points": [[0, 0]]}"#, "not a valid curve file"),
        (
            r#"{"control_points": [[0, 0]], "lamda": [1]}"#,
            "unknown field",
        ),
        (r#"{"control_points": []}"#, "empty"),
        (
            r#"{"control_points": [[0, 0, 1]]}"#,
            "not a valid curve file",
        ),
        (r#"{"control_points": [[0, 0], [1, 1e999]]}"#, "not a valid"),
        (
            r#"{"control_points": [[0,0],[1,2],[3,1]], "lambda": [1, 2]}"#,
            "λ",
        ),
    ] {
        match parse_curve_json(text, "curve.json") {
            Err(Error::InvalidInput { what, message }) => {
                assert_eq!(what, "curve.json");
                assert!(message.contains(expect), "{text}: {message}");
            }
            other => panic!("{text}: {other:?}"),
        }
    }
    assert!(matches!(
        read_curve_json(std::path::Path::new("/nonexistent/curve.json")),
        Err(Error::Read { .. })
    ));
}

#[test]
fn svg_picture_has_both_curves() {
    let p = example1();
    let r = reduce(&p, &ReduceOptions::new(4)).unwrap();
    let svg = reduction_svg(&p, &r).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("viewBox"));
    assert_eq!(svg.matches("<polyline").count(), 4);
    assert_eq!(svg.matches("<circle").count(), 7 + 5);
}
