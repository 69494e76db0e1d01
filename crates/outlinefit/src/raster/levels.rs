//! How a [`Bitmap`](super::Bitmap) stores its coverage: one small integer level per pixel
//! and a table of what each level means, so that a large image costs one or two bytes per
//! pixel instead of a 32-bit float.
//!
//! * 8-bit grey images keep their own bytes (the decoded buffer itself when the image is
//!   owned): a 256-entry table maps each byte to exactly the coverage the float
//!   conversion gives it.
//! * 16-bit grey images keep their 16-bit values, with a 65 536-entry table.
//! * Everything else (colour, grey with alpha, floating point, coverage given as floats)
//!   is quantised to 16 bits: level round(c × 65535), worth level / 65535. The rounding
//!   moves a coverage by at most 7.7 × 10⁻⁶, which moves an integrated edge by less than
//!   10⁻⁴ px.

/// Number of 16-bit levels.
const WORD_LEVELS: usize = 1 << 16;

/// Coverage levels, row-major, with the coverage of every level.
#[derive(Clone, Debug)]
pub(super) enum Levels {
    /// One byte per pixel.
    Byte(Vec<u8>, Box<[f32; 256]>),
    /// Two bytes per pixel.
    Word(Vec<u16>, Box<[f32; WORD_LEVELS]>),
}

impl Levels {
    /// Bytes as levels, each worth `value(byte)`.
    pub(super) fn bytes(levels: Vec<u8>, value: impl Fn(u8) -> f32) -> Levels {
        let mut table = Box::new([0.0f32; 256]);
        for (v, t) in (0..=u8::MAX).zip(table.iter_mut()) {
            *t = clamp(value(v));
        }
        Levels::Byte(levels, table)
    }

    /// 16-bit values as levels, each worth `value(word)`.
    pub(super) fn words(levels: Vec<u16>, value: impl Fn(u16) -> f32) -> Levels {
        let mut table = word_table();
        for (v, t) in (0..=u16::MAX).zip(table.iter_mut()) {
            *t = clamp(value(v));
        }
        Levels::Word(levels, table)
    }

    /// Levels made by [`quantise`].
    pub(super) fn quantised(levels: Vec<u16>) -> Levels {
        let mut table = word_table();
        for (v, t) in (0..=u16::MAX).zip(table.iter_mut()) {
            *t = f32::from(v) / 65535.0;
        }
        Levels::Word(levels, table)
    }

    /// Number of pixels.
    pub(super) fn len(&self) -> usize {
        match self {
            Levels::Byte(v, _) => v.len(),
            Levels::Word(v, _) => v.len(),
        }
    }

    /// Coverage of pixel `i` (row-major), `None` past the end.
    #[inline]
    pub(super) fn get(&self, i: usize) -> Option<f32> {
        match self {
            Levels::Byte(v, t) => v.get(i).map(|&l| t[usize::from(l)]),
            Levels::Word(v, t) => v.get(i).map(|&l| t[usize::from(l)]),
        }
    }

    /// The coverage of pixels `start..start + out.len()` written to `out` (zeros past the
    /// end).
    pub(super) fn read(&self, start: usize, out: &mut [f32]) {
        fn copy<L: Copy>(v: &[L], start: usize, out: &mut [f32], value: impl Fn(L) -> f32) {
            let src = v.get(start..).unwrap_or(&[]);
            let n = src.len().min(out.len());
            for (o, &l) in out[..n].iter_mut().zip(&src[..n]) {
                *o = value(l);
            }
            out[n..].fill(0.0);
        }
        match self {
            Levels::Byte(v, t) => copy(v, start, out, |l| t[usize::from(l)]),
            Levels::Word(v, t) => copy(v, start, out, |l| t[usize::from(l)]),
        }
    }

    /// How many pixels have each coverage value: (value, count) for every level used.
    pub(super) fn histogram(&self) -> Vec<(f32, u64)> {
        fn used(table: &[f32], counts: impl Iterator<Item = u64>) -> Vec<(f32, u64)> {
            table
                .iter()
                .zip(counts)
                .filter(|&(_, n)| n > 0)
                .map(|(&t, n)| (t, n))
                .collect()
        }
        match self {
            Levels::Byte(v, t) => {
                // A large image is counted in chunks on the thread pool; the counts are
                // whole numbers, so their sum is the same on any number of threads.
                let counts = if v.len() >= 2 * HISTOGRAM_CHUNK {
                    use rayon::prelude::*;
                    v.par_chunks(HISTOGRAM_CHUNK).map(byte_counts).reduce(
                        || [0; 256],
                        |mut a, b| {
                            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
                            a
                        },
                    )
                } else {
                    byte_counts(v)
                };
                used(&t[..], counts.into_iter())
            }
            Levels::Word(v, t) => {
                let mut counts = vec![0u64; t.len()];
                for &l in v {
                    counts[usize::from(l)] += 1;
                }
                used(&t[..], counts.into_iter())
            }
        }
    }
}

/// Pixels per chunk in which [`Levels::histogram`] counts a large 8-bit image in parallel.
const HISTOGRAM_CHUNK: usize = 1 << 20;

/// How many of `levels` have each 8-bit level.
fn byte_counts(levels: &[u8]) -> [u64; 256] {
    // Four interleaved tallies: runs of one level (a page's white paper) would otherwise
    // make every increment wait for the one before it.
    let mut lanes = [[0u64; 256]; 4];
    let mut quads = levels.chunks_exact(4);
    for quad in &mut quads {
        for (lane, &l) in lanes.iter_mut().zip(quad) {
            lane[usize::from(l)] += 1;
        }
    }
    for &l in quads.remainder() {
        lanes[0][usize::from(l)] += 1;
    }
    std::array::from_fn(|k| lanes.iter().map(|lane| lane[k]).sum())
}

/// A zeroed table of 16-bit levels (256 KiB).
fn word_table() -> Box<[f32; WORD_LEVELS]> {
    Box::new([0.0f32; WORD_LEVELS])
}

/// Coverage clamped to [0, 1], NaN as 0.
#[inline]
fn clamp(v: f32) -> f32 {
    // `!(v >= 0)` also catches NaN.
    if v >= 0.0 {
        v.min(1.0)
    } else {
        0.0
    }
}

/// The 16-bit level nearest to a coverage value (clamped to [0, 1], NaN as 0).
#[inline]
pub(super) fn quantise(v: f32) -> u16 {
    (clamp(v) * 65535.0 + 0.5) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantised_levels_are_within_half_a_step() {
        let values: Vec<f32> = (0..=1000).map(|i| i as f32 / 1000.0).collect();
        let levels = Levels::quantised(values.iter().map(|&v| quantise(v)).collect());
        for (i, &v) in values.iter().enumerate() {
            let got = levels.get(i).unwrap();
            assert!(
                (got - v).abs() <= 0.5 / 65535.0 + 1e-7,
                "{v} stored as {got}"
            );
            // 8-bit values come back exactly.
            let byte = (i % 256) as f32 / 255.0;
            let stored = Levels::quantised(vec![quantise(byte)]).get(0).unwrap();
            assert_eq!(stored.to_bits(), byte.to_bits(), "{byte}");
        }
        assert_eq!(levels.get(0), Some(0.0));
        assert_eq!(levels.get(1000), Some(1.0));
        assert_eq!(levels.get(1001), None);
    }

    #[test]
    fn out_of_range_values_are_clamped() {
        let levels = Levels::quantised([f32::NAN, -2.0, 7.0, 0.25].map(quantise).to_vec());
        let mut out = [9.0; 6];
        levels.read(0, &mut out);
        assert_eq!(out, [0.0, 0.0, 1.0, 16384.0 / 65535.0, 0.0, 0.0]);
        let bytes = Levels::bytes(vec![0, 255], |v| 2.0 - f32::from(v) / 100.0);
        assert_eq!((bytes.get(0), bytes.get(1)), (Some(1.0), Some(0.0)));
    }

    #[test]
    fn a_large_histogram_counted_in_chunks_is_the_plain_count() {
        let n = 2 * HISTOGRAM_CHUNK + 12_345;
        let pixels: Vec<u8> = (0..n).map(|i| ((i * 7919) % 251) as u8).collect();
        let mut plain = [0u64; 256];
        for &l in &pixels {
            plain[usize::from(l)] += 1;
        }
        let levels = Levels::bytes(pixels, |l| f32::from(l) / 255.0);
        let counted = levels.histogram();
        assert_eq!(counted.len(), 251);
        for (v, n) in counted {
            assert_eq!(n, plain[(v * 255.0).round() as usize], "level {v}");
        }
    }

    #[test]
    fn histogram_counts_every_pixel_once() {
        let levels = Levels::bytes(vec![3, 3, 7, 200, 3], |v| f32::from(v) / 255.0);
        let h = levels.histogram();
        assert_eq!(h.iter().map(|&(_, n)| n).sum::<u64>(), 5);
        assert_eq!(h[0], (3.0 / 255.0, 3));
        assert_eq!(h.len(), 3);
    }
}
