//! Where a check after a repair has to look again: the tiles around the contours the
//! repair changed. Everything a check finds at a pixel (inside or outside the drawn shape,
//! near or far from its outline, the contours near a region) depends only on the drawn
//! edges within a fixed reach of it, and the changed contours' edges, old and new, lie in
//! their boxes: outside those boxes widened by the reach, the earlier findings stand.

/// Side (px) of the tiles.
const TILE: usize = 16;

/// A set of tiles of [`TILE`] px over a `width` × `height` image.
pub(super) struct Dirty {
    width: usize,
    height: usize,
    /// Per tile row, the marked tiles as column spans `[from, to)` in pixels, in order.
    spans: Vec<Vec<(usize, usize)>>,
}

/// Tiles being marked, to become a [`Dirty`].
pub(super) struct Marks {
    width: usize,
    height: usize,
    cols: usize,
    rows: usize,
    marked: Vec<bool>,
}

impl Marks {
    /// No tile of a `width` × `height` image marked.
    pub(super) fn new(width: usize, height: usize) -> Marks {
        let (cols, rows) = (width.div_ceil(TILE), height.div_ceil(TILE));
        Marks {
            width,
            height,
            cols,
            rows,
            marked: vec![false; cols * rows],
        }
    }

    /// Marks the tiles that meet the box from (`x0`, `y0`) to (`x1`, `y1`) (px) widened
    /// by `margin`.
    #[inline]
    pub(super) fn mark(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, margin: f64) {
        if !(x0 - margin < self.width as f64 && y0 - margin < self.height as f64)
            || x1 + margin < 0.0
            || y1 + margin < 0.0
        {
            return;
        }
        let tile = |v: f64, count: usize| {
            ((v / TILE as f64).floor().max(0.0) as usize).min(count.saturating_sub(1))
        };
        let (c0, c1) = (tile(x0 - margin, self.cols), tile(x1 + margin, self.cols));
        let (r0, r1) = (tile(y0 - margin, self.rows), tile(y1 + margin, self.rows));
        for r in r0..=r1 {
            self.marked[r * self.cols + c0..=r * self.cols + c1].fill(true);
        }
    }

    /// Marks the tiles that meet the pixels within `margin` (whole pixels) of pixel
    /// corner or pixel (`x`, `y`), unless they are `last`'s; returns them, for the next
    /// call's `last` (a walk along an outline stays in the same tiles for a while).
    #[inline]
    pub(super) fn mark_near(
        &mut self,
        x: i64,
        y: i64,
        margin: i64,
        last: [usize; 4],
    ) -> [usize; 4] {
        let tile = |v: i64, count: usize| ((v.max(0) as usize) / TILE).min(count.saturating_sub(1));
        let range = [
            tile(x - margin, self.cols),
            tile(x + margin, self.cols),
            tile(y - margin, self.rows),
            tile(y + margin, self.rows),
        ];
        if range != last {
            let [c0, c1, r0, r1] = range;
            for r in r0..=r1 {
                self.marked[r * self.cols + c0..=r * self.cols + c1].fill(true);
            }
        }
        range
    }

    /// Marks every tile that `other` (of the same image) marks.
    pub(super) fn add(&mut self, other: &Marks) {
        for (m, &o) in self.marked.iter_mut().zip(&other.marked) {
            *m |= o;
        }
    }

    /// Marks the tiles along the image's four sides.
    pub(super) fn sides(&mut self) {
        let (cols, rows) = (self.cols, self.rows);
        for r in 0..rows {
            for c in 0..cols {
                if r == 0 || c == 0 || r + 1 == rows || c + 1 == cols {
                    self.marked[r * cols + c] = true;
                }
            }
        }
    }

    /// The marked tiles.
    pub(super) fn into_dirty(self) -> Dirty {
        let (cols, marked) = (self.cols, &self.marked);
        let spans = (0..self.rows)
            .map(|r| {
                let mut out: Vec<(usize, usize)> = Vec::new();
                for c in (0..cols).filter(|&c| marked[r * cols + c]) {
                    let (from, to) = (c * TILE, ((c + 1) * TILE).min(self.width));
                    match out.last_mut() {
                        Some(last) if last.1 == from => last.1 = to,
                        _ => out.push((from, to)),
                    }
                }
                out
            })
            .collect();
        Dirty {
            width: self.width,
            height: self.height,
            spans,
        }
    }
}

impl Dirty {
    /// The tiles that meet any of `boxes` (`[x0, y0, x1, y1]`, px) widened by `margin`.
    pub(super) fn new(width: usize, height: usize, boxes: &[[f64; 4]], margin: f64) -> Dirty {
        let mut marks = Marks::new(width, height);
        for b in boxes {
            marks.mark(b[0], b[1], b[2], b[3], margin);
        }
        marks.into_dirty()
    }

    /// True when pixel (`col`, `row`) lies in a marked tile and one of its 8 neighbours
    /// in the image does not: on the edge of the marked area.
    pub(super) fn on_edge(&self, col: usize, row: usize) -> bool {
        let inner = |v: usize| !v.is_multiple_of(TILE) && v % TILE != TILE - 1;
        if inner(col) && inner(row) {
            // Its neighbours lie in its own tile.
            return false;
        }
        self.contains(col, row)
            && (row.saturating_sub(1)..=(row + 1).min(self.height - 1)).any(|r| {
                (col.saturating_sub(1)..=(col + 1).min(self.width - 1))
                    .any(|c| !self.contains(c, r))
            })
    }

    /// Every tile of the image.
    pub(super) fn all(width: usize, height: usize) -> Dirty {
        Dirty::new(
            width,
            height,
            &[[0.0, 0.0, width as f64, height as f64]],
            0.0,
        )
    }

    /// The marked column spans of pixel row `row`.
    pub(super) fn spans(&self, row: usize) -> &[(usize, usize)] {
        self.spans.get(row / TILE).map_or(&[], Vec::as_slice)
    }

    /// True when pixel (`col`, `row`) lies in a marked tile.
    pub(super) fn contains(&self, col: usize, row: usize) -> bool {
        col < self.width && row < self.height && {
            let spans = self.spans(row);
            let k = spans.partition_point(|s| s.1 <= col);
            spans.get(k).is_some_and(|s| s.0 <= col)
        }
    }

    /// True when pixel index `p` (row × width + column) or one of its 8 neighbours lies
    /// in a marked tile.
    pub(super) fn touches(&self, p: u32) -> bool {
        let (col, row) = (p as usize % self.width, p as usize / self.width);
        (row.saturating_sub(1)..=row + 1)
            .any(|r| (col.saturating_sub(1)..=col + 1).any(|c| self.contains(c, r)))
    }

    /// The box `[x0, y0, x1, y1]` (px) of the marked tiles widened by `margin`, if any.
    pub(super) fn bounds(&self, margin: f64) -> Option<[f64; 4]> {
        let rows: Vec<usize> = (0..self.spans.len())
            .filter(|&r| !self.spans[r].is_empty())
            .collect();
        let (first, last) = (*rows.first()?, *rows.last()?);
        let x0 = rows.iter().map(|&r| self.spans[r][0].0).min()?;
        let x1 = rows
            .iter()
            .filter_map(|&r| self.spans[r].last())
            .map(|s| s.1)
            .max()?;
        Some([
            x0 as f64 - margin,
            (first * TILE) as f64 - margin,
            x1 as f64 + margin,
            ((last + 1) * TILE).min(self.height) as f64 + margin,
        ])
    }

    /// True when an edge from `a` to `b` passes within `margin` px of a marked tile
    /// (tested on its box).
    pub(super) fn near_box(&self, [x0, y0, x1, y1]: [f64; 4], margin: f64) -> bool {
        let t = TILE as f64;
        let r0 = ((y0 - margin) / t).floor().max(0.0) as usize;
        let r1 = ((y1 + margin) / t).floor();
        if r1 < 0.0 {
            return false;
        }
        let r1 = (r1 as usize).min(self.spans.len().saturating_sub(1));
        (r0..=r1).any(|r| {
            self.spans.get(r).is_some_and(|s| {
                s.iter()
                    .any(|&(from, to)| x1 + margin >= from as f64 && x0 - margin <= to as f64)
            })
        })
    }
}
