//! One frame of an animation (GIF, APNG, animated WebP) or one page of a multi-page TIFF,
//! chosen by `--frame`, and TIFF pages the `image` crate cannot read (floating-point grey).
//!
//! The `image` crate decodes only the first frame of such a file through its plain path;
//! these functions count the frames and return the one asked for. Animation frames are
//! full-canvas RGBA, composited as a viewer shows them. TIFF pages are read with the
//! `tiff` crate (which `image` itself uses): grey, grey + alpha, RGB and RGBA with 1-, 8- or
//! 16-bit integer or 32- or 64-bit float samples (floats: 0 is black, 1 white).

use crate::error::{Error, Result};
use image::{AnimationDecoder, DynamicImage, ImageBuffer, ImageDecoder, Limits};
use std::io::Cursor;
use std::path::Path;

/// Frame `frame` of an animated file and the number of frames it has, or `None` when the
/// file is not an animation (a still PNG or WebP; every other format but GIF). `check`
/// (width, height, bytes per decoded pixel) runs before any frame is decoded.
pub(crate) fn animation_frame(
    bytes: &[u8],
    format: Option<image::ImageFormat>,
    frame: u32,
    limits: &Limits,
    name: &Path,
    check: &dyn Fn(u32, u32, u64) -> Result<()>,
) -> Result<Option<(DynamicImage, u32)>> {
    use image::codecs::{gif::GifDecoder, png::PngDecoder, webp::WebPDecoder};
    use image::ImageFormat;
    let fail = |source| Error::Decode {
        path: name.to_path_buf(),
        source,
    };
    let frames = match format {
        Some(ImageFormat::Gif) => {
            let mut d = GifDecoder::new(Cursor::new(bytes)).map_err(fail)?;
            let (w, h) = d.dimensions();
            check(w, h, 4)?;
            d.set_limits(limits.clone()).map_err(fail)?;
            d.into_frames()
        }
        Some(ImageFormat::Png) => {
            let mut d = PngDecoder::new(Cursor::new(bytes)).map_err(fail)?;
            if !d.is_apng().map_err(fail)? {
                return Ok(None);
            }
            let (w, h) = d.dimensions();
            check(w, h, 4)?;
            d.set_limits(limits.clone()).map_err(fail)?;
            d.apng().map_err(fail)?.into_frames()
        }
        Some(ImageFormat::WebP) => {
            let mut d = WebPDecoder::new(Cursor::new(bytes)).map_err(fail)?;
            if !d.has_animation() {
                return Ok(None);
            }
            let (w, h) = d.dimensions();
            check(w, h, 4)?;
            d.set_limits(limits.clone()).map_err(fail)?;
            d.into_frames()
        }
        _ => return Ok(None),
    };
    let mut chosen = None;
    let mut count = 0u32;
    for f in frames {
        let f = f.map_err(fail)?;
        if count == frame {
            chosen = Some(DynamicImage::ImageRgba8(f.into_buffer()));
        }
        count += 1;
    }
    match chosen {
        Some(img) => Ok(Some((img, count))),
        None => Err(out_of_range(frame, count)),
    }
}

/// The number of pages (image file directories) of a TIFF file.
pub(crate) fn tiff_page_count(bytes: &[u8], name: &Path) -> Result<u32> {
    let mut d = tiff::decoder::Decoder::new(Cursor::new(bytes)).map_err(|e| tiff_error(e, name))?;
    let mut pages = 1;
    while d.more_images() {
        d.next_image().map_err(|e| tiff_error(e, name))?;
        pages += 1;
    }
    Ok(pages)
}

/// Page `page` of a TIFF file, decoded by the `tiff` crate; `max_bytes` caps its buffer.
/// The caller has checked `page` against [`tiff_page_count`] and passes the size check
/// `check` (width, height, decoded bytes per pixel), run before any pixel is decoded.
pub(crate) fn tiff_page(
    bytes: &[u8],
    page: u32,
    max_bytes: u64,
    name: &Path,
    check: impl FnOnce(u32, u32, u64) -> Result<()>,
) -> Result<DynamicImage> {
    use tiff::decoder::DecodingResult as D;
    use tiff::ColorType as C;
    let err = |e| tiff_error(e, name);
    let mut limits = tiff::decoder::Limits::default();
    limits.decoding_buffer_size = usize::try_from(max_bytes).unwrap_or(usize::MAX);
    let mut d = tiff::decoder::Decoder::new(Cursor::new(bytes))
        .map_err(err)?
        .with_limits(limits);
    d.seek_to_image(page as usize).map_err(err)?;
    let (w, h) = d.dimensions().map_err(err)?;
    // Up to 16 bytes per pixel once decoded (float RGBA).
    check(w, h, 16)?;
    let colour = d.colortype().map_err(err)?;
    let data = d.read_image().map_err(err)?;
    let samples = match &data {
        D::U8(_) => "8-bit unsigned integer",
        D::U16(_) => "16-bit unsigned integer",
        D::U32(_) => "32-bit unsigned integer",
        D::U64(_) => "64-bit unsigned integer",
        D::I8(_) => "8-bit signed integer",
        D::I16(_) => "16-bit signed integer",
        D::I32(_) => "32-bit signed integer",
        D::I64(_) => "64-bit signed integer",
        D::F16(_) => "16-bit float",
        D::F32(_) => "32-bit float",
        D::F64(_) => "64-bit float",
    };
    let unsupported = || {
        Error::Unsupported {
        path: name.to_path_buf(),
        message: format!(
            "TIFF page {page} has colour type {colour:?} with {samples} samples; outlinefit reads grey, grey + alpha, RGB and RGBA pages with 1-, 8- or 16-bit integer or 32- or 64-bit float samples"
        ),
    }
    };
    let img = match (colour, data) {
        (C::Gray(1), D::U8(v)) => {
            // Rows are padded to whole bytes; a set bit is white (BlackIsZero).
            let row = w.div_ceil(8) as usize;
            let px = ImageBuffer::from_fn(w, h, |x, y| {
                let byte = v
                    .get(y as usize * row + x as usize / 8)
                    .copied()
                    .unwrap_or(0);
                image::Luma([if byte & (0x80 >> (x % 8)) != 0 {
                    255
                } else {
                    0
                }])
            });
            Some(DynamicImage::ImageLuma8(px))
        }
        (C::Gray(8), D::U8(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageLuma8),
        (C::GrayA(8), D::U8(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageLumaA8),
        (C::RGB(8), D::U8(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgb8),
        (C::RGBA(8), D::U8(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgba8),
        (C::Gray(16), D::U16(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageLuma16),
        (C::GrayA(16), D::U16(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageLumaA16),
        (C::RGB(16), D::U16(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgb16),
        (C::RGBA(16), D::U16(v)) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgba16),
        (colour, D::F32(v)) => floats(w, h, colour, v.into_iter()),
        (colour, D::F64(v)) => floats(w, h, colour, v.into_iter().map(|x| x as f32)),
        _ => None,
    }
    .ok_or_else(unsupported)?;
    Ok(img)
}

/// A float TIFF page as 32-bit float RGB(A), grey replicated into the three channels.
fn floats(
    w: u32,
    h: u32,
    colour: tiff::ColorType,
    v: impl Iterator<Item = f32>,
) -> Option<DynamicImage> {
    use tiff::ColorType as C;
    let v: Vec<f32> = v.collect();
    match colour {
        C::Gray(_) => ImageBuffer::from_raw(w, h, v.iter().flat_map(|&g| [g, g, g]).collect())
            .map(DynamicImage::ImageRgb32F),
        C::GrayA(_) => ImageBuffer::from_raw(
            w,
            h,
            v.chunks_exact(2)
                .flat_map(|p| [p[0], p[0], p[0], p[1]])
                .collect(),
        )
        .map(DynamicImage::ImageRgba32F),
        C::RGB(_) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgb32F),
        C::RGBA(_) => ImageBuffer::from_raw(w, h, v).map(DynamicImage::ImageRgba32F),
        _ => None,
    }
}

/// `--frame` beyond the last frame.
pub(crate) fn out_of_range(frame: u32, frames: u32) -> Error {
    Error::InvalidOption {
        name: "frame",
        message: format!(
            "{frame} is past the last frame: the file has {frames} frame{} (0 to {})",
            if frames == 1 { "" } else { "s" },
            frames.saturating_sub(1)
        ),
    }
}

/// A `tiff` crate error as the `image` crate would report it.
fn tiff_error(e: tiff::TiffError, name: &Path) -> Error {
    Error::Decode {
        path: name.to_path_buf(),
        source: image::ImageError::Decoding(image::error::DecodingError::new(
            image::ImageFormat::Tiff.into(),
            e,
        )),
    }
}
