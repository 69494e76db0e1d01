//! Tests of surface fitting: exact recovery, the fast objective against the direct sum,
//! correction against the classical rules, and validation.

use super::examples::Example;
use super::*;

/// A degree (η, σ) surface with irregular poles.
fn known_surface(eta: usize, sigma: usize) -> BezierSurface {
    let mut poles = Vec::new();
    for i in 0..=eta {
        for j in 0..=sigma {
            let (x, y) = (i as f64 / eta as f64, j as f64 / sigma as f64);
            let k = (i * 7 + j * 3) as f64;
            poles.push([
                x + 0.25 * k.sin(),
                y + 0.2 * (1.7 * k).cos(),
                0.5 * (0.9 * k).sin(),
            ]);
        }
    }
    BezierSurface {
        degree_u: eta,
        degree_v: sigma,
        poles,
    }
}

/// Non-uniform parameters from 0 to 1.
fn warped(n: usize, a: f64) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let s = k as f64 / (n - 1) as f64;
            s + a * (std::f64::consts::PI * s).sin() * s * (1.0 - s)
        })
        .collect()
}

fn grid_cloud(s: &BezierSurface, tau: &[f64], zeta: &[f64]) -> PointCloud {
    let points = tau
        .iter()
        .flat_map(|&t| zeta.iter().map(move |&z| s.eval(t, z)))
        .collect();
    PointCloud {
        points,
        grid: Some((tau.len(), zeta.len())),
    }
}

#[test]
fn least_squares_recovers_poles_at_the_true_parameters() {
    let s = known_surface(4, 3);
    let (tau, zeta) = (warped(11, 0.8), warped(9, -0.6));
    let grid = grid_cloud(&s, &tau, &zeta);
    let params = Params {
        tau: tau.clone(),
        zeta: zeta.clone(),
    };
    let fitter = solve::Fitter::new(&grid, (4, 3));
    let got = fitter.surface(&params);
    for (a, b) in got.poles.iter().zip(&s.poles) {
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-10), "{a:?} {b:?}");
    }
    // The same points, unorganized, at their own parameters.
    let mut us = Vec::new();
    let mut vs = Vec::new();
    for &t in &tau {
        for &z in &zeta {
            us.push(t);
            vs.push(z);
        }
    }
    let scattered = PointCloud {
        points: grid.points.clone(),
        grid: None,
    };
    let fitter = solve::Fitter::new(&scattered, (4, 3));
    let got = fitter.surface(&Params { tau: us, zeta: vs });
    for (a, b) in got.poles.iter().zip(&s.poles) {
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-9), "{a:?} {b:?}");
    }
}

#[test]
fn correction_recovers_an_exact_surface() {
    // Points sampled without noise from a known degree (5, 5) surface at known, uneven
    // parameters: correction from the centripetal ones finds the poles within 1e-8 and
    // Y below 1e-12.
    let s = known_surface(5, 5);
    let (tau, zeta) = (warped(19, 0.4), warped(23, -0.3));
    let cloud = grid_cloud(&s, &tau, &zeta);
    let fitted = fit(&cloud, &SurfaceOptions::default()).unwrap();
    assert!(fitted.error < 1e-12, "Y = {:e}", fitted.error);
    let worst = fitted
        .surface
        .poles
        .iter()
        .zip(&s.poles)
        .flat_map(|(a, b)| (0..3).map(move |k| (a[k] - b[k]).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-8, "pole error {worst:e}");
    let centripetal = fit(
        &cloud,
        &SurfaceOptions {
            method: ParamMethod::Centripetal,
            ..SurfaceOptions::default()
        },
    )
    .unwrap();
    assert!(centripetal.error > 1e-6, "the start was not already exact");
}

#[test]
fn the_fast_objective_matches_the_point_by_point_error() {
    for ex in Example::ALL {
        let cloud = ex.generate(3);
        let fitter = solve::Fitter::new(&cloud, ex.degree());
        let params = classical(&cloud, Rule::Centripetal);
        let fast = fitter.objective(&params);
        let direct = fitter.error(&fitter.surface(&params), &params);
        assert!(
            (fast - direct).abs() < 1e-9 * direct,
            "{ex:?} {fast} {direct}"
        );
    }
}

#[test]
fn correction_beats_every_classical_rule_on_the_examples() {
    for ex in Example::ALL {
        let cloud = ex.generate(11);
        let degree = ex.degree();
        let y = |method| {
            fit(
                &cloud,
                &SurfaceOptions {
                    degree,
                    method,
                    ..SurfaceOptions::default()
                },
            )
            .unwrap()
            .error
        };
        let corrected = y(ParamMethod::Correct);
        for m in [
            ParamMethod::Uniform,
            ParamMethod::Chordal,
            ParamMethod::Centripetal,
        ] {
            assert!(
                corrected < y(m),
                "{ex:?}: correct {corrected} vs {m:?} {}",
                y(m)
            );
        }
    }
}

#[test]
fn a_short_search_is_reproducible_and_reports_its_own_error() {
    let cloud = Example::I.generate(5);
    let options = SurfaceOptions {
        method: ParamMethod::Cs,
        budget: 600,
        seed: 9,
        ..SurfaceOptions::default()
    };
    let a = fit(&cloud, &options).unwrap();
    let b = fit(&cloud, &options).unwrap();
    assert_eq!(a.params, b.params);
    assert_eq!(a.evaluations, 600);
    let fitter = solve::Fitter::new(&cloud, (5, 5));
    let direct = fitter.error(&a.surface, &a.params);
    assert_eq!(direct, a.error);
    assert!((a.rmse - (a.error / 841.0).sqrt()).abs() < 1e-15);
}

#[test]
fn validation_names_what_is_wrong() {
    let cloud = PointCloud {
        points: vec![[0.0; 3]; 12],
        grid: Some((3, 4)),
    };
    let msg = |c: &PointCloud, o: &SurfaceOptions| validate(c, o).unwrap_err().to_string();
    let o = SurfaceOptions::default();
    assert_eq!(
        msg(&cloud, &o),
        "the points: a 3×4 grid is too small for degree (5, 5): it needs at least 6 rows and 6 columns"
    );
    let scattered = PointCloud {
        points: vec![[0.0; 3]; 12],
        grid: None,
    };
    assert_eq!(
        msg(&scattered, &o),
        "the points: 12 points are too few for degree (5, 5), which has 36 poles"
    );
    let wrong = PointCloud {
        points: vec![[0.0; 3]; 12],
        grid: Some((5, 5)),
    };
    assert_eq!(
        msg(&wrong, &o),
        "the points: a 5×5 grid needs 25 points, got 12"
    );
    let bad_degree = SurfaceOptions {
        degree: (0, 3),
        ..o
    };
    assert!(msg(&scattered, &bad_degree).contains("from 1 to 20"));
}
