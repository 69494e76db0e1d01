//! Rendering helpers shared by the end-to-end tests (`mod common;` from a
//! `tests/*.rs` file; the program's tests include this file in theirs).
//!
//! * [`render_svg_coverage`] / [`render_svg_coverage_scaled`] rasterise an
//!   SVG (for instance one produced by the tracer) with `resvg` and return
//!   per-pixel coverage taken from alpha, so the fill colour does not matter;
//! * [`image_coverage`] reads a sample PNG the way the tracer sees it
//!   (alpha if at least a tenth of the pixels are mostly transparent, else `1 - luma`);
//! * [`coverage_iou`] compares two coverage fields (Σ min / Σ max);
//! * [`samples_dir`] / [`sample_paths`] locate the bundled samples;
//! * [`scratch`] makes an empty folder for one test;
//! * [`supersampled_coverage`] draws a shape given by an inside test, `ss` × `ss`
//!   samples per pixel.
//!
//! Coverage fields are row-major, `width * height` values in `[0, 1]`,
//! 1 meaning "inside the shape".

// Each test binary uses only some of these helpers, and `pub` items of a
// private module are unreachable by construction.
#![allow(dead_code, unreachable_pub)]

use std::path::{Path, PathBuf};

use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg;

/// A fresh, empty scratch folder for one test, named after the test file, the process and
/// `name`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "outlinefit-{}-{}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Renders `svg` at 1× (user units = pixels) onto a transparent
/// `width`×`height` pixmap and returns per-pixel coverage in `[0, 1]` from
/// the alpha channel.
///
/// Panics (this is test code) if the SVG does not parse or the size is zero.
pub fn render_svg_coverage(svg: &str, width: u32, height: u32) -> Vec<f32> {
    render_svg_coverage_scaled(svg, width, height, 1.0)
}

/// Like [`render_svg_coverage`] but scales the drawing by `scale` first
/// (user unit `u` lands at pixel `u * scale`); `width` and `height` are the
/// size of the output pixmap, in pixels.
pub fn render_svg_coverage_scaled(svg: &str, width: u32, height: u32, scale: f32) -> Vec<f32> {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default())
        .unwrap_or_else(|e| panic!("SVG does not parse: {e}\n{svg}"));
    let mut pixmap =
        Pixmap::new(width, height).unwrap_or_else(|| panic!("bad pixmap size {width}x{height}"));
    resvg::render(
        &tree,
        Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .pixels()
        .iter()
        .map(|p| f32::from(p.alpha()) / 255.0)
        .collect()
}

/// Loads an image and returns `(width, height, coverage)`, the way the tracer
/// sees it: if at least a tenth of the pixels have alpha below one half, coverage is
/// alpha; otherwise it is `1 - luma` (dark = inside), with
/// luma from the `image` crate's Rec. 709 conversion (exact for grayscale).
///
/// Panics with the path in the message if the image cannot be read.
pub fn image_coverage(path: &Path) -> (u32, u32, Vec<f32>) {
    let img = image::open(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let la = img.to_luma_alpha32f();
    let (width, height) = la.dimensions();
    let transparent = la.pixels().filter(|p| p.0[1] < 0.5).count();
    let use_alpha = transparent * 10 >= la.pixels().count();
    let coverage = la
        .pixels()
        .map(|p| {
            let c = if use_alpha { p.0[1] } else { 1.0 - p.0[0] };
            c.clamp(0.0, 1.0)
        })
        .collect();
    (width, height, coverage)
}

/// Intersection over union of two coverage fields: Σ min(a, b) / Σ max(a, b).
///
/// Two empty fields count as identical (IoU 1). Panics if the lengths differ.
pub fn coverage_iou(a: &[f32], b: &[f32]) -> f64 {
    assert_eq!(a.len(), b.len(), "coverage fields differ in size");
    let (mut inter, mut union) = (0.0f64, 0.0f64);
    for (&x, &y) in a.iter().zip(b) {
        inter += f64::from(x.min(y));
        union += f64::from(x.max(y));
    }
    if union == 0.0 {
        1.0
    } else {
        inter / union
    }
}

/// The repository's `samples/` directory (two levels above each crate).
pub fn samples_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples")
}

/// All `samples/*.png`, sorted by path.
pub fn sample_paths() -> Vec<PathBuf> {
    let dir = samples_dir();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|ext| ext == "png"))
        .collect();
    paths.sort();
    paths
}

/// Coverage of a `w` × `h` image by the shape `inside` (true inside, in pixel
/// coordinates), from `ss` × `ss` samples per pixel at (column + (j + 0.5) / ss,
/// row + (i + 0.5) / ss).
pub fn supersampled_coverage(
    w: usize,
    h: usize,
    ss: u32,
    inside: impl Fn(f64, f64) -> bool,
) -> Vec<f32> {
    let mut out = vec![0f32; w * h];
    for (k, c) in out.iter_mut().enumerate() {
        let (px, py) = ((k % w) as f64, (k / w) as f64);
        let mut hits = 0;
        for i in 0..ss {
            for j in 0..ss {
                let x = px + (f64::from(j) + 0.5) / f64::from(ss);
                let y = py + (f64::from(i) + 0.5) / f64::from(ss);
                hits += u32::from(inside(x, y));
            }
        }
        *c = hits as f32 / (ss * ss) as f32;
    }
    out
}
