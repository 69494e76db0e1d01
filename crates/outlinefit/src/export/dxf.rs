//! The outline as a DXF drawing, for CAD, laser and CNC software.
//!
//! * **R2000** (`AC1015`, [`Format::Dxf`](super::Format::Dxf)): each closed contour is one
//!   `SPLINE` entity of degree 3 that holds its rational cubics exactly: control points
//!   C0 C1 C2 C3 C1' C2' C3' … (each joint once), weights 1 w1 w2 1 w1' w2' 1 …, and the
//!   clamped knot vector 0 0 0 0 1 1 1 2 2 2 … n n n n, whose knots of multiplicity 3 at
//!   every joint make each span exactly one segment's rational Bézier curve. The last
//!   control point is the first, so the spline is a closed loop. A merged Wang–Ball run
//!   (`--merge`) is written as the polynomial cubics that draw it, within the bound.
//! * **R12** (`AC1009`, [`Format::DxfR12`](super::Format::DxfR12)), for older software
//!   that has no splines: each contour is a closed `POLYLINE`, the drawn cubics flattened
//!   within the bound (so within twice the bound of the fitted curves).
//!
//! Holes are loops of their own, in the same layer as their outer borders (`outline`);
//! coordinates have y up and the origin at the image's bottom-left corner, in the
//! options' unit (`$INSUNITS` says which: unitless for pixels). The drawing itself
//! (header, tables, handles) is written by the `dxf` crate.

use super::options::{ExportOptions, Unit};
use super::shapes::{drawn_loop, exact_pieces, flatten, holes_of, Drawn, FlipY};
use crate::trace::TraceResult;
use dxf::entities::{Entity, EntityType, Polyline, Spline, Vertex};
use dxf::enums::{AcadVersion, Units};
use dxf::tables::Layer;
use dxf::{Color, Drawing, Point};

/// The layer every outline is drawn in.
pub const LAYER: &str = "outline";

/// Why a drawing could not be written.
#[derive(Debug)]
pub(crate) enum DxfError {
    /// DXF has no unit for it.
    Unit(Unit),
    /// The `dxf` crate failed.
    Write(String),
}

/// Writes the outline as a DXF drawing (see the module docs); `r12` picks the old flavour.
pub(crate) fn to_dxf(
    result: &TraceResult,
    opts: &ExportOptions,
    r12: bool,
) -> Result<Vec<u8>, DxfError> {
    let units = match opts.size.unit {
        Unit::Px => Units::Unitless,
        Unit::Mm => Units::Millimeters,
        Unit::Cm => Units::Centimeters,
        Unit::In => Units::Inches,
        Unit::Pt => return Err(DxfError::Unit(Unit::Pt)),
    };
    let flip = FlipY {
        height: f64::from(result.image.height),
        per_pixel: opts.size.unit_per_pixel(),
    };
    let bound = opts.effective_bound();
    let mut drawing = Drawing::new();
    drawing.header.version = if r12 {
        AcadVersion::R12
    } else {
        AcadVersion::R2000
    };
    drawing.header.default_drawing_units = units;
    let w = f64::from(result.image.width) * flip.per_pixel;
    let h = f64::from(result.image.height) * flip.per_pixel;
    drawing.header.minimum_drawing_extents = Point::new(0.0, 0.0, 0.0);
    drawing.header.maximum_drawing_extents = Point::new(w, h, 0.0);
    drawing.header.minimum_drawing_limits = dxf::Point::new(0.0, 0.0, 0.0);
    drawing.header.maximum_drawing_limits = dxf::Point::new(w, h, 0.0);
    drawing.add_layer(Layer {
        name: LAYER.to_string(),
        color: Color::from_index(7),
        ..Default::default()
    });
    let to_point = |p: crate::geom::Point| {
        let q = flip.apply(p);
        Point::new(q.x, q.y, 0.0)
    };
    // A hole without its outer border would read as a shape of its own: left out, as
    // in every format.
    let (_, orphans) = holes_of(result);
    for (i, contour) in result.contours.iter().enumerate() {
        if orphans.contains(&i) {
            continue;
        }
        let merged = result.merged_of(i);
        let specific = if r12 {
            let straight = 0.5 * 10f64.powi(-(opts.effective_precision() as i32));
            let Drawn::Loop(l) = drawn_loop(contour, merged, bound, straight) else {
                continue;
            };
            let mut polyline = Polyline::default();
            polyline.set_is_closed(true);
            for p in flatten(&l, bound) {
                polyline.add_vertex(&mut drawing, Vertex::new(to_point(p)));
            }
            EntityType::Polyline(polyline)
        } else {
            let Some(pieces) = exact_pieces(contour, merged, bound) else {
                continue;
            };
            EntityType::Spline(spline(&pieces, &to_point))
        };
        let mut entity = Entity::new(specific);
        entity.common.layer = LAYER.to_string();
        drawing.add_entity(entity);
    }
    let mut out = Vec::new();
    drawing
        .save(&mut out)
        .map_err(|e| DxfError::Write(e.to_string()))?;
    Ok(out)
}

/// The closed chain of rational cubics as one exact degree-3 spline.
fn spline(
    pieces: &[crate::curve::RationalCubic],
    to_point: &dyn Fn(crate::geom::Point) -> Point,
) -> Spline {
    let n = pieces.len();
    let mut s = Spline {
        degree_of_curve: 3,
        normal: dxf::Vector::z_axis(),
        ..Default::default()
    };
    s.set_is_rational(true);
    s.set_is_planar(true);
    s.control_points.push(to_point(pieces[0].points[0]));
    s.weight_values.push(1.0);
    for c in pieces {
        for (k, p) in c.points[1..].iter().enumerate() {
            s.control_points.push(to_point(*p));
            s.weight_values.push(if k < 2 { c.weights[k] } else { 1.0 });
        }
    }
    s.knot_values = std::iter::repeat_n(0.0, 4)
        .chain((1..n).flat_map(|k| std::iter::repeat_n(k as f64, 3)))
        .chain(std::iter::repeat_n(n as f64, 4))
        .collect();
    s
}
