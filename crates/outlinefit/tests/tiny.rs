//! Every bilevel image up to 4 × 4 pixels (and a seeded sample of 5 × 5 and 6 × 6 ones)
//! traces without a panic: each gives an outline or one of the typed "no shape" errors,
//! at the default minimum area and with none. (A 1 × 1 black image panicked in the
//! shape count of the "no shape" message.) An outline whose check holds matches the
//! pixels, rendered by resvg: no more pixel centres clearly on the wrong side than the
//! check allows (twelve 64ths of the pixels near an outline and two more), not counting,
//! at the default minimum area, the specks of one or two pixels that it drops.

mod common;

use image::{DynamicImage, GrayImage, Luma};
use outlinefit::{to_svg, trace_bitmap, Bitmap, Config, Error, ExportOptions};
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;

/// The image of `bits` (bit `i` set: pixel `i` in row order is black).
fn image(w: u32, h: u32, bits: u64) -> DynamicImage {
    DynamicImage::ImageLuma8(GrayImage::from_fn(w, h, |x, y| {
        let i = y * w + x;
        Luma([if bits >> i & 1 == 1 { 0 } else { 255 }])
    }))
}

/// A panic is caught and listed by [`check`]; thousands of them would bury the log.
fn quiet_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| std::panic::set_hook(Box::new(|_| {})));
}

/// Traces the image with both minimum areas; what went wrong, if anything.
fn check(w: u32, h: u32, bits: u64) -> Option<String> {
    for min_area in [2.0, 0.0] {
        let config = Config {
            min_area,
            timings: false,
            ..Config::default()
        };
        let img = image(w, h, bits);
        let outcome = std::panic::catch_unwind(|| {
            let bitmap = Bitmap::from_image(&img, &config.raster_options())?;
            trace_bitmap(&bitmap, &config)
        });
        let name = format!("{w}x{h} pattern {bits:#x}, min_area {min_area}");
        match outcome {
            Err(_) => return Some(format!("{name}: panicked")),
            Ok(Ok(result)) => {
                if result.contours.is_empty() {
                    return Some(format!("{name}: an outline of no contour"));
                }
                if result.fidelity.held {
                    let svg = to_svg(&result, &ExportOptions::default());
                    let wrong = wrong_centres(w, h, bits, &svg);
                    // With the default minimum area, the specks it drops are wrong on
                    // purpose. Beyond them, no more wrong centres than the dense limit of
                    // one tile and the region limit allow.
                    let specks = if min_area > 0.0 {
                        small_components(w, h, bits, 2)
                    } else {
                        Vec::new()
                    };
                    let wrong = wrong.iter().filter(|i| !specks.contains(i)).count();
                    let allowed = (w * h) as usize * 12 / 64 + 2;
                    if wrong > allowed {
                        return Some(format!("{name}: held with {wrong} wrong pixel centres"));
                    }
                }
            }
            Ok(Err(Error::NoForeground { .. } | Error::AllBelowMinArea { .. })) => {
                if bits != 0 && min_area == 0.0 {
                    return Some(format!("{name}: ink found no shape at min_area 0"));
                }
            }
            Ok(Err(e)) => return Some(format!("{name}: {e}")),
        }
    }
    None
}

/// Pixels (row-order indices) whose centre the drawn SVG puts on the other side than
/// `bits`, clearly: rendered at 5×, the 3 × 3 rendered pixels around the centre (0.3 px
/// each way) all on the wrong side. A centre that an edge passes within a few hundredths
/// of a pixel is on either side by rounding, for the check as for a renderer.
fn wrong_centres(w: u32, h: u32, bits: u64, svg: &str) -> Vec<usize> {
    let drawn = common::render_svg_coverage_scaled(svg, 5 * w, 5 * h, 5.0);
    let stride = 5 * w as usize;
    (0..(w * h) as usize)
        .filter(|&i| {
            let (x, y) = (i % w as usize, i / w as usize);
            let ink = bits >> i & 1 == 1;
            (5 * y + 1..=5 * y + 3)
                .all(|r| (5 * x + 1..=5 * x + 3).all(|c| (drawn[r * stride + c] >= 0.5) != ink))
        })
        .collect()
}

/// The pixels of components of at most `most` pixels, which a minimum area of 2 px² may
/// drop (a pair's pixel-edge midpoints enclose 1.5 px² at most): shapes and holes (white
/// pixels not joined to the outside), taken both 4- and 8-connected, since where two
/// pixels touch only at a corner the border follower may join or part them.
fn small_components(w: u32, h: u32, bits: u64, most: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for diagonal in [false, true] {
        out.extend(components_of_at_most(w, h, bits, most, diagonal));
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// [`small_components`] with one connectivity: 8 when `diagonal`, 4 otherwise.
fn components_of_at_most(w: u32, h: u32, bits: u64, most: usize, diagonal: bool) -> Vec<usize> {
    let (w, h) = (w as i64, h as i64);
    let ink = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h && bits >> (y * w + x) & 1 == 1;
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for start in 0..w * h {
        if seen[start as usize] {
            continue;
        }
        let colour = ink(start % w, start / w);
        let (mut stack, mut component, mut outside) = (vec![start], Vec::new(), false);
        seen[start as usize] = true;
        while let Some(p) = stack.pop() {
            component.push(p as usize);
            let (x, y) = (p % w, p / w);
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if (dx, dy) == (0, 0) || (!diagonal && dx != 0 && dy != 0) {
                        continue;
                    }
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w || ny >= h {
                        outside = true;
                        continue;
                    }
                    let q = ny * w + nx;
                    if ink(nx, ny) == colour && !seen[q as usize] {
                        seen[q as usize] = true;
                        stack.push(q);
                    }
                }
            }
        }
        if (colour || !outside) && component.len() <= most {
            out.extend(component);
        }
    }
    out
}

#[test]
fn every_bilevel_image_up_to_4x4_traces_or_says_why_not() {
    quiet_panics();
    let mut failures: Vec<String> = Vec::new();
    for (w, h) in (1..=4u32).flat_map(|w| (1..=4u32).map(move |h| (w, h))) {
        let n = 1u64 << (w * h);
        failures.extend(
            (0..n)
                .into_par_iter()
                .filter_map(|bits| check(w, h, bits))
                .collect::<Vec<_>>(),
        );
    }
    // The panic hook is silenced for the traces; the failures are printed here.
    for f in failures.iter().take(10) {
        eprintln!("{f}");
    }
    assert!(
        failures.is_empty(),
        "{} failures, the first: {:?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}

#[test]
fn random_5x5_and_6x6_images_trace_or_say_why_not() {
    quiet_panics();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
    let cases: Vec<(u32, u64)> = (0..2000)
        .map(|k| {
            let side = if k % 2 == 0 { 5 } else { 6 };
            (side, rng.random::<u64>() & ((1u64 << (side * side)) - 1))
        })
        .collect();
    let failures: Vec<String> = cases
        .into_par_iter()
        .filter_map(|(side, bits)| check(side, side, bits))
        .collect();
    for f in failures.iter().take(10) {
        eprintln!("{f}");
    }
    assert!(
        failures.is_empty(),
        "{:?}",
        &failures[..failures.len().min(10)]
    );
}
