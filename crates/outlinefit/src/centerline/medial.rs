//! The sub-pixel centre and radius of a stroke at a skeleton point, from the traced
//! boundary: the boundary's closed polygons (sub-pixel on anti-aliased input, as for
//! outlines) are put in a grid of cells, and a point is moved along the stroke's normal
//! until its distances to the boundary on the two sides are equal; the radius is then that
//! distance.

use crate::geom::Point;

/// Side of a grid cell, px.
const CELL: f64 = 4.0;

/// The boundary's edges, bucketed by cell.
pub(crate) struct BoundaryIndex {
    edges: Vec<(Point, Point)>,
    cells: Vec<Vec<u32>>,
    columns: usize,
    rows: usize,
}

impl BoundaryIndex {
    /// Indexes the edges of closed polygons covering a `width` × `height` image.
    pub(crate) fn new(polygons: &[Vec<Point>], width: u32, height: u32) -> Self {
        let columns = (f64::from(width) / CELL).ceil() as usize + 1;
        let rows = (f64::from(height) / CELL).ceil() as usize + 1;
        let mut cells = vec![Vec::new(); columns * rows];
        let mut edges = Vec::new();
        for poly in polygons {
            for (k, &a) in poly.iter().enumerate() {
                let b = poly[(k + 1) % poly.len()];
                let id = edges.len() as u32;
                edges.push((a, b));
                let (x0, x1) = (a.x.min(b.x), a.x.max(b.x));
                let (y0, y1) = (a.y.min(b.y), a.y.max(b.y));
                let cx = |x: f64| ((x / CELL).floor().max(0.0) as usize).min(columns - 1);
                let cy = |y: f64| ((y / CELL).floor().max(0.0) as usize).min(rows - 1);
                for row in cy(y0)..=cy(y1) {
                    for col in cx(x0)..=cx(x1) {
                        cells[row * columns + col].push(id);
                    }
                }
            }
        }
        BoundaryIndex {
            edges,
            cells,
            columns,
            rows,
        }
    }

    /// Calls `f` with every edge in the cells within `reach` of `p`, once each: an edge
    /// listed in several cells is taken in the first of them (lowest row, then column)
    /// that the query covers.
    fn near(&self, p: Point, reach: f64, mut f: impl FnMut(Point, Point)) {
        let cell = |v: f64, n: usize| ((v / CELL).floor().max(0.0) as usize).min(n - 1);
        let (c0, c1) = (
            cell(p.x - reach, self.columns),
            cell(p.x + reach, self.columns),
        );
        let (r0, r1) = (cell(p.y - reach, self.rows), cell(p.y + reach, self.rows));
        for row in r0..=r1 {
            for col in c0..=c1 {
                for &id in &self.cells[row * self.columns + col] {
                    let (a, b) = self.edges[id as usize];
                    let first_row = cell(a.y.min(b.y), self.rows).max(r0);
                    let first_col = cell(a.x.min(b.x), self.columns).max(c0);
                    if row == first_row && col == first_col {
                        f(a, b);
                    }
                }
            }
        }
    }

    /// Distance from `p` to the nearest boundary edge, searching out to `reach` (then
    /// doubling, up to 4 times); `None` when none is found.
    pub(crate) fn distance(&self, p: Point, reach: f64) -> Option<f64> {
        let mut reach = reach.max(CELL);
        for _ in 0..5 {
            let mut best = f64::INFINITY;
            self.near(p, reach, |a, b| {
                best = best.min(crate::geom::segment_distance(p, a, b));
            });
            if best <= reach {
                return Some(best);
            }
            reach *= 2.0;
        }
        None
    }

    /// How far the ray from `p` along the unit direction `d` goes before it meets the
    /// boundary, looking up to `max` px.
    pub(crate) fn ray(&self, p: Point, d: Point, max: f64) -> Option<f64> {
        let mut best: Option<f64> = None;
        self.near(p, max, |a, b| {
            let e = b - a;
            let den = d.cross(e);
            if den.abs() < 1e-12 {
                return;
            }
            let q = a - p;
            let t = q.cross(e) / den;
            let u = q.cross(d) / den;
            if t >= 0.0 && t <= max && (0.0..=1.0).contains(&u) && best.is_none_or(|b| t < b) {
                best = Some(t);
            }
        });
        best
    }

    /// The distances from `p` to the boundary on either side of the line through `p` along
    /// `tangent`: over the part of each edge with `(q − p)·n ≥ 0` (left, `n` the tangent's
    /// perpendicular) and `≤ 0` (right).
    pub(crate) fn side_distances(&self, p: Point, tangent: Point, reach: f64) -> (f64, f64) {
        let n = tangent.perp();
        let (mut left, mut right) = (f64::INFINITY, f64::INFINITY);
        self.near(p, reach, |a, b| {
            let (sa, sb) = ((a - p).dot(n), (b - p).dot(n));
            for (side, sign) in [(&mut left, 1.0), (&mut right, -1.0)] {
                let (ta, tb) = (sa * sign, sb * sign);
                if ta < 0.0 && tb < 0.0 {
                    continue;
                }
                // The part of the edge on this side.
                let (mut u, mut v) = (a, b);
                if ta < 0.0 {
                    u = a.lerp(b, ta / (ta - tb));
                } else if tb < 0.0 {
                    v = a.lerp(b, ta / (ta - tb));
                }
                *side = side.min(crate::geom::segment_distance(p, u, v));
            }
        });
        (left, right)
    }

    /// Moves `p` along the normal of `tangent` to where the two side distances are equal
    /// (three rounds, each step at most one pixel), and returns the centre with the radius.
    /// `None` when a side has no boundary within `reach`.
    pub(crate) fn centre(&self, p: Point, tangent: Point, reach: f64) -> Option<(Point, f64)> {
        let n = tangent.perp();
        let mut c = p;
        let mut radius = None;
        for _ in 0..3 {
            let (l, r) = self.side_distances(c, tangent, reach);
            if !l.is_finite() || !r.is_finite() {
                return radius.map(|r| (c, r)).or(None);
            }
            let step = ((l - r) / 2.0).clamp(-1.0, 1.0);
            c += n * step;
            radius = Some((l + r) / 2.0);
            if step.abs() < 1e-3 {
                break;
            }
        }
        let (l, r) = self.side_distances(c, tangent, reach);
        if l.is_finite() && r.is_finite() {
            radius = Some((l + r) / 2.0);
        }
        radius.map(|r| (c, r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_of_a_band_is_found_from_an_off_centre_start() {
        // The band 10.3 < y < 15.9 as a long rectangle.
        let rect = vec![
            Point::new(0.0, 10.3),
            Point::new(60.0, 10.3),
            Point::new(60.0, 15.9),
            Point::new(0.0, 15.9),
        ];
        let index = BoundaryIndex::new(&[rect], 64, 32);
        let (c, r) = index
            .centre(Point::new(30.0, 12.0), Point::new(1.0, 0.0), 10.0)
            .unwrap();
        assert!(
            (c.y - 13.1).abs() < 1e-9 && (c.x - 30.0).abs() < 1e-12,
            "{c:?}"
        );
        assert!((r - 2.8).abs() < 1e-9);
        assert!((index.distance(Point::new(30.0, 12.0), 4.0).unwrap() - 1.7).abs() < 1e-12);
        let ahead = index
            .ray(Point::new(50.0, 13.0), Point::new(1.0, 0.0), 20.0)
            .unwrap();
        assert!((ahead - 10.0).abs() < 1e-12);
        assert!(index
            .ray(Point::new(50.0, 13.0), Point::new(1.0, 0.0), 5.0)
            .is_none());
    }
}
