//! A uniform grid of the drawn outline's edges, for nearest-edge queries.

use crate::geom::{floor_i64, segment_distance, Point};

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

/// Every edge of `polylines`, in order.
pub(super) fn all_edges(polylines: &[Vec<Vertex>]) -> impl Iterator<Item = Edge> + '_ {
    polylines
        .iter()
        .enumerate()
        .filter(|(_, line)| line.len() >= 2)
        .flat_map(move |(i, line)| {
            (0..line.len() as u32).map(move |k| edge_of(polylines, (i as u32, k)))
        })
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
        keep: impl Fn(&Edge) -> bool,
    ) -> EdgeGrid<'a> {
        // Counted first, so that the list is allocated at its size (a page has a million
        // edges; growing by doubling would leave up to half of it unused).
        let kept = all_edges(polylines).filter(|e| keep(e)).count();
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(kept);
        edges.extend(
            all_edges(polylines)
                .filter(|e| keep(e))
                .map(|e| (e.contour, e.index)),
        );
        let all_edges = || edges.iter().map(|&e| edge_of(polylines, e));
        let (width, height) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        let origin = Point::new(x0, y0);
        let max_cells = (CELLS_PER_EDGE * edges.len() as f64).max(MIN_CELLS);
        let cell = CELL.max((width * height / max_cells).sqrt());
        let cols = (width / cell).ceil() as i64 + 1;
        let rows = (height / cell).ceil() as i64 + 1;
        let cells = (cols * rows) as usize;
        let range = |e: &Edge| {
            let (a, b) = (e.a - origin, e.b - origin);
            let c0 = floor_i64(a.x.min(b.x) / cell).clamp(0, cols - 1);
            let c1 = floor_i64(a.x.max(b.x) / cell).clamp(0, cols - 1);
            let r0 = floor_i64(a.y.min(b.y) / cell).clamp(0, rows - 1);
            let r1 = floor_i64(a.y.max(b.y) / cell).clamp(0, rows - 1);
            (c0, c1, r0, r1)
        };
        let mut count = vec![0u32; cells + 1];
        for e in all_edges() {
            let (c0, c1, r0, r1) = range(&e);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    count[(r * cols + c) as usize + 1] += 1;
                }
            }
        }
        for k in 0..cells {
            count[k + 1] += count[k];
        }
        let mut items = vec![0u32; count[cells] as usize];
        // `count[cell]` serves as the cell's fill cursor, which ends at the next cell's
        // start; shifting by one afterwards restores the starts.
        for (i, e) in all_edges().enumerate() {
            let (c0, c1, r0, r1) = range(&e);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    let cell = (r * cols + c) as usize;
                    items[count[cell] as usize] = i as u32;
                    count[cell] += 1;
                }
            }
        }
        count.copy_within(0..cells, 1);
        count[0] = 0;
        EdgeGrid {
            polylines,
            edges,
            origin,
            cell,
            cols,
            rows,
            start: count,
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
