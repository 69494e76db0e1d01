//! # outlinefit
//!
//! Traces bitmap outlines (letters, logos, silhouettes) into closed chains of
//! G1-continuous rational cubic Bézier segments and reports, segment by segment, how well
//! each one fits its data.
//!
//! The pipeline is a chain of plain functions, one module per stage:
//!
//! ```text
//! image ─► raster::load ─► contour::extract_contours ─► breaks::find_breaks ─► fit ─► export
//!          Bitmap           Vec<Contour>                 Vec<SegmentedContour>   Vec<FittedContour>
//! ```
//!
//! [`trace_file`] and [`trace_bitmap`] run the whole chain with a [`Config`]; the [`trace`]
//! module owns them and is the one place that turns a `Config` into stage options.
//!
//! ## Tracing an image held in memory
//!
//! Any image the `image` crate holds becomes a [`Bitmap`] through [`raster::from_image`];
//! [`export::svg::to_svg`] writes the result:
//!
//! ```
//! use image::{DynamicImage, GrayImage, Luma};
//! use outlinefit::{to_svg, SvgOptions};
//! use outlinefit::{raster, trace_bitmap, Config};
//!
//! // A black disk of radius 20 px on white paper.
//! let disk = GrayImage::from_fn(64, 64, |x, y| {
//!     let (dx, dy) = (x as f64 + 0.5 - 32.0, y as f64 + 0.5 - 32.0);
//!     Luma([if dx.hypot(dy) < 20.0 { 0 } else { 255 }])
//! });
//! let config = Config::default();
//! let bitmap = raster::from_image(&DynamicImage::ImageLuma8(disk), &config.raster_options())?;
//! let traced = trace_bitmap(&bitmap, &config)?;
//! let svg = to_svg(&traced, &SvgOptions::for_tolerance(config.tolerance));
//!
//! assert_eq!(traced.contours.len(), 1); // one outline, no hole
//! assert!(traced.max_distance() <= config.tolerance); // every edge point within 0.3 px
//! assert!(traced.fidelity.held); // nothing lost or invented
//! assert_eq!(svg.matches("<path").count(), 1);
//! # Ok::<(), outlinefit::Error>(())
//! ```
//!
//! ## Features
//!
//! Without default features the crate is the tracer alone (every stage above, the SVG
//! writer and the reports). `lab` adds `compare` (its charts in `compare::plot`) and
//! `stats` (`plotters`); `papers` adds `bspline`, `reduce` and `surface` (and `lab`;
//! `exmex`); `cli`, the default, builds the `outlinefit` program (`clap`, `indicatif`,
//! `anyhow`, `ctrlc`) with both.

mod breaks;
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
pub mod quad;
mod raster;
mod repair;
pub mod report;
pub mod svg_writer;
mod trace;

pub use crate::breaks::{
    find_breaks, Break, BreakOptions, BreakReason, JointKind, SegmentedContour,
};
pub use crate::contour::{extract_contours, Contour, ContourOptions};
pub use crate::curve::{CubicBez, ParamCurve, RationalCubic};
pub use crate::error::{Error, ForegroundHint, Result};
pub use crate::export::{to_overlay_svg, to_svg, OverlayOptions, SvgOptions};
pub use crate::fidelity::Fidelity;
pub use crate::fit::placement::BreakPlacement;
pub use crate::fit::refit::Search;
pub use crate::fit::{FittedContour, FittedSegment, Joint, Method, SegmentError};
pub use crate::geom::{Bounds, Point};
pub use crate::raster::{AlphaRule, Bitmap, RasterOptions, ThresholdScale};
pub use crate::trace::{trace_bitmap, trace_file, Config, ImageInfo, TraceResult};

/// The version of this crate, recorded in reports.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
