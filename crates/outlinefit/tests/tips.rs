//! Tips between straight sides on a large grey-level image: a corner is sharpened to where
//! its sides meet only where the pixels show the wedge. The blunt apex of a serif "A" at
//! 600 dpi has straight sides that meet 6 px above its ink; sharpened, it invented a
//! spike that the fidelity check then sent down the repair ladder (29 such regions on a
//! scanned page of text).

mod common;

use outlinefit::{trace_bitmap, Bitmap, Config, TraceResult};

/// Side of the image: large enough that the break window is at its widest (8 px).
const SIDE: usize = 900;
/// The wedge's vertex (x, y); it opens downwards.
const VERTEX: (f64, f64) = (450.0, 200.0);
/// Half-opening of the wedge (degrees).
const HALF_OPENING: f64 = 20.0;
/// Where the wedge is cut off at the bottom.
const BOTTOM: f64 = 700.0;

/// A wedge whose tip is rounded by a circle of radius `r` tangent to both sides (`r` = 0:
/// sharp), drawn anti-aliased with 8 × 8 samples per pixel and blurred by a Gaussian of
/// `sigma` px (0: not blurred), as a scanner blurs.
fn wedge(r: f64, sigma: f64) -> Bitmap {
    let (s, c) = HALF_OPENING.to_radians().sin_cos();
    // The circle's centre lies on the axis, r / sin α below the vertex; it touches the
    // sides where they are r·cos α / sin α · cos α below the vertex along the axis.
    let centre = VERTEX.1 + r / s;
    let tangent_depth = (r / s) * c * c;
    let coverage = common::supersampled_coverage(SIDE, SIDE, 8, |x, y| {
        let (dx, depth) = (x - VERTEX.0, y - VERTEX.1);
        let in_wedge = depth > 0.0 && dx.abs() < depth * s / c && y < BOTTOM;
        in_wedge && (depth >= tangent_depth || dx.hypot(y - centre) <= r)
    });
    let coverage = if sigma > 0.0 {
        blur(&coverage, sigma)
    } else {
        coverage
    };
    Bitmap::from_coverage(SIDE as u32, SIDE as u32, coverage, Some(0.5)).unwrap()
}

/// `field` (SIDE × SIDE) blurred by a Gaussian of `sigma` px, rows then columns.
fn blur(field: &[f32], sigma: f64) -> Vec<f32> {
    let reach = (3.0 * sigma).ceil() as i64;
    let kernel: Vec<f64> = (-reach..=reach)
        .map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp())
        .collect();
    let sum: f64 = kernel.iter().sum();
    let pass = |src: &[f32], step: (usize, usize)| -> Vec<f32> {
        let mut out = vec![0f32; src.len()];
        for y in 0..SIDE {
            for x in 0..SIDE {
                let mut acc = 0.0;
                for (j, w) in kernel.iter().enumerate() {
                    let d = j as i64 - reach;
                    let (xx, yy) = (x as i64 + d * step.0 as i64, y as i64 + d * step.1 as i64);
                    let (xx, yy) = (xx.clamp(0, SIDE as i64 - 1), yy.clamp(0, SIDE as i64 - 1));
                    acc += w * f64::from(src[yy as usize * SIDE + xx as usize]);
                }
                out[y * SIDE + x] = (acc / sum) as f32;
            }
        }
        out
    };
    pass(&pass(field, (1, 0)), (0, 1))
}

/// The highest point (smallest y) of the traced outline, sampled along every segment.
fn top(result: &TraceResult) -> f64 {
    result
        .contours
        .iter()
        .flat_map(|c| &c.segments)
        .flat_map(|s| (0..=64).map(move |k| s.curve.eval(f64::from(k) / 64.0).y))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_blunt_tip_between_straight_sides_keeps_its_shape() {
    // Rounded by 3 px: the ink ends 3 / sin 20° − 3 = 5.77 px below where the sides meet.
    let r = 3.0;
    let ink_top = VERTEX.1 + r / HALF_OPENING.to_radians().sin() - r;
    let result = trace_bitmap(&wedge(r, 0.0), &Config::default()).unwrap();
    let top = top(&result);
    assert!(
        (top - ink_top).abs() < 0.3,
        "the outline's top is at y = {top:.2}, the ink's at {ink_top:.2} (the sides meet at {})",
        VERTEX.1
    );
    assert!(result.fidelity.held, "{:?}", result.fidelity);
    assert_eq!(
        result.fidelity.repaired_contours, 0,
        "the first fit should need no repair"
    );
}

#[test]
fn a_sharp_tip_is_still_sharpened_to_where_its_sides_meet() {
    // Thresholding cuts a 40° wedge where it is narrower than about a pixel, 1.4 px from
    // its vertex, and blur rounds it further (without the sides' intersection the tip
    // ends 2.25 px short at σ = 1); the intersection brings the tip back. At σ = 1.5 it
    // comes 0.4 px short.
    for (sigma, bound) in [(0.0, 0.3), (1.0, 0.3), (1.5, 0.5)] {
        let result = trace_bitmap(&wedge(0.0, sigma), &Config::default()).unwrap();
        let top = top(&result);
        assert!(
            (top - VERTEX.1).abs() < bound,
            "blur {sigma}: the outline's top is at y = {top:.2}, the vertex at {}",
            VERTEX.1
        );
        assert!(result.fidelity.held, "blur {sigma}: {:?}", result.fidelity);
    }
}
