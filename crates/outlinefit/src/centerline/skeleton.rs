//! A one-pixel-wide skeleton of the thresholded foreground: Zhang–Suen thinning (with Lü
//! and Wang's correction for diagonal lines), then the
//! staircase pixels that 8-connectivity does not need are removed, so that every skeleton
//! pixel with three or more skeleton neighbours is a true branch point.
//!
//! `imageproc` has distance transforms but no thinning, so this is written by hand (about
//! sixty lines). The skeleton only gives the strokes' topology and a first centre; the
//! sub-pixel centre and the radius come from the traced boundary (`medial`).

/// A binary image, row-major, `true` = foreground.
#[derive(Clone, Debug)]
pub(crate) struct Grid {
    pub(crate) width: usize,
    pub(crate) height: usize,
    pub(crate) cells: Vec<bool>,
}

/// The 8 neighbours in ring order: N, NE, E, SE, S, SW, W, NW (y grows downwards).
pub(crate) const RING: [(isize, isize); 8] = [
    (0, -1),
    (1, -1),
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
];

impl Grid {
    pub(crate) fn get(&self, x: isize, y: isize) -> bool {
        x >= 0
            && y >= 0
            && (x as usize) < self.width
            && (y as usize) < self.height
            && self.cells[y as usize * self.width + x as usize]
    }

    /// The 8 neighbours of (x, y) in ring order.
    pub(crate) fn ring(&self, x: isize, y: isize) -> [bool; 8] {
        RING.map(|(dx, dy)| self.get(x + dx, y + dy))
    }

    /// How many of the 8 neighbours are set.
    pub(crate) fn neighbours(&self, x: isize, y: isize) -> usize {
        self.ring(x, y).iter().filter(|&&b| b).count()
    }
}

/// Thins `grid` to its skeleton in place.
pub(crate) fn thin(grid: &mut Grid) {
    let (w, h) = (grid.width as isize, grid.height as isize);
    let mut remove = Vec::new();
    loop {
        let mut changed = false;
        for pass in 0..2 {
            remove.clear();
            for y in 0..h {
                for x in 0..w {
                    if grid.get(x, y) && zhang_suen_removes(&grid.ring(x, y), pass) {
                        remove.push(y as usize * grid.width + x as usize);
                    }
                }
            }
            // Zhang–Suen removes the four pixels of a 2 × 2 block together (what a disk
            // thins to), and the shape with them: the block's top-left pixel stays.
            let marked = |grid: &Grid, i: usize| remove.binary_search(&i).is_ok() && grid.cells[i];
            let keep: Vec<usize> = remove
                .iter()
                .copied()
                .filter(|&i| {
                    let (x, y) = (i % grid.width, i / grid.width);
                    x + 1 < grid.width
                        && y + 1 < grid.height
                        && marked(grid, i + 1)
                        && marked(grid, i + grid.width)
                        && marked(grid, i + grid.width + 1)
                })
                .collect();
            for &i in &remove {
                if keep.binary_search(&i).is_err() {
                    grid.cells[i] = false;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    // Staircases: a pixel whose set neighbours stay 8-connected without it, and that is
    // the corner of an L of 4-neighbours, is redundant. Removed one at a time in raster
    // order, so connectivity is kept.
    for y in 0..h {
        for x in 0..w {
            let r = grid.ring(x, y);
            let l_corner = (0..4).any(|k| r[2 * k] && r[(2 * k + 2) % 8]);
            if grid.get(x, y) && l_corner && components(&r) == 1 {
                grid.cells[y as usize * grid.width + x as usize] = false;
            }
        }
    }
}

/// Zhang–Suen's test for the sub-iteration `pass` (0 or 1): a border pixel with 3–6
/// neighbours, one 0→1 transition around it, and the pass's two products zero. Zhang and
/// Suen allow 2 neighbours; Lü and Wang's correction (3) keeps lines two pixels thick on a
/// diagonal, which the original erases entirely.
fn zhang_suen_removes(r: &[bool; 8], pass: usize) -> bool {
    let b = r.iter().filter(|&&v| v).count();
    if !(3..=6).contains(&b) {
        return false;
    }
    let transitions = (0..8).filter(|&k| !r[k] && r[(k + 1) % 8]).count();
    if transitions != 1 {
        return false;
    }
    let (n, e, s, w) = (r[0], r[2], r[4], r[6]);
    // Pass 0: N·E·S = 0 and E·S·W = 0; pass 1: N·E·W = 0 and N·S·W = 0.
    if pass == 0 {
        !(e && s && (n || w))
    } else {
        !(n && w && (e || s))
    }
}

/// The number of 8-connected groups among the set neighbours of a ring (two ring
/// positions touch when they are at most one step apart in x and in y).
pub(crate) fn components(r: &[bool; 8]) -> usize {
    let mut seen = [false; 8];
    let mut count = 0;
    for start in 0..8 {
        if !r[start] || seen[start] {
            continue;
        }
        count += 1;
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(a) = stack.pop() {
            for b in 0..8 {
                let (da, db) = (RING[a], RING[b]);
                let touch = (da.0 - db.0).abs() <= 1 && (da.1 - db.1).abs() <= 1;
                if r[b] && !seen[b] && touch {
                    seen[b] = true;
                    stack.push(b);
                }
            }
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_from(rows: &[&str]) -> Grid {
        Grid {
            width: rows[0].len(),
            height: rows.len(),
            cells: rows
                .iter()
                .flat_map(|r| r.bytes().map(|b| b == b'#'))
                .collect(),
        }
    }

    #[test]
    fn a_bar_thins_to_a_line_with_two_ends_and_no_branch() {
        let mut g = Grid {
            width: 40,
            height: 12,
            cells: (0..480)
                .map(|i| (3..9).contains(&(i / 40)) && (4..36).contains(&(i % 40)))
                .collect(),
        };
        thin(&mut g);
        let pixels: Vec<(isize, isize)> = (0..480)
            .filter(|&i| g.cells[i])
            .map(|i| ((i % 40) as isize, (i / 40) as isize))
            .collect();
        assert!(pixels.len() >= 20, "{pixels:?}");
        let ends = pixels
            .iter()
            .filter(|&&(x, y)| g.neighbours(x, y) == 1)
            .count();
        let branches = pixels
            .iter()
            .filter(|&&(x, y)| g.neighbours(x, y) >= 3)
            .count();
        assert_eq!((ends, branches), (2, 0));
        // Rows 3..9: the centre lies between rows 5 and 6.
        assert!(pixels.iter().all(|&(_, y)| y == 5 || y == 6));
    }

    #[test]
    fn staircase_pixels_are_removed_but_connectivity_kept() {
        let mut g = grid_from(&[".....", ".##..", "..##.", "....."]);
        thin(&mut g);
        let n = g.cells.iter().filter(|&&b| b).count();
        assert_eq!(n, 3);
        // A 2 × 2 block keeps a pixel.
        let mut g = grid_from(&["....", ".##.", ".##.", "...."]);
        thin(&mut g);
        assert!(g.cells.iter().any(|&b| b));
        assert_eq!(
            components(&[true, false, false, false, false, false, false, false]),
            1
        );
        assert_eq!(
            components(&[true, false, false, false, true, false, false, false]),
            2
        );
        assert_eq!(
            components(&[true, false, true, false, false, false, false, false]),
            1
        );
    }
}
