//! An image with many contours has them fitted in parallel; the result must not depend on
//! the number of threads, down to the last bit of every number.

mod common;

use outlinefit::optim::Algorithm;
use outlinefit::Bitmap;
use outlinefit::{to_svg, ExportOptions};
use outlinefit::{trace_bitmap, Config, Method, TraceResult};

/// A 480 × 360 page of 12 × 9 anti-aliased rings and disks (4 × 4 supersampled), radii
/// 9 to 15 px: about a hundred contours of similar size.
fn page() -> Bitmap {
    let (w, h) = (480usize, 360usize);
    let shapes: Vec<(f64, f64, f64, bool)> = (0..12 * 9)
        .map(|k| {
            let (i, j) = (k % 12, k / 12);
            let r = 9.0 + (k * 7 % 13) as f64 / 2.0;
            let centre = (
                20.0 + 40.0 * i as f64 + 0.37 * j as f64,
                20.0 + 40.0 * j as f64,
            );
            (centre.0, centre.1, r, k % 3 == 0)
        })
        .collect();
    let inside = |x: f64, y: f64| {
        shapes.iter().any(|&(cx, cy, r, ring)| {
            let d = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt();
            d < r && !(ring && d < 0.45 * r)
        })
    };
    supersampled(w, h, inside)
}

/// A `w` × `h` coverage image of the shape `inside` (true inside), from 4 × 4 samples
/// per pixel.
fn supersampled(w: usize, h: usize, inside: impl Fn(f64, f64) -> bool) -> Bitmap {
    let coverage = common::supersampled_coverage(w, h, 4, inside);
    Bitmap::from_coverage(w as u32, h as u32, coverage, None).unwrap()
}

fn on_threads(threads: usize, bitmap: &Bitmap, config: &Config) -> TraceResult {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| trace_bitmap(bitmap, config).unwrap())
}

#[test]
fn many_contours_give_the_same_result_on_one_and_three_threads() {
    let bitmap = page();
    // Enough work outside the largest contour for the parallel path.
    let lsq = Config {
        timings: false,
        ..Config::default()
    };
    let contours = trace_bitmap(&bitmap, &lsq).unwrap().contours;
    let sizes: Vec<usize> = contours.iter().map(|c| c.points.len()).collect();
    let beside_largest = sizes.iter().sum::<usize>() - sizes.iter().max().unwrap();
    assert!(contours.len() >= 140 && beside_largest >= 6000, "{sizes:?}");
    for optimizer in [Method::Lsq, Method::Metaheuristic(Algorithm::Hs)] {
        let config = Config {
            optimizer,
            budget: 300,
            seed: 9,
            timings: false,
            ..Config::default()
        };
        let one = on_threads(1, &bitmap, &config);
        let three = on_threads(3, &bitmap, &config);
        assert_eq!(one.contours.len(), contours.len());
        assert_eq!(one.segment_count(), three.segment_count(), "{optimizer}");
        assert_eq!(
            one.sum_sq().to_bits(),
            three.sum_sq().to_bits(),
            "{optimizer}"
        );
        for (a, b) in one.contours.iter().zip(&three.contours) {
            for (s, t) in a.segments.iter().zip(&b.segments) {
                assert_eq!(s.curve.points, t.curve.points, "{optimizer}");
                assert_eq!(s.curve.weights, t.curve.weights, "{optimizer}");
            }
        }
        let opts = ExportOptions::default();
        assert_eq!(to_svg(&one, &opts), to_svg(&three, &opts), "{optimizer}");
        assert!(one.fidelity.held, "{optimizer}");
    }
}

/// A 840 × 840 star of 20 spikes (radii 400 and 300 px, 4 × 4 supersampled): one contour
/// of more than 4 000 points with 40 corners, whose cracks are refined, and whose runs
/// from corner to corner and segment errors are computed, in parallel.
fn star() -> Bitmap {
    let n = 840usize;
    let c = n as f64 / 2.0;
    let vertices: Vec<(f64, f64)> = (0..40)
        .map(|k| {
            let a = k as f64 * std::f64::consts::PI / 20.0 + 0.05;
            let r = if k % 2 == 0 { 400.0 } else { 300.0 };
            (c + r * a.cos(), c + r * a.sin())
        })
        .collect();
    // Even-odd rule over the polygon's edges.
    let inside = |x: f64, y: f64| {
        let mut odd = false;
        for k in 0..vertices.len() {
            let (a, b) = (vertices[k], vertices[(k + 1) % vertices.len()]);
            if (a.1 > y) != (b.1 > y) && x < a.0 + (b.0 - a.0) * (y - a.1) / (b.1 - a.1) {
                odd = !odd;
            }
        }
        odd
    };
    supersampled(n, n, inside)
}

#[test]
fn one_large_contour_with_corners_gives_the_same_result_on_one_and_three_threads() {
    let bitmap = star();
    let config = Config {
        timings: false,
        ..Config::default()
    };
    let one = on_threads(1, &bitmap, &config);
    let three = on_threads(3, &bitmap, &config);
    assert_eq!(one.contours.len(), 1);
    let contour = &one.contours[0];
    assert!(contour.points.len() >= 4000, "{}", contour.points.len());
    assert_eq!(contour.points, three.contours[0].points);
    let corners = contour
        .joints
        .iter()
        .filter(|j| j.kind == outlinefit::JointKind::Corner)
        .count();
    assert_eq!(corners, 40);
    // Corner to corner the star's sides are straight: one segment each.
    assert_eq!(contour.segments.len(), 40);
    for (s, t) in contour.segments.iter().zip(&three.contours[0].segments) {
        assert_eq!(s.curve.points, t.curve.points);
        assert_eq!(s.curve.weights, t.curve.weights);
        assert_eq!(
            s.error.max_distance.to_bits(),
            t.error.max_distance.to_bits()
        );
    }
    let opts = ExportOptions::default();
    assert_eq!(to_svg(&one, &opts), to_svg(&three, &opts));
    assert!(one.fidelity.held);
}

/// A 1120 × 800 page of 28 × 20 anti-aliased rings and disks at a 40 px pitch: enough
/// pixel-edge cracks and data points beside the largest border that the borders are
/// refined, and the fidelity check measured, on the thread pool.
fn large_page() -> Bitmap {
    let (cols, rows, pitch) = (28usize, 20usize, 40.0);
    let shape = |k: usize| {
        let (i, j) = (k % cols, k / cols);
        let r = 9.0 + (k * 7 % 13) as f64 / 2.0;
        let centre = (
            20.0 + pitch * i as f64 + 0.37 * (j % 5) as f64,
            20.0 + pitch * j as f64 + 0.21 * (i % 3) as f64,
        );
        (centre, r, k.is_multiple_of(3))
    };
    let inside = |x: f64, y: f64| {
        let (i, j) = ((x / pitch) as usize, (y / pitch) as usize);
        if i >= cols || j >= rows {
            return false;
        }
        let ((cx, cy), r, ring) = shape(j * cols + i);
        let d = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt();
        d < r && !(ring && d < 0.45 * r)
    };
    supersampled(cols * pitch as usize, rows * pitch as usize, inside)
}

#[test]
fn contour_refinement_and_fidelity_check_give_the_same_result_on_one_and_three_threads() {
    let bitmap = large_page();
    let config = Config {
        timings: false,
        ..Config::default()
    };
    let one = on_threads(1, &bitmap, &config);
    let three = on_threads(3, &bitmap, &config);
    // 560 shapes, a third of them rings with a hole.
    assert_eq!(one.contours.len(), 560 + 187);
    let points: usize = one.contours.iter().map(|c| c.points.len()).sum();
    assert!(points >= 40_000, "{points}");
    assert_eq!(one.contours.len(), three.contours.len());
    for (a, b) in one.contours.iter().zip(&three.contours) {
        assert_eq!(a.points, b.points);
        assert_eq!(a.is_hole, b.is_hole);
        assert_eq!(a.parent, b.parent);
    }
    let opts = ExportOptions::default();
    assert_eq!(to_svg(&one, &opts), to_svg(&three, &opts));
    assert!(one.fidelity.held && three.fidelity.held);
    assert_eq!(
        one.fidelity.max_deviation.to_bits(),
        three.fidelity.max_deviation.to_bits()
    );
    assert!(
        one.fidelity.max_deviation <= 0.325,
        "{}",
        one.fidelity.max_deviation
    );
}

/// The large page with grain (uniform noise of ±0.2, from a fixed seed) and flecks (one
/// pixel in 60 flipped to full ink; at one in 500 the fit's corners for short runs leave
/// nothing to repair): contours fail the check where the grain bends them or a fleck
/// touches them, so the repair's rounds refit several at once and the check after them
/// looks again only around those. The result is the same on one and three threads.
#[test]
fn repair_rounds_give_the_same_result_on_one_and_three_threads() {
    use rand::{RngExt, SeedableRng};
    let page = large_page();
    let (w, h) = (page.width(), page.height());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let coverage: Vec<f32> = (0..w as i64 * h as i64)
        .map(|i| {
            let c = page.coverage_at(i % w as i64, i / w as i64);
            let grain: f32 = rng.random_range(-0.2..0.2);
            if rng.random_range(0..60) == 0 {
                1.0
            } else {
                (c + grain).clamp(0.0, 1.0)
            }
        })
        .collect();
    let bitmap = Bitmap::from_coverage(w, h, coverage, None).unwrap();
    let config = Config {
        timings: false,
        ..Config::default()
    };
    let one = on_threads(1, &bitmap, &config);
    let three = on_threads(3, &bitmap, &config);
    assert!(
        one.fidelity.repaired_contours >= 4,
        "{}",
        one.fidelity.repaired_contours
    );
    assert_eq!(
        one.fidelity.repaired_contours,
        three.fidelity.repaired_contours
    );
    assert_eq!(one.fidelity.held, three.fidelity.held);
    let opts = ExportOptions::default();
    assert_eq!(to_svg(&one, &opts), to_svg(&three, &opts));
    for (a, b) in one.contours.iter().zip(&three.contours) {
        for (s, t) in a.segments.iter().zip(&b.segments) {
            assert_eq!(s.curve.points, t.curve.points);
            assert_eq!(s.curve.weights, t.curve.weights);
        }
    }
}
