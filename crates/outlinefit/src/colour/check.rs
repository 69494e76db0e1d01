//! The check of a colour trace against its input: every layer's drawn path (the cubics the
//! SVG writes, flattened within `fidelity::FLATTEN_ERROR`) is filled at the pixel centres
//! (even-odd, in drawing order, so each pixel gets the colour drawn last over it) and
//! compared with the colour every pixel was given. A pixel drawn in another colour that is
//! more than a pixel away from every boundary of the input's colours is *far*: at a
//! boundary a pixel's centre may fall on either side, farther it may not. Far pixels are
//! grouped 8-connected; a group larger than max(`--min-area`, 2) px² is a lost, invented or
//! mis-coloured part and the check fails, naming the largest.

use super::result::{ColourFidelity, ColourTrace};
use super::svg::loop_pieces;
use crate::fidelity::flatten_steps;
use crate::geom::Point;
use crate::trace::Config;

/// Fills the flattened `loops` at pixel centres with `value` (even-odd).
fn fill(loops: &[Vec<Point>], w: usize, h: usize, value: u16, out: &mut [u16]) {
    let mut rows: Vec<Vec<f64>> = vec![Vec::new(); h];
    for lp in loops {
        let n = lp.len();
        for i in 0..n {
            let (p, q) = (lp[i], lp[(i + 1) % n]);
            if p.y == q.y {
                continue;
            }
            let (lo, hi) = if p.y < q.y { (p, q) } else { (q, p) };
            // Rows whose centre y + 0.5 lies in [lo.y, hi.y).
            let first = (lo.y - 0.5).ceil().max(0.0) as usize;
            let last = ((hi.y - 0.5).ceil().min(h as f64)).max(0.0) as usize;
            for (y, row) in rows.iter_mut().enumerate().take(last).skip(first) {
                let cy = y as f64 + 0.5;
                row.push(lo.x + (cy - lo.y) / (hi.y - lo.y) * (hi.x - lo.x));
            }
        }
    }
    for (y, row) in rows.iter_mut().enumerate() {
        row.sort_by(f64::total_cmp);
        for pair in row.chunks_exact(2) {
            let a = (pair[0] - 0.5).ceil().max(0.0) as usize;
            let b = ((pair[1] - 0.5).ceil().min(w as f64)).max(0.0) as usize;
            for x in a..b {
                out[y * w + x] = value;
            }
        }
    }
}

/// The colour drawn at every pixel centre (0 where nothing is drawn).
pub(crate) fn drawn_colours(trace: &ColourTrace, bound: f64) -> Vec<u16> {
    let (w, h) = (trace.width as usize, trace.height as usize);
    let mut drawn = vec![0u16; w * h];
    for layer in &trace.layers {
        let loops: Vec<Vec<Point>> = layer
            .loops
            .iter()
            .map(|lp| {
                let mut pts = Vec::new();
                for (_, cubics) in loop_pieces(trace, lp, bound) {
                    for c in &cubics {
                        let n = flatten_steps(c);
                        pts.extend((0..n).map(|k| c.eval(k as f64 / n as f64)));
                    }
                    // The end of the last cubic (the loop closes from there).
                    pts.extend(cubics.last().map(|c| c.points[3]));
                }
                pts
            })
            .collect();
        fill(&loops, w, h, layer.colour as u16, &mut drawn);
    }
    drawn
}

/// Checks `trace` against the pixels' colours `label` (see the module docs).
pub(crate) fn check(
    trace: &ColourTrace,
    label: &[u16],
    config: &Config,
    bound: f64,
) -> ColourFidelity {
    let (w, h) = (trace.width as usize, trace.height as usize);
    let drawn = drawn_colours(trace, bound);
    let near_boundary = |i: usize| {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        (-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                let (cx, cy) = (x + dx, y + dy);
                cx >= 0
                    && cy >= 0
                    && cx < w as i64
                    && cy < h as i64
                    && label[cy as usize * w + cx as usize] != label[i]
            })
        })
    };
    let far: std::collections::HashSet<usize> = (0..w * h)
        .filter(|&i| drawn[i] != label[i] && !near_boundary(i))
        .collect();
    let groups = crate::geom::groups_8(&far, w, h);
    let largest = groups.iter().max_by_key(|g| g.len());
    let region_limit = config.min_area.max(2.0);
    let largest_region = largest.map_or(0.0, |g| g.len() as f64);
    let region_box = largest.map(|g| {
        let xs = g.iter().map(|&i| (i % w) as u32);
        let ys = g.iter().map(|&i| (i / w) as u32);
        [
            xs.clone().min().unwrap_or(0),
            ys.clone().min().unwrap_or(0),
            xs.max().unwrap_or(0),
            ys.max().unwrap_or(0),
        ]
    });
    let region_colours = largest.map(|g| [usize::from(label[g[0]]), usize::from(drawn[g[0]])]);
    let distances = trace
        .boundaries
        .iter()
        .flat_map(|b| &b.segments)
        .map(|s| s.error.max_distance);
    let max_deviation = distances.clone().fold(0.0, f64::max);
    let segments_over_tolerance = distances.filter(|&d| d > config.tolerance).count();
    ColourFidelity {
        held: largest_region <= region_limit,
        far_pixels: far.len() as u64,
        largest_region,
        region_limit,
        region_box,
        region_colours,
        max_deviation,
        segments_over_tolerance,
    }
}
