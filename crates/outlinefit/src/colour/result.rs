//! What a colour trace gives: the palette, regions, boundaries with their fitted segments,
//! the layers in drawing order, and the check's verdict.

use super::palette::{PaletteSize, Swatch};
use crate::fit::FittedSegment;
use crate::geom::Point;
use serde::Serialize;

/// How colour layers are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// Each layer extends under the later ones: no seam can show (the default).
    #[default]
    Stacked,
    /// Each layer is exactly its regions; layers abut on shared curves.
    Cutout,
}

impl std::str::FromStr for Layout {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "stacked" => Ok(Layout::Stacked),
            "cutout" => Ok(Layout::Cutout),
            _ => Err("expected `stacked` or `cutout`".to_string()),
        }
    }
}

/// Options of a colour trace beside the [`crate::Config`] (whose tolerance, corner angle,
/// `min_area`, `max_pixels` and frame it uses).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct ColourOptions {
    /// How many colours.
    pub palette: PaletteSize,
    /// How layers are drawn.
    pub layout: Layout,
}

/// One region: a 4-connected area of one colour.
#[derive(Clone, Debug, Serialize)]
pub struct Region {
    /// Index into [`ColourTrace::palette`] (0 is transparency).
    pub colour: usize,
    /// Pixels.
    pub area: u64,
}

/// One boundary between two regions (or a region and the transparent outside), fitted
/// once and used by both.
#[derive(Clone, Debug, Serialize)]
pub struct Boundary {
    /// Region on the right of the boundary's direction (y down), `None` for transparency.
    pub right: Option<usize>,
    /// Region on the left.
    pub left: Option<usize>,
    /// Palette index of the colour on the right and on the left (0 for transparency).
    pub colours: [usize; 2],
    /// True for a closed loop without junctions.
    pub closed: bool,
    /// The sub-pixel edge points the segments were fitted to.
    #[serde(skip)]
    pub points: Vec<Point>,
    /// The fitted segments, in order (their `start`/`end` index `points`).
    pub segments: Vec<FittedSegment>,
}

impl Boundary {
    /// Largest point-to-curve distance of its segments.
    pub fn max_distance(&self) -> f64 {
        self.segments
            .iter()
            .map(|s| s.error.max_distance)
            .fold(0.0, f64::max)
    }
}

/// One drawn layer: a colour and its closed loops, each a list of (boundary, forwards).
#[derive(Clone, Debug, Serialize)]
pub struct Layer {
    /// Palette index.
    pub colour: usize,
    /// Closed loops; the layer lies on the right of each.
    pub loops: Vec<Vec<(usize, bool)>>,
}

/// The outcome of a colour trace.
#[derive(Clone, Debug, Serialize)]
pub struct ColourTrace {
    /// Image width (px).
    pub width: u32,
    /// Image height (px).
    pub height: u32,
    /// The palette; index 0 is transparency, never drawn.
    pub palette: Vec<Swatch>,
    /// Pixels whose colour was a mix of two palette colours (anti-aliasing).
    pub mixed_pixels: usize,
    /// The regions.
    pub regions: Vec<Region>,
    /// The boundaries.
    pub boundaries: Vec<Boundary>,
    /// How the layers are drawn.
    pub layout: Layout,
    /// The layers in drawing order.
    pub layers: Vec<Layer>,
    /// The check of the drawn layers against the input.
    pub fidelity: ColourFidelity,
    /// Wall time (s), 0 when timing is off.
    pub seconds: f64,
}

impl ColourTrace {
    /// Segments over all boundaries.
    pub fn segment_count(&self) -> usize {
        self.boundaries.iter().map(|b| b.segments.len()).sum()
    }
}

/// The verdict on a colour trace.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ColourFidelity {
    /// True when no group of far mis-coloured pixels is larger than `region_limit` and
    /// the check ran.
    pub held: bool,
    /// Pixels drawn in another colour than the input's, more than a pixel from any
    /// boundary of the input.
    pub far_pixels: u64,
    /// Area (px²) of the largest 8-connected group of them.
    pub largest_region: f64,
    /// Largest group accepted: max(`--min-area`, 2) px².
    pub region_limit: f64,
    /// Bounding box `[x0, y0, x1, y1]` (pixels, inclusive) of the largest group.
    pub region_box: Option<[u32; 4]>,
    /// Palette index the input has in the largest group, and the one drawn there.
    pub region_colours: Option<[usize; 2]>,
    /// Largest distance (px) from a boundary's edge point to its fitted curve.
    pub max_deviation: f64,
    /// Segments whose largest distance is above `--tolerance` (pieces too short to split).
    pub segments_over_tolerance: usize,
}
