//! Self-test of the rendering helpers in `tests/common/mod.rs`: SVG coverage
//! on hand-written shapes with known answers, IoU, and the bundled samples
//! (present, loadable, non-trivial, and with the properties their names
//! promise).

mod common;

use common::{
    coverage_iou, image_coverage, render_svg_coverage, render_svg_coverage_scaled, sample_paths,
    samples_dir,
};

fn svg(path: &str, w: u32, h: u32) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}"><path d="{path}" fill="#123"/></svg>"##
    )
}

/// Coverage of an axis-aligned box [x0, x1) × [y0, y1) in whole pixels.
fn box_coverage(w: u32, h: u32, x0: u32, x1: u32, y0: u32, y1: u32) -> Vec<f32> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x0..x1).contains(&x) && (y0..y1).contains(&y)))
        .map(|inside| if inside { 1.0 } else { 0.0 })
        .collect()
}

#[test]
fn rectangle_renders_with_full_and_zero_coverage() {
    let (w, h) = (16, 10);
    let cov = render_svg_coverage(&svg("M 2 2 H 12 V 8 H 2 Z", w, h), w, h);
    assert_eq!(cov.len(), (w * h) as usize);
    let expected = box_coverage(w, h, 2, 12, 2, 8);
    for (i, (&got, &want)) in cov.iter().zip(&expected).enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        assert!(
            (got - want).abs() < 1e-3,
            "pixel ({x}, {y}): coverage {got}, expected {want}"
        );
    }
    let iou = coverage_iou(&cov, &expected);
    assert!((iou - 1.0).abs() < 1e-6, "IoU {iou}");
}

#[test]
fn half_pixel_edge_gives_half_coverage() {
    let (w, h) = (16, 10);
    let cov = render_svg_coverage(&svg("M 2 2 H 12.5 V 8 H 2 Z", w, h), w, h);
    for y in 2..8 {
        let c = cov[(y * w + 12) as usize];
        assert!((c - 0.5).abs() <= 0.02, "row {y}: edge pixel coverage {c}");
        assert!(cov[(y * w + 11) as usize] > 0.99);
        assert!(cov[(y * w + 13) as usize] < 0.01);
    }
}

#[test]
fn scaled_rendering_scales_the_shape() {
    let cov = render_svg_coverage_scaled(&svg("M 2 2 H 12 V 8 H 2 Z", 16, 10), 32, 20, 2.0);
    let iou = coverage_iou(&cov, &box_coverage(32, 20, 4, 24, 4, 16));
    assert!(iou > 0.999, "IoU {iou}");
}

#[test]
fn iou_of_partial_overlap() {
    let a = [1.0, 1.0, 0.0, 0.5];
    let b = [1.0, 0.0, 1.0, 0.5];
    // min: 1 + 0 + 0 + 0.5 = 1.5; max: 1 + 1 + 1 + 0.5 = 3.5.
    assert!((coverage_iou(&a, &b) - 1.5 / 3.5).abs() < 1e-9);
    assert_eq!(coverage_iou(&[0.0; 3], &[0.0; 3]), 1.0);
}

#[test]
fn every_sample_loads_with_nontrivial_foreground() {
    let paths = sample_paths();
    for name in [
        "s.png",
        "e.png",
        "aeroplane.png",
        "pear.png",
        "glyph_aa.png",
        "glyph_bw.png",
        "logo.png",
    ] {
        assert!(
            paths.contains(&samples_dir().join(name)),
            "missing sample {name}"
        );
    }
    for path in &paths {
        let (w, h, cov) = image_coverage(path);
        assert_eq!(cov.len(), (w * h) as usize);
        assert!(
            w <= 320 && h <= 320,
            "{} is {w}x{h}: keep samples small",
            path.display()
        );
        let fraction = cov.iter().map(|&c| f64::from(c)).sum::<f64>() / cov.len() as f64;
        assert!(
            (0.02..=0.80).contains(&fraction),
            "{}: foreground fraction {fraction:.3}",
            path.display()
        );
        // Background (first pixel is in the margin) must read as empty.
        assert!(
            cov[0] < 0.01,
            "{}: corner pixel coverage {}",
            path.display(),
            cov[0]
        );
    }
}

#[test]
fn glyph_bw_is_bilevel() {
    let img = image::open(samples_dir().join("glyph_bw.png")).expect("glyph_bw.png loads");
    let gray = img.as_luma8().expect("glyph_bw.png is 8-bit grayscale");
    assert!(
        gray.pixels().all(|p| p.0[0] == 0 || p.0[0] == 255),
        "non-bilevel value"
    );
    assert!(gray.pixels().any(|p| p.0[0] == 0) && gray.pixels().any(|p| p.0[0] == 255));
}

#[test]
fn logo_shape_is_in_alpha() {
    let path = samples_dir().join("logo.png");
    let img = image::open(&path).expect("logo.png loads");
    let rgba = img.as_rgba8().expect("logo.png is RGBA8");
    assert!(
        rgba.pixels().any(|p| p.0[3] == 0),
        "logo.png has no transparent pixel"
    );
    assert!(
        rgba.pixels().any(|p| p.0[3] == 255),
        "logo.png has no opaque pixel"
    );
    // Coverage comes from alpha, not from the (constant, dark) colour.
    let (_, _, cov) = image_coverage(&path);
    for (p, c) in rgba.pixels().zip(&cov) {
        assert!((f32::from(p.0[3]) / 255.0 - c).abs() < 1e-6);
    }
}
