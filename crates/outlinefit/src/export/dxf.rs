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
//! options' unit (R2000's `$INSUNITS` says which: unitless for pixels; R12 has no such
//! variable). The R2000 drawing (header, tables, handles, objects) is written by the
//! `dxf` crate; R12 is written here, because the crate puts R2000's subclass markers
//! into R12 tables, which strict readers refuse. R12 needs only a header, the layer
//! table and the entities.

use super::options::{ExportOptions, Unit};
use super::shapes::{drawn_loop, exact_pieces, flatten, holes_of, Drawn, FlipY};
use crate::trace::TraceResult;
use dxf::entities::{Entity, EntityType, Spline};
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
    /// The `dxf` crate failed (it cannot fail on a buffer in memory, but for a missing
    /// source of random bytes when it starts a drawing).
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
    if r12 {
        return Ok(to_dxf_r12(result, opts).into_bytes());
    }
    let flip = FlipY {
        height: f64::from(result.image.height),
        per_pixel: opts.size.unit_per_pixel(),
    };
    let bound = opts.effective_bound();
    // The crate draws random GUIDs for a new drawing (replaced below); where the system
    // has no source of random bytes it panics, which becomes an error here.
    let mut drawing = std::panic::catch_unwind(Drawing::new).map_err(|_| {
        DxfError::Write(
            "the DXF writer found no source of random bytes (/dev/random, /dev/urandom)"
                .to_string(),
        )
    })?;
    drawing.header.version = AcadVersion::R2000;
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
        let Some(pieces) = exact_pieces(contour, merged, bound) else {
            continue;
        };
        let specific = EntityType::Spline(spline(&pieces, &to_point));
        let mut entity = Entity::new(specific);
        entity.common.layer = LAYER.to_string();
        drawing.add_entity(entity);
    }
    let mut out = Vec::new();
    drawing
        .save(&mut out)
        .map_err(|e| DxfError::Write(e.to_string()))?;
    Ok(reproducible(&out))
}

/// The fixed creation and update date written: 1 January 2000, 00:00, as a Julian date.
const FIXED_DATE: &str = "2451544.5";

/// The drawing with the header's time stamps and GUIDs pinned. The `dxf` crate stamps
/// every drawing with the time it was made ($TDCREATE, $TDUPDATE and their UTC twins)
/// and random GUIDs ($FINGERPRINTGUID, $VERSIONGUID), so the same trace would give
/// different bytes at every run; here the dates become [`FIXED_DATE`] and the GUIDs a
/// hash of the entities, so that the same outline gives the same file.
fn reproducible(bytes: &[u8]) -> Vec<u8> {
    let text = String::from_utf8_lossy(bytes);
    let entities = text.find("ENTITIES").map_or("", |k| &text[k..]);
    // FNV-1a, twice with different offsets, for 128 bits; then the UUID version (8,
    // custom) and variant bits.
    let fnv = |offset: u64| {
        entities.bytes().fold(offset, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let mut id =
        (u128::from(fnv(0xcbf2_9ce4_8422_2325)) << 64) | u128::from(fnv(0x6c62_272e_07bb_0142));
    id = (id & !(0xf << 76)) | (0x8 << 76);
    id = (id & !(0x3 << 62)) | (0x2 << 62);
    let hex = format!("{id:032x}");
    let guid = format!(
        "{}-{}-{}-{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    );
    let mut out = String::with_capacity(text.len());
    // Group codes (even lines) and values (odd lines) alternate; a header variable's
    // name is a value, and the value after the next group code is what is pinned.
    let mut pending: Option<&str> = None;
    for (k, line) in text.split_inclusive('\n').enumerate() {
        let value = line.trim_end_matches(['\r', '\n']);
        if k % 2 == 1 {
            if let Some(new) = pending.take() {
                out.push_str(new);
                out.push_str(&line[value.len()..]);
                continue;
            }
            pending = match value {
                "$TDCREATE" | "$TDUCREATE" | "$TDUPDATE" | "$TDUUPDATE" => Some(FIXED_DATE),
                "$FINGERPRINTGUID" | "$VERSIONGUID" => Some(guid.as_str()),
                _ => None,
            };
        }
        out.push_str(line);
    }
    out.into_bytes()
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

/// The R12 drawing: closed polylines in the layer [`LAYER`], written as group codes.
fn to_dxf_r12(result: &TraceResult, opts: &ExportOptions) -> String {
    let flip = FlipY {
        height: f64::from(result.image.height),
        per_pixel: opts.size.unit_per_pixel(),
    };
    let bound = opts.effective_bound();
    let straight = opts.half_unit();
    let precision = opts.precision_in(opts.size.unit);
    let n = |x: f64| crate::svg_writer::number(x, precision);
    let (w, h) = (
        f64::from(result.image.width) * flip.per_pixel,
        f64::from(result.image.height) * flip.per_pixel,
    );
    let mut out = String::new();
    let mut pair = |code: u32, value: &str| {
        // CR LF, as AutoCAD writes (and the R2000 writer does).
        out.push_str(&format!("{code:>3}\r\n{value}\r\n"));
    };
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$ACADVER");
    pair(1, "AC1009");
    for (name, x, y) in [
        ("$EXTMIN", 0.0, 0.0),
        ("$EXTMAX", w, h),
        ("$LIMMIN", 0.0, 0.0),
        ("$LIMMAX", w, h),
    ] {
        pair(9, name);
        pair(10, &n(x));
        pair(20, &n(y));
    }
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "TABLES");
    pair(0, "TABLE");
    pair(2, "LTYPE");
    pair(70, "1");
    pair(0, "LTYPE");
    pair(2, "CONTINUOUS");
    pair(70, "0");
    pair(3, "Solid line");
    pair(72, "65");
    pair(73, "0");
    pair(40, "0.0");
    pair(0, "ENDTAB");
    pair(0, "TABLE");
    pair(2, "LAYER");
    pair(70, "1");
    pair(0, "LAYER");
    pair(2, LAYER);
    pair(70, "0");
    pair(62, "7");
    pair(6, "CONTINUOUS");
    pair(0, "ENDTAB");
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    let (_, orphans) = holes_of(result);
    for (i, contour) in result.contours.iter().enumerate() {
        if orphans.contains(&i) {
            continue;
        }
        let Drawn::Loop(l) = drawn_loop(contour, result.merged_of(i), bound, straight) else {
            continue;
        };
        pair(0, "POLYLINE");
        pair(8, LAYER);
        pair(66, "1");
        pair(10, "0.0");
        pair(20, "0.0");
        pair(30, "0.0");
        pair(70, "1");
        for p in flatten(&l, bound) {
            let q = flip.apply(p);
            pair(0, "VERTEX");
            pair(8, LAYER);
            pair(10, &n(q.x));
            pair(20, &n(q.y));
            pair(30, "0.0");
        }
        pair(0, "SEQEND");
        pair(8, LAYER);
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    out
}
