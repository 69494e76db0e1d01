//! The colour pipeline as one call (see the module docs of `colour`).

use super::check;
use super::edges;
use super::fit;
use super::map::{self, Map, VOID_SIDE};
use super::palette::{self, Swatch};
use super::result::{Boundary, ColourFidelity, ColourOptions, ColourTrace, Layer, Layout, Region};
use crate::breaks::BreakOptions;
use crate::error::{Error, Result};
use crate::fit::lsq::LsqOptions;
use crate::geom::Point;
use crate::raster;
use crate::trace::Config;
use image::DynamicImage;
use std::path::Path;
use std::time::Instant;

/// Loads an image file and traces it in colour.
pub fn trace_colour_file(
    path: &Path,
    config: &Config,
    opts: &ColourOptions,
) -> Result<ColourTrace> {
    config.validate()?;
    let (img, _) = raster::decode_file(path, config.raster_options().decoding())?;
    trace_colour(&img, config, opts)
}

/// Decodes an image file's bytes (`name` for messages) and traces it in colour.
pub fn trace_colour_bytes(
    bytes: &[u8],
    name: &Path,
    config: &Config,
    opts: &ColourOptions,
) -> Result<ColourTrace> {
    config.validate()?;
    let (img, _) = raster::decode_bytes(bytes, name, config.raster_options().decoding())?;
    trace_colour(&img, config, opts)
}

/// Traces an image in colour (see the module docs).
pub fn trace_colour(
    img: &DynamicImage,
    config: &Config,
    opts: &ColourOptions,
) -> Result<ColourTrace> {
    config.validate()?;
    let started = Instant::now();
    let rgba = img.to_rgba8();
    let (w, h) = (rgba.width() as usize, rgba.height() as usize);
    if w == 0 || h == 0 {
        return Err(Error::ZeroSize {
            width: w as u32,
            height: h as u32,
        });
    }
    let px: Vec<[u8; 4]> = rgba.pixels().map(|p| p.0).collect();
    drop(rgba);
    let mut swatches = palette::find_palette(&px, w, h, opts.palette);
    let colours: Vec<[f32; 4]> = px.iter().map(|p| palette::premultiplied(*p)).collect();
    drop(px);
    let (mut label, pure, mixed_pixels) = palette::label_pixels(&colours, w, h, &swatches);
    let regions = map::regions(&mut label, &pure, w, h, config.min_area);
    drop(pure);
    for s in swatches.iter_mut() {
        s.pixels = 0;
    }
    for &l in &label {
        swatches[l as usize].pixels += 1;
    }
    let map = Map::new(&regions, w, h);
    let pixels = edges::Pixels {
        colours: &colours,
        label: &label,
        palette: &swatches,
        region_colour: &regions.colour,
    };
    let lines = edges::chain_polylines(&pixels, &map, mixed_pixels);
    let breaks = BreakOptions::for_image(config.corner_angle, w as u32, h as u32);
    let lsq = LsqOptions::for_tolerance(config.tolerance, config.timings);
    let fit_one =
        |(line, ch): (&Vec<Point>, &map::Chain)| fit::fit_boundary(line, ch.closed, &breaks, &lsq);
    let fitted: Vec<fit::FittedChain> = {
        use rayon::prelude::*;
        lines
            .par_iter()
            .zip(map.chains.par_iter())
            .map(fit_one)
            .collect()
    };
    let side = |s: u32| (s != VOID_SIDE).then_some(s as usize);
    let colour_of = |s: u32| side(s).map_or(0, |r| usize::from(regions.colour[r]));
    let boundaries: Vec<Boundary> = fitted
        .into_iter()
        .zip(&map.chains)
        .map(|(f, ch)| Boundary {
            right: side(ch.right),
            left: side(ch.left),
            colours: [colour_of(ch.right), colour_of(ch.left)],
            closed: ch.closed,
            points: f.points,
            segments: f.segments,
        })
        .collect();
    let layers = layers(&map, &regions, &swatches, opts.layout);
    let region_list: Vec<Region> = regions
        .colour
        .iter()
        .zip(&regions.area)
        .map(|(&c, &a)| Region {
            colour: usize::from(c),
            area: a,
        })
        .collect();
    let export_bound = lsq.export_bound;
    let mut trace = ColourTrace {
        width: w as u32,
        height: h as u32,
        palette: swatches,
        mixed_pixels,
        regions: region_list,
        boundaries,
        layout: opts.layout,
        layers,
        fidelity: ColourFidelity::default(),
        seconds: 0.0,
    };
    if config.check {
        trace.fidelity = check::check(&trace, &label, config, export_bound);
    }
    if config.timings {
        trace.seconds = started.elapsed().as_secs_f64();
    }
    Ok(trace)
}

/// The drawing order of the colours: most pixels first.
fn colour_order(palette: &[Swatch]) -> Vec<usize> {
    let mut order: Vec<usize> = (1..palette.len())
        .filter(|&c| palette[c].pixels > 0)
        .collect();
    order.sort_by(|&a, &b| palette[b].pixels.cmp(&palette[a].pixels).then(a.cmp(&b)));
    order
}

/// The layers of `layout` (see the module docs).
fn layers(map: &Map, regions: &map::Regions, palette: &[Swatch], layout: Layout) -> Vec<Layer> {
    let order = colour_order(palette);
    let mut rank = vec![usize::MAX; palette.len()];
    for (k, &c) in order.iter().enumerate() {
        rank[c] = k;
    }
    let colour = |r: u32| usize::from(regions.colour[r as usize]);
    order
        .iter()
        .map(|&c| {
            let loops = match layout {
                Layout::Cutout => map.loops(&|r| colour(r) == c),
                Layout::Stacked => {
                    // Regions that may extend this layer: later colours, opaque ones only
                    // (a translucent region over this colour would show it through).
                    let allowed = |r: u32| {
                        let k = colour(r);
                        k == c || (rank[k] > rank[c] && palette[k].alpha == 255)
                    };
                    let n = regions.colour.len();
                    let mut parent: Vec<u32> = (0..n as u32).collect();
                    fn find(parent: &mut [u32], mut x: u32) -> u32 {
                        while parent[x as usize] != x {
                            parent[x as usize] = parent[parent[x as usize] as usize];
                            x = parent[x as usize];
                        }
                        x
                    }
                    for ch in &map.chains {
                        if ch.right != VOID_SIDE
                            && ch.left != VOID_SIDE
                            && allowed(ch.right)
                            && allowed(ch.left)
                        {
                            let (a, b) = (find(&mut parent, ch.right), find(&mut parent, ch.left));
                            parent[a.max(b) as usize] = a.min(b);
                        }
                    }
                    let mut keep = vec![false; n];
                    for r in 0..n as u32 {
                        if colour(r) == c {
                            let root = find(&mut parent, r);
                            keep[root as usize] = true;
                        }
                    }
                    let inside: Vec<bool> = (0..n as u32)
                        .map(|r| allowed(r) && keep[find(&mut parent, r) as usize])
                        .collect();
                    map.loops(&|r| inside[r as usize])
                }
            };
            Layer { colour: c, loops }
        })
        .collect()
}
