//! The thresholded image as one bit per pixel, in the padded layout of the border scan
//! (one pixel of background on every side, `width + 2` bits per row): made once with
//! the bitmap, whose bilevel count reads its changes, and handed to the border scan.

/// Writes the foreground classes (1 or 0) of image row `row` into the buffer, whose
/// length is the image's width.
pub(crate) type ReadRow<'a> = &'a (dyn Fn(usize, &mut [u8]) + Sync);

/// The foreground bits of a `w` × `h` image whose rows `read_row` gives, in the padded
/// layout: a large image is thresholded in chunks of words on the thread pool, each
/// chunk owning its words, so the bits are the same in any order.
pub(crate) fn padded_foreground(w: usize, h: usize, read_row: ReadRow<'_>) -> Bits {
    let pw = w + 2;
    let mut foreground = Bits::new(pw * (h + 2));
    // Each part's words are written (zeros) before they are filled: the fill reads a
    // word before it writes it, and a fresh page read first is mapped to the shared zero
    // page, whose replacement at the write then interrupts the other core to flush its
    // address cache. On the 4096 px horse, filled on two threads without this, the mask
    // took 5.0 ms instead of 1.7 (medians of 30 time-stamped runs).
    if w * h >= 2 * 64 * MASK_CHUNK_WORDS {
        use rayon::prelude::*;
        foreground
            .0
            .par_chunks_mut(MASK_CHUNK_WORDS)
            .enumerate()
            .for_each(|(k, words)| {
                words.fill(0);
                fill_words(read_row, w, h, k * MASK_CHUNK_WORDS, words);
            });
    } else {
        foreground.0.fill(0);
        fill_words(read_row, w, h, 0, &mut foreground.0);
    }
    foreground
}

/// One bit per pixel, row-major.
pub(crate) struct Bits(pub(crate) Vec<u64>);

impl Bits {
    pub(crate) fn new(len: usize) -> Bits {
        Bits(vec![0; len.div_ceil(64)])
    }

    #[inline]
    pub(crate) fn get(&self, i: usize) -> bool {
        self.0.get(i >> 6).is_some_and(|w| (w >> (i & 63)) & 1 != 0)
    }

    #[inline]
    pub(crate) fn set(&mut self, i: usize) {
        if let Some(w) = self.0.get_mut(i >> 6) {
            *w |= 1 << (i & 63);
        }
    }

    /// The indices `i` in `first..last` (`first ≥ 1`) whose bit differs from bit `i − 1`,
    /// in order, found a 64-bit word at a time.
    pub(crate) fn changes(&self, first: usize, last: usize) -> impl Iterator<Item = usize> + '_ {
        let words = first / 64..last.div_ceil(64).min(self.0.len());
        words.flat_map(move |k| {
            let word = self.0[k];
            let carry = if k > 0 { self.0[k - 1] >> 63 } else { 0 };
            let base = 64 * k;
            let mut changes = (word ^ ((word << 1) | carry))
                & bit_range(first.saturating_sub(base), (last - base).min(64));
            std::iter::from_fn(move || {
                if changes == 0 {
                    return None;
                }
                let i = base + changes.trailing_zeros() as usize;
                changes &= changes - 1;
                Some(i)
            })
        })
    }

    #[inline]
    pub(crate) fn clear(&mut self, i: usize) {
        if let Some(w) = self.0.get_mut(i >> 6) {
            *w &= !(1 << (i & 63));
        }
    }
}

/// A word with bits `lo..hi` set (`lo ≤ hi ≤ 64`; none when `lo ≥ hi`).
fn bit_range(lo: usize, hi: usize) -> u64 {
    if lo >= hi {
        return 0;
    }
    let below_hi = if hi >= 64 { u64::MAX } else { (1 << hi) - 1 };
    below_hi & !((1 << lo) - 1)
}

/// Words of the mask (64 pixels each) per chunk that [`padded_foreground`] fills in
/// parallel on a large image.
pub(crate) const MASK_CHUNK_WORDS: usize = 1 << 14;

/// Sets the foreground bits of `words`, the mask's words from index `first` on, in the
/// padded layout (`w + 2` bits per row, one row and one column of padding before the
/// image's `h` rows). Reads every image row the words touch; at a chunk's seam a row is
/// read by both chunks, but each bit is set by the chunk that owns its word.
pub(crate) fn fill_words(
    read_row: ReadRow<'_>,
    w: usize,
    h: usize,
    first: usize,
    words: &mut [u64],
) {
    let pw = w + 2;
    let (lo, hi) = (64 * first, 64 * (first + words.len()));
    let mut row = vec![0u8; w];
    // Padded row r + 1 holds image row r after one padding pixel.
    let rows = (lo / pw).max(1)..(hi.div_ceil(pw)).min(h + 1);
    for padded in rows {
        let start = padded * pw + 1;
        let (from, to) = (lo.max(start), hi.min(start + w));
        if from >= to {
            continue;
        }
        read_row(padded - 1, &mut row);
        set_bits(words, from - lo, &row[from - start..to - start]);
    }
}

/// Multiplier that gathers the low bits of eight bytes into the top byte of a word (see
/// [`set_bits`]): 2^(56 − 7i) for i = 0 … 7.
const GATHER_BYTES: u64 = 0x0102_0408_1020_4080;

/// Sets bit `at + k` of `words` for every `bits[k]` that is 1 (each is 0 or 1), a word
/// at a time: 64 bytes are gathered into a register and written once, rather than 64
/// read-modify-writes of one word that each wait for the one before.
pub(crate) fn set_bits(words: &mut [u64], at: usize, bits: &[u8]) {
    let (mut j, mut rest) = (at, bits);
    // The first word, up to its end.
    let lead = ((64 - j % 64) % 64).min(rest.len());
    let (head, tail) = rest.split_at(lead);
    for &b in head {
        words[j >> 6] |= u64::from(b) << (j & 63);
        j += 1;
    }
    rest = tail;
    // Whole words, eight bytes at a time: read as one little-endian number, the eight
    // 0/1 bytes sit at bits 0, 8, …, 56, and the product with [`GATHER_BYTES`] carries
    // byte i to bit 56 + i and nothing else there (its partial products fall on distinct
    // bits, so nothing carries), so its top byte holds the eight bits in order.
    let mut chunks = rest.chunks_exact(64);
    for chunk in &mut chunks {
        let mut word = 0u64;
        for (k, eight) in chunk.chunks_exact(8).enumerate() {
            let bytes = u64::from_le_bytes(eight.try_into().unwrap_or([0; 8]));
            word |= (bytes.wrapping_mul(GATHER_BYTES) >> 56) << (8 * k);
        }
        words[j >> 6] |= word;
        j += 64;
    }
    for &b in chunks.remainder() {
        words[j >> 6] |= u64::from(b) << (j & 63);
        j += 1;
    }
}

/// The 64 bits of `bits` from bit `pos` on (zeros past the end).
#[inline]
fn word_at(bits: &Bits, pos: usize) -> u64 {
    let (k, shift) = (pos / 64, pos % 64);
    let low = bits.0.get(k).copied().unwrap_or(0) >> shift;
    if shift == 0 {
        low
    } else {
        low | (bits.0.get(k + 1).copied().unwrap_or(0) << (64 - shift))
    }
}

/// For the image rows `rows` of a `w`-pixel-wide image whose foreground is `bits` (padded
/// layout): every pair of neighbouring pixels on a row, or of a pixel and the one below,
/// that differ in the foreground counts twice in the first number, and each of its
/// pixels for which `grey(column, row)` holds once in the second: the counts of
/// [`Bitmap::is_bilevel`], read from the bits' changes instead of from every pixel.
pub(crate) fn crossings(
    bits: &Bits,
    w: usize,
    h: usize,
    rows: std::ops::Range<usize>,
    grey: impl Fn(usize, usize) -> bool,
) -> (u64, u64) {
    let pw = w + 2;
    let (mut edge, mut grey_edge) = (0u64, 0u64);
    let mut pair = |a: (usize, usize), b: (usize, usize)| {
        edge += 2;
        grey_edge += u64::from(grey(a.0, a.1)) + u64::from(grey(b.0, b.1));
    };
    for r in rows {
        // Image row r is padded row r + 1, its pixel c at bit (r + 1)·pw + c + 1.
        let start = (r + 1) * pw + 1;
        for i in bits.changes(start + 1, start + w) {
            let c = i - start;
            pair((c - 1, r), (c, r));
        }
        if r + 1 >= h {
            continue;
        }
        for c0 in (0..w).step_by(64) {
            let n = (w - c0).min(64);
            let mut differ = word_at(bits, start + c0) ^ word_at(bits, start + pw + c0);
            if n < 64 {
                differ &= (1u64 << n) - 1;
            }
            while differ != 0 {
                let c = c0 + differ.trailing_zeros() as usize;
                differ &= differ - 1;
                pair((c, r), (c, r + 1));
            }
        }
    }
    (edge, grey_edge)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every offset into a word and every length up to three words, against setting the
    /// bits one at a time: the gathered words must hold exactly the 1 bytes, and keep the
    /// bits that were set before.
    #[test]
    fn whole_words_hold_the_bits_one_by_one_would_set() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for at in 0..70 {
            for len in [0, 1, 7, 8, 9, 63, 64, 65, 127, 128, 130, 191] {
                let bits: Vec<u8> = (0..len).map(|_| u8::from(rng.random_bool(0.5))).collect();
                let before: Vec<u64> = (0..5)
                    .map(|_| rng.random::<u64>() & rng.random::<u64>())
                    .collect();
                let mut expected = before.clone();
                for (k, &b) in bits.iter().enumerate() {
                    let j = at + k;
                    expected[j >> 6] |= u64::from(b) << (j & 63);
                }
                let mut words = before.clone();
                set_bits(&mut words, at, &bits);
                assert_eq!(words, expected, "offset {at}, {len} bits");
            }
        }
    }
}
