//! Colour tracing (`--palette`): flat-colour art as regions whose shared boundaries are
//! fitted once.
//!
//! 1. **Palette and pixels** (`palette`): the flat colours, transparency as a colour of its
//!    own, and every pixel's colour, an anti-aliased pixel taking the colour it is more of.
//! 2. **Planar map** (`map`): regions (4-connected, the ones below `--min-area` joined to
//!    their neighbour), boundaries between two regions from junction to junction.
//! 3. **Edge points** (`edges`): each boundary placed to a fraction of a pixel from the
//!    mixed pixels along it, junctions where the boundaries' lines meet.
//! 4. **Fit** (`fit`): each boundary once, with the breaks and the `lsq` fit of one-colour
//!    outlines; both regions use that same curve, one forwards and one backwards.
//! 5. **Layers**: one per colour, drawn in order of pixel count (largest first). In the
//!    `stacked` layout a colour's layer is the union of its regions with every opaque region
//!    of a later colour connected to them, so each boundary is drawn by the later region
//!    over an earlier one that extends under it — a renderer's anti-aliasing never shows the
//!    background through a seam. In the `cutout` layout each layer is exactly its regions,
//!    and neighbouring layers abut on the same curves (vinyl cutters, screen printing).
//! 6. **Check** (`check`): the drawn layers rasterised at the pixel centres against the
//!    input's colours.
//!
//! `trace` runs the steps (`trace_colour`) and builds the layers; `result` holds what a
//! trace gives; `svg` and `page` write it (SVG; PDF, EPS, PostScript), `report` its JSON and
//! CSV reports.

mod check;
mod edges;
mod fit;
mod map;
mod page;
mod palette;
mod report;
mod result;
mod svg;
mod trace;

pub use page::{colour_pdf, colour_postscript, export_colour};
pub use palette::{PaletteSize, Swatch};
pub use report::{to_csv, write_json};
pub use result::{Boundary, ColourFidelity, ColourOptions, ColourTrace, Layer, Layout, Region};
pub use svg::colour_svg;
pub use trace::{trace_colour, trace_colour_bytes, trace_colour_file};
