//! Dense disagreement: pixels wrong in bulk near an outline, counted per tile (see the
//! parent module's third step).

use crate::geom::groups_8;
use std::collections::{HashMap, HashSet};

/// Side (px) of the tiles in which dense disagreement is counted.
pub(super) const TILE: usize = 8;

/// Share of a tile's pixels that may disagree with the drawn outline near it, per pixel
/// of [`super::Limits::far`]: traces of bilevel glyphs, icons and stress shapes on the
/// development corpus disagree at up to 8 pixel centres of an 8 × 8 tile (where an edge
/// runs through a row of centres, each falls either way), a checkerboard of 2 × 2 or
/// 3 × 3 cells drawn as diagonal stripes at 18 to 20.
pub(super) const DENSE_SHARE: f64 = 12.0 / 64.0;

/// On grey levels, pixels whose coverage lies within this of the threshold are
/// undecided (anti-aliased edge pixels) and never count as dense disagreement.
pub(super) const UNDECIDED: f64 = 0.25;

/// Groups of 8-connected tiles of [`TILE`] px in which more than [`DENSE_SHARE`] ×
/// `far` of the pixels disagree near the outline (`near`: their indices), as the
/// disagreeing pixels of each group: where pixels are wrong in bulk though none lies far
/// from an outline (a checkerboard drawn as stripes: every pixel is within 1 px of one).
pub(super) fn dense_regions(near: &[u32], w: usize, h: usize, far: f64) -> Vec<Vec<u32>> {
    if near.is_empty() {
        return Vec::new();
    }
    let (tw, th) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let tile_of = |p: u32| {
        let (c, r) = (p as usize % w, p as usize / w);
        (r / TILE) * tw + c / TILE
    };
    let mut count: HashMap<usize, usize> = HashMap::new();
    for &p in near {
        *count.entry(tile_of(p)).or_default() += 1;
    }
    let dense: HashSet<usize> = count
        .iter()
        .filter(|&(&t, &n)| {
            let (c, r) = (t % tw, t / tw);
            let pixels = (TILE.min(w - c * TILE) * TILE.min(h - r * TILE)) as f64;
            n as f64 > DENSE_SHARE * pixels * far
        })
        .map(|(&t, _)| t)
        .collect();
    if dense.is_empty() {
        return Vec::new();
    }
    // Connected groups of dense tiles, in tile order.
    let mut group_of: HashMap<usize, usize> = HashMap::new();
    let groups = groups_8(&dense, tw, th);
    for (g, tiles) in groups.iter().enumerate() {
        group_of.extend(tiles.iter().map(|&t| (t, g)));
    }
    let mut out = vec![Vec::new(); groups.len()];
    for &p in near {
        if let Some(&g) = group_of.get(&tile_of(p)) {
            out[g].push(p);
        }
    }
    out
}
