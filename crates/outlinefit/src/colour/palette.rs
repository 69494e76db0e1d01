//! The flat colours of an image, and every pixel's colour among them.
//!
//! **Palette.** A pixel is *flat* when its four neighbours have (nearly) its colour: the
//! inside of a region, not an anti-aliased edge. The colours of flat pixels are counted
//! and grouped greedily, most frequent first: a colour within [`MERGE_DELTA_E`] (CIE76 ΔE
//! in CIELAB, by the `palette` crate) and [`MERGE_ALPHA`] of a group's first colour joins
//! that group, so a flat input keeps its exact colours and JPEG noise around a flat colour
//! joins it. A group is a palette colour when it covers at least [`MIN_FLAT_SHARE`] of the
//! flat pixels or [`MIN_FLAT_PIXELS`] of them; `--palette N` then merges the smallest colour
//! into its nearest one until N are left. Its value is the group's mean colour. The
//! grouping is written here rather than taken from a clustering crate: the greedy rule
//! keeps exact colours exact, which k-means does not, and needs no seed.
//!
//! **Transparency** is a colour of its own, index [`VOID`], always present: it is what the
//! outside of the image is, and it is never drawn.
//!
//! **Pixels.** Colours are compared premultiplied, in the sRGB-encoded values that
//! renderers (browsers, resvg, Cairo) blend in, so an anti-aliased pixel between colours A
//! and B lies on the segment from A to B: c = t·A + (1 − t)·B with t the area of A in the
//! pixel. A pixel within [`PURE_DISTANCE`] of a palette colour is that colour; any other is
//! explained as such a mix of two colours found pure in its 5×5 neighbourhood (or, where
//! there are not two, the two nearest), and takes the colour it is more of. A pixel that
//! no mix explains within [`MIX_RESIDUAL`] takes the nearest colour.

use palette::{FromColor, Lab, Srgb};
use serde::Serialize;

/// Index of the transparent colour in every palette.
pub(crate) const VOID: u16 = 0;

/// Largest ΔE (CIE76) between a colour and the first colour of the group it joins.
const MERGE_DELTA_E: f32 = 8.0;
/// Largest difference of alpha (0–255) between a colour and its group's first colour.
const MERGE_ALPHA: i32 = 24;
/// Largest difference (0–255, per channel) between a flat pixel and its neighbours.
const FLAT_SLACK: i32 = 6;
/// Share of the flat pixels that makes a group a palette colour.
const MIN_FLAT_SHARE: f64 = 0.0005;
/// Number of flat pixels that makes a group a palette colour, whatever its share.
const MIN_FLAT_PIXELS: u64 = 8;
/// Most colours `--palette auto` keeps.
pub(crate) const AUTO_MAX: usize = 64;
/// Largest distance (premultiplied, 0–1 per channel) of a pixel from its palette colour.
const PURE_DISTANCE: f32 = 0.05;
/// Largest distance of a pixel from the mix of two colours that explains it.
const MIX_RESIDUAL: f32 = 0.12;
/// Alpha (0–255) below which a pixel is transparent.
const CLEAR_ALPHA: u8 = 8;

/// How many colours the palette may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PaletteSize {
    /// The flat colours found, at most 64.
    Auto,
    /// At most this many (transparency not counted).
    Max(usize),
}

impl std::str::FromStr for PaletteSize {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(PaletteSize::Auto);
        }
        match s.parse::<usize>() {
            Ok(n) if (1..=AUTO_MAX * 4).contains(&n) => Ok(PaletteSize::Max(n)),
            _ => Err(format!(
                "expected `auto` or a number of colours from 1 to {}",
                AUTO_MAX * 4
            )),
        }
    }
}

/// One palette colour.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Swatch {
    /// sRGB, 0–255 (straight, not premultiplied).
    pub rgb: [u8; 3],
    /// Opacity, 0–255 (0 for the transparent colour).
    pub alpha: u8,
    /// Pixels of this colour after labelling and merging of small regions.
    pub pixels: u64,
    #[serde(skip)]
    pub(crate) premul: [f32; 4],
    #[serde(skip)]
    lab: [f32; 3],
}

impl Swatch {
    fn new(rgba: [u8; 4]) -> Swatch {
        let lab: Lab = Lab::from_color(Srgb::new(rgba[0], rgba[1], rgba[2]).into_format::<f32>());
        Swatch {
            rgb: [rgba[0], rgba[1], rgba[2]],
            alpha: rgba[3],
            pixels: 0,
            premul: premultiplied(rgba),
            lab: [lab.l, lab.a, lab.b],
        }
    }

    /// `#rrggbb`.
    pub fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.rgb[0], self.rgb[1], self.rgb[2])
    }

    /// ΔE (CIE76) to `o`, plus the difference of opacity weighted so that a clearly
    /// different alpha is a different colour.
    fn distance(&self, o: &Swatch) -> f32 {
        self.delta_e(o) + (f32::from(self.alpha) - f32::from(o.alpha)).abs() * 0.5
    }

    /// ΔE (CIE76) to `o`, colour alone.
    fn delta_e(&self, o: &Swatch) -> f32 {
        (0..3)
            .map(|k| (self.lab[k] - o.lab[k]).powi(2))
            .sum::<f32>()
            .sqrt()
    }
}

/// `rgba` premultiplied by its alpha, 0–1.
pub(crate) fn premultiplied(rgba: [u8; 4]) -> [f32; 4] {
    let a = f32::from(rgba[3]) / 255.0;
    [
        f32::from(rgba[0]) / 255.0 * a,
        f32::from(rgba[1]) / 255.0 * a,
        f32::from(rgba[2]) / 255.0 * a,
        a,
    ]
}

/// A pixel's key: its RGBA value, or 0 for (nearly) transparent.
fn key(p: [u8; 4]) -> u32 {
    if p[3] < CLEAR_ALPHA {
        0
    } else {
        u32::from_be_bytes(p)
    }
}

/// True when the pixel at `i` and its four neighbours have nearly the same colour.
fn is_flat(px: &[[u8; 4]], w: usize, h: usize, i: usize) -> bool {
    let (x, y) = (i % w, i / w);
    let c = px[i];
    let near = |j: usize| {
        let o = px[j];
        if (c[3] < CLEAR_ALPHA) != (o[3] < CLEAR_ALPHA) {
            return false;
        }
        c[3] < CLEAR_ALPHA
            || (0..4).all(|k| (i32::from(c[k]) - i32::from(o[k])).abs() <= FLAT_SLACK)
    };
    (x == 0 || near(i - 1))
        && (x + 1 == w || near(i + 1))
        && (y == 0 || near(i - w))
        && (y + 1 == h || near(i + w))
}

/// The palette of an image (`px`, row-major RGBA): [`VOID`] first, then the colours found,
/// most frequent first.
pub(crate) fn find_palette(px: &[[u8; 4]], w: usize, h: usize, size: PaletteSize) -> Vec<Swatch> {
    let mut flat_keys: Vec<u32> = (0..px.len())
        .filter(|&i| is_flat(px, w, h, i))
        .map(|i| key(px[i]))
        .collect();
    if flat_keys.is_empty() {
        // Nothing is flat (a tiny or noisy image): every pixel counts.
        flat_keys = px.iter().map(|p| key(*p)).collect();
    }
    let flat = flat_keys.len() as u64;
    flat_keys.sort_unstable();
    let mut counts: Vec<(u32, u64)> = Vec::new();
    for k in flat_keys {
        match counts.last_mut() {
            Some((last, n)) if *last == k => *n += 1,
            _ => counts.push((k, 1)),
        }
    }
    let mut keys = counts;
    keys.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    // Groups: (first colour, weighted sums of RGBA, count); transparency is group 0.
    struct Group {
        seed: Swatch,
        sum: [f64; 4],
        count: u64,
    }
    let mut groups: Vec<Group> = vec![Group {
        seed: Swatch::new([0, 0, 0, 0]),
        sum: [0.0; 4],
        count: 0,
    }];
    // The grouping is quadratic in the number of groups: past a few thousand distinct flat
    // colours (a photograph), the rarest colours are left to the pixel labelling.
    const MAX_GROUPS: usize = 2048;
    for (k, n) in keys {
        if k == 0 {
            groups[0].count += n;
            continue;
        }
        let rgba = k.to_be_bytes();
        let s = Swatch::new(rgba);
        let near = groups[1..]
            .iter()
            .position(|g| {
                (i32::from(g.seed.alpha) - i32::from(s.alpha)).abs() <= MERGE_ALPHA
                    && g.seed.delta_e(&s) <= MERGE_DELTA_E
            })
            .map(|g| g + 1);
        let g = match near {
            Some(g) => g,
            None if groups.len() < MAX_GROUPS => {
                groups.push(Group {
                    seed: s,
                    sum: [0.0; 4],
                    count: 0,
                });
                groups.len() - 1
            }
            None => continue,
        };
        for c in 0..4 {
            groups[g].sum[c] += f64::from(rgba[c]) * n as f64;
        }
        groups[g].count += n;
    }
    let min_count = ((flat as f64 * MIN_FLAT_SHARE).ceil() as u64).min(MIN_FLAT_PIXELS);
    let mut kept: Vec<(Swatch, u64)> = groups
        .iter()
        .skip(1)
        .filter(|g| g.count >= min_count.max(1))
        .map(|g| {
            let mean = |c: usize| (g.sum[c] / g.count as f64).round().clamp(0.0, 255.0) as u8;
            (Swatch::new([mean(0), mean(1), mean(2), mean(3)]), g.count)
        })
        .collect();
    if kept.is_empty() {
        if let Some(g) = groups.iter().skip(1).max_by_key(|g| g.count) {
            kept.push((g.seed, g.count));
        }
    }
    let cap = match size {
        PaletteSize::Auto => AUTO_MAX,
        PaletteSize::Max(n) => n,
    };
    while kept.len() > cap.max(1) {
        // The rarest colour goes into its nearest.
        let (r, _) = kept
            .iter()
            .enumerate()
            .min_by(|a, b| a.1 .1.cmp(&b.1 .1).then(b.0.cmp(&a.0)))
            .expect("palette has more than one colour");
        let (rare, n) = kept.remove(r);
        let near = (0..kept.len())
            .min_by(|&a, &b| {
                kept[a]
                    .0
                    .distance(&rare)
                    .total_cmp(&kept[b].0.distance(&rare))
            })
            .expect("palette keeps a colour");
        kept[near].1 += n;
    }
    kept.sort_by_key(|k| std::cmp::Reverse(k.1));
    std::iter::once(groups[0].seed)
        .chain(kept.into_iter().map(|(s, _)| s))
        .collect()
}

/// Squared distance of two premultiplied colours.
fn dist2(a: &[f32; 4], b: &[f32; 4]) -> f32 {
    (0..4).map(|k| (a[k] - b[k]).powi(2)).sum()
}

/// Coverage of colour `a` in `c`, a mix of `a` and `b` (0–1), and the distance of `c` from
/// that mix.
pub(crate) fn mix(c: &[f32; 4], a: &[f32; 4], b: &[f32; 4]) -> (f32, f32) {
    let ab: [f32; 4] = std::array::from_fn(|k| a[k] - b[k]);
    let len2 = dist2(a, b);
    if len2 <= 1e-12 {
        return (1.0, dist2(c, a).sqrt());
    }
    let t = ((0..4).map(|k| (c[k] - b[k]) * ab[k]).sum::<f32>() / len2).clamp(0.0, 1.0);
    let m: [f32; 4] = std::array::from_fn(|k| b[k] + t * ab[k]);
    (t, dist2(c, &m).sqrt())
}

/// Every pixel's palette index (see the module docs), whether it is pure (within
/// [`PURE_DISTANCE`] of its colour), and how many pixels were mixed.
pub(crate) fn label_pixels(
    colours: &[[f32; 4]],
    w: usize,
    h: usize,
    palette: &[Swatch],
) -> (Vec<u16>, Vec<bool>, usize) {
    let nearest = |c: &[f32; 4]| -> (u16, f32) {
        palette
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u16, dist2(c, &s.premul)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .expect("the palette is never empty")
    };
    const UNSET: u16 = u16::MAX;
    let mut label = vec![UNSET; w * h];
    for (i, c) in colours.iter().enumerate() {
        let (k, d2) = nearest(c);
        if d2.sqrt() <= PURE_DISTANCE {
            label[i] = k;
        }
    }
    let pure = label.clone();
    let mut mixed = 0;
    let mut candidates: Vec<u16> = Vec::with_capacity(25);
    for i in 0..w * h {
        if pure[i] != UNSET {
            continue;
        }
        mixed += 1;
        let c = &colours[i];
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        candidates.clear();
        for dy in -2..=2i64 {
            for dx in -2..=2i64 {
                let (cx, cy) = (x + dx, y + dy);
                if cx < 0 || cy < 0 || cx >= w as i64 || cy >= h as i64 {
                    continue;
                }
                let l = pure[cy as usize * w + cx as usize];
                if l != UNSET && !candidates.contains(&l) {
                    candidates.push(l);
                }
            }
        }
        if candidates.len() < 2 {
            let mut order: Vec<u16> = (0..palette.len() as u16).collect();
            order.sort_by(|&a, &b| {
                dist2(c, &palette[a as usize].premul)
                    .total_cmp(&dist2(c, &palette[b as usize].premul))
                    .then(a.cmp(&b))
            });
            for k in order.into_iter().take(2) {
                if !candidates.contains(&k) {
                    candidates.push(k);
                }
            }
        }
        let mut best: Option<(f32, u16)> = None;
        for (ia, &a) in candidates.iter().enumerate() {
            for &b in &candidates[ia + 1..] {
                let (t, r) = mix(c, &palette[a as usize].premul, &palette[b as usize].premul);
                let l = if t >= 0.5 { a } else { b };
                if best.is_none_or(|(br, bl)| r < br || (r == br && l < bl)) {
                    best = Some((r, l));
                }
            }
        }
        label[i] = match best {
            Some((r, l)) if r <= MIX_RESIDUAL => l,
            _ => nearest(c).0,
        };
    }
    let pure = pure.iter().map(|&l| l != UNSET).collect();
    (label, pure, mixed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_colours_are_found_exactly_and_mixes_take_the_nearer_colour() {
        // Red on the left, blue (larger) on the right, an anti-aliased column between them at
        // 30 % red.
        let (w, h) = (20usize, 10usize);
        let red = [200u8, 30, 40, 255];
        let blue = [10u8, 40, 220, 255];
        let mixed: [u8; 4] = std::array::from_fn(|k| {
            (0.3 * f32::from(red[k]) + 0.7 * f32::from(blue[k])).round() as u8
        });
        let px: Vec<[u8; 4]> = (0..w * h)
            .map(|i| match i % w {
                0..=7 => red,
                8 => mixed,
                _ => blue,
            })
            .collect();
        let pal = find_palette(&px, w, h, PaletteSize::Auto);
        assert_eq!(pal.len(), 3);
        assert_eq!(pal[1].rgb, [10, 40, 220]); // the larger colour first
        assert_eq!(pal[2].rgb, [200, 30, 40]);
        let colours: Vec<[f32; 4]> = px.iter().map(|p| premultiplied(*p)).collect();
        let (labels, _, n_mixed) = label_pixels(&colours, w, h, &pal);
        assert_eq!(n_mixed, h);
        assert!(labels
            .iter()
            .enumerate()
            .all(|(i, &l)| l == if i % w < 8 { 2 } else { 1 }));
        let (t, r) = mix(&colours[8], &pal[2].premul, &pal[1].premul);
        assert!((t - 0.3).abs() < 0.01 && r < 0.01, "t {t} r {r}");
    }

    #[test]
    fn the_cap_merges_the_rarest_colour_into_its_nearest() {
        let (w, h) = (30usize, 10usize);
        let px: Vec<[u8; 4]> = (0..w * h)
            .map(|i| match i % w {
                0..=14 => [0, 0, 0, 255],
                15..=24 => [250, 250, 250, 255],
                _ => [60, 60, 60, 255],
            })
            .collect();
        let pal = find_palette(&px, w, h, PaletteSize::Max(2));
        assert_eq!(pal.len(), 3);
        assert_eq!((pal[1].rgb, pal[2].rgb), ([0, 0, 0], [250, 250, 250]));
    }
}
