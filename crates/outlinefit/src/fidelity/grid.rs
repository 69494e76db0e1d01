//! A uniform grid of the drawn outline's edges, for nearest-edge queries.

use crate::geom::{floor_i64, segment_distance, Point};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

/// Cell size (px) of the spatial grid of drawn edges: small, so that a query looks at few
/// edges, but the grid never holds more than `CELLS_PER_EDGE` cells per edge.
const CELL: f64 = 2.0;
/// Most cells of the edge grid per drawn edge (and at least `MIN_CELLS`): the grid's
/// memory follows the outline's length, not the image's area (a 4096 px image with a
/// simple outline would otherwise spend 4 bytes per pixel on mostly empty cells). One cell
/// per edge: on the 600 dpi scan (a million edges) the cells are then 5.9 px wide and the
/// grid takes 11 MB less than with four (3 px cells), for the same check time; a query
/// looks at more edges per cell but at fewer cells.
const CELLS_PER_EDGE: f64 = 1.0;
/// Fewest cells the grid is allowed to shrink to.
const MIN_CELLS: f64 = 4096.0;

/// An edge of the flattened drawn outline (a copy of its end points).
#[derive(Clone, Copy, Debug)]
pub(super) struct Edge {
    pub(super) a: Point,
    pub(super) b: Point,
    pub(super) contour: u32,
    /// Index of its first point in the contour's polyline.
    pub(super) index: u32,
}

/// A vertex of the flattened drawn outline, in single precision: the check compares the
/// outline with pixels at tenths of a pixel, and a coordinate of a page 10 000 px wide is
/// kept to 0.001 px, while the outline of a 600 dpi page takes half the memory (7 MB less).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Vertex {
    x: f32,
    y: f32,
}

impl Vertex {
    /// `p` rounded to single precision.
    #[inline]
    pub(super) fn new(p: Point) -> Vertex {
        Vertex {
            x: p.x as f32,
            y: p.y as f32,
        }
    }

    /// The vertex as a point.
    #[inline]
    pub(super) fn point(self) -> Point {
        Point::new(f64::from(self.x), f64::from(self.y))
    }

    /// True when both coordinates are finite.
    pub(super) fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl From<Vertex> for Point {
    fn from(v: Vertex) -> Point {
        v.point()
    }
}

/// Edge `k` of polyline `contour` (from point k to the next, closing the loop).
#[inline]
pub(super) fn edge_of(polylines: &[Vec<Vertex>], (contour, k): (u32, u32)) -> Edge {
    let line = &polylines[contour as usize];
    let k = k as usize;
    // The next point, wrapping at the end (a compare, not a division: this runs for
    // every edge looked at).
    let next = if k + 1 == line.len() { 0 } else { k + 1 };
    Edge {
        a: line[k].point(),
        b: line[next].point(),
        contour,
        index: k as u32,
    }
}

/// Fewest polyline points for which the grid is built on the thread pool (a page of text
/// has a million; a glyph a few hundred, where handing out work costs more than it
/// saves).
const PARALLEL_EDGES: usize = 50_000;

/// The edges of `polylines` that `keep` accepts, as (contour, index) keys in contour
/// order. Counted first, so that the list is allocated at its size (a page has a million
/// edges; growing by doubling would leave up to half of it unused); on a large outline
/// each contour's keys are counted and written on the thread pool, into its own part of
/// the list.
fn kept_edges(
    polylines: &[Vec<Vertex>],
    keep: &(impl Fn(&Edge) -> bool + Sync),
    parallel: bool,
) -> Vec<(u32, u32)> {
    let line_edges = |i: usize| {
        let n = if polylines[i].len() >= 2 {
            polylines[i].len() as u32
        } else {
            0
        };
        (0..n)
            .map(move |k| edge_of(polylines, (i as u32, k)))
            .filter(|e| keep(e))
            .map(|e| (e.contour, e.index))
    };
    if !parallel {
        let kept = (0..polylines.len()).map(|i| line_edges(i).count()).sum();
        let mut edges = Vec::with_capacity(kept);
        edges.extend((0..polylines.len()).flat_map(line_edges));
        return edges;
    }
    let counts: Vec<usize> = (0..polylines.len())
        .into_par_iter()
        .map(|i| line_edges(i).count())
        .collect();
    let mut edges = vec![(0u32, 0u32); counts.iter().sum()];
    let mut parts = Vec::with_capacity(counts.len());
    let mut rest = edges.as_mut_slice();
    for &k in &counts {
        let (part, tail) = rest.split_at_mut(k);
        parts.push(part);
        rest = tail;
    }
    parts.into_par_iter().enumerate().for_each(|(i, part)| {
        for (slot, key) in part.iter_mut().zip(line_edges(i)) {
            *slot = key;
        }
    });
    edges
}

/// The compressed rows of the grid (`start`, `items`) on one thread: each edge's index
/// listed in every cell `cells_of` gives for it, in edge order.
fn fill_serial<I: Iterator<Item = usize>>(
    edges: &[(u32, u32)],
    cells: usize,
    cells_of: impl Fn((u32, u32)) -> I,
) -> (Vec<u32>, Vec<u32>) {
    let mut count = vec![0u32; cells + 1];
    for &key in edges {
        for cell in cells_of(key) {
            count[cell + 1] += 1;
        }
    }
    for k in 0..cells {
        count[k + 1] += count[k];
    }
    let mut items = vec![0u32; count[cells] as usize];
    // `count[cell]` serves as the cell's fill cursor, which ends at the next cell's
    // start; shifting by one afterwards restores the starts.
    for (i, &key) in edges.iter().enumerate() {
        for cell in cells_of(key) {
            items[count[cell] as usize] = i as u32;
            count[cell] += 1;
        }
    }
    count.copy_within(0..cells, 1);
    count[0] = 0;
    (count, items)
}

/// [`fill_serial`] on the thread pool: the counts and the fill cursors are atomic, so a
/// cell's edges may be listed in any order. No query depends on that order (the nearest
/// edge breaks ties by its key, `any_within` answers yes or no), so every answer is the
/// same on any number of threads.
fn fill_parallel<I: Iterator<Item = usize>>(
    edges: &[(u32, u32)],
    cells: usize,
    cells_of: impl Fn((u32, u32)) -> I + Sync,
) -> (Vec<u32>, Vec<u32>) {
    let mut count: Vec<AtomicU32> = (0..=cells).map(|_| AtomicU32::new(0)).collect();
    edges.par_iter().for_each(|&key| {
        for cell in cells_of(key) {
            count[cell + 1].fetch_add(1, Relaxed);
        }
    });
    for k in 0..cells {
        let before = *count[k].get_mut();
        *count[k + 1].get_mut() += before;
    }
    let total = *count[cells].get_mut() as usize;
    let items: Vec<AtomicU32> = (0..total).map(|_| AtomicU32::new(0)).collect();
    edges.par_iter().enumerate().for_each(|(i, &key)| {
        for cell in cells_of(key) {
            let slot = count[cell].fetch_add(1, Relaxed);
            items[slot as usize].store(i as u32, Relaxed);
        }
    });
    // Collected in place: the atomics' memory becomes the plain lists'.
    let mut count: Vec<u32> = count.into_iter().map(AtomicU32::into_inner).collect();
    let items: Vec<u32> = items.into_iter().map(AtomicU32::into_inner).collect();
    count.copy_within(0..cells, 1);
    count[0] = 0;
    (count, items)
}

/// A uniform grid of edges over a box (compressed rows: `start[cell]..start[cell + 1]`
/// index `items`). Edges beyond the box are listed in its border cells.
pub(super) struct EdgeGrid<'a> {
    polylines: &'a [Vec<Vertex>],
    /// Every edge as (contour, index of its first point): 8 bytes instead of a copy of
    /// its end points (a text page at 600 dpi has millions).
    edges: Vec<(u32, u32)>,
    origin: Point,
    cell: f64,
    cols: i64,
    rows: i64,
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> EdgeGrid<'a> {
    /// The grid over the box `[x0, y0, x1, y1]` of the edges of `polylines` that `keep`
    /// accepts: a query at a point `p` is exact for every edge it accepts, so a grid of
    /// the edges within `r` of a region answers queries of reach `r` from inside it.
    pub(super) fn new(
        polylines: &'a [Vec<Vertex>],
        [x0, y0, x1, y1]: [f64; 4],
        keep: impl Fn(&Edge) -> bool + Sync,
    ) -> EdgeGrid<'a> {
        let parallel = polylines.iter().map(Vec::len).sum::<usize>() >= PARALLEL_EDGES;
        let edges = kept_edges(polylines, &keep, parallel);
        let (width, height) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        let origin = Point::new(x0, y0);
        let max_cells = (CELLS_PER_EDGE * edges.len() as f64).max(MIN_CELLS);
        let cell = CELL.max((width * height / max_cells).sqrt());
        let cols = (width / cell).ceil() as i64 + 1;
        let rows = (height / cell).ceil() as i64 + 1;
        let cells = (cols * rows) as usize;
        // The cells an edge is listed in: those its bounding box touches.
        let cells_of = |key: (u32, u32)| {
            let e = edge_of(polylines, key);
            let (a, b) = (e.a - origin, e.b - origin);
            let c0 = floor_i64(a.x.min(b.x) / cell).clamp(0, cols - 1);
            let c1 = floor_i64(a.x.max(b.x) / cell).clamp(0, cols - 1);
            let r0 = floor_i64(a.y.min(b.y) / cell).clamp(0, rows - 1);
            let r1 = floor_i64(a.y.max(b.y) / cell).clamp(0, rows - 1);
            (r0..=r1).flat_map(move |r| (c0..=c1).map(move |c| (r * cols + c) as usize))
        };
        let (start, items) = if parallel {
            fill_parallel(&edges, cells, cells_of)
        } else {
            fill_serial(&edges, cells, cells_of)
        };
        EdgeGrid {
            polylines,
            edges,
            origin,
            cell,
            cols,
            rows,
            start,
            items,
        }
    }

    /// The edge with end points copied out.
    #[inline]
    fn edge(&self, e: (u32, u32)) -> Edge {
        edge_of(self.polylines, e)
    }

    /// Nearest edge to `p` within `reach` px (of contour `only`, if given): distance and
    /// contour, or `None` when there is none that close. Cells are searched ring by ring
    /// outwards from `p`'s own, and the search stops once the best distance found is
    /// below what any further ring could hold. (Edges beyond the grid are listed in its
    /// border cells, nearer to a point inside; for a point outside, the rings before the
    /// grid are empty, so nothing is skipped until the grid is reached.)
    pub(super) fn nearest(
        &self,
        p: Point,
        reach: f64,
        only: Option<u32>,
    ) -> Option<(f64, (u32, u32))> {
        let q = p - self.origin;
        let c = floor_i64(q.x / self.cell);
        let r = floor_i64(q.y / self.cell);
        let k = (reach / self.cell).ceil() as i64;
        // Ring j ≥ 1 lies outside the block of rings below it, at least (j − 1) cells
        // plus `margin` (the distance from `p` to its own cell's sides) away.
        let (fx, fy) = (q.x - c as f64 * self.cell, q.y - r as f64 * self.cell);
        let margin = (fx.min(self.cell - fx).min(fy).min(self.cell - fy) - 1e-9).max(0.0);
        let mut best: Option<(f64, (u32, u32))> = None;
        for ring in 0..=k {
            if ring > 0 && best.is_some_and(|(d, _)| d <= (ring - 1) as f64 * self.cell + margin) {
                break;
            }
            for row in r - ring..=r + ring {
                // The ring's cells on this row: all of it on the top and bottom rows, its
                // two ends otherwise.
                let step = if (row - r).abs() == ring { 1 } else { 2 * ring };
                for col in (c - ring..=c + ring).step_by(step.max(1) as usize) {
                    for &key in self.cell_keys(row, col) {
                        if only.is_some_and(|o| o != key.0) {
                            continue;
                        }
                        let e = self.edge(key);
                        let d = segment_distance(p, e.a, e.b);
                        // Ties go to the first edge in contour order, whatever the
                        // order the cells are visited in.
                        if d <= reach && best.is_none_or(|(bd, bk)| d < bd || (d == bd && key < bk))
                        {
                            best = Some((d, key));
                        }
                    }
                }
            }
        }
        best
    }

    /// The edges listed in cell (`row`, `col`) as (contour, index) keys; none outside the
    /// grid.
    fn cell_keys(&self, row: i64, col: i64) -> impl Iterator<Item = &(u32, u32)> + '_ {
        let inside = (0..self.rows).contains(&row) && (0..self.cols).contains(&col);
        let items = if inside {
            let cell = (row * self.cols + col) as usize;
            &self.items[self.start[cell] as usize..self.start[cell + 1] as usize]
        } else {
            &[]
        };
        items.iter().map(|&i| &self.edges[i as usize])
    }

    /// The edges listed in cell (`row`, `col`); none outside the grid.
    fn cell_edges(&self, row: i64, col: i64) -> impl Iterator<Item = Edge> + '_ {
        self.cell_keys(row, col).map(|&key| self.edge(key))
    }

    /// True when some edge lies within `reach` px of `p` (stops at the first).
    pub(super) fn any_within(&self, p: Point, reach: f64) -> bool {
        let q = p - self.origin;
        let c = floor_i64(q.x / self.cell);
        let r = floor_i64(q.y / self.cell);
        let k = (reach / self.cell).ceil() as i64;
        for row in (r - k).max(0)..=(r + k).min(self.rows - 1) {
            for col in (c - k).max(0)..=(c + k).min(self.cols - 1) {
                if self
                    .cell_edges(row, col)
                    .any(|e| segment_distance(p, e.a, e.b) <= reach)
                {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// `count` closed random polygons of 3 to 40 vertices scattered over a `w` × `h` box.
    fn random_polylines(count: usize, w: f64, h: f64, seed: u64) -> Vec<Vec<Vertex>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..count)
            .map(|_| {
                let (cx, cy) = (rng.random_range(0.0..w), rng.random_range(0.0..h));
                let n = rng.random_range(3..40);
                (0..n)
                    .map(|k| {
                        let a = k as f64 / n as f64 * std::f64::consts::TAU;
                        let r = rng.random_range(2.0..12.0);
                        Vertex::new(Point::new(cx + r * a.cos(), cy + r * a.sin()))
                    })
                    .collect()
            })
            .collect()
    }

    /// The parallel fill lists every edge in exactly the cells the serial one does (in
    /// any order within a cell), with the same cell starts.
    #[test]
    fn parallel_fill_lists_the_same_edges_per_cell() {
        let lines = random_polylines(3000, 900.0, 700.0, 5);
        let edges = kept_edges(&lines, &|_: &Edge| true, true);
        assert_eq!(edges, kept_edges(&lines, &|_: &Edge| true, false));
        let keep_odd = |e: &Edge| e.index % 2 == 1;
        assert_eq!(
            kept_edges(&lines, &keep_odd, true),
            kept_edges(&lines, &keep_odd, false)
        );
        let (cols, cell) = (100usize, 9.0);
        let cells_of = |key: (u32, u32)| {
            let e = edge_of(&lines, key);
            let c0 = (e.a.x.min(e.b.x) / cell).clamp(0.0, 99.0) as usize;
            let c1 = (e.a.x.max(e.b.x) / cell).clamp(0.0, 99.0) as usize;
            let r0 = (e.a.y.min(e.b.y) / cell).clamp(0.0, 79.0) as usize;
            let r1 = (e.a.y.max(e.b.y) / cell).clamp(0.0, 79.0) as usize;
            (r0..=r1).flat_map(move |r| (c0..=c1).map(move |c| r * cols + c))
        };
        let cells = cols * 80;
        let (start_s, items_s) = fill_serial(&edges, cells, cells_of);
        let (start_p, items_p) = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| fill_parallel(&edges, cells, cells_of));
        assert_eq!(start_s, start_p);
        assert!(items_s.len() > edges.len());
        for c in 0..cells {
            let range = start_s[c] as usize..start_s[c + 1] as usize;
            let mut p = items_p[range.clone()].to_vec();
            p.sort_unstable();
            assert_eq!(items_s[range], p[..], "cell {c}");
        }
    }

    /// On an outline large enough to be gridded in parallel, the nearest edge of every
    /// query is the one a search of all edges finds (distance and key), and
    /// `any_within` agrees with it.
    #[test]
    fn parallel_grid_finds_the_nearest_edge() {
        let lines = random_polylines(2500, 800.0, 600.0, 11);
        let points: usize = lines.iter().map(Vec::len).sum();
        assert!(points >= PARALLEL_EDGES, "{points}");
        let grid = EdgeGrid::new(&lines, [0.0, 0.0, 800.0, 600.0], |_| true);
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for _ in 0..300 {
            let p = Point::new(rng.random_range(-5.0..805.0), rng.random_range(-5.0..605.0));
            let mut best: Option<(f64, (u32, u32))> = None;
            for (i, line) in lines.iter().enumerate() {
                for k in 0..line.len() as u32 {
                    let e = edge_of(&lines, (i as u32, k));
                    let d = segment_distance(p, e.a, e.b);
                    if d <= 6.0 && best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, (i as u32, k)));
                    }
                }
            }
            assert_eq!(grid.nearest(p, 6.0, None), best, "{p:?}");
            assert_eq!(grid.any_within(p, 6.0), best.is_some(), "{p:?}");
        }
    }
}
