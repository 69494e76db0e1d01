//! A large 8-bit grey PNG decoded on two cores, with its histogram counted while the
//! rows arrive.
//!
//! Decoding a PNG is two chained halves: inflating the compressed stream, then undoing
//! each row's filter against the row above (Paeth's predictor waits on the pixel before
//! it, byte after byte). The `png` crate does both on one core while the other waits:
//! on the 600 dpi scan of `make_scan.py` about 0.09 s, 67 ms of it inflating; on the
//! 4096 px horse about 30 ms, 20 of them unfiltering. Here the `png` crate's streaming
//! decoder reads the chunks (checking their CRCs) and inflates on this thread, which
//! copies each filtered row into the pixel buffer; a helper thread undoes the filters
//! band by band as they come ([`unfilter`], the specification's five filters; a Paeth
//! row takes the sub filter's short chain wherever the row above is level, most of a
//! flat image). The threshold needs the histogram of every pixel, which used to be a
//! pass of its own once decoding ended: each unfiltered band is counted by whichever
//! thread has time (a chunk of equal bytes at once). The 4096 px horse now decodes in
//! about 9 ms.
//! Where inflating is the longer half (many compressed bytes per pixel, a scanned page),
//! a third thread writes to every fresh page of the buffer ahead of the decoding thread,
//! so that the kernel maps and clears them there (on the scan 8 500 page faults).
//!
//! The pixels are the ones the `image` crate's decoder gives (tests compare them for
//! every filter type); images this path does not cover (other colour types or depths,
//! interlaced, with a transparent level, an EXIF orientation or an animation, small)
//! and any decoding error go through the `image` crate as before, so errors read the
//! same.

use super::levels::byte_counts;
use crate::error::Result;
use image::GrayImage;
use png::Decoded;
use std::io::{BufRead, Seek};

/// Fewest pixels for which [`decode_counted`] decodes: below it a helper thread costs
/// about what it saves (counting the histogram after decoding takes about a millisecond
/// at this size, and smaller images are counted on one thread).
pub(super) const COUNTED_PIXELS: u64 = 1 << 21;

/// Bytes of rows handed between the decoder and the helper thread at a time.
const BAND_BYTES: usize = 1 << 18;

/// Compressed bytes per pixel from which inflating, not unfiltering, is the longer half
/// of decoding (see [`decode_counted`]): then a thread of its own maps the pixel
/// buffer's pages. Against the `png` crate's decoder on one thread, medians of paired
/// runs of the whole trace: the scan of `make_scan.py` (0.53 bytes per pixel) 0.99× the
/// wall time with that thread, 1.02× without; the 4096 px horse (0.012) 1.01× with,
/// 0.93× without; the upscaled page (0.17) 0.97× with, 0.95× without.
const INFLATE_HEAVY_BYTES_PER_PIXEL: f64 = 0.4;

/// Bytes of a memory page (the smallest on the systems this runs on).
const PAGE_BYTES: usize = 4096;

/// How many pixels have each 8-bit level.
pub(super) type ByteCounts = Box<[u64; 256]>;

/// A decoded 8-bit grey image and how many of its pixels have each level.
pub(super) struct CountedGrey {
    pub(super) image: GrayImage,
    pub(super) counts: ByteCounts,
}

/// The still 8-bit grey, non-interlaced PNG image in `reader` with at least
/// [`COUNTED_PIXELS`] pixels, and its histogram; `None` for every other image and for
/// data the decoder rejects (the caller decodes those through the `image` crate, which
/// reports the error). `check` (width, height, bytes per pixel) is asked from the header,
/// before any pixel is decoded, as the `image` path asks it. The chunk reader holds at
/// most the `png` crate's default 64 MiB of chunk data (text, colour profiles); a smaller
/// `max_alloc` leaves the image to the `image` path, which applies it.
///
/// This thread inflates and copies the filtered rows into the pixel buffer band by band,
/// the helper unfilters them (see the module docs); a band is counted by the helper
/// when no band waits for it, else by this thread. A third thread maps the buffer's
/// pages where inflating is the longer half ([`INFLATE_HEAVY_BYTES_PER_PIXEL`]).
pub(super) fn decode_counted<R: BufRead + Seek>(
    reader: R,
    max_alloc: u64,
    check: &dyn Fn(u32, u32, u64) -> Result<()>,
) -> Result<Option<CountedGrey>> {
    if usize::try_from(max_alloc).unwrap_or(usize::MAX) < png::Limits::default().bytes {
        return Ok(None);
    }
    // Inflating costs about 3.6 ns per compressed byte here, unfiltering (mostly Paeth's
    // predictor, one pixel after another) and counting about 1.7 ns per pixel: the scan
    // of `make_scan.py` has 0.53 compressed bytes per pixel, its upscaled page 0.17, the
    // 4096 px horse 0.012.
    let mut reader = reader;
    let compressed = reader.seek(std::io::SeekFrom::End(0)).unwrap_or(0);
    if reader.rewind().is_err() {
        return Ok(None);
    }
    let mut stream = Stream {
        reader,
        decoder: png::StreamingDecoder::new(),
        data: Vec::new(),
        region: png::UnfilterRegion::default(),
        consumed: 0,
        flushed: false,
    };
    // The header and every chunk before the image data (a transparent level, an EXIF
    // orientation or an animation, which this path declines, come before it).
    loop {
        match stream.next(false) {
            Some(Decoded::ChunkBegin(_, png::chunk::IDAT)) => break,
            Some(Decoded::ChunkComplete(png::chunk::IEND)) | None => return Ok(None),
            Some(_) => {}
        }
    }
    let Some(info) = stream.decoder.info() else {
        return Ok(None);
    };
    let (width, height) = (info.width, info.height);
    let plain_grey = info.color_type == png::ColorType::Grayscale
        && info.bit_depth == png::BitDepth::Eight
        && !info.interlaced
        && info.trns.is_none()
        && info.animation_control.is_none()
        // An EXIF orientation would turn the image: left to the `image` path.
        && info.exif_metadata.is_none();
    let pixels = u64::from(width) * u64::from(height);
    if !plain_grey || pixels < COUNTED_PIXELS {
        return Ok(None);
    }
    check(width, height, 1)?;
    let (w, len) = (width as usize, pixels as usize);
    let inflating_is_longer = compressed as f64 >= INFLATE_HEAVY_BYTES_PER_PIXEL * pixels as f64;
    // Zeroed by the allocator (fresh pages), not by a pass over the buffer; the memory
    // was checked above.
    let mut buf = vec![0u8; len];
    let band = (BAND_BYTES / w).max(1) * w;
    let bands: Vec<&mut [u8]> = buf.chunks_mut(band).collect();
    let decoded = std::thread::scope(|scope| {
        // Bands filled with filtered rows (and their filter types) go to the helper;
        // unfiltered back here to be counted, when the helper has the next band waiting.
        let (to_helper, filled) = std::sync::mpsc::channel::<(&mut [u8], Vec<u8>)>();
        let (to_counter, unfiltered) = std::sync::mpsc::channel::<&[u8]>();
        let spawn = |name: &str| std::thread::Builder::new().name(name.into());
        // The kernel maps and clears a fresh page at its first write. Where inflating is
        // the longer half, a third thread does that ahead of this one, which would
        // otherwise stop at every page; where unfiltering is, this thread has the time
        // and a third would only take the helper's core.
        let fresh: Box<dyn Iterator<Item = &mut [u8]>> = if inflating_is_longer {
            let (to_decoder, fresh) = std::sync::mpsc::channel::<&mut [u8]>();
            spawn("outlinefit-pages")
                .spawn_scoped(scope, move || {
                    for band in bands {
                        band.iter_mut().step_by(PAGE_BYTES).for_each(|b| *b = 0);
                        if to_decoder.send(band).is_err() {
                            break;
                        }
                    }
                })
                .ok()?;
            Box::new(fresh.into_iter())
        } else {
            Box::new(bands.into_iter())
        };
        let helper = spawn("outlinefit-png")
            .spawn_scoped(scope, move || {
                let mut counts = Box::new([0u64; 256]);
                // The last row of the band before (none above the first row).
                let mut above: Vec<u8> = Vec::new();
                let mut next = filled.recv().ok();
                while let Some((rows, filters)) = next.take() {
                    for (k, &filter) in filters.iter().enumerate() {
                        let (done, rest) = rows.split_at_mut(k * w);
                        let prev = match k {
                            0 => &above[..],
                            _ => &done[(k - 1) * w..],
                        };
                        unfilter(filter, prev, &mut rest[..w])?;
                    }
                    above.clear();
                    above.extend_from_slice(&rows[rows.len() - w..]);
                    let rows: &[u8] = rows;
                    // Counted here while no band waits, else by the decoding thread.
                    next = filled.try_recv().ok();
                    if next.is_some() {
                        to_counter.send(rows).ok()?;
                    } else {
                        add_counts(&mut counts, rows);
                        next = filled.recv().ok();
                    }
                }
                Some(counts)
            })
            .ok()?;
        let mut counts = Box::new([0u64; 256]);
        let mut ok = true;
        for rows in fresh {
            let mut filters = Vec::with_capacity(rows.len() / w);
            for row in rows.chunks_mut(w) {
                let Some(line) = stream.row(w + 1) else {
                    ok = false;
                    break;
                };
                filters.push(line[0]);
                row.copy_from_slice(&line[1..]);
            }
            if !ok || to_helper.send((rows, filters)).is_err() {
                ok = false;
                break;
            }
            unfiltered
                .try_iter()
                .for_each(|rows| add_counts(&mut counts, rows));
        }
        // Past the last row the image data is read to its end (and checked), as the
        // `image` crate's decoding of the whole frame does.
        ok = ok && stream.finish();
        drop(to_helper);
        unfiltered
            .iter()
            .for_each(|rows| add_counts(&mut counts, rows));
        let theirs = helper.join().ok().flatten()?;
        counts
            .iter_mut()
            .zip(theirs.iter())
            .for_each(|(a, b)| *a += b);
        ok.then_some(counts)
    });
    let Some(counts) = decoded else {
        return Ok(None);
    };
    Ok(GrayImage::from_raw(width, height, buf).map(|image| CountedGrey { image, counts }))
}

/// Adds the levels of `rows` to `counts`.
fn add_counts(counts: &mut [u64; 256], rows: &[u8]) {
    let c = byte_counts(rows);
    counts.iter_mut().zip(c).for_each(|(a, b)| *a += b);
}

/// Bytes the inflater may write past the decompressed ones in one call (it asks for
/// 8 KB at a time).
const INFLATE_ROOM: usize = 1 << 15;

/// Bytes of rows read out of the inflater's buffer after which the rest is moved down.
const COMPACT_BYTES: usize = 1 << 16;

/// The `png` crate's streaming decoder over `reader`, its image data inflated into
/// `data`: `data[consumed..region.available]` holds filtered rows not yet read, and
/// `data[region.available..region.filled]` the inflater's look-back, which must stay.
struct Stream<R> {
    reader: R,
    decoder: png::StreamingDecoder,
    data: Vec<u8>,
    region: png::UnfilterRegion,
    consumed: usize,
    /// The image data has ended.
    flushed: bool,
}

impl<R: BufRead> Stream<R> {
    /// The decoder's next event, its image data (with `image`) appended to `data`;
    /// `None` at an error or the end of the input.
    fn next(&mut self, image: bool) -> Option<Decoded> {
        if image && self.data.len() < self.region.filled + INFLATE_ROOM {
            self.data.resize(self.region.filled + INFLATE_ROOM, 0);
        }
        let input = self.reader.fill_buf().ok()?;
        if input.is_empty() {
            return None;
        }
        let (used, event) = if image {
            let mut out = self.region.as_buf(&mut self.data);
            self.decoder.update(input, Some(&mut out)).ok()?
        } else {
            self.decoder.update(input, None).ok()?
        };
        self.reader.consume(used);
        Some(event)
    }

    /// The next filtered row, `len` bytes with its filter type first; `None` when the
    /// image data ends before it or is corrupt.
    fn row(&mut self, len: usize) -> Option<&[u8]> {
        while self.region.available - self.consumed < len {
            if self.flushed {
                return None;
            }
            if self.consumed >= COMPACT_BYTES {
                self.compact();
            }
            if let Decoded::ImageDataFlushed = self.next(true)? {
                self.flushed = true;
            }
        }
        let start = self.consumed;
        self.consumed += len;
        Some(&self.data[start..self.consumed])
    }

    /// Moves the bytes not yet read down to the buffer's start.
    fn compact(&mut self) {
        self.data.copy_within(self.consumed..self.region.filled, 0);
        self.region.available -= self.consumed;
        self.region.filled -= self.consumed;
        self.consumed = 0;
    }

    /// Reads the image data to its end (what follows the last row is discarded); false
    /// when it is corrupt or the input ends first.
    fn finish(&mut self) -> bool {
        while !self.flushed {
            self.consumed = self.region.available;
            self.compact();
            match self.next(true) {
                Some(Decoded::ImageDataFlushed) => self.flushed = true,
                Some(_) => {}
                None => return false,
            }
        }
        true
    }
}

/// Undoes the PNG filter `filter` (0 to 4: none, sub, up, average, Paeth) of one row of
/// 8-bit grey pixels in place, given the unfiltered row above (empty for the first row,
/// which counts as zeros); `None` for an unknown filter type. Each pixel depends on the
/// one before, so a row is one chain: this is what the helper thread does while the
/// decoder inflates.
fn unfilter(filter: u8, above: &[u8], row: &mut [u8]) -> Option<()> {
    let first_row = above.is_empty();
    let sub = |row: &mut [u8]| {
        for i in 1..row.len() {
            row[i] = row[i].wrapping_add(row[i - 1]);
        }
    };
    match filter {
        0 => {}
        1 => sub(row),
        // Paeth's predictor of the first row is the left neighbour: sub.
        4 if first_row => sub(row),
        2 if first_row => {}
        2 => row
            .iter_mut()
            .zip(above)
            .for_each(|(r, &b)| *r = r.wrapping_add(b)),
        3 => {
            let up = |i: usize| if first_row { 0 } else { u16::from(above[i]) };
            row[0] = row[0].wrapping_add((up(0) / 2) as u8);
            for i in 1..row.len() {
                let mean = (u16::from(row[i - 1]) + up(i)) / 2;
                row[i] = row[i].wrapping_add(mean as u8);
            }
        }
        4 => {
            // Left and upper-left are 0 at the row's start: the predictor is the pixel
            // above.
            row[0] = row[0].wrapping_add(above[0]);
            paeth_rest(above, row);
        }
        _ => return None,
    }
    Some(())
}

/// Pixels of a chunk that [`paeth_rest`] tests for a level row above at once.
const CHUNK: usize = 16;

/// A 16-byte chunk of `bytes` from `at`, read as one number.
#[inline]
fn chunk(bytes: &[u8], at: usize) -> u128 {
    let mut c = [0u8; CHUNK];
    c.copy_from_slice(&bytes[at..at + CHUNK]);
    u128::from_ne_bytes(c)
}

/// Undoes the Paeth filter of a row from its second pixel on (the first is done). Where
/// the row above is level across a chunk and the pixel before it (b = c at every
/// pixel), Paeth's predictor is the left neighbour (|p − a| = |b − c| = 0, and ties go
/// to the left), so the chunk is undone as the sub filter, one addition after another
/// instead of the predictor's chain; a chunk of zeros then repeats the pixel before it.
/// A flat image (a silhouette, a page's margins) is mostly such chunks: the 4096 px
/// horse has 96 % of its Paeth rows' chunks level above and zero. Other chunks go
/// through [`paeth`]. The same bytes either way (a test compares the two).
fn paeth_rest(above: &[u8], row: &mut [u8]) {
    let n = row.len().min(above.len());
    // The pixel before the one being undone, carried from one to the next.
    let mut left = row[0];
    let mut i = 1;
    while i < n {
        let end = (i + CHUNK).min(n);
        let span = &mut row[i..end];
        if end == i + CHUNK && chunk(above, i - 1) == chunk(above, i) {
            if chunk(span, 0) == 0 {
                span.fill(left);
            } else {
                for r in span {
                    left = r.wrapping_add(left);
                    *r = left;
                }
            }
        } else {
            let mut upper_left = above[i - 1];
            for (r, &up) in span.iter_mut().zip(&above[i..end]) {
                left = r.wrapping_add(paeth(left, up, upper_left));
                *r = left;
                upper_left = up;
            }
        }
        i = end;
    }
}

/// Paeth's predictor of a pixel from its left (`a`), upper (`b`) and upper-left (`c`)
/// neighbours: the one nearest to a + b − c, ties to `a`, then `b`. Written without
/// branches: with p = a + b − c, a or b wins (the smaller or the larger of them) unless
/// c lies between them and nearer p; the comparisons reduce to 3c − (a + b) against
/// min(a, b) and max(a, b) (the formulation of public-domain stb_image). A test compares
/// it with the specification's on every triple.
#[inline]
fn paeth(a: u8, b: u8, c: u8) -> u8 {
    let (a, b, c) = (i16::from(a), i16::from(b), i16::from(c));
    let thresh = 3 * c - (a + b);
    let (lo, hi) = (a.min(b), a.max(b));
    let t0 = if hi <= thresh { lo } else { c };
    let t1 = if thresh <= lo { hi } else { t0 };
    t1 as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;
    use crate::raster::{from_image, load_bytes, AlphaRule, RasterOptions, ThresholdMode};
    use image::{DynamicImage, ImageFormat, Luma};
    use std::io::Cursor;
    use std::path::Path;

    fn pass(_: u32, _: u32, _: u64) -> crate::error::Result<()> {
        Ok(())
    }

    fn options(mode: ThresholdMode) -> RasterOptions {
        RasterOptions {
            threshold: None,
            alpha: AlphaRule::Auto,
            invert: false,
            max_pixels: 1 << 30,
            frame: 0,
            threshold_mode: mode,
        }
    }

    /// A grey page over [`COUNTED_PIXELS`]: a dark disc and a bar on light paper, with
    /// noise, so that the encoder's adaptive filters use every filter type.
    fn page(w: u32, h: u32) -> image::GrayImage {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        image::GrayImage::from_fn(w, h, |c, r| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let noise = (state >> 59) as u8;
            let disc = (f64::from(c) - 700.0).hypot(f64::from(r) - 600.0) < 350.0;
            let bar = (100..180).contains(&c);
            let base: u8 = if disc || bar { 30 } else { 220 };
            Luma([base + noise])
        })
    }

    fn png_bytes(img: DynamicImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        img.write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
            .unwrap();
        bytes
    }

    #[test]
    fn a_large_grey_png_decodes_to_the_image_crates_pixels_with_their_counts() {
        let (w, h) = (1600, 1400);
        assert!(u64::from(w * h) >= COUNTED_PIXELS);
        let bytes = png_bytes(DynamicImage::ImageLuma8(page(w, h)));
        let counted = decode_counted(Cursor::new(&bytes[..]), u64::MAX, &pass)
            .unwrap()
            .expect("a large 8-bit grey PNG is decoded here");
        let reference = image::load_from_memory(&bytes).unwrap();
        let reference = reference.as_luma8().expect("8-bit grey");
        assert_eq!(counted.image.as_raw(), reference.as_raw());
        assert_eq!(*counted.counts, byte_counts(reference.as_raw()));
        // The bitmap of the counted decode is the one of the image decoded whole, in
        // every threshold mode (the counts replace the histogram of the pixels).
        for mode in [
            ThresholdMode::Auto,
            ThresholdMode::Global,
            ThresholdMode::Local,
        ] {
            let opts = options(mode);
            let fast = load_bytes(&bytes, Path::new("page.png"), &opts).unwrap();
            let whole = from_image(&DynamicImage::ImageLuma8(reference.clone()), &opts).unwrap();
            assert_eq!(
                fast.threshold().to_bits(),
                whole.threshold().to_bits(),
                "{mode:?}"
            );
            assert_eq!(fast.is_bilevel(), whole.is_bilevel());
            for (r, c) in [(600, 700), (5, 5), (700, 140), (1399, 1599)] {
                assert_eq!(fast.coverage_at(c, r), whole.coverage_at(c, r), "{mode:?}");
            }
        }
    }

    /// Paeth's predictor as the PNG specification writes it.
    fn paeth_by_the_book(a: u8, b: u8, c: u8) -> u8 {
        let p = i16::from(a) + i16::from(b) - i16::from(c);
        let (pa, pb, pc) = (
            (p - i16::from(a)).abs(),
            (p - i16::from(b)).abs(),
            (p - i16::from(c)).abs(),
        );
        if pa <= pb && pa <= pc {
            a
        } else if pb <= pc {
            b
        } else {
            c
        }
    }

    #[test]
    fn paeth_rows_with_level_chunks_undo_as_the_predictor_does() {
        // Rows above with level stretches (so that chunks take the shortcut), steps and
        // noise; filtered rows with zero runs, small values and noise; every length
        // around a chunk's multiple.
        use rand::{RngExt, SeedableRng};
        let mut rng = crate::optim::SeededRng::seed_from_u64(19);
        let mut next = move || rng.random::<u64>();
        let mut shortcuts = 0;
        for len in [1, 2, 15, 16, 17, 31, 32, 33, 47, 100, 257] {
            for case in 0..200 {
                let above: Vec<u8> = (0..len)
                    .map(|k| match case % 4 {
                        0 => 7,
                        1 => ((k / 20) * 60) as u8,
                        2 if next() % 8 != 0 => 200,
                        _ => next() as u8,
                    })
                    .collect();
                let filtered: Vec<u8> = (0..len)
                    .map(|_| match (case / 4) % 3 {
                        0 => 0,
                        1 if next() % 5 != 0 => 0,
                        _ => next() as u8,
                    })
                    .collect();
                let mut expected = filtered.clone();
                expected[0] = expected[0].wrapping_add(above[0]);
                for i in 1..len {
                    let p = paeth_by_the_book(expected[i - 1], above[i], above[i - 1]);
                    expected[i] = expected[i].wrapping_add(p);
                }
                let mut row = filtered.clone();
                unfilter(4, &above, &mut row).unwrap();
                assert_eq!(row, expected, "length {len}, case {case}");
                shortcuts += usize::from(len > CHUNK && chunk(&above, 0) == chunk(&above, 1));
            }
        }
        assert!(
            shortcuts > 500,
            "only {shortcuts} rows could take the shortcut"
        );
    }

    #[test]
    fn paeths_predictor_is_the_specifications_on_every_triple() {
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                for c in 0..=255u8 {
                    assert_eq!(paeth(a, b, c), paeth_by_the_book(a, b, c), "{a} {b} {c}");
                }
            }
        }
    }

    /// Each of the five filters, every row filtered alike (and an odd width, so that
    /// bands hold whole rows that do not fill them), decodes to the `image` crate's
    /// pixels and counts; an unknown filter type leaves the image to the `image` crate.
    #[test]
    fn every_filter_type_decodes_to_the_image_crates_pixels() {
        let (w, h) = (1601, 1399);
        let grey = page(w, h);
        for filter in [
            png::Filter::NoFilter,
            png::Filter::Sub,
            png::Filter::Up,
            png::Filter::Avg,
            png::Filter::Paeth,
        ] {
            let mut bytes = Vec::new();
            let mut encoder = png::Encoder::new(&mut bytes, w, h);
            encoder.set_color(png::ColorType::Grayscale);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_filter(filter);
            let mut writer = encoder.write_header().unwrap();
            writer.write_image_data(grey.as_raw()).unwrap();
            writer.finish().unwrap();
            let counted = decode_counted(Cursor::new(&bytes[..]), u64::MAX, &pass)
                .unwrap()
                .expect("decoded here");
            let reference = image::load_from_memory(&bytes).unwrap();
            let reference = reference.as_luma8().expect("8-bit grey");
            assert_eq!(counted.image.as_raw(), reference.as_raw(), "{filter:?}");
            assert_eq!(counted.image.as_raw(), grey.as_raw(), "{filter:?}");
            assert_eq!(
                *counted.counts,
                byte_counts(reference.as_raw()),
                "{filter:?}"
            );
        }
        let row = vec![7u8; 9];
        let mut bad = row.clone();
        assert!(unfilter(5, &row, &mut bad).is_none());
    }

    /// A noisy page compresses to more bytes per pixel than
    /// [`INFLATE_HEAVY_BYTES_PER_PIXEL`], a smooth one to fewer: both ways of mapping
    /// the pages (a thread of their own, or the decoding thread) give the same pixels.
    #[test]
    fn pages_mapped_either_way_give_the_same_pixels() {
        let (w, h) = (1600, 1400);
        let noisy = page(w, h);
        let smooth = image::GrayImage::from_fn(w, h, |c, r| {
            let disc = (f64::from(c) - 700.0).hypot(f64::from(r) - 600.0) < 350.0;
            Luma([if disc { 30 } else { 220 }])
        });
        let pixels = f64::from(w * h);
        for (img, heavy) in [(noisy, true), (smooth, false)] {
            let bytes = png_bytes(DynamicImage::ImageLuma8(img.clone()));
            let per_pixel = bytes.len() as f64 / pixels;
            assert_eq!(
                per_pixel >= INFLATE_HEAVY_BYTES_PER_PIXEL,
                heavy,
                "{per_pixel}"
            );
            let counted = decode_counted(Cursor::new(&bytes[..]), u64::MAX, &pass)
                .unwrap()
                .expect("decoded here");
            assert_eq!(counted.image.as_raw(), img.as_raw());
            assert_eq!(*counted.counts, byte_counts(img.as_raw()));
        }
    }

    #[test]
    fn other_pngs_and_broken_data_are_left_to_the_image_crate() {
        let (w, h) = (1600, 1400);
        let grey = page(w, h);
        let decline = |bytes: &[u8]| {
            decode_counted(Cursor::new(bytes), u64::MAX, &pass)
                .unwrap()
                .is_none()
        };
        let rgb = DynamicImage::ImageLuma8(grey.clone()).to_rgb8();
        assert!(decline(&png_bytes(DynamicImage::ImageRgb8(rgb))));
        let deep = DynamicImage::ImageLuma8(grey.clone()).to_luma16();
        assert!(decline(&png_bytes(DynamicImage::ImageLuma16(deep))));
        let small = image::imageops::crop_imm(&grey, 0, 0, 200, 200).to_image();
        assert!(decline(&png_bytes(DynamicImage::ImageLuma8(small))));
        // Cut short: declined here, and the image crate reports the error as before.
        let bytes = png_bytes(DynamicImage::ImageLuma8(grey));
        let cut = &bytes[..bytes.len() * 2 / 3];
        assert!(decline(cut));
        let res = load_bytes(cut, Path::new("cut.png"), &options(ThresholdMode::Auto));
        assert!(matches!(res, Err(Error::Decode { .. })), "{res:?}");
        // The size limits hold as before.
        let few = RasterOptions {
            max_pixels: 1000,
            ..options(ThresholdMode::Auto)
        };
        let res = load_bytes(&bytes, Path::new("page.png"), &few);
        assert!(
            matches!(res, Err(Error::TooLarge { .. })),
            "{:?}",
            res.err()
        );
    }
}
