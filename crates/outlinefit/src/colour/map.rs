//! The planar map of a labelled image: regions, the boundaries between them from junction
//! to junction, and the closed loops that outline any union of regions.
//!
//! **Regions** are the 4-connected components of equal colour. A region smaller than
//! `--min-area` takes the colour most of its neighbouring pixels have (it joins its
//! neighbour rather than becoming a hole), repeated until none is left.
//!
//! **Boundaries** run on the pixel edges ("cracks") between two regions, or between a
//! region and the transparent outside (every transparent pixel and everything beyond the
//! image border is one *void*). Where three or four cracks meet at a pixel corner there is a
//! *junction*; a boundary ("chain") runs from junction to junction with the same two
//! regions on its sides, or round a closed loop without one. Each chain is stored once,
//! with the region on its right and the one on its left (screen coordinates, y down).
//!
//! **Loops.** The outline of a set of regions is a set of closed loops made of whole
//! chains, each used forwards or backwards so that the set is on its right. At a junction
//! the loop turns right first, so a set is 4-connected like its regions are.

use super::palette::VOID;
use std::collections::HashMap;

/// The key of the void (transparent pixels, outside the image) on a side of a crack.
pub(crate) const VOID_SIDE: u32 = u32::MAX;

/// Directions on the crack grid: east, south, west, north (y down).
const DELTA: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// Pixels to the right and the left of the crack from vertex (x, y) in direction `d`.
fn sides(x: i64, y: i64, d: u8) -> ((i64, i64), (i64, i64)) {
    match d {
        0 => ((x, y), (x, y - 1)),
        1 => ((x - 1, y), (x, y)),
        2 => ((x - 1, y - 1), (x - 1, y)),
        _ => ((x, y - 1), (x - 1, y - 1)),
    }
}

/// A boundary between two regions.
#[derive(Clone, Debug)]
pub(crate) struct Chain {
    /// Crack vertices (pixel corners) in order; a closed chain does not repeat its first.
    pub vertices: Vec<(u32, u32)>,
    /// Region on the right ([`VOID_SIDE`] for the void).
    pub right: u32,
    /// Region on the left.
    pub left: u32,
    /// True for a loop without junctions.
    pub closed: bool,
}

impl Chain {
    /// Direction of the crack from vertex `k` to `k + 1` (cyclic for closed chains).
    pub(crate) fn direction(&self, k: usize) -> u8 {
        let n = self.vertices.len();
        let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
        let (dx, dy) = (
            i64::from(b.0) - i64::from(a.0),
            i64::from(b.1) - i64::from(a.1),
        );
        DELTA
            .iter()
            .position(|&d| d == (dx, dy))
            .expect("cracks join neighbouring corners") as u8
    }

    /// Number of cracks.
    pub(crate) fn cracks(&self) -> usize {
        if self.closed {
            self.vertices.len()
        } else {
            self.vertices.len() - 1
        }
    }
}

/// Regions of a labelled image.
pub(crate) struct Regions {
    /// Region of every pixel, row-major.
    pub id: Vec<u32>,
    /// Palette index of every region.
    pub colour: Vec<u16>,
    /// Pixels of every region.
    pub area: Vec<u64>,
}

/// Largest region (px) made only of mixed pixels that is taken for anti-aliasing between
/// its neighbours, not for a colour of its own, and joins its neighbour.
const MIXED_REGION_AREA: u64 = 64;

/// The 4-neighbours of pixel `i` inside a `w` × `h` image.
fn neighbours(i: usize, w: usize, h: usize) -> impl Iterator<Item = usize> {
    let (x, y) = (i % w, i / w);
    [
        (x > 0).then(|| i - 1),
        (x + 1 < w).then(|| i + 1),
        (y > 0).then(|| i - w),
        (y + 1 < h).then(|| i + w),
    ]
    .into_iter()
    .flatten()
}

/// 4-connected components of `label`.
fn components(label: &[u16], w: usize, h: usize) -> Regions {
    let mut id = vec![u32::MAX; w * h];
    let mut colour = Vec::new();
    let mut area = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..w * h {
        if id[seed] != u32::MAX {
            continue;
        }
        let r = colour.len() as u32;
        let l = label[seed];
        id[seed] = r;
        stack.push(seed);
        let mut n = 0u64;
        while let Some(i) = stack.pop() {
            n += 1;
            for j in neighbours(i, w, h) {
                if id[j] == u32::MAX && label[j] == l {
                    id[j] = r;
                    stack.push(j);
                }
            }
        }
        colour.push(l);
        area.push(n);
    }
    Regions { id, colour, area }
}

/// The regions of `label`, after every region smaller than `min_area` px², and every small
/// region without a single pure pixel (`pure`), joined its most common neighbouring colour
/// (`label` is updated to match).
pub(crate) fn regions(
    label: &mut [u16],
    pure: &[bool],
    w: usize,
    h: usize,
    min_area: f64,
) -> Regions {
    for _round in 0..16 {
        let r = components(label, w, h);
        let mut has_pure = vec![false; r.area.len()];
        for (i, &p) in pure.iter().enumerate() {
            if p {
                has_pure[r.id[i] as usize] = true;
            }
        }
        let small: Vec<u32> = (0..r.area.len() as u32)
            .filter(|&k| {
                let area = r.area[k as usize];
                (area as f64) < min_area || (!has_pure[k as usize] && area <= MIXED_REGION_AREA)
            })
            .collect();
        if small.is_empty() || r.area.len() == 1 {
            return r;
        }
        // Neighbouring colours of each small region, by number of shared cracks.
        let mut slot = vec![usize::MAX; r.area.len()];
        for (k, &region) in small.iter().enumerate() {
            slot[region as usize] = k;
        }
        let mut votes: Vec<HashMap<u16, u64>> = vec![HashMap::new(); small.len()];
        for i in 0..w * h {
            let k = slot[r.id[i] as usize];
            if k == usize::MAX {
                continue;
            }
            for j in neighbours(i, w, h) {
                if r.id[j] != r.id[i] {
                    *votes[k].entry(label[j]).or_insert(0) += 1;
                }
            }
        }
        let new_colour: Vec<Option<u16>> = votes
            .into_iter()
            .map(|v| {
                let best = v
                    .into_iter()
                    .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))?;
                Some(best.0)
            })
            .collect();
        let mut changed = false;
        for i in 0..w * h {
            let k = slot[r.id[i] as usize];
            if let Some(c) = new_colour.get(k).copied().flatten() {
                changed |= label[i] != c;
                label[i] = c;
            }
        }
        if !changed {
            return r;
        }
    }
    components(label, w, h)
}

/// The chains of a labelled image (see the module docs).
pub(crate) struct Map {
    pub width: usize,
    pub height: usize,
    /// Side key of every pixel: its region, or [`VOID_SIDE`].
    side: Vec<u32>,
    /// The boundaries.
    pub chains: Vec<Chain>,
    /// The chain that starts at a junction vertex in a direction, and whether it runs
    /// forwards from there.
    ends: HashMap<((u32, u32), u8), (usize, bool)>,
}

impl Map {
    /// Builds the chains of `regions`.
    pub(crate) fn new(regions: &Regions, w: usize, h: usize) -> Map {
        let side = regions
            .id
            .iter()
            .map(|&r| {
                if regions.colour[r as usize] == VOID {
                    VOID_SIDE
                } else {
                    r
                }
            })
            .collect();
        let mut map = Map {
            width: w,
            height: h,
            side,
            chains: Vec::new(),
            ends: HashMap::new(),
        };
        map.build_chains();
        map
    }

    /// Side key of pixel (x, y), [`VOID_SIDE`] outside the image.
    pub(crate) fn side_at(&self, x: i64, y: i64) -> u32 {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            VOID_SIDE
        } else {
            self.side[y as usize * self.width + x as usize]
        }
    }

    /// The sides (right, left) of the crack from vertex `v` in direction `d`.
    pub(crate) fn crack_sides(&self, v: (u32, u32), d: u8) -> (u32, u32) {
        let (r, l) = sides(i64::from(v.0), i64::from(v.1), d);
        (self.side_at(r.0, r.1), self.side_at(l.0, l.1))
    }

    /// True when the crack from `v` in direction `d` separates two regions.
    fn has_crack(&self, v: (u32, u32), d: u8) -> bool {
        let (dx, dy) = DELTA[d as usize];
        let (x, y) = (i64::from(v.0) + dx, i64::from(v.1) + dy);
        if x < 0 || y < 0 || x > self.width as i64 || y > self.height as i64 {
            return false;
        }
        let (r, l) = self.crack_sides(v, d);
        r != l
    }

    fn degree(&self, v: (u32, u32)) -> usize {
        (0..4).filter(|&d| self.has_crack(v, d)).count()
    }

    /// Index of the crack from `v` in direction `d` among all cracks.
    fn crack_index(&self, v: (u32, u32), d: u8) -> usize {
        let (x, y) = (v.0 as usize, v.1 as usize);
        let (w, h) = (self.width, self.height);
        match d {
            0 => y * w + x,
            2 => y * w + x - 1,
            1 => w * (h + 1) + y * (w + 1) + x,
            _ => w * (h + 1) + (y - 1) * (w + 1) + x,
        }
    }

    fn step(v: (u32, u32), d: u8) -> (u32, u32) {
        let (dx, dy) = DELTA[d as usize];
        ((i64::from(v.0) + dx) as u32, (i64::from(v.1) + dy) as u32)
    }

    fn build_chains(&mut self) {
        let (w, h) = (self.width, self.height);
        let mut seen = vec![false; w * (h + 1) + (w + 1) * h];
        let junction: Vec<bool> = (0..(w + 1) * (h + 1))
            .map(|i| self.degree(((i % (w + 1)) as u32, (i / (w + 1)) as u32)) >= 3)
            .collect();
        let is_junction = |v: (u32, u32)| junction[v.1 as usize * (w + 1) + v.0 as usize];
        let walk = |map: &mut Map, start: (u32, u32), d0: u8, seen: &mut Vec<bool>| {
            let (right, left) = map.crack_sides(start, d0);
            let mut vertices = vec![start];
            let (mut v, mut d) = (start, d0);
            let closed = loop {
                seen[map.crack_index(v, d)] = true;
                v = Map::step(v, d);
                if v == start {
                    break !is_junction(start);
                }
                vertices.push(v);
                if is_junction(v) {
                    break false;
                }
                let back = (d + 2) % 4;
                d = (0..4)
                    .find(|&e| e != back && map.has_crack(v, e))
                    .expect("a corner with two cracks continues");
            };
            if closed {
                // The loop came back to its start: the start is not repeated.
            } else if v == start {
                vertices.push(v);
            }
            let k = map.chains.len();
            if !closed {
                let last = vertices.len() - 1;
                map.ends.insert((start, d0), (k, true));
                map.ends.insert((vertices[last], (d + 2) % 4), (k, false));
            }
            map.chains.push(Chain {
                vertices,
                right,
                left,
                closed,
            });
        };
        for y in 0..=h as u32 {
            for x in 0..=w as u32 {
                let v = (x, y);
                if !is_junction(v) {
                    continue;
                }
                for d in 0..4 {
                    if self.has_crack(v, d) && !seen[self.crack_index(v, d)] {
                        walk(self, v, d, &mut seen);
                    }
                }
            }
        }
        // Loops without junctions: start at their first crack in scan order.
        for y in 0..=h as u32 {
            for x in 0..=w as u32 {
                let v = (x, y);
                for d in [0u8, 1] {
                    if self.has_crack(v, d) && !seen[self.crack_index(v, d)] {
                        walk(self, v, d, &mut seen);
                    }
                }
            }
        }
    }

    /// The closed loops outlining the set of regions for which `inside` holds (never the
    /// void), each a list of (chain, forwards) with the set on the right.
    pub(crate) fn loops(&self, inside: &dyn Fn(u32) -> bool) -> Vec<Vec<(usize, bool)>> {
        let is_in = |s: u32| s != VOID_SIDE && inside(s);
        let mut used = vec![false; self.chains.len()];
        let mut loops = Vec::new();
        for (c, chain) in self.chains.iter().enumerate() {
            if used[c] || is_in(chain.right) == is_in(chain.left) {
                continue;
            }
            let start = (c, is_in(chain.right));
            let mut run = Vec::new();
            let mut cur = start;
            loop {
                run.push(cur);
                used[cur.0] = true;
                let ch = &self.chains[cur.0];
                if ch.closed {
                    break;
                }
                let n = ch.vertices.len();
                let (v, din) = if cur.1 {
                    (ch.vertices[n - 1], ch.direction(n - 2))
                } else {
                    (ch.vertices[0], (ch.direction(0) + 2) % 4)
                };
                let next = [(din + 1) % 4, din, (din + 3) % 4]
                    .into_iter()
                    .find_map(|d| {
                        if !self.has_crack(v, d) {
                            return None;
                        }
                        let (r, l) = self.crack_sides(v, d);
                        (is_in(r) && !is_in(l)).then(|| self.ends.get(&(v, d)).copied())?
                    });
                match next {
                    Some(next) if next != start => cur = next,
                    _ => break,
                }
            }
            loops.push(run);
        }
        loops
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Labels from rows of digits.
    fn labels(rows: &[&str]) -> (Vec<u16>, usize, usize) {
        let w = rows[0].len();
        let l = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| u16::from(b - b'0')))
            .collect();
        (l, w, rows.len())
    }

    #[test]
    fn three_colours_meet_at_junctions_and_every_loop_closes() {
        // 1 on the left, 2 top right, 3 bottom right: junctions where the three meet and
        // where the 2|3 boundary and the 1|2, 1|3 boundaries reach the image border.
        let (mut l, w, h) = labels(&["1122", "1122", "1133", "1133"]);
        let r = regions(&mut l, &vec![true; w * h], w, h, 0.0);
        assert_eq!(r.area, vec![8, 4, 4]);
        let map = Map::new(&r, w, h);
        // 1|2, 1|3, 2|3 and three outer boundaries with the void.
        assert_eq!(map.chains.len(), 6);
        assert!(map.chains.iter().all(|c| !c.closed));
        for region in 0..3u32 {
            let loops = map.loops(&|s| s == region);
            assert_eq!(loops.len(), 1, "region {region}");
            let cracks: usize = loops[0].iter().map(|&(c, _)| map.chains[c].cracks()).sum();
            assert_eq!(cracks as u64, 2 * r.area[region as usize] / 2 + 4);
        }
        // The union of 2 and 3 is one loop of 2 + 2 + 4 cracks.
        let both = map.loops(&|s| s != 0);
        assert_eq!(both.len(), 1);
        let cracks: usize = both[0].iter().map(|&(c, _)| map.chains[c].cracks()).sum();
        assert_eq!(cracks, 12);
    }

    #[test]
    fn a_hole_is_a_closed_chain_and_a_small_region_joins_its_neighbour() {
        let (mut l, w, h) = labels(&["11111", "12221", "12321", "12221", "11111"]);
        let r = regions(&mut l, &vec![true; w * h], w, h, 2.0);
        // The single 3 joined the 2s around it.
        assert_eq!(r.area, vec![16, 9]);
        let map = Map::new(&r, w, h);
        assert_eq!(map.chains.len(), 2);
        assert!(map.chains.iter().all(|c| c.closed));
        let outer = map.loops(&|s| s == 0);
        assert_eq!(outer.len(), 2); // its border and its hole
    }
}
