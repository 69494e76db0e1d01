//! The thresholded mask and its borders: every boundary between foreground and background
//! pixels as a closed loop of pixel edges ("cracks"), with its kind (outer border or hole)
//! and the border that encloses it.
//!
//! Foreground is 8-connected and background 4-connected, as in Suzuki and Abe's border
//! following (what `imageproc::contours::find_contours` implements, and what a test here
//! compares against). Their algorithm keeps a label per pixel to know which border each
//! pixel belongs to; here a raster scan starts a loop at every vertical crack not traced
//! yet (one bit per pixel in the mask's own bytes) and the nesting is read afterwards
//! from the crack nearest to the left of each loop's first crack, so that tracing needs
//! no memory beyond the mask and the loops themselves.

use crate::geom::Point;
use crate::raster::bits::Bits;
use crate::raster::Bitmap;

/// One pixel edge between a foreground and a background pixel: the vertex it leaves (in
/// padded coordinates) and its direction, with the foreground on its right. Twelve bytes,
/// the geometry derived on demand; a border kept after the scan stores its cracks as a
/// [`CrackLoop`], a byte each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Crack {
    x: i32,
    y: i32,
    dir: u8,
}

impl Crack {
    /// The foreground pixel (column, row) in image coordinates.
    #[inline]
    pub(super) fn inside(self) -> (i64, i64) {
        let ((rx, ry), _) = side_pixels(i64::from(self.x), i64::from(self.y), self.dir.into());
        (rx - 1, ry - 1)
    }

    /// Midpoint of the pixel edge, in image coordinates.
    #[inline]
    pub(super) fn mid(self) -> Point {
        let (dx, dy) = DIRS[usize::from(self.dir)];
        Point::new(
            f64::from(self.x) + 0.5 * dx as f64 - 1.0,
            f64::from(self.y) + 0.5 * dy as f64 - 1.0,
        )
    }

    /// The vertex the crack leaves, in image coordinates (a pixel corner).
    #[inline]
    pub(super) fn start(self) -> Point {
        Point::new(f64::from(self.x) - 1.0, f64::from(self.y) - 1.0)
    }

    /// Unit normal from the foreground pixel to the background pixel (the crack's left).
    #[inline]
    pub(super) fn normal(self) -> Point {
        let (lx, ly) = DIRS[(usize::from(self.dir) + 3) % 4];
        Point::new(lx as f64, ly as f64)
    }

    /// The background pixel across the crack, in image coordinates.
    #[inline]
    pub(super) fn outside(self) -> (i64, i64) {
        let (lx, ly) = DIRS[(usize::from(self.dir) + 3) % 4];
        let (c, r) = self.inside();
        (c + lx, r + ly)
    }
}

/// A loop of cracks kept compactly: the vertex its first crack leaves, and the direction
/// of every crack (each crack leaves the vertex the one before it reaches). A byte per
/// crack instead of twelve: every border of a page is kept for re-tracing (7 MB less on a
/// 600 dpi page).
#[derive(Clone, Debug, Default)]
pub(super) struct CrackLoop {
    x: i32,
    y: i32,
    dirs: Vec<u8>,
}

impl CrackLoop {
    /// The loop of `cracks`, which must be a chain (as [`PaddedMask::trace`] makes them).
    pub(super) fn new(cracks: &[Crack]) -> CrackLoop {
        debug_assert!(cracks.windows(2).all(|w| {
            let (dx, dy) = DIRS[usize::from(w[0].dir)];
            (i64::from(w[0].x) + dx, i64::from(w[0].y) + dy)
                == (i64::from(w[1].x), i64::from(w[1].y))
        }));
        let first = cracks
            .first()
            .copied()
            .unwrap_or(Crack { x: 0, y: 0, dir: 0 });
        CrackLoop {
            x: first.x,
            y: first.y,
            dirs: cracks.iter().map(|c| c.dir).collect(),
        }
    }

    /// Number of cracks.
    pub(super) fn len(&self) -> usize {
        self.dirs.len()
    }

    /// The cracks in order.
    pub(super) fn iter(&self) -> impl Iterator<Item = Crack> + '_ {
        self.dirs.iter().scan((self.x, self.y), |at, &dir| {
            let crack = Crack {
                x: at.0,
                y: at.1,
                dir,
            };
            let (dx, dy) = DIRS[usize::from(dir)];
            *at = (at.0 + dx as i32, at.1 + dy as i32);
            Some(crack)
        })
    }

    /// The vertex each crack leaves, in image coordinates (pixel corners), in order.
    pub(super) fn vertices(&self) -> impl Iterator<Item = (i32, i32)> + '_ {
        self.dirs.iter().scan((self.x - 1, self.y - 1), |at, &dir| {
            let here = *at;
            let (dx, dy) = DIRS[usize::from(dir)];
            *at = (at.0 + dx as i32, at.1 + dy as i32);
            Some(here)
        })
    }

    /// The cracks as a list.
    pub(super) fn to_vec(&self) -> Vec<Crack> {
        self.iter().collect()
    }
}

/// Directions on the vertex grid: east, south, west, north (clockwise on screen).
const DIRS: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The pixels to the right and to the left of the crack leaving vertex (x, y) in direction
/// `d`.
#[inline]
fn side_pixels(x: i64, y: i64, d: usize) -> ((i64, i64), (i64, i64)) {
    match d {
        0 => ((x, y), (x, y - 1)),
        1 => ((x - 1, y), (x, y)),
        2 => ((x - 1, y - 1), (x - 1, y)),
        _ => ((x, y - 1), (x - 1, y - 1)),
    }
}

/// Half-width (pixels) of the window in which [`resolve_diagonals`] counts the majority.
const DIAGONAL_WINDOW: usize = 2;

/// Ambiguous diagonals, decided like potrace's "minority" turn policy. Where two
/// background pixels touch only at a corner between two foreground pixels, the border
/// follower (8-connected foreground, 4-connected background) always joins the foreground
/// and cuts the background apart, so a thin light line across a dark shape (a diagonal
/// cut, a gap thinner than a pixel) falls apart into one-pixel holes that `min_area`
/// drops. Here the colour in the minority around the pair wins: where the background is
/// the minority, the fainter of the two foreground pixels becomes background and the
/// light line stays connected. Dark lines on light (the foreground in the minority) keep
/// the border follower's choice.
fn resolve_diagonals(mask: &mut Bits, width: usize, height: usize, bitmap: &Bitmap) {
    if width < 2 * DIAGONAL_WINDOW + 2 || height < 2 * DIAGONAL_WINDOW + 2 {
        return;
    }
    let fg = |mask: &Bits, c: usize, r: usize| mask.get(r * width + c);
    let mut flips = Vec::new();
    for r in 1..height - 2 {
        // A pair at columns c, c + 1 (1 ≤ c < width − 2) needs this row's colour to change
        // between them: visit the changes a 64-pixel word at a time (bit i of `changes`
        // says pixel i differs from pixel i − 1).
        let row = r * width;
        for i in mask.changes(row + 2, row + width - 1) {
            let c = i - 1 - row;
            let (a, b) = (fg(mask, c, r), fg(mask, c + 1, r));
            let (d, e) = (fg(mask, c, r + 1), fg(mask, c + 1, r + 1));
            // Background on one diagonal, foreground on the other.
            let pair = match (a, b, d, e) {
                (false, true, true, false) => [(c + 1, r), (c, r + 1)],
                (true, false, false, true) => [(c, r), (c + 1, r + 1)],
                _ => continue,
            };
            let (r0, r1) = (
                r.saturating_sub(DIAGONAL_WINDOW - 1),
                (r + DIAGONAL_WINDOW).min(height - 1),
            );
            let (c0, c1) = (
                c.saturating_sub(DIAGONAL_WINDOW - 1),
                (c + DIAGONAL_WINDOW).min(width - 1),
            );
            let (mut ink, mut all) = (0, 0);
            for rr in r0..=r1 {
                for cc in c0..=c1 {
                    ink += usize::from(fg(mask, cc, rr));
                    all += 1;
                }
            }
            if 2 * ink <= all {
                continue;
            }
            // Padded coordinates → image pixels.
            let cov = |(cc, rr): (usize, usize)| bitmap.coverage_at(cc as i64 - 1, rr as i64 - 1);
            let faint = if cov(pair[0]) <= cov(pair[1]) {
                pair[0]
            } else {
                pair[1]
            };
            flips.push(faint);
        }
    }
    for (c, r) in flips {
        mask.clear(r * width + c);
    }
}

/// The padded binary mask: 1 pixel of background around the image.
pub(super) struct PaddedMask {
    pub(super) width: i64,
    pub(super) height: i64,
    /// Foreground pixels.
    foreground: Bits,
}

impl PaddedMask {
    /// `None` when the padded size does not fit the cracks' 32-bit coordinates.
    pub(super) fn new(bitmap: &Bitmap) -> Option<PaddedMask> {
        let (w, h) = (bitmap.width() as usize, bitmap.height() as usize);
        let pw = w + 2;
        // Cracks store their vertices as i32.
        i32::try_from(pw + 1).ok()?;
        i32::try_from(h + 3).ok()?;
        // Made with the bitmap (its bilevel count reads them), else made here.
        let mut foreground = bitmap
            .take_padded_foreground()
            .unwrap_or_else(|| bitmap.padded_foreground());
        resolve_diagonals(&mut foreground, pw, h + 2, bitmap);
        Some(PaddedMask {
            width: i64::try_from(pw).ok()?,
            height: i64::try_from(h.checked_add(2)?).ok()?,
            foreground,
        })
    }

    #[inline]
    pub(super) fn is_foreground(&self, (x, y): (i64, i64)) -> bool {
        x >= 0
            && y >= 0
            && x < self.width
            && y < self.height
            && self.foreground.get((y * self.width + x) as usize)
    }

    /// True when the crack leaves a *pinch*: a vertex where two foreground pixels touch
    /// only at their corners (and two background pixels across the other diagonal), so
    /// that the border passes it twice, or two borders meet there.
    pub(super) fn leaves_pinch(&self, crack: Crack) -> bool {
        let (x, y) = (i64::from(crack.x), i64::from(crack.y));
        let nw = self.is_foreground((x - 1, y - 1));
        let ne = self.is_foreground((x, y - 1));
        let sw = self.is_foreground((x - 1, y));
        let se = self.is_foreground((x, y));
        nw == se && ne == sw && nw != ne
    }

    /// Follows the crack loop that starts by leaving vertex `start` in direction `dir`,
    /// with the foreground on the right, and appends its cracks (in image coordinates) to
    /// `out`.
    pub(super) fn trace(&self, start: (i64, i64), dir: usize, out: &mut Vec<Crack>) {
        out.clear();
        let (mut x, mut y, mut d) = (start.0, start.1, dir);
        // Every crack is visited at most once per loop.
        let limit = 4 * self.width * self.height + 4;
        for _ in 0..limit {
            let (dx, dy) = DIRS[d];
            // Coordinates fit: `new` refuses masks wider or taller than i32 allows.
            out.push(Crack {
                x: x as i32,
                y: y as i32,
                dir: d as u8,
            });
            x += dx;
            y += dy;
            let (right, left) = side_pixels(x, y, d);
            d = if self.is_foreground(left) {
                (d + 3) % 4
            } else if self.is_foreground(right) {
                d
            } else {
                (d + 1) % 4
            };
            if (x, y, d) == (start.0, start.1, dir) {
                return;
            }
        }
    }
}

/// One border of the mask: its cracks, from its first one in raster order, with the
/// foreground on the right.
pub(super) struct FoundBorder {
    pub(super) cracks: Vec<Crack>,
    /// True for the border of a hole (background enclosed by foreground).
    pub(super) is_hole: bool,
    /// Index of the enclosing border: for an outer border the hole it sits in (`None` at
    /// the top level), for a hole the outer border of its shape.
    pub(super) parent: Option<usize>,
}

impl PaddedMask {
    /// Every border of the mask, in the order of their first vertical crack in a raster
    /// scan (row by row, left to right), so that a parent always comes before its
    /// children.
    pub(super) fn borders(&self) -> Vec<FoundBorder> {
        let mut found = Vec::new();
        let parents = self.scan_borders(|cracks, is_hole| {
            found.push(FoundBorder {
                cracks,
                is_hole,
                parent: None,
            })
        });
        for (border, parent) in found.iter_mut().zip(parents) {
            border.parent = parent;
        }
        found
    }

    /// Hands every border of the mask to `each` (its cracks and whether it is a hole) as
    /// the raster scan finds it, in the order of [`PaddedMask::borders`], and returns the
    /// parent of each (see [`FoundBorder::parent`]), which is known only once the scan is
    /// done. A caller can start work on the first borders while the scan goes on.
    pub(super) fn scan_borders(
        &self,
        mut each: impl FnMut(Vec<Crack>, bool),
    ) -> Vec<Option<usize>> {
        let (w, h) = (self.width as usize, self.height as usize);
        // Pixels whose left side is a crack already traced.
        let mut traced = Bits::new(self.foreground.0.len() * 64);
        // Every border's kind, and the row, column and border of each of its vertical
        // cracks: the crack just left of a border's first crack bounds the region that
        // border sits in.
        let mut holes: Vec<bool> = Vec::new();
        let mut firsts: Vec<(usize, usize)> = Vec::new();
        let mut vertical: Vec<(u32, u32, u32)> = Vec::new();
        let mut cracks = Vec::new();
        // Vertical cracks are where a pixel differs from its left neighbour; they are
        // found a 64-pixel word at a time (rows are consecutive in the bit sets, and the
        // padding column keeps a row's first pixel from pairing with the row above).
        let (first, last) = (w + 1, h.saturating_sub(1) * w);
        for i in self.foreground.changes(first, last) {
            // A loop traced earlier in the scan may have passed here.
            if traced.get(i) {
                continue;
            }
            let (x, y) = (i % w, i / w);
            let is_hole = !self.foreground.get(i);
            let (xi, yi) = (x as i64, y as i64);
            if is_hole {
                // Down the right side of the foreground pixel on the left.
                self.trace((xi, yi), 1, &mut cracks);
            } else {
                // Up the left side of this foreground pixel.
                self.trace((xi, yi + 1), 3, &mut cracks);
            }
            let index = holes.len() as u32;
            for (cx, cy) in cracks.iter().filter_map(vertical_crack) {
                traced.set(cy * w + cx);
                vertical.push((cy as u32, cx as u32, index));
            }
            holes.push(is_hole);
            // Every border starts with the vertical crack the scan found it by.
            firsts.push((x, y));
            // A copy at its size: the buffer grew by doubling and is reused.
            each(cracks.clone(), is_hole);
        }
        drop(traced);
        // The vertical cracks by row, sorted by column within a row.
        let mut row_start = vec![0usize; h + 1];
        for &(cy, _, _) in &vertical {
            row_start[cy as usize + 1] += 1;
        }
        for y in 0..h {
            row_start[y + 1] += row_start[y];
        }
        let mut fill = row_start.clone();
        let mut by_row = vec![(0u32, 0u32); vertical.len()];
        for &(cy, cx, b) in &vertical {
            by_row[fill[cy as usize]] = (cx, b);
            fill[cy as usize] += 1;
        }
        drop(vertical);
        for y in 0..h {
            by_row[row_start[y]..row_start[y + 1]].sort_unstable();
        }
        let mut parents: Vec<Option<usize>> = Vec::with_capacity(holes.len());
        for (i, &(x, y)) in firsts.iter().enumerate() {
            let row = &by_row[row_start[y]..row_start[y + 1]];
            let at = row.partition_point(|&(cx, _)| (cx as usize) < x);
            let parent = at.checked_sub(1).and_then(|k| {
                let left = row[k].1 as usize;
                // The region between the two cracks is the inside of the left border
                // when the kinds differ (an island in a hole, a hole in a shape), and
                // the region around it otherwise (two shapes side by side).
                if holes[left] != holes[i] {
                    Some(left)
                } else {
                    parents[left]
                }
            });
            parents.push(parent);
        }
        parents
    }
}

/// The padded (column, row) of the pixel on the right of a vertical crack (whose bit in
/// `traced` marks it). `None` for a horizontal crack.
fn vertical_crack(c: &Crack) -> Option<(usize, usize)> {
    let (x, y) = (c.x as usize, c.y as usize);
    match c.dir {
        // Down from (x, y): the crack between vertices (x, y) and (x, y + 1).
        1 => Some((x, y)),
        // Up from (x, y): the crack between vertices (x, y − 1) and (x, y).
        3 => Some((x, y.checked_sub(1)?)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::bits::{fill_words, set_bits, MASK_CHUNK_WORDS};
    use imageproc::contours::{find_contours, BorderType};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn bits_set_a_word_at_a_time_are_those_set_one_by_one() {
        // Every start within a word and lengths across zero, one and several words.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for at in 0..130 {
            for len in [0, 1, 5, 63, 64, 65, 127, 128, 200, 333] {
                let bits: Vec<u8> = (0..len).map(|_| rng.random_range(0..2u8)).collect();
                let mut words = vec![0x8000_0000_0000_0001u64; 10];
                let mut direct = words.clone();
                set_bits(&mut words, at, &bits);
                for (k, &b) in bits.iter().enumerate() {
                    let j = at + k;
                    direct[j >> 6] |= u64::from(b) << (j & 63);
                }
                assert_eq!(words, direct, "at {at}, {len} bits");
            }
        }
    }

    /// A mask of random blobs: each pixel foreground with probability `p`, then smoothed
    /// by a majority vote `rounds` times, so that shapes, holes, islands in holes and
    /// diagonal contacts all occur.
    fn random_mask(rng: &mut ChaCha8Rng, w: usize, h: usize, p: f64, rounds: usize) -> Bitmap {
        let mut on: Vec<bool> = (0..w * h).map(|_| rng.random::<f64>() < p).collect();
        for _ in 0..rounds {
            let at = |on: &[bool], c: i64, r: i64| {
                c >= 0 && r >= 0 && c < w as i64 && r < h as i64 && on[r as usize * w + c as usize]
            };
            on = (0..w * h)
                .map(|i| {
                    let (c, r) = ((i % w) as i64, (i / w) as i64);
                    let n: usize = (-1..=1)
                        .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                        .map(|(dx, dy)| usize::from(at(&on, c + dx, r + dy)))
                        .sum();
                    n >= 5
                })
                .collect();
        }
        let coverage = on.iter().map(|&v| f32::from(u8::from(v))).collect();
        Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap()
    }

    /// A large image's mask is filled in chunks of words whose seams fall inside rows:
    /// chunk by chunk it holds the same words as one pass over all of them, and that pass
    /// sets exactly the pixels at or above the threshold (and no padding).
    #[test]
    fn chunked_threshold_matches_one_pass_pixel_for_pixel() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (w, h) = (1531, 1409);
        assert!(
            w * h >= 2 * 64 * MASK_CHUNK_WORDS,
            "the test must take the parallel path"
        );
        let coverage: Vec<f32> = (0..w * h).map(|_| rng.random::<f32>()).collect();
        let bitmap = Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap();
        let pw = w + 2;
        let len = (pw * (h + 2)).div_ceil(64);
        let mut whole = vec![0u64; len];
        let t = bitmap.threshold();
        let classes = bitmap.level_classes(|v| u8::from(f64::from(v) >= t));
        let read_row = |r: usize, out: &mut [u8]| bitmap.read_row_classes(r, 0, &classes, out);
        fill_words(&read_row, w, h, 0, &mut whole);
        let mut chunked = vec![0u64; len];
        // Uneven chunks, one of a single word, seams anywhere in a row.
        let mut first = 0;
        for size in [1, 77, 5000, 1, 12_345]
            .into_iter()
            .chain(std::iter::repeat(9_999))
        {
            if first >= len {
                break;
            }
            let end = (first + size).min(len);
            fill_words(&read_row, w, h, first, &mut chunked[first..end]);
            first = end;
        }
        assert_eq!(chunked, whole);
        let t = bitmap.threshold();
        for r in 0..h + 2 {
            for c in 0..pw {
                let i = r * pw + c;
                let set = (whole[i >> 6] >> (i & 63)) & 1 != 0;
                let inside = (1..=h).contains(&r) && (1..=w).contains(&c);
                let expected =
                    inside && f64::from(bitmap.coverage_at(c as i64 - 1, r as i64 - 1)) >= t;
                assert_eq!(set, expected, "pixel ({c}, {r})");
            }
        }
        // The mask built on the thread pool holds the same bits before its diagonal pass.
        let mask = PaddedMask::new(&bitmap).unwrap();
        let mut plain = Bits(whole);
        resolve_diagonals(&mut plain, pw, h + 2, &bitmap);
        assert_eq!(plain.0, mask.foreground.0);
    }

    /// The mask after the diagonal pass, pixel for pixel as a plain scan of every 2 × 2
    /// square of a byte grid decides it (the pass itself visits only where a row changes,
    /// a word at a time), on random grey images up to 150 px wide.
    #[test]
    fn diagonal_pass_matches_a_plain_scan() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut flipped = 0;
        for case in 0..200 {
            let (w, h) = (rng.random_range(1..150), rng.random_range(1..40));
            let density = rng.random_range(0.3..0.7);
            let coverage: Vec<f32> = (0..w * h)
                .map(|_| {
                    let v: f32 = rng.random();
                    if rng.random::<f64>() < density {
                        0.5 + v / 2.0
                    } else {
                        v / 2.0
                    }
                })
                .collect();
            let bitmap = Bitmap::from_coverage(w as u32, h as u32, coverage, Some(0.5)).unwrap();
            let mask = PaddedMask::new(&bitmap).unwrap();
            // The reference: threshold into bytes, then every square in turn.
            let (pw, ph) = (w + 2, h + 2);
            let mut data = vec![0u8; pw * ph];
            for r in 0..h {
                for c in 0..w {
                    let v = bitmap.coverage_at(c as i64, r as i64);
                    data[(r + 1) * pw + c + 1] = u8::from(f64::from(v) >= bitmap.threshold());
                }
            }
            let mut flips = Vec::new();
            if pw >= 2 * DIAGONAL_WINDOW + 2 && ph >= 2 * DIAGONAL_WINDOW + 2 {
                let fg = |c: usize, r: usize| data[r * pw + c] != 0;
                for r in 1..ph - 2 {
                    for c in 1..pw - 2 {
                        let pair = match (fg(c, r), fg(c + 1, r), fg(c, r + 1), fg(c + 1, r + 1)) {
                            (false, true, true, false) => [(c + 1, r), (c, r + 1)],
                            (true, false, false, true) => [(c, r), (c + 1, r + 1)],
                            _ => continue,
                        };
                        let (r0, r1) = (
                            r - (DIAGONAL_WINDOW - 1).min(r),
                            (r + DIAGONAL_WINDOW).min(ph - 1),
                        );
                        let (c0, c1) = (
                            c - (DIAGONAL_WINDOW - 1).min(c),
                            (c + DIAGONAL_WINDOW).min(pw - 1),
                        );
                        let ink: usize = (r0..=r1)
                            .flat_map(|rr| (c0..=c1).map(move |cc| (cc, rr)))
                            .map(|(cc, rr)| usize::from(fg(cc, rr)))
                            .sum();
                        if 2 * ink <= (r1 - r0 + 1) * (c1 - c0 + 1) {
                            continue;
                        }
                        let cov = |(cc, rr): (usize, usize)| {
                            bitmap.coverage_at(cc as i64 - 1, rr as i64 - 1)
                        };
                        flips.push(if cov(pair[0]) <= cov(pair[1]) {
                            pair[0]
                        } else {
                            pair[1]
                        });
                    }
                }
            }
            flipped += flips.len();
            for (c, r) in flips {
                data[r * pw + c] = 0;
            }
            for r in 0..ph {
                for c in 0..pw {
                    assert_eq!(
                        mask.is_foreground((c as i64, r as i64)),
                        data[r * pw + c] != 0,
                        "case {case}: pixel ({c}, {r}) of {pw} x {ph}"
                    );
                }
            }
        }
        assert!(flipped > 500, "only {flipped} pairs resolved");
    }

    /// The same borders, kinds, parents and first pixels as Suzuki and Abe's border
    /// following (imageproc's), on random masks with every kind of nesting.
    #[test]
    fn borders_match_suzuki_abe() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut compared = 0;
        let mut holes = 0;
        let mut islands = 0;
        for case in 0..300 {
            // Widths past 128 px give rows that span several 64-bit words of the scan.
            let (w, h) = (rng.random_range(1..150), rng.random_range(1..60));
            let p = rng.random_range(0.2..0.8);
            let bitmap = random_mask(&mut rng, w, h, p, case % 4);
            let mask = PaddedMask::new(&bitmap).unwrap();
            let image = image::GrayImage::from_fn(mask.width as u32, mask.height as u32, |x, y| {
                image::Luma([if mask.is_foreground((x.into(), y.into())) {
                    255
                } else {
                    0
                }])
            });
            let theirs = find_contours::<i32>(&image);
            let ours = mask.borders();
            assert_eq!(ours.len(), theirs.len(), "case {case}: border count");
            for (i, (a, b)) in ours.iter().zip(&theirs).enumerate() {
                assert_eq!(
                    a.is_hole,
                    b.border_type == BorderType::Hole,
                    "case {case}, border {i}: kind"
                );
                assert_eq!(a.parent, b.parent, "case {case}, border {i}: parent");
                let first = b.points[0];
                let first = (i64::from(first.x) - 1, i64::from(first.y) - 1);
                assert_eq!(
                    a.cracks[0].inside(),
                    first,
                    "case {case}, border {i}: start"
                );
                holes += usize::from(a.is_hole);
                islands += usize::from(!a.is_hole && a.parent.is_some());
            }
            compared += ours.len();
        }
        assert!(
            compared > 3000 && holes > 1000 && islands > 30,
            "{compared} {holes} {islands}"
        );
    }

    /// Every crack of the mask is on exactly one border, and each border is closed.
    #[test]
    fn every_crack_is_traced_once() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..50 {
            let bitmap = random_mask(&mut rng, 40, 30, 0.5, 1);
            let mask = PaddedMask::new(&bitmap).unwrap();
            let found = mask.borders();
            let mut seen = std::collections::HashSet::new();
            for b in &found {
                for c in &b.cracks {
                    let key = ((c.mid().x * 2.0) as i64, (c.mid().y * 2.0) as i64);
                    assert!(seen.insert(key), "crack at {:?} on two borders", c.mid());
                }
                let (first, last) = (b.cracks[0].mid(), b.cracks[b.cracks.len() - 1].mid());
                assert!(first.distance(last) <= 1.0, "open loop");
            }
            let (w, h) = (mask.width, mask.height);
            let mut all = 0;
            for y in 0..h {
                for x in 0..w {
                    let fg = |x: i64, y: i64| mask.is_foreground((x, y));
                    all += usize::from(fg(x, y) != fg(x + 1, y));
                    all += usize::from(fg(x, y) != fg(x, y + 1));
                }
            }
            assert_eq!(seen.len(), all);
        }
    }

    /// A border kept as a crack loop gives back exactly the cracks it was made from.
    #[test]
    fn crack_loops_give_back_their_cracks() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        for _ in 0..20 {
            let bitmap = random_mask(&mut rng, 40, 30, 0.5, 1);
            let mask = PaddedMask::new(&bitmap).unwrap();
            for b in mask.borders() {
                let kept = CrackLoop::new(&b.cracks);
                assert_eq!(kept.len(), b.cracks.len());
                assert_eq!(kept.to_vec(), b.cracks);
            }
        }
    }
}
