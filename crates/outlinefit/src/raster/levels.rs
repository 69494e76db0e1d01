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

    /// What `class` makes of every level (see [`Classes`]). Passes that only ask which
    /// side of the threshold a pixel is on, or whether it is grey, read these classes
    /// through [`Levels::read_classes`] instead of converting every pixel to a float and
    /// comparing it: the same answer per level, decided once per level.
    pub(super) fn classes(&self, class: impl Fn(f32) -> u8) -> Classes {
        match self {
            Levels::Byte(_, t) => {
                let table: Vec<u8> = t.iter().map(|&v| class(v)).collect();
                let bands = byte_bands(&table);
                Classes::new(table, bands)
            }
            Levels::Word(_, t) => Classes::new(t.iter().map(|&v| class(v)).collect(), None),
        }
    }

    /// The classes of pixels `start..start + out.len()` written to `out` (zeros past the
    /// end).
    pub(super) fn read_classes(&self, start: usize, classes: &Classes, out: &mut [u8]) {
        fn copy<L: Copy>(v: &[L], start: usize, out: &mut [u8], class: impl Fn(L) -> u8) {
            let src = v.get(start..).unwrap_or(&[]);
            let n = src.len().min(out.len());
            for (o, &l) in out[..n].iter_mut().zip(&src[..n]) {
                *o = class(l);
            }
            out[n..].fill(0);
        }
        /// The class of level `l` from the bands of its first `N` bits (the others are
        /// never set): comparisons only, so that it vectorises.
        #[inline(always)]
        fn banded<const N: usize>(bands: &[(u8, u8, bool); 8], l: u8) -> u8 {
            let mut c = 0;
            for (bit, &(lo, span, outside)) in bands[..N].iter().enumerate() {
                let inside = l.wrapping_sub(lo) <= span;
                c |= u8::from(inside != outside) << bit;
            }
            c
        }
        match (self, &classes.bands) {
            (Levels::Byte(v, _), Some(bands)) => match classes.bits {
                0 | 1 => copy(v, start, out, |l| banded::<1>(bands, l)),
                2 => copy(v, start, out, |l| banded::<2>(bands, l)),
                3 => copy(v, start, out, |l| banded::<3>(bands, l)),
                _ => copy(v, start, out, |l| banded::<8>(bands, l)),
            },
            (Levels::Byte(v, _), None) => {
                let table: &[u8; 256] = classes.table[..].try_into().expect("8-bit levels");
                copy(v, start, out, |l| table[usize::from(l)]);
            }
            (Levels::Word(v, _), _) => {
                let table: &[u8; WORD_LEVELS] =
                    classes.table[..].try_into().expect("16-bit levels");
                copy(v, start, out, |l| table[usize::from(l)]);
            }
        }
    }

    /// How many pixels fall in each of 256 bins, `bin` (below 256) of a pixel's coverage
    /// deciding its bin. `counts`: the 8-bit levels' counts when they are known already
    /// (counted as they were decoded, see `grey_png`). A large image is counted in chunks
    /// on the thread pool; the counts are whole numbers, so their sums are the same on any
    /// number of threads.
    pub(super) fn binned(
        &self,
        bin: impl Fn(f32) -> usize,
        counts: Option<&[u64; 256]>,
    ) -> [u64; 256] {
        use rayon::prelude::*;
        let add = |mut a: [u64; 256], b: [u64; 256]| {
            a.iter_mut().zip(b).for_each(|(a, b)| *a += b);
            a
        };
        let mut out = [0u64; 256];
        match self {
            Levels::Byte(v, t) => {
                let counts = match counts {
                    Some(c) => {
                        debug_assert_eq!(c.iter().sum::<u64>(), v.len() as u64);
                        *c
                    }
                    None if v.len() >= 2 * HISTOGRAM_CHUNK => v
                        .par_chunks(HISTOGRAM_CHUNK)
                        .map(byte_counts)
                        .reduce(|| [0; 256], add),
                    None => byte_counts(v),
                };
                for (&value, n) in t.iter().zip(counts) {
                    out[bin(value)] += n;
                }
            }
            Levels::Word(v, t) => {
                // Each 16-bit level's bin once, then the bins counted as bytes are.
                let bins: Vec<u8> = t.iter().map(|&value| bin(value) as u8).collect();
                let count = |chunk: &[u16]| tally(chunk, |l| usize::from(bins[usize::from(l)]));
                out = if v.len() >= 2 * HISTOGRAM_CHUNK {
                    v.par_chunks(HISTOGRAM_CHUNK)
                        .map(count)
                        .reduce(|| [0; 256], add)
                } else {
                    count(v)
                };
            }
        }
        out
    }
}

/// A class (a byte of bits) for every level of a [`Levels`], made by [`Levels::classes`].
#[derive(Clone, Debug)]
pub(crate) struct Classes {
    /// The class of each level.
    table: Vec<u8>,
    /// For 8-bit levels whose every class bit is set on one band of consecutive levels
    /// (or off on one band), as the bits of a threshold or a grey range are when the
    /// coverage is monotone in the byte: per bit, the band's first level, its length
    /// minus one and whether the bit is set outside it. Reading classes is then
    /// comparisons, without a table lookup per pixel.
    bands: Option<[(u8, u8, bool); 8]>,
    /// Bits that any class uses: the ones below the highest bit set in some class.
    bits: u32,
}

impl Classes {
    fn new(table: Vec<u8>, bands: Option<[(u8, u8, bool); 8]>) -> Classes {
        let used = table.iter().fold(0u8, |a, &c| a | c);
        Classes {
            table,
            bands,
            bits: 8 - used.leading_zeros(),
        }
    }
}

/// The bands of [`Classes::bands`] for a 256-entry table, when every bit has one.
fn byte_bands(table: &[u8]) -> Option<[(u8, u8, bool); 8]> {
    let mut bands = [(0u8, 255u8, false); 8];
    for (bit, band) in bands.iter_mut().enumerate() {
        let set: Vec<bool> = table.iter().map(|&c| c >> bit & 1 == 1).collect();
        // A band of `on` levels: the first and last with the bit `on`, and every level
        // between them the same.
        let band_of = |on: bool| -> Option<(u8, u8)> {
            let first = set.iter().position(|&b| b == on)?;
            let last = set.iter().rposition(|&b| b == on)?;
            set[first..=last]
                .iter()
                .all(|&b| b == on)
                .then(|| (first as u8, (last - first) as u8))
        };
        *band = if !set.contains(&true) {
            // Never set: set only outside the band of all levels.
            (0, 255, true)
        } else if let Some((lo, span)) = band_of(true) {
            (lo, span, false)
        } else {
            let (lo, span) = band_of(false)?;
            (lo, span, true)
        };
    }
    Some(bands)
}

/// Pixels per chunk in which [`Levels::histogram`] counts a large 8-bit image in parallel.
const HISTOGRAM_CHUNK: usize = 1 << 20;

/// How many of `levels` have each 8-bit level. A chunk of 16 equal bytes (flat paper,
/// a silhouette's inside) is counted at once, the other chunks byte by byte as
/// [`tally`] counts them: the same counts (a test compares them), and the 4096 px horse,
/// 98 % flat, counted in a fraction of the time.
pub(super) fn byte_counts(levels: &[u8]) -> [u64; 256] {
    const RUN: usize = 16;
    let mut lanes = [[0u64; 256]; 4];
    let mut runs = levels.chunks_exact(RUN);
    for run in &mut runs {
        let mut bytes = [0u8; RUN];
        bytes.copy_from_slice(run);
        let first = run[0];
        if u128::from_ne_bytes(bytes) == u128::from_ne_bytes([first; RUN]) {
            lanes[0][usize::from(first)] += RUN as u64;
        } else {
            tally_into(&mut lanes, run, usize::from);
        }
    }
    tally_into(&mut lanes, runs.remainder(), usize::from);
    lanes_total(&lanes)
}

/// How many of `levels` fall in each of 256 bins, `bin` (below 256) giving a level's.
fn tally<L: Copy>(levels: &[L], bin: impl Fn(L) -> usize) -> [u64; 256] {
    let mut lanes = [[0u64; 256]; 4];
    tally_into(&mut lanes, levels, bin);
    lanes_total(&lanes)
}

/// The counts of the four tallies of [`tally_into`] added up.
fn lanes_total(lanes: &[[u64; 256]; 4]) -> [u64; 256] {
    std::array::from_fn(|k| lanes.iter().map(|lane| lane[k]).sum())
}

/// Adds the bins of `levels` to four interleaved tallies: runs of one level (a page's
/// white paper) would otherwise make every increment wait for the one before it.
fn tally_into<L: Copy>(lanes: &mut [[u64; 256]; 4], levels: &[L], bin: impl Fn(L) -> usize) {
    let mut quads = levels.chunks_exact(4);
    for quad in &mut quads {
        for (lane, &l) in lanes.iter_mut().zip(quad) {
            lane[bin(l)] += 1;
        }
    }
    for &l in quads.remainder() {
        lanes[0][bin(l)] += 1;
    }
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
        let counted = levels.binned(|v| (v * 255.0).round() as usize, None);
        assert_eq!(counted, plain);
        // 16-bit levels, in chunks too, binned through their values.
        let words: Vec<u16> = (0..n).map(|i| ((i * 7919) % 65_521) as u16).collect();
        let mut plain = [0u64; 256];
        for &l in &words {
            plain[usize::from(l >> 8)] += 1;
        }
        let levels = Levels::quantised(words);
        let bin = |v: f32| ((v * 65535.0).round() as usize) >> 8;
        assert_eq!(levels.binned(bin, None), plain);
    }

    #[test]
    fn byte_counts_of_flat_and_mixed_stretches_are_the_plain_count() {
        // Flat runs of every length from 1 to 40 at every offset, between noise, with
        // lengths that leave every remainder of a 16-byte chunk.
        use rand::{RngExt, SeedableRng};
        let mut rng = crate::optim::SeededRng::seed_from_u64(19);
        let mut noise = move || rng.random::<u8>();
        let mut levels = Vec::new();
        for run in 1..=40usize {
            for gap in 0..3 {
                levels.extend((0..gap).map(|_| noise()));
                levels.extend(std::iter::repeat_n((run * 37) as u8, run));
            }
        }
        levels.extend(std::iter::repeat_n(255u8, 4096));
        let mut flat_chunks = 0;
        for len in [0, 1, 15, 16, 17, 100, levels.len() - 3, levels.len()] {
            let part = &levels[..len];
            let mut plain = [0u64; 256];
            for &l in part {
                plain[usize::from(l)] += 1;
            }
            assert_eq!(byte_counts(part), plain, "the first {len} bytes");
            flat_chunks += part
                .chunks_exact(16)
                .filter(|c| c.iter().all(|&b| b == c[0]))
                .count();
        }
        assert!(flat_chunks > 500, "{flat_chunks} flat chunks");
    }

    #[test]
    fn classes_read_by_bands_are_the_table_lookup() {
        // Coverage rising or falling with the byte (the usual grey images) gives every
        // threshold-like bit one band, and the compared classes must be the table's; a
        // coverage that is not monotone falls back to the table.
        let pixels: Vec<u8> = (0..=255).chain((0..=255).rev()).collect();
        let values: [fn(u8) -> f32; 3] = [
            |l| f32::from(l) / 255.0,
            |l| 1.0 - f32::from(l) / 255.0,
            |l| f32::from(l % 7) / 6.0,
        ];
        let rules: [fn(f32) -> u8; 4] = [
            |v| u8::from(v >= 0.5),
            |v| u8::from(v >= 0.3) | u8::from(v > 0.05 && v < 0.95) << 1,
            |v| u8::from(f64::from(v) >= 0.41) | u8::from((v - 0.41).abs() >= 0.1) << 1,
            |v| u8::from(v > 2.0) | 1 << 3,
        ];
        for (k, value) in values.iter().enumerate() {
            let levels = Levels::bytes(pixels.clone(), value);
            for (r, rule) in rules.into_iter().enumerate() {
                let classes = levels.classes(rule);
                // The last rule's bits are constant: bands whatever the coverage.
                assert_eq!(
                    classes.bands.is_some(),
                    k < 2 || r == 3,
                    "values {k}, rule {r}"
                );
                let mut out = vec![9u8; pixels.len() + 3];
                levels.read_classes(0, &classes, &mut out);
                for (i, &l) in pixels.iter().enumerate() {
                    assert_eq!(out[i], rule(levels.get(i).unwrap()), "level {l}");
                }
                assert_eq!(&out[pixels.len()..], &[0, 0, 0]);
                // From an offset, as a row's span is read.
                let mut part = vec![0u8; 10];
                levels.read_classes(300, &classes, &mut part);
                assert_eq!(part, out[300..310]);
            }
        }
        // 16-bit levels read through their table.
        let words = Levels::quantised(vec![0, 30000, 65535]);
        let classes = words.classes(|v| u8::from(v >= 0.4));
        let mut out = [7u8; 3];
        words.read_classes(0, &classes, &mut out);
        assert_eq!(out, [0, 1, 1]);
    }

    #[test]
    fn histogram_counts_every_pixel_once() {
        let levels = Levels::bytes(vec![3, 3, 7, 200, 3], |v| f32::from(v) / 255.0);
        let bin = |v: f32| (v * 255.0).round() as usize;
        let h = levels.binned(bin, None);
        assert_eq!(h.iter().sum::<u64>(), 5);
        assert_eq!((h[3], h[7], h[200]), (3, 1, 1));
        // Counts given for the bytes are taken as they are.
        let mut given = [0u64; 256];
        given[3] = 2;
        given[9] = 3;
        let h = levels.binned(bin, Some(&given));
        assert_eq!((h[3], h[9], h[7]), (2, 3, 0));
    }
}
