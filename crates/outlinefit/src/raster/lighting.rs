//! The local threshold: uneven lighting taken out of a luminance image before it is
//! thresholded.
//!
//! A scan or a photo of a page is lit unevenly: one side darker, a shadow near the
//! binding, vignetting. Luminance is reflectance × light, so the paper's own luminance
//! follows the light, and a global threshold (Otsu's) that separates ink from paper on
//! the bright side paints the dark side's paper as ink. Here the paper's level is
//! estimated across the page and divided out, which is a local threshold (the paper
//! level plus a fixed share of the contrast, as in Bradley's and Sauvola's methods) that
//! also keeps the grey levels at edges meaningful for the sub-pixel refinement.
//!
//! * **Paper level.** The image is cut into square blocks of [`block_size`] px (1/16 of
//!   its longer side, 16 to 128 px: larger than a letter's stroke, smaller than the
//!   light's changes); in each, the paper's coverage is the 10th percentile (text and
//!   line art cover much less than nine tenths of a block) of a 16 × 16 grid of samples
//!   or more. A 3 × 3 median over the
//!   blocks replaces blocks that ink fills (a thick bar, a large dot) by their
//!   neighbours' paper. The level at a pixel is the bilinear interpolation between block
//!   centres, capped at [`PAPER_CAP`].
//! * **Flattening.** Coverage c is 1 − luminance; paper of level p has luminance 1 − p,
//!   so the reflectance is (1 − c)/(1 − p) and the flattened coverage is
//!   (c − p)/(1 − p), clamped to [0, 1]: the paper becomes 0 everywhere and the ink keeps
//!   its contrast. The threshold (Otsu's, or `--threshold`) is then chosen on the
//!   flattened image.
//! * **When (`ThresholdMode::Auto`).** Only where the global threshold would paint paper
//!   as ink: blocks whose paper level is at or above the global threshold and that are
//!   joined to clearly light paper (below the threshold by [`SMOOTH_STEP`]) through
//!   neighbouring blocks whose paper levels differ by at most [`SMOOTH_STEP`]: light
//!   changes smoothly, while a filled shape's edge is a jump from paper to ink. At
//!   least [`UNEVEN_BLOCKS`] of the blocks (and two) must be such, so that a soft shadow
//!   in one corner keeps the global threshold; in a colour image only grey blocks count
//!   (mean chroma at most [`PAPER_CHROMA`]: lit paper is grey, the flat colours of a
//!   logo are not); and ink must lie on that paper somewhere
//!   (a block with a sample [`INK_CONTRAST`] darker than its paper): a smooth ramp with
//!   nothing on it is a drawing, not a lit page. Images traced from their alpha channel
//!   are never flattened (alpha is not lit).

use super::levels::{self, Levels};
use image::{DynamicImage, GenericImageView};
use std::collections::VecDeque;

/// Fewest pixels for which [`PaperMap::flatten`] runs on the thread pool.
const PARALLEL_FLATTEN_PIXELS: usize = 1 << 20;

/// How an image is thresholded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThresholdMode {
    /// One threshold for the whole image (Otsu's, or `threshold`).
    Global,
    /// The paper's level estimated across the image and divided out first (see the
    /// module docs of `raster::lighting`), then one threshold.
    Local,
    /// Local when the global threshold would paint large areas of unevenly lit paper as
    /// ink, global otherwise.
    #[default]
    Auto,
}

/// Highest paper level (coverage) divided out: darker "paper" is ink.
const PAPER_CAP: f32 = 0.8;
/// Largest difference (coverage) between the paper levels of neighbouring blocks that
/// counts as the same lit paper.
const SMOOTH_STEP: f32 = 0.1;
/// Share of the blocks that must be unevenly lit paper for `Auto` to choose `Local`.
const UNEVEN_BLOCKS: f64 = 0.02;
/// The paper's percentile within a block.
const PAPER_PERCENTILE: f64 = 0.10;
/// Largest mean chroma of a block that counts as paper (a scan's or a photo's tinted
/// paper stays well below; the flat green of a logo is about 0.5).
const PAPER_CHROMA: f32 = 0.12;
/// Coverage above the paper's that marks ink in a block.
const INK_CONTRAST: f32 = 0.3;

/// Side (px) of the blocks of an image whose longer side is `longest` px.
fn block_size(longest: usize) -> usize {
    (longest / 16).clamp(16, 128)
}

/// The blocks of an image's paper map and the grid of samples in them.
#[derive(Clone, Copy)]
struct Grid {
    /// Side of a block (px), [`block_size`].
    block: usize,
    /// Blocks across and down.
    cols: usize,
    rows: usize,
    /// Every `step`-th pixel of every `step`-th row is a sample: 256 or more per block, a
    /// 64th of a large page's pixels.
    step: usize,
}

impl Grid {
    fn of(width: usize, height: usize) -> Grid {
        let block = block_size(width.max(height));
        Grid {
            block,
            cols: width.div_ceil(block),
            rows: height.div_ceil(block),
            step: (block / 16).max(1),
        }
    }

    /// The columns `start..end` of block column `bx` of an image `width` px wide, whose
    /// every `step`-th from `start` (the multiples of `step`) is sampled.
    fn columns(self, bx: usize, width: usize) -> (usize, usize) {
        let end = ((bx + 1) * self.block).min(width);
        (
            ((bx * self.block).div_ceil(self.step) * self.step).min(end),
            end,
        )
    }
}

/// The 256-bin histogram's bin of a coverage.
fn bin(v: f32) -> usize {
    ((v * 255.0 + 0.5) as i32).clamp(0, 255) as usize
}

/// The rank (1-based) of a block's paper level among its `samples`: the level is the
/// first bin at which the count from the lightest bin reaches it.
fn paper_rank(samples: u32) -> u32 {
    (f64::from(samples) * PAPER_PERCENTILE).ceil().max(1.0) as u32
}

/// The histogram of one block's samples over the 256 bins, with the range of bins it
/// holds: reading the paper level and the darkest bin, and clearing it for the next row
/// of blocks, then touch only that range (a block of clean paper holds a bin or two).
#[derive(Clone)]
struct Tally {
    counts: [u32; 256],
    samples: u32,
    lightest: usize,
    darkest: usize,
}

impl Default for Tally {
    fn default() -> Tally {
        Tally {
            counts: [0; 256],
            samples: 0,
            lightest: usize::MAX,
            darkest: 0,
        }
    }
}

impl Tally {
    #[inline]
    fn add(&mut self, bin: usize, n: u32) {
        self.counts[bin] += n;
        self.samples += n;
        self.lightest = self.lightest.min(bin);
        self.darkest = self.darkest.max(bin);
    }

    /// The paper's bin (the first at which the count from the lightest reaches
    /// [`paper_rank`]) and the darkest bin holding a sample, both 0 without samples;
    /// the tally is empty afterwards.
    fn paper_and_darkest(&mut self) -> (usize, usize) {
        if self.samples == 0 {
            return (0, 0);
        }
        let target = paper_rank(self.samples);
        let range = self.lightest..=self.darkest;
        let mut seen = 0;
        let paper = range
            .clone()
            .find(|&b| {
                seen += self.counts[b];
                seen >= target
            })
            .unwrap_or(self.darkest);
        let darkest = self.darkest;
        self.counts[range].fill(0);
        (self.samples, self.lightest, self.darkest) = (0, usize::MAX, 0);
        (paper, darkest)
    }
}

/// True when every block's paper level in the map [`PaperMap::new`] would make lies below
/// `threshold`: then no block is dark paper, [`PaperMap::is_uneven`] is false at that
/// threshold whatever the rest of the map, and the map is not needed. A block's own level
/// lies below the first bin that is dark paper exactly when at least [`paper_rank`] of its
/// samples lie in lighter bins: one count per block over the same samples, instead of a
/// histogram. The map's level is the 3 × 3 median of its blocks' own, which lies below
/// the threshold exactly when more than half of them do ([`median_is_light`]): a glyph's
/// stroke that fills a block or two leaves the page light, a clean page (the common case)
/// is light everywhere.
pub(super) fn paper_is_light(
    coverage: &Levels,
    width: usize,
    height: usize,
    threshold: f64,
) -> bool {
    let t = threshold as f32;
    // The first bin whose level `is_uneven` counts as dark (level / 255 ≥ t).
    let Some(dark) = (0..256usize).find(|&b| b as f32 / 255.0 >= t) else {
        return true;
    };
    let grid = Grid::of(width, height);
    let Grid {
        block,
        cols,
        rows,
        step,
    } = grid;
    let (mut light, mut samples) = (vec![0u32; cols], vec![0u32; cols]);
    // 8-bit levels: whether each of the 256 levels is in a light bin, once.
    let light_bytes = match coverage {
        Levels::Byte(v, t) => Some((
            v,
            std::array::from_fn::<u8, 256, _>(|l| u8::from(bin(t[l]) < dark)),
        )),
        Levels::Word(..) => None,
    };
    let mut row = vec![0.0f32; if light_bytes.is_some() { 0 } else { width }];
    // Each block column's samples on a sampled row, counted once.
    let per_row: Vec<u32> = (0..cols)
        .map(|bx| {
            let (start, end) = grid.columns(bx, width);
            (end - start).div_ceil(step) as u32
        })
        .collect();
    // The light levels as one range when they are one (a coverage that falls as the level
    // rises, or rises, makes them the levels above or below one): counted by comparison
    // rather than by table, every sample when the step is 1.
    let light_range = light_bytes.as_ref().and_then(|(_, is_light)| {
        let first = is_light.iter().position(|&l| l == 1)?;
        let last = is_light.iter().rposition(|&l| l == 1)?;
        is_light[first..=last]
            .iter()
            .all(|&l| l == 1)
            .then_some((first as u8, (last - first) as u8))
    });
    // Whether each block's own paper level lies below the threshold, row-major.
    let mut own = Vec::with_capacity(rows * cols);
    for by in 0..rows {
        light.fill(0);
        samples.fill(0);
        for y in (by * block..((by + 1) * block).min(height)).step_by(step) {
            match &light_bytes {
                Some((levels, is_light)) => {
                    let line = &levels[y * width..(y + 1) * width];
                    for (bx, (l, n)) in light.iter_mut().zip(&mut samples).enumerate() {
                        let (start, end) = grid.columns(bx, width);
                        *n += per_row[bx];
                        *l += match (step, light_range) {
                            (1, Some((low, span))) => line[start..end]
                                .iter()
                                .map(|&v| u32::from(v.wrapping_sub(low) <= span))
                                .sum::<u32>(),
                            _ => line[start..end]
                                .iter()
                                .step_by(step)
                                .map(|&v| u32::from(is_light[usize::from(v)]))
                                .sum::<u32>(),
                        };
                    }
                }
                None => {
                    coverage.read(y * width, &mut row);
                    for x in (0..width).step_by(step) {
                        samples[x / block] += 1;
                        light[x / block] += u32::from(bin(row[x]) < dark);
                    }
                }
            }
        }
        // A block without samples (a last column narrower than the sample step) has the
        // map's level 0, the lightest bin.
        own.extend(light.iter().zip(&samples).map(|(&l, &n)| {
            if n == 0 {
                dark > 0
            } else {
                l >= paper_rank(n)
            }
        }));
    }
    median_is_light(&own, rows, cols)
}

/// Whether the 3 × 3 median of every block (over the blocks that exist, as
/// [`PaperMap::median_filter`] takes it: the element at index k / 2 of k sorted levels)
/// lies below the threshold, given whether each block's own level does (`light`,
/// row-major over `rows × cols`): the median of k levels does exactly when at least
/// k / 2 + 1 of them do.
fn median_is_light(light: &[bool], rows: usize, cols: usize) -> bool {
    (0..rows).all(|r| {
        (0..cols).all(|c| {
            let (mut k, mut n) = (0, 0);
            for i in neighbourhood(r, c, rows, cols) {
                k += 1;
                n += usize::from(light[i]);
            }
            n > k / 2
        })
    })
}

/// The row-major indices of the blocks of a `rows × cols` grid in the 3 × 3 neighbourhood
/// of block (`r`, `c`), itself included: those that exist.
fn neighbourhood(r: usize, c: usize, rows: usize, cols: usize) -> impl Iterator<Item = usize> {
    (r.saturating_sub(1)..=(r + 1).min(rows - 1)).flat_map(move |rr| {
        (c.saturating_sub(1)..=(c + 1).min(cols - 1)).map(move |cc| rr * cols + cc)
    })
}

/// The paper's coverage per block, row-major over a `cols × rows` grid of `block` px.
pub(super) struct PaperMap {
    block: usize,
    cols: usize,
    rows: usize,
    paper: Vec<f32>,
    /// Per block: whether it holds ink, some sample at least [`INK_CONTRAST`] above the
    /// block's paper.
    ink: Vec<bool>,
}

impl PaperMap {
    /// Estimates the paper level of every block of a `width × height` coverage field.
    pub(super) fn new(coverage: &Levels, width: usize, height: usize) -> PaperMap {
        let grid = Grid::of(width, height);
        let Grid {
            block,
            cols,
            rows,
            step,
        } = grid;
        let mut levels = Vec::with_capacity(cols * rows);
        // One 256-bin histogram per block of the current row of blocks.
        let mut hist = vec![Tally::default(); cols];
        // 8-bit levels: the bin of each of the 256 levels once, then one table look-up per
        // sample instead of converting every pixel of the row (the same bins).
        let byte_bins = match coverage {
            Levels::Byte(v, t) => Some((v, std::array::from_fn::<u8, 256, _>(|l| bin(t[l]) as u8))),
            Levels::Word(..) => None,
        };
        // 16-bit levels read each sampled row whole.
        let mut row = vec![0.0f32; if byte_bins.is_some() { 0 } else { width }];
        for by in 0..rows {
            let (y0, y1) = (by * block, ((by + 1) * block).min(height));
            for y in (y0..y1).step_by(step) {
                match &byte_bins {
                    Some((levels, bins)) => {
                        let line = &levels[y * width..(y + 1) * width];
                        let bin_of = |l: u8| usize::from(bins[usize::from(l)]);
                        for (bx, h) in hist.iter_mut().enumerate() {
                            let (start, end) = grid.columns(bx, width);
                            // Counted by runs of one level: paper is mostly one level,
                            // and adding one to the same bin again and again waits for
                            // each addition to land before the next. A stretch of one
                            // level (every sample, on a small image) is counted at once.
                            let Some(&first) = line[start..end].first() else {
                                continue;
                            };
                            if step == 1 && line[start..end].iter().all(|&l| l == first) {
                                h.add(bin_of(first), (end - start) as u32);
                                continue;
                            }
                            let mut samples = line[start..end].iter().step_by(step);
                            samples.next();
                            let (mut level, mut run) = (first, 1);
                            for &next in samples {
                                if next == level {
                                    run += 1;
                                } else {
                                    h.add(bin_of(level), run);
                                    (level, run) = (next, 1);
                                }
                            }
                            h.add(bin_of(level), run);
                        }
                    }
                    None => {
                        coverage.read(y * width, &mut row);
                        for x in (0..width).step_by(step) {
                            hist[x / block].add(bin(row[x]), 1);
                        }
                    }
                }
            }
            levels.extend(hist.iter_mut().map(Tally::paper_and_darkest));
        }
        PaperMap::of_blocks(grid, &levels)
    }

    /// The map of a grid's blocks from each block's paper bin and darkest bin (row-major):
    /// their levels, whether they hold ink, then the 3 × 3 median.
    fn of_blocks(grid: Grid, levels: &[(usize, usize)]) -> PaperMap {
        let paper = levels.iter().map(|&(l, _)| l as f32 / 255.0).collect();
        let ink = levels
            .iter()
            .map(|&(l, darkest)| (darkest - l) as f32 / 255.0 >= INK_CONTRAST)
            .collect();
        let mut map = PaperMap {
            block: grid.block,
            cols: grid.cols,
            rows: grid.rows,
            paper,
            ink,
        };
        map.median_filter();
        map
    }

    /// Replaces every block's level by the median of its 3 × 3 neighbourhood (the blocks
    /// that exist).
    fn median_filter(&mut self) {
        let mut out = Vec::with_capacity(self.paper.len());
        let mut near = Vec::with_capacity(9);
        for r in 0..self.rows {
            for c in 0..self.cols {
                near.clear();
                near.extend(neighbourhood(r, c, self.rows, self.cols).map(|i| self.paper[i]));
                near.sort_by(f32::total_cmp);
                out.push(near[near.len() / 2]);
            }
        }
        self.paper = out;
    }

    /// The mean chroma (largest minus smallest of R, G, B, on [0, 1]) of every block of
    /// `img`, from the same sample grid as the paper levels.
    pub(super) fn block_chroma(&self, img: &DynamicImage) -> Vec<f32> {
        let (w, h) = (img.width() as usize, img.height() as usize);
        let step = (self.block / 16).max(1);
        let mut sum = vec![(0.0f32, 0u32); self.cols * self.rows];
        for y in (0..h).step_by(step) {
            for x in (0..w).step_by(step) {
                let [r, g, b, _] = img.get_pixel(x as u32, y as u32).0;
                let chroma = f32::from(r.max(g).max(b) - r.min(g).min(b)) / 255.0;
                let cell = &mut sum[(y / self.block) * self.cols + x / self.block];
                cell.0 += chroma;
                cell.1 += 1;
            }
        }
        sum.into_iter()
            .map(|(s, n)| if n == 0 { 0.0 } else { s / n as f32 })
            .collect()
    }

    /// True when, at global threshold `threshold`, large areas of paper would be ink
    /// (the rule of the module docs). `chroma` (per block, for a colour image) leaves
    /// out coloured blocks: lit paper is grey, a flat colour of a drawing is not.
    pub(super) fn is_uneven(&self, threshold: f64, chroma: Option<&[f32]>) -> bool {
        let t = threshold as f32;
        let n = self.paper.len();
        // Blocks reached from clearly light paper through smooth steps.
        let mut reached = vec![false; n];
        let mut queue: VecDeque<usize> = (0..n)
            .filter(|&i| self.paper[i] < t - SMOOTH_STEP)
            .collect();
        for &i in &queue {
            reached[i] = true;
        }
        while let Some(i) = queue.pop_front() {
            let (r, c) = (i / self.cols, i % self.cols);
            let neighbours = [
                (r > 0).then(|| i - self.cols),
                (r + 1 < self.rows).then(|| i + self.cols),
                (c > 0).then(|| i - 1),
                (c + 1 < self.cols).then(|| i + 1),
            ];
            for j in neighbours.into_iter().flatten() {
                if !reached[j] && (self.paper[j] - self.paper[i]).abs() <= SMOOTH_STEP {
                    reached[j] = true;
                    queue.push_back(j);
                }
            }
        }
        let neutral = |i: usize| chroma.is_none_or(|c| c[i] <= PAPER_CHROMA);
        let dark_paper = || (0..n).filter(|&i| reached[i] && self.paper[i] >= t && neutral(i));
        let count = dark_paper().count();
        count >= 2 && count as f64 >= UNEVEN_BLOCKS * n as f64 && dark_paper().any(|i| self.ink[i])
    }

    /// Where each of `width` pixel columns lies between block centres: the two block
    /// columns it is interpolated from and the second one's share. The same on every
    /// row, so a page computes it once instead of once per pixel.
    fn column_weights(&self, width: usize) -> Vec<(usize, usize, f32)> {
        (0..width)
            .map(|x| self.between_centres(x, self.cols))
            .collect()
    }

    /// Where pixel `v` lies between the centres of `n` blocks along one axis: the two
    /// blocks it is interpolated from and the second one's share (its position in
    /// block-centre units, clamped to the grid).
    fn between_centres(&self, v: usize, n: usize) -> (usize, usize, f32) {
        let f = ((v as f32 + 0.5) / self.block as f32 - 0.5).clamp(0.0, (n - 1) as f32);
        let first = f as usize;
        (first, (first + 1).min(n - 1), f - first as f32)
    }

    /// The paper level of every pixel of row `y`: bilinear between block centres, capped.
    /// `columns` is [`PaperMap::column_weights`] of the row's width. `along` holds the
    /// two block rows that `y` lies between, interpolated along the row (the same for
    /// every image row between their centres, so made again only when they change):
    /// each pixel then takes one blend of the two, with no look-up.
    fn level_row(
        &self,
        y: usize,
        columns: &[(usize, usize, f32)],
        along: &mut BlockRows,
        out: &mut [f32],
    ) {
        let (r0, r1, ty) = self.between_centres(y, self.rows);
        if along.rows != Some((r0, r1)) {
            let (top_row, bottom_row) = (
                &self.paper[r0 * self.cols..(r0 + 1) * self.cols],
                &self.paper[r1 * self.cols..(r1 + 1) * self.cols],
            );
            along.top.clear();
            along.bottom.clear();
            for &(c0, c1, tx) in columns {
                along
                    .top
                    .push(top_row[c0] + (top_row[c1] - top_row[c0]) * tx);
                along
                    .bottom
                    .push(bottom_row[c0] + (bottom_row[c1] - bottom_row[c0]) * tx);
            }
            along.rows = Some((r0, r1));
        }
        for ((o, &top), &bottom) in out.iter_mut().zip(&along.top).zip(&along.bottom) {
            *o = (top + (bottom - top) * ty).min(PAPER_CAP);
        }
    }

    /// The coverage with the paper divided out: (c − p)/(1 − p), clamped to [0, 1].
    /// Rows are independent: a large image is flattened in parallel, each row the same
    /// on any number of threads.
    pub(super) fn flatten(&self, coverage: &Levels, width: usize, height: usize) -> Levels {
        let mut out = vec![0u16; width * height];
        if width == 0 {
            return Levels::quantised(out);
        }
        let columns = self.column_weights(width);
        let buffers = || {
            (
                vec![0.0f32; width],
                vec![0.0f32; width],
                BlockRows::default(),
            )
        };
        let flatten_row = |(row, paper, along): &mut (Vec<f32>, Vec<f32>, BlockRows),
                           y: usize,
                           out: &mut [u16]| {
            coverage.read(y * width, row);
            self.level_row(y, &columns, along, paper);
            for ((o, &c), &p) in out.iter_mut().zip(row.iter()).zip(paper.iter()) {
                *o = levels::quantise((c - p) / (1.0 - p));
            }
        };
        if width * height >= PARALLEL_FLATTEN_PIXELS {
            use rayon::prelude::*;
            out.par_chunks_mut(width)
                .enumerate()
                .for_each_init(buffers, |buf, (y, o)| flatten_row(buf, y, o));
        } else {
            let mut buf = buffers();
            for (y, o) in out.chunks_mut(width).enumerate() {
                flatten_row(&mut buf, y, o);
            }
        }
        Levels::quantised(out)
    }
}

/// Two rows of block centres interpolated along an image row ([`PaperMap::level_row`]),
/// kept while the image rows lie between the same two.
#[derive(Default)]
struct BlockRows {
    /// The block rows interpolated, if any yet.
    rows: Option<(usize, usize)>,
    /// The upper block row's paper level at each pixel column.
    top: Vec<f32>,
    /// The lower block row's.
    bottom: Vec<f32>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A page of dark bars on paper whose coverage rises from `left` to `right`.
    fn lit_page(w: usize, h: usize, left: f32, right: f32) -> Vec<f32> {
        let mut out = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let paper = left + (right - left) * x as f32 / (w - 1) as f32;
                let ink = (y / 8) % 3 == 0 && (x / 6) % 4 == 1;
                let reflect = if ink { 0.1 } else { 1.0 };
                out.push(1.0 - (1.0 - paper) * reflect);
            }
        }
        out
    }

    fn levels_of(v: &[f32]) -> Levels {
        Levels::quantised(v.iter().map(|&c| levels::quantise(c)).collect())
    }

    /// 8-bit levels take a shortcut through a table of bins; 16-bit levels with the same
    /// coverage read every row. Both must give the same map, on pages whose blocks are
    /// not whole multiples of the sampling step and whose last column of blocks is short
    /// (even shorter than a step).
    #[test]
    fn byte_levels_give_the_map_of_the_same_coverage_in_words() {
        for (w, h) in [(1700, 900), (1601, 700), (203, 130), (64, 64)] {
            let page = lit_page(w, h, 0.05, 0.6);
            let bytes: Vec<u8> = page.iter().map(|&c| (c * 255.0).round() as u8).collect();
            let value = |b: u8| f32::from(b) / 255.0;
            let as_bytes = Levels::bytes(bytes.clone(), value);
            let as_words = Levels::words(bytes.iter().map(|&b| u16::from(b)).collect(), |v| {
                value(v as u8)
            });
            assert!(matches!(as_bytes, Levels::Byte(..)));
            let (a, b) = (
                PaperMap::new(&as_bytes, w, h),
                PaperMap::new(&as_words, w, h),
            );
            assert_eq!((a.cols, a.rows, a.block), (b.cols, b.rows, b.block));
            assert_eq!(a.paper, b.paper, "{w} × {h}");
            assert_eq!(a.ink, b.ink, "{w} × {h}");
            // The page is lit from 0.05 to 0.6: its paper levels are not all alike.
            let (lo, hi) = a
                .paper
                .iter()
                .fold((1f32, 0f32), |(l, h), &p| (l.min(p), h.max(p)));
            assert!(hi - lo > 0.25, "{w} × {h}: paper from {lo} to {hi}");
        }
        // Clean paper with a bar of ink: blocks of one level, counted at once.
        for (w, h) in [(64, 64), (333, 250)] {
            let bytes: Vec<u8> = (0..w * h)
                .map(|i| {
                    if (i % w) / 7 == 3 && i / w > 5 {
                        230
                    } else {
                        0
                    }
                })
                .collect();
            let value = |b: u8| f32::from(b) / 255.0;
            let as_bytes = Levels::bytes(bytes.clone(), value);
            let as_words = Levels::words(bytes.iter().map(|&b| u16::from(b)).collect(), |v| {
                value(v as u8)
            });
            let (a, b) = (
                PaperMap::new(&as_bytes, w, h),
                PaperMap::new(&as_words, w, h),
            );
            assert_eq!(a.paper, b.paper, "{w} × {h}");
            assert_eq!(a.ink, b.ink, "{w} × {h}");
            assert!(a.ink.iter().any(|&i| i) && !a.ink.iter().all(|&i| i));
        }
    }

    /// The map's levels are those of the module docs: per block, the [`paper_rank`]-th
    /// lightest of its samples' bins (sorted here) and whether its darkest sample is
    /// [`INK_CONTRAST`] darker, then the 3 × 3 median; on lit pages, clean paper with
    /// ink, and blocks short of a sampling step.
    #[test]
    fn the_paper_levels_are_the_rank_of_each_blocks_sorted_samples() {
        let bars = |w: usize, h: usize| -> Vec<f32> {
            (0..w * h)
                .map(|i| {
                    if (i % w) / 7 == 3 && i / w > 5 {
                        0.9
                    } else {
                        0.02
                    }
                })
                .collect()
        };
        for (page, w, h) in [
            (lit_page(1700, 900, 0.05, 0.6), 1700, 900),
            (lit_page(203, 130, 0.0, 0.7), 203, 130),
            (bars(333, 250), 333, 250),
            (bars(64, 64), 64, 64),
        ] {
            let cov = levels_of(&page);
            let map = PaperMap::new(&cov, w, h);
            let grid = Grid::of(w, h);
            let Grid {
                block,
                cols,
                rows,
                step,
            } = grid;
            let mut levels = Vec::new();
            let mut row = vec![0.0f32; w];
            for by in 0..rows {
                for bx in 0..cols {
                    let (start, end) = grid.columns(bx, w);
                    let mut bins = Vec::new();
                    for y in (by * block..((by + 1) * block).min(h)).step_by(step) {
                        cov.read(y * w, &mut row);
                        bins.extend(row[start..end].iter().step_by(step).map(|&v| bin(v)));
                    }
                    bins.sort_unstable();
                    levels.push(match bins.last() {
                        Some(&last) => (bins[paper_rank(bins.len() as u32) as usize - 1], last),
                        None => (0, 0),
                    });
                }
            }
            let want = PaperMap::of_blocks(grid, &levels);
            assert_eq!(map.paper, want.paper, "{w} × {h}");
            assert_eq!(map.ink, want.ink, "{w} × {h}");
        }
    }

    /// [`paper_is_light`] answers for the map without building it: it says light exactly
    /// when every block of the map (after the median) lies below the threshold, and then
    /// the page is not uneven; it says so on a clean page and beside bars of ink that
    /// fill a column and a row of blocks, not on a lit page or a large disk of ink; on a
    /// page of one level it is exactly "that level lies below the threshold", bin
    /// boundaries included; 8-bit and 16-bit levels of the same coverage agree.
    #[test]
    fn paper_that_is_light_everywhere_needs_no_map() {
        let disk = |w: usize, h: usize| -> Vec<f32> {
            (0..w * h)
                .map(|i| {
                    let (x, y) = (
                        (i % w) as f32 - w as f32 / 2.0,
                        (i / w) as f32 - h as f32 / 2.0,
                    );
                    if x * x + y * y < (h as f32 / 3.0).powi(2) {
                        0.9
                    } else {
                        0.04
                    }
                })
                .collect()
        };
        // A stroke 40 px wide and a bar 24 px tall beside it: each fills a column or a
        // row of the 16 px blocks, as a glyph's strokes do.
        let bars = |w: usize, h: usize| -> Vec<f32> {
            (0..w * h)
                .map(|i| {
                    let (x, y) = (i % w, i / w);
                    if (100..140).contains(&x) || (x < 80 && (60..84).contains(&y)) {
                        0.95
                    } else {
                        0.03
                    }
                })
                .collect()
        };
        let pages = [
            (bars(256, 256), 256, 256),
            (lit_page(400, 300, 0.0, 0.7), 400, 300),
            (lit_page(1601, 700, 0.05, 0.6), 1601, 700),
            (lit_page(203, 130, 0.05, 0.15), 203, 130),
            (disk(176, 251), 176, 251),
            (disk(1700, 900), 1700, 900),
        ];
        for (page, w, h) in &pages {
            let (w, h) = (*w, *h);
            let bytes: Vec<u8> = page.iter().map(|&c| (c * 255.0).round() as u8).collect();
            let value = |b: u8| f32::from(b) / 255.0;
            let as_words = Levels::words(bytes.iter().map(|&b| u16::from(b)).collect(), |v| {
                value(v as u8)
            });
            let as_bytes = Levels::bytes(bytes, value);
            let map = PaperMap::new(&as_words, w, h);
            for k in 1..512 {
                let t = f64::from(k) / 511.0;
                let light = paper_is_light(&as_words, w, h, t);
                assert_eq!(
                    light,
                    paper_is_light(&as_bytes, w, h, t),
                    "{w} × {h} at {t}"
                );
                assert_eq!(
                    light,
                    map.paper.iter().all(|&p| p < t as f32),
                    "{w} × {h} at {t}"
                );
                if light {
                    assert!(!map.is_uneven(t, None), "{w} × {h} at {t}");
                }
            }
        }
        // Blocks filled by the bars are dark on their own, light after the median.
        assert!(paper_is_light(&levels_of(&pages[0].0), 256, 256, 0.5));
        assert!(!paper_is_light(&levels_of(&pages[1].0), 400, 300, 0.5));
        assert!(paper_is_light(&levels_of(&pages[3].0), 203, 130, 0.5));
        // The middle of the disk is all ink: its paper is dark even after the median.
        assert!(!paper_is_light(&levels_of(&pages[4].0), 176, 251, 0.5));
        for level in [0u8, 1, 37, 128, 254, 255] {
            let (w, h) = (97, 61);
            let cov = Levels::bytes(vec![level; w * h], |b| f32::from(b) / 255.0);
            let paper = f32::from(level) / 255.0;
            for t in [paper - 1e-4, paper, paper + 1e-4, paper + 0.5 / 255.0] {
                let t = f64::from(t);
                assert_eq!(
                    paper_is_light(&cov, w, h, t),
                    paper < t as f32,
                    "{level} at {t}"
                );
            }
        }
    }

    #[test]
    fn a_gradient_page_is_uneven_and_flattens_to_clean_paper() {
        let (w, h) = (400, 300);
        let page = lit_page(w, h, 0.0, 0.7);
        let cov = levels_of(&page);
        let map = PaperMap::new(&cov, w, h);
        assert!(map.is_uneven(0.5, None));
        let flat = map.flatten(&cov, w, h);
        let mut row = vec![0.0; w];
        for y in 0..h {
            flat.read(y * w, &mut row);
            for (x, &v) in row.iter().enumerate() {
                let ink = (y / 8) % 3 == 0 && (x / 6) % 4 == 1;
                // Paper within 0.15 of 0 (the light changes across a block), ink at
                // least 0.8, whatever the light.
                if ink {
                    assert!(v >= 0.8, "ink ({x}, {y}) {v}");
                } else {
                    assert!(v <= 0.15, "paper ({x}, {y}) {v}");
                }
            }
        }
    }

    /// The paper level at pixel (x, y) computed on its own: the bilinear interpolation
    /// between block centres, capped, as the module docs define it.
    fn level_at(map: &PaperMap, x: usize, y: usize) -> f32 {
        let b = map.block as f32;
        let centre = |v: usize, n: usize| ((v as f32 + 0.5) / b - 0.5).clamp(0.0, (n - 1) as f32);
        let (fx, fy) = (centre(x, map.cols), centre(y, map.rows));
        let (c0, r0) = (fx as usize, fy as usize);
        let (c1, r1) = ((c0 + 1).min(map.cols - 1), (r0 + 1).min(map.rows - 1));
        let (tx, ty) = (fx - c0 as f32, fy - r0 as f32);
        let at = |r: usize, c: usize| map.paper[r * map.cols + c];
        let top = at(r0, c0) + (at(r0, c1) - at(r0, c0)) * tx;
        let bottom = at(r1, c0) + (at(r1, c1) - at(r1, c0)) * tx;
        (top + (bottom - top) * ty).min(PAPER_CAP)
    }

    /// A page large enough to be flattened on the thread pool gives, pixel for pixel and
    /// bit for bit, the formula (c − p)/(1 − p) of its coverage and the paper level
    /// computed pixel by pixel (the flattening takes the columns' share once per page).
    #[test]
    fn a_large_page_flattened_in_parallel_is_the_pixel_by_pixel_formula() {
        let (w, h) = (1301, 900);
        assert!(w * h >= PARALLEL_FLATTEN_PIXELS);
        // Lit from left to right, and darker towards the bottom: the paper level changes
        // along both axes.
        let mut page = lit_page(w, h, 0.05, 0.45);
        for (i, c) in page.iter_mut().enumerate() {
            let shade = 0.2 * (i / w) as f32 / h as f32;
            *c = 1.0 - (1.0 - *c) * (1.0 - shade);
        }
        let cov = levels_of(&page);
        let map = PaperMap::new(&cov, w, h);
        let (top, bottom) = (map.paper[0], map.paper[(map.rows - 1) * map.cols]);
        assert!(bottom - top > 0.1, "paper from {top} down to {bottom}");
        let flat = map.flatten(&cov, w, h);
        let (mut row, mut got) = (vec![0.0; w], vec![0.0; w]);
        for y in 0..h {
            cov.read(y * w, &mut row);
            flat.read(y * w, &mut got);
            for x in 0..w {
                let paper = level_at(&map, x, y);
                let want = levels::quantise((row[x] - paper) / (1.0 - paper));
                let want = f32::from(want) / 65535.0;
                assert_eq!(got[x].to_bits(), want.to_bits(), "({x}, {y})");
            }
        }
        assert_eq!(flat.len(), w * h);
    }

    /// The gradient page in green instead of grey is a drawing's colour, not lit paper.
    #[test]
    fn coloured_paper_is_not_lit_paper() {
        let (w, h) = (400, 300);
        let page = lit_page(w, h, 0.0, 0.7);
        let cov = levels_of(&page);
        let map = PaperMap::new(&cov, w, h);
        let tint = |green: f32| {
            let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
                let lum = 255.0 * (1.0 - page[y as usize * w + x as usize]);
                image::Rgb([
                    (lum * (1.0 - green)) as u8,
                    lum as u8,
                    (lum * (1.0 - green)) as u8,
                ])
            });
            DynamicImage::ImageRgb8(img)
        };
        assert!(map.is_uneven(0.5, Some(&map.block_chroma(&tint(0.0)))));
        assert!(!map.is_uneven(0.5, Some(&map.block_chroma(&tint(0.6)))));
    }

    #[test]
    fn even_light_and_filled_shapes_keep_the_global_threshold() {
        let (w, h) = (400, 300);
        assert!(!PaperMap::new(&levels_of(&lit_page(w, h, 0.05, 0.15)), w, h).is_uneven(0.5, None));
        // A black disk filling much of a white page: its edge is a jump, not light.
        let disk: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32 - 200.0, (i / w) as f32 - 150.0);
                f32::from(u8::from(x * x + y * y < 120.0 * 120.0))
            })
            .collect();
        assert!(!PaperMap::new(&levels_of(&disk), w, h).is_uneven(0.5, None));
        // A smooth ramp with nothing on it is a drawing.
        let ramp: Vec<f32> = (0..w * h).map(|i| (i % w) as f32 / w as f32).collect();
        assert!(!PaperMap::new(&levels_of(&ramp), w, h).is_uneven(0.5, None));
    }
}
