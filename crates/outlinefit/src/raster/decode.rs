//! Decoding an image file or its bytes into a `DynamicImage`, within the limits: the
//! pixel count from the header before any pixel is decoded, the decoder's memory, and
//! the memory the system has available. The format is recognised from the content; an
//! animation's frame or a TIFF file's page is picked here (`frames`), and a large still
//! PNG is decoded straight from its file.

use super::frames;
use super::grey_png::{decode_counted, ByteCounts, CountedGrey};
use crate::error::{Error, Result};
use image::{DynamicImage, ImageDecoder, ImageReader, Limits};
use std::path::Path;

/// What decoding takes from the raster options: the pixel limit and the frame (or page)
/// to decode.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Request {
    /// Largest accepted width × height.
    pub(crate) max_pixels: u64,
    /// The frame of an animation or page of a TIFF file, from 0.
    pub(crate) frame: u32,
}

/// Bytes per pixel budgeted for the decoder (RGBA with 32-bit float channels).
const DECODE_BYTES_PER_PIXEL: u64 = 16;
/// Extra decoder working memory allowed on top of the pixel buffer.
const DECODE_SLACK_BYTES: u64 = 64 << 20;
/// Checks a width and height against the zero-size and `max_pixels` rules.
pub(super) fn check_dimensions(width: u32, height: u32, max_pixels: u64) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::ZeroSize { width, height });
    }
    let pixels = u64::from(width) * u64::from(height);
    if pixels > max_pixels {
        return Err(Error::TooLarge {
            width,
            height,
            pixels,
            limit: max_pixels,
        });
    }
    Ok(())
}

/// Bytes per pixel that tracing needs beyond the decoded image: the coverage levels (2,
/// none when an 8-bit grey image's own buffer becomes them) and the thresholded mask
/// while it is built (1), with room to spare (measured peak on a 4096 × 3359 grey
/// silhouette: 34 MB in all, 2.5 bytes per pixel including the decoded image).
const TRACE_BYTES_PER_PIXEL: u64 = 4;

/// Checks that decoding (`decoded_bpp` bytes per pixel) and tracing a `width`×`height`
/// image fits in the memory the system has available, so that a huge image is refused
/// with a message instead of aborting on a failed allocation. Only where the available
/// memory can be read (Linux: `MemAvailable` in /proc/meminfo); elsewhere it passes.
/// An image that needs less than [`UNCHECKED_BYTES`] passes without reading it.
fn check_memory(width: u32, height: u32, decoded_bpp: u64) -> Result<()> {
    let pixels = u64::from(width) * u64::from(height);
    let needed = pixels.saturating_mul(decoded_bpp + TRACE_BYTES_PER_PIXEL);
    if needed < UNCHECKED_BYTES {
        return Ok(());
    }
    match available_memory() {
        Some(available) if needed > available => Err(Error::OutOfMemory {
            width,
            height,
            needed_mb: needed >> 20,
            available_mb: available >> 20,
        }),
        _ => Ok(()),
    }
}

/// Memory below which an image is not checked against the available memory: reading
/// /proc/meminfo takes about 40 µs, a hundredth of tracing a 256 px glyph, and a machine
/// that runs the program has this much to spare (16 MiB: an 8-bit grey image of about
/// 1800 × 1800).
const UNCHECKED_BYTES: u64 = 16 << 20;

/// The memory the system can give this process without swapping, in bytes, if known.
fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// An image file, decoded already or read whole (see [`open_image`]).
pub(super) enum Opened {
    /// With the counts of its levels when it was decoded by `grey_png`.
    Decoded(DynamicImage, Option<ByteCounts>),
    Bytes(Vec<u8>),
}

/// Smallest PNG file that [`open_image`] decodes straight from the file.
pub(super) const STREAM_PNG_BYTES: u64 = 1 << 20;

/// Reads an image file whole, except a still PNG file of at least [`STREAM_PNG_BYTES`],
/// which is decoded from the file through a small buffer, as [`decode_bytes`] would
/// decode its bytes (same limits, checks and orientation). Reading a page's 18 MB into
/// memory first costs a fresh allocation that the kernel must map and clear page by page
/// before decoding can start (10 to 25 ms of the 600 dpi scan's time on one core), and
/// holds the bytes until the pixels are decoded.
pub(super) fn open_image(path: &Path, opts: Request) -> Result<Opened> {
    use std::io::{Read, Seek};
    let read_error = |source| Error::Read {
        path: path.to_path_buf(),
        source,
    };
    let mut file = std::fs::File::open(path).map_err(read_error)?;
    let len = file.metadata().map(|m| m.len()).ok();
    if opts.frame == 0 && len.is_some_and(|n| n >= STREAM_PNG_BYTES) {
        if let Some((img, counts)) = decode_png_file(&mut file, path, opts)? {
            return Ok(Opened::Decoded(img, counts));
        }
        file.rewind().map_err(read_error)?;
    }
    let mut bytes = Vec::new();
    // As `std::fs::read` does: one allocation at the file's size.
    bytes
        .try_reserve_exact(len.unwrap_or(0) as usize)
        .map_err(|e| read_error(std::io::Error::new(std::io::ErrorKind::OutOfMemory, e)))?;
    file.read_to_end(&mut bytes).map_err(read_error)?;
    Ok(Opened::Bytes(bytes))
}

/// The still PNG image in `file` (see [`open_image`]), with its levels' counts when it is
/// a large 8-bit grey one ([`decode_counted_png`]); `None` when the file is not a PNG or
/// is an animated one, which [`decode_bytes`] decodes from its bytes.
fn decode_png_file(
    file: &mut std::fs::File,
    path: &Path,
    opts: Request,
) -> Result<Option<(DynamicImage, Option<ByteCounts>)>> {
    use image::codecs::png::PngDecoder;
    use std::io::{BufReader, Read, Seek};
    let read_error = |source| Error::Read {
        path: path.to_path_buf(),
        source,
    };
    let mut magic = [0u8; 8];
    if file.read_exact(&mut magic).is_err() || magic != *b"\x89PNG\r\n\x1a\n" {
        return Ok(None);
    }
    file.rewind().map_err(read_error)?;
    if let Some(grey) = decode_counted_png(BufReader::with_capacity(1 << 16, &mut *file), opts)? {
        return Ok(Some((
            DynamicImage::ImageLuma8(grey.image),
            Some(grey.counts),
        )));
    }
    file.rewind().map_err(read_error)?;
    // Its chunks before the pixels say whether it is animated.
    let animated = PngDecoder::new(BufReader::new(&mut *file))
        .and_then(|d| d.is_apng())
        .map_err(|source| Error::Decode {
            path: path.to_path_buf(),
            source,
        })?;
    if animated {
        return Ok(None);
    }
    file.rewind().map_err(read_error)?;
    let reader = ImageReader::with_format(
        BufReader::with_capacity(1 << 16, file),
        image::ImageFormat::Png,
    );
    let check = |w, h, bpp| decode_check(w, h, bpp, opts);
    decode_still(reader, decode_limits(opts), path, &check).map(|img| Some((img, None)))
}

/// A large 8-bit grey PNG decoded with its histogram (see `grey_png`), within the
/// limits of `opts`; `None` for any other image, any frame but the first, and data the
/// decoder rejects, which the `image` crate then decodes (and reports).
pub(super) fn decode_counted_png<R: std::io::BufRead + std::io::Seek>(
    reader: R,
    opts: Request,
) -> Result<Option<CountedGrey>> {
    if opts.frame != 0 {
        return Ok(None);
    }
    let max_alloc = decode_limits(opts).max_alloc.unwrap_or(u64::MAX);
    decode_counted(reader, max_alloc, &|w, h, bpp| {
        decode_check(w, h, bpp, opts)
    })
}

/// The decoder's memory cap for `opts.max_pixels` (see [`decode_bytes`]).
fn decode_limits(opts: Request) -> Limits {
    let mut limits = Limits::default();
    limits.max_alloc = Some(
        opts.max_pixels
            .saturating_mul(DECODE_BYTES_PER_PIXEL)
            .saturating_add(DECODE_SLACK_BYTES),
    );
    limits
}

/// The size checks made from a header before any pixel is decoded: the pixel limit and
/// the memory the decoded image (`bpp` bytes a pixel) will need.
fn decode_check(width: u32, height: u32, bpp: u64, opts: Request) -> Result<()> {
    check_dimensions(width, height, opts.max_pixels)?;
    check_memory(width, height, bpp)
}

/// Reads and decodes an image file as [`decode_bytes`] does.
pub(crate) fn decode_file(path: &Path, opts: Request) -> Result<(DynamicImage, u32)> {
    match open_image(path, opts)? {
        Opened::Decoded(img, _) => Ok((img, 1)),
        Opened::Bytes(bytes) => decode_bytes(&bytes, path, opts),
    }
}

/// Decodes the frame `opts.frame` of an image file's bytes, within `opts.max_pixels`, with
/// its orientation applied; also returns the number of frames (pages) of the file.
pub(crate) fn decode_bytes(
    bytes: &[u8],
    name: &Path,
    opts: Request,
) -> Result<(DynamicImage, u32)> {
    let decode_error = |source| Error::Decode {
        path: name.to_path_buf(),
        source,
    };
    let reader = ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|source| Error::Read {
            path: name.to_path_buf(),
            source,
        })?;
    if reader.format() == Some(image::ImageFormat::Jpeg) && !jpeg_is_complete(bytes) {
        return Err(decode_error(image::ImageError::IoError(
            std::io::Error::new(
                std::io::ErrorKind::UnexpectedEof,
                "truncated JPEG (no end-of-image marker)",
            ),
        )));
    }
    let limits = decode_limits(opts);
    let max_bytes = limits.max_alloc.unwrap_or(u64::MAX);
    let format = reader.format();
    let check = |w, h, bpp| decode_check(w, h, bpp, opts);
    let (img, frames) = if let Some(found) =
        frames::animation_frame(bytes, format, opts.frame, &limits, name, &check)?
    {
        found
    } else if format == Some(image::ImageFormat::Tiff) {
        let pages = frames::tiff_page_count(bytes, name)?;
        if opts.frame >= pages {
            return Err(frames::out_of_range(opts.frame, pages));
        }
        // The `image` crate reads the first page (with its orientation); other pages, and
        // first pages it does not support (floating-point grey), go through `tiff`.
        let img = match (opts.frame == 0).then(|| decode_still(reader, limits, name, &check)) {
            Some(Ok(img)) => img,
            Some(Err(Error::Decode {
                source: image::ImageError::Unsupported(_),
                ..
            }))
            | None => frames::tiff_page(bytes, opts.frame, max_bytes, name, check)?,
            Some(Err(e)) => return Err(e),
        };
        (img, pages)
    } else {
        if opts.frame > 0 {
            return Err(frames::out_of_range(opts.frame, 1));
        }
        (decode_still(reader, limits, name, &check)?, 1)
    };
    Ok((img, frames))
}

/// Decodes a still image (or an animation's first frame) with `limits`, checking its size
/// with `check` before any pixel is decoded and applying its EXIF orientation.
fn decode_still<R: std::io::BufRead + std::io::Seek>(
    mut reader: ImageReader<R>,
    limits: Limits,
    name: &Path,
    check: &dyn Fn(u32, u32, u64) -> Result<()>,
) -> Result<DynamicImage> {
    let decode_error = |source| Error::Decode {
        path: name.to_path_buf(),
        source,
    };
    reader.limits(limits);
    let mut decoder = reader.into_decoder().map_err(decode_error)?;
    let (width, height) = decoder.dimensions();
    check(
        width,
        height,
        u64::from(decoder.color_type().bytes_per_pixel()),
    )?;
    // A missing or unreadable orientation tag means upright.
    let orientation = decoder
        .orientation()
        .unwrap_or(image::metadata::Orientation::NoTransforms);
    let mut img = DynamicImage::from_decoder(decoder).map_err(decode_error)?;
    img.apply_orientation(orientation);
    Ok(img)
}

/// True when JPEG data ends with its end-of-image marker (FF D9), allowing for the
/// padding some writers append after it.
fn jpeg_is_complete(bytes: &[u8]) -> bool {
    let tail = &bytes[bytes.len().saturating_sub(JPEG_TAIL_SLACK)..];
    tail.windows(2).any(|w| w == [0xFF, 0xD9])
}

/// Bytes after a JPEG's last end-of-image marker that are still accepted (zero padding,
/// a camera's trailer).
const JPEG_TAIL_SLACK: usize = 4096;
