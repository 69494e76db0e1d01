//! Every bilevel image up to 4 × 4 pixels (and a seeded sample of 5 × 5 and 6 × 6 ones)
//! traces without a panic: each gives an outline or one of the typed "no shape" errors,
//! at the default minimum area and with none. (A 1 × 1 black image panicked in the
//! shape count of the "no shape" message.)

use image::{DynamicImage, GrayImage, Luma};
use outlinefit::{trace_bitmap, Bitmap, Config, Error};
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
    assert!(
        failures.is_empty(),
        "{:?}",
        &failures[..failures.len().min(10)]
    );
}
