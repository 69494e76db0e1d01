//! A large 8-bit grey PNG decoded row by row, with its histogram counted on a second
//! thread while the rows arrive.
//!
//! Decoding a PNG is one stream (inflating, then undoing each row's filter against the
//! row above), so it runs on one core while the other waits: on the 600 dpi scan of
//! `make_scan.py` about 0.1 s, on the 4096 px horse 30 ms. The threshold needs the
//! histogram of every pixel, which used to be a pass of its own once decoding ended.
//! Here a helper thread works beside the decoder: it first writes to every page of the
//! fresh pixel buffer, band by band ahead of the decoder, so that the kernel maps and
//! clears them there (on the 4096 px horse 3 400 of its 6 400 page faults, which the
//! decoder used to take one by one), then counts each band the decoder hands back, so the
//! counts are ready when the last row is. The pixels are the ones the `image`
//! crate's decoder gives (the same `png` decoder with the same transformation); images
//! this path does not cover (other colour types or depths, interlaced, with a
//! transparent level or an EXIF orientation, small) and any decoding error go through
//! the `image` crate as before, so errors read the same.

use super::levels::byte_counts;
use crate::error::Result;
use image::GrayImage;
use std::io::{BufRead, Seek};

/// Fewest pixels for which [`decode_counted`] decodes: below it a helper thread costs
/// about what it saves (counting the histogram after decoding takes about a millisecond
/// at this size, and smaller images are counted on one thread).
pub(super) const COUNTED_PIXELS: u64 = 1 << 21;

/// Bytes of rows handed between the decoder and the helper thread at a time.
const BAND_BYTES: usize = 1 << 18;

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
/// before any pixel is decoded, as the `image` path asks it; the decoder allocates at
/// most `max_alloc` bytes.
pub(super) fn decode_counted<R: BufRead + Seek>(
    reader: R,
    max_alloc: u64,
    check: &dyn Fn(u32, u32, u64) -> Result<()>,
) -> Result<Option<CountedGrey>> {
    let limits = png::Limits {
        bytes: usize::try_from(max_alloc).unwrap_or(usize::MAX),
    };
    let mut decoder = png::Decoder::new_with_limits(reader, limits);
    // As the `image` crate's PNG decoder: low depths widened to 8 bits, a transparent
    // level made an alpha channel (which this path then declines).
    decoder.set_transformations(png::Transformations::EXPAND);
    let Ok(mut reader) = decoder.read_info() else {
        return Ok(None);
    };
    let info = reader.info();
    let (width, height) = (info.width, info.height);
    let plain_grey = reader.output_color_type()
        == (png::ColorType::Grayscale, png::BitDepth::Eight)
        && !info.interlaced
        && info.animation_control.is_none()
        // An EXIF orientation would turn the image: left to the `image` path.
        && info.exif_metadata.is_none();
    let pixels = u64::from(width) * u64::from(height);
    if !plain_grey || pixels < COUNTED_PIXELS {
        return Ok(None);
    }
    check(width, height, 1)?;
    let (w, len) = (width as usize, pixels as usize);
    // Zeroed by the allocator (fresh pages), not by a pass over the buffer; the memory
    // was checked above.
    let mut buf = vec![0u8; len];
    let band = (BAND_BYTES / w).max(1) * w;
    let bands: Vec<&mut [u8]> = buf.chunks_mut(band).collect();
    let decoded = std::thread::scope(|scope| {
        // Bands go to the decoder once their pages are mapped, and back once decoded.
        let (to_decoder, fresh) = std::sync::mpsc::channel::<&mut [u8]>();
        let (to_counter, decoded) = std::sync::mpsc::channel::<&[u8]>();
        let helper = std::thread::Builder::new()
            .name("outlinefit-png".into())
            .spawn_scoped(scope, move || {
                // The kernel maps and clears a fresh page at its first write: done here
                // ahead of the decoder, which would otherwise stop at every page.
                for band in bands {
                    band.iter_mut().step_by(PAGE_BYTES).for_each(|b| *b = 0);
                    if to_decoder.send(band).is_err() {
                        break;
                    }
                }
                drop(to_decoder);
                let mut counts = Box::new([0u64; 256]);
                for rows in decoded {
                    let c = byte_counts(rows);
                    counts.iter_mut().zip(c).for_each(|(a, b)| *a += b);
                }
                counts
            })
            .ok()?;
        let mut ok = true;
        for rows in fresh {
            ok = rows
                .chunks_mut(w)
                .all(|row| matches!(reader.read_row(row), Ok(Some(_))));
            // The band is finished: the counter may read it while the next one decodes.
            let rows: &[u8] = rows;
            if !ok || to_counter.send(rows).is_err() {
                break;
            }
        }
        // Past the last row the decoder reads to the end of the image data (and checks
        // it), as the `image` crate's decoding of the whole frame does.
        ok = ok && matches!(reader.read_row(&mut []), Ok(None));
        drop(to_counter);
        let counts = helper.join().ok()?;
        ok.then_some(counts)
    });
    let Some(counts) = decoded else {
        return Ok(None);
    };
    Ok(GrayImage::from_raw(width, height, buf).map(|image| CountedGrey { image, counts }))
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
