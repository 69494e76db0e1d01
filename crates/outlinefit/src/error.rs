//! The library's error type. Every failure a user can cause (a missing or undecodable
//! file, an empty or oversized image, an unwritable output) is a variant here; the binary
//! prints it as one line.
//!
//! An error about an option names the options field (`tolerance`, `max_pixels`), not a
//! command-line flag: the command line maps fields to its flags.

use std::path::PathBuf;

/// Everything that can go wrong while tracing.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The input is not an image `image` can decode (or it is truncated).
    #[error("{}: not a readable image: {source}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's error.
        #[source]
        source: image::ImageError,
    },
    /// The image decodes but its pixel layout is one the tracer does not read.
    #[error("{}: not a readable image: {message}", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// What is not supported and what is.
        message: String,
    },
    /// The image has no pixels.
    #[error("the image has zero size ({width}×{height})")]
    ZeroSize {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// The image has more pixels than allowed.
    #[error("the image is {width}×{height} = {pixels} pixels, more than the limit of {limit} (max_pixels)")]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// width × height.
        pixels: u64,
        /// The configured limit.
        limit: u64,
    },
    /// Tracing the image would need more memory than the system has available.
    #[error("the image is {width}×{height}: tracing it needs about {needed_mb} MB of memory, but only {available_mb} MB are available")]
    OutOfMemory {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// Estimated need, MB.
        needed_mb: u64,
        /// Available memory when the check ran, MB.
        available_mb: u64,
    },
    /// Nothing was found to trace: no pixel passes the threshold, so every pixel is
    /// background.
    #[error("no shape found: no pixel has {threshold}, so every pixel is background; {hint}")]
    NoForeground {
        /// The threshold that was used, as a user reads it (e.g. "luminance below 136.0").
        threshold: String,
        /// What to try.
        hint: ForegroundHint,
    },
    /// Every shape of the image is smaller than the speck size, so none was traced.
    #[error("no shape found: all {shapes} shapes are smaller than the minimum area of {min_area} px² (lower min_area to keep them)")]
    AllBelowMinArea {
        /// Number of foreground shapes (8-connected components at the threshold).
        shapes: usize,
        /// The minimum area that removed them, px².
        min_area: f64,
    },
    /// An output could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// An option has a value outside its domain.
    #[error("invalid option {name}: {message}")]
    InvalidOption {
        /// The options field, e.g. `tolerance` of [`crate::Config`] (`omega/lambda/mu`
        /// when several fields are at fault together).
        name: &'static str,
        /// What is wrong with it.
        message: String,
    },
    /// Data that is readable but not valid (two curves that cannot be merged …).
    #[error("{what}: {message}")]
    InvalidInput {
        /// What was read, e.g. the file's path.
        what: String,
        /// What is wrong with it.
        message: String,
    },
}

/// What to try when an image has no foreground at the threshold used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ForegroundHint {
    /// The luminance was traced although part of the image is transparent: tracing the
    /// alpha channel ([`crate::raster::AlphaRule::Alpha`]) may find the shape.
    TraceAlpha {
        /// Fraction of the image that is mostly transparent, in (0, 1].
        transparent: f64,
    },
    /// Light shapes on a dark background need `invert`; otherwise another `threshold`.
    InvertOrThreshold,
}

impl std::fmt::Display for ForegroundHint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ForegroundHint::TraceAlpha { transparent } => write!(
                f,
                "{:.1} % of the image is transparent: AlphaRule::Alpha traces its alpha channel",
                100.0 * transparent
            ),
            ForegroundHint::InvertOrThreshold => f.write_str(
                "if the shapes are light on a dark background try invert, otherwise threshold",
            ),
        }
    }
}

/// Shorthand for results whose error is [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
