//! A colour trace as an SVG document: one `<g>` per colour, in drawing order, named by its
//! colour (`id="colour-ea5a47"`) and filled with it (`fill-opacity` where the input's colour
//! was translucent), holding one `<path>` with the layer's loops (`fill-rule="evenodd"`).
//! Each boundary is drawn from the same cubics wherever it appears (forwards for one region,
//! backwards for the other), written in the compact relative syntax of the one-colour SVG.

use super::result::ColourTrace;
use crate::curve::CubicBez;
use crate::export::options::ExportOptions;
use crate::export::svg::{pieces_path_data, scaled_document};
use crate::geom::Point;
use crate::svg_writer::{grid_per_unit, number, Group, Path, PathUnits};

/// The cubics that draw boundary `b` of `trace`, forwards or backwards.
pub(crate) fn boundary_cubics(
    trace: &ColourTrace,
    b: usize,
    forwards: bool,
    bound: f64,
) -> Vec<CubicBez> {
    let mut cubics: Vec<CubicBez> = trace.boundaries[b]
        .segments
        .iter()
        .flat_map(|s| s.drawn_cubics(bound).into_owned())
        .collect();
    if !forwards {
        cubics.reverse();
        for c in &mut cubics {
            c.points.reverse();
        }
    }
    cubics
}

/// The cubics of one loop of a layer, as one piece (start point, cubics): its boundaries
/// in turn, consecutive straight cubics on one line joined into one (a boundary along the
/// image border or a straight edge cut at a junction is one line when drawn), and a last
/// straight cubic back to the start left to the closing `z`.
pub(crate) fn loop_pieces(
    trace: &ColourTrace,
    lp: &[(usize, bool)],
    bound: f64,
) -> Vec<(Point, Vec<CubicBez>)> {
    let mut cubics: Vec<CubicBez> = Vec::new();
    for &(b, fwd) in lp {
        for c in boundary_cubics(trace, b, fwd, bound) {
            match cubics.last_mut() {
                Some(last) if same_line(last, &c) => {
                    let (p, q) = (last.points[0], c.points[3]);
                    *last = CubicBez {
                        points: [p, p.lerp(q, 1.0 / 3.0), p.lerp(q, 2.0 / 3.0), q],
                    };
                }
                _ => cubics.push(c),
            }
        }
    }
    // A closing straight line is what `z` (and a fill) draws anyway.
    if cubics.len() > 2 && is_line(&cubics[cubics.len() - 1]) {
        cubics.pop();
    }
    match cubics.first() {
        Some(first) => vec![(first.points[0], cubics)],
        None => Vec::new(),
    }
}

/// True when every control point of `c` lies on its chord.
fn is_line(c: &CubicBez) -> bool {
    let (p, q) = (c.points[0], c.points[3]);
    (q - p).normalized().is_some_and(|dir| {
        c.points
            .iter()
            .all(|&x| (x - p).cross(dir).abs() <= ON_LINE)
    })
}

/// Largest distance (px) from a line at which a cubic counts as lying on it.
const ON_LINE: f64 = 1e-6;

/// True when `a` and `b` (which follows it) are straight and run on along one line.
fn same_line(a: &CubicBez, b: &CubicBez) -> bool {
    let (p, q) = (a.points[0], b.points[3]);
    let Some(dir) = (q - p).normalized() else {
        return false;
    };
    let off = |x: Point| (x - p).cross(dir).abs();
    a.points.iter().chain(&b.points).all(|&x| off(x) <= ON_LINE)
        && a.points
            .windows(2)
            .chain(b.points.windows(2))
            .all(|w| (w[1] - w[0]).dot(dir) >= 0.0)
}

/// Writes a colour trace as SVG (see the module docs). Deterministic.
pub fn colour_svg(trace: &ColourTrace, opts: &ExportOptions) -> String {
    let precision = opts.effective_precision();
    let bound = opts.effective_bound();
    let grid = grid_per_unit(precision);
    let mut doc = scaled_document(trace.width, trace.height, opts, grid);
    let mut used_ids = std::collections::HashSet::new();
    for layer in &trace.layers {
        let swatch = &trace.palette[layer.colour];
        let mut data = String::new();
        for lp in &layer.loops {
            let pieces = loop_pieces(trace, lp, bound);
            let finite = pieces
                .iter()
                .all(|(_, cs)| cs.iter().all(|c| c.points.iter().all(|p| p.is_finite())));
            if pieces.is_empty() {
                continue;
            }
            if !finite {
                doc.comment(&format!(
                    "a loop of colour {} skipped: non-finite coordinates",
                    swatch.hex()
                ));
                continue;
            }
            data.push_str(&pieces_path_data(&pieces, precision, PathUnits::Grid));
        }
        if data.is_empty() {
            continue;
        }
        let hex = swatch.hex();
        let mut id = format!("colour-{}", &hex[1..]);
        if swatch.alpha < 255 {
            id.push_str(&format!("-{:02x}", swatch.alpha));
        }
        if !used_ids.insert(id.clone()) {
            id.push_str(&format!("-{}", layer.colour));
        }
        let path = if opts.stroke_only {
            Path::new()
                .set("fill", "none")
                .set("stroke", hex.as_str())
                .set(
                    "stroke-width",
                    number(crate::export::svg::STROKE_WIDTH * grid, 0),
                )
                .set("d", data)
        } else {
            Path::new().set("fill-rule", "evenodd").set("d", data)
        };
        let mut group = Group::new().set("id", id);
        if !opts.stroke_only {
            group = group.set("fill", hex.as_str());
        }
        if swatch.alpha < 255 {
            group = group.set("fill-opacity", number(f64::from(swatch.alpha) / 255.0, 3));
        }
        doc.add(group.add(path));
    }
    doc.finish()
}
