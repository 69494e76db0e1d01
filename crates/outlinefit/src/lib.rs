//! # outlinefit
//!
//! Traces bitmap outlines (letters, logos, silhouettes) into closed chains of
//! G1-continuous rational cubic Bézier segments and reports, segment by segment, how well
//! each one fits its data.
//!
//! The pipeline is a chain of stages, one module each: the image becomes a [`Bitmap`];
//! its contours are extracted with sub-pixel points; break points are found by curvature;
//! each piece is fitted ([`fit`]); adjacent segments are optionally merged into disk
//! Wang–Ball curves ([`merge`]); the drawn result is checked against the pixels and
//! repaired where it lost or invented a part ([`Fidelity`]); [`export`] (SVG, PDF, EPS,
//! DXF, GeoJSON) and [`report`] write it. [`trace_file`] and [`trace_bitmap`] run the whole chain with a [`Config`].
//!
//! ## Tracing an image held in memory
//!
//! Any image the `image` crate holds becomes a [`Bitmap`] through [`Bitmap::from_image`];
//! [`to_svg`] writes the result. Every name used is at the crate root:
//!
//! ```
//! use image::{DynamicImage, GrayImage, Luma};
//! use outlinefit::{to_svg, trace_bitmap, Bitmap, Config, ExportOptions};
//!
//! // A black disk of radius 20 px on white paper.
//! let disk = GrayImage::from_fn(64, 64, |x, y| {
//!     let (dx, dy) = (x as f64 + 0.5 - 32.0, y as f64 + 0.5 - 32.0);
//!     Luma([if dx.hypot(dy) < 20.0 { 0 } else { 255 }])
//! });
//! let config = Config::default();
//! let bitmap = Bitmap::from_image(&DynamicImage::ImageLuma8(disk), &config.raster_options())?;
//! let traced = trace_bitmap(&bitmap, &config)?;
//! let svg = to_svg(&traced, &ExportOptions::for_tolerance(config.tolerance));
//!
//! assert_eq!(traced.contours.len(), 1); // one outline, no hole
//! assert!(traced.max_distance() <= config.tolerance); // every edge point within 0.3 px
//! assert!(traced.fidelity.held); // nothing lost or invented
//! assert_eq!(svg.matches("<path").count(), 1);
//! # Ok::<(), outlinefit::Error>(())
//! ```
//!
//! ## Colour
//!
//! [`colour::trace_colour`] traces an image's flat colours as regions whose shared
//! boundaries are fitted once (the program's `--palette`); [`colour::colour_svg`] writes
//! them as one SVG group per colour, stacked or cut out.
//!
//! ## Modules
//!
//! The root holds what a tracing program needs. A few modules hold the rest: [`colour`]
//! (colour tracing), [`centerline`] (line art as centre lines with their width, as chains
//! of disk Wang–Ball curves), [`curve`]
//! (the curve kernel: rational and polynomial cubics, Bernstein and Wang–Ball machinery),
//! [`optim`] (the papers' metaheuristics behind one trait), [`fit`] (refitting a
//! segmentation with them), [`merge`] (merging two disk Wang–Ball curves), [`report`]
//! (JSON and CSV), [`progress`] (a trace's progress, for a display), [`io`] (atomic output files), [`svg_writer`] (the number and path
//! formatting every picture shares) and [`quad`] (Gauss–Legendre quadrature).
//!
//! The crate has no command-line or plotting dependency: the `outlinefit` program is the
//! `outlinefit-cli` crate, and the optimizer comparisons, B-splines, degree reduction and
//! surface fitting of the papers are the `outlinefit-lab` crate.

mod breaks;
pub mod centerline;
pub mod colour;
mod contour;
pub mod curve;
mod error;
mod export;
mod fidelity;
pub mod fit;
mod geom;
pub mod io;
mod linalg;
pub mod merge;
pub mod optim;
mod param;
pub mod progress;
pub mod quad;
mod raster;
mod repair;
pub mod report;
pub mod svg_writer;
mod trace;

pub use crate::breaks::JointKind;
pub use crate::curve::{CubicBez, ParamCurve, RationalCubic};
pub use crate::error::{Error, ForegroundHint, Result};
pub use crate::export::{
    export, to_geojson, to_overlay_svg, to_pdf, to_postscript, to_svg, ExportOptions, Format,
    OverlayOptions, Rgb, Size, Unit, DEFAULT_DPI, DXF_LAYER,
};
pub use crate::fidelity::Fidelity;
pub use crate::fit::placement::BreakPlacement;
pub use crate::fit::{FittedContour, FittedSegment, Joint, Method, Search, SegmentError};
pub use crate::geom::{Bounds, Point};
pub use crate::raster::{AlphaRule, Bitmap, RasterOptions, ThresholdMode, ThresholdScale};
pub use crate::trace::{
    trace_bitmap, trace_bitmap_with_progress, trace_file, Config, ImageInfo, TraceResult,
};

/// The version of this crate, recorded in reports.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
