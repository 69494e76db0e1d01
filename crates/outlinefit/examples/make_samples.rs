//! Regenerates the bundled sample images in `samples/`.
//!
//! Run with `cargo run --release --example make_samples`. Every image is
//! produced from fixed geometry (hand-written `tiny_skia` paths) or from the
//! bundled font `samples/fonts/DejaVuSans.ttf` rendered with `ab_glyph`, with
//! no randomness, clock or system font involved, so the PNGs are byte-identical
//! on every run.
//!
//! Written files (see `samples/README.md` for what each one tests):
//!
//! * `s.png`, `e.png` — letters "s" and "e", ~200 px tall, anti-aliased,
//!   8-bit grayscale, black on white;
//! * `aeroplane.png` — top view of an aeroplane (smooth nose, sharp wing
//!   and tail-plane tips), anti-aliased grayscale;
//! * `pear.png` — pear silhouette with a waist and a short stalk, grayscale;
//! * `glyph_aa.png` — a small anti-aliased "A" (em 64 px): a hole and corners;
//! * `glyph_bw.png` — a bilevel "R" (em 128 px, thresholded at 50 %): only
//!   the values 0 and 255;
//! * `logo.png` — RGBA logo on a transparent background: a ring with a disk
//!   inside it (hole and island) and a rounded square with two round holes;
//!   the alpha channel is the shape.

use std::error::Error;
use std::path::{Path, PathBuf};

use ab_glyph::{point, Font, FontRef, PxScale};
use image::ExtendedColorType;
use resvg::tiny_skia::{FillRule, LineCap, Paint, PathBuilder, Pixmap, Stroke, Transform};

type Res<T> = Result<T, Box<dyn Error>>;

/// A point of a hand-written outline.
type P = (f32, f32);

/// One segment of a half outline; the start point is the previous end point.
#[derive(Clone, Copy)]
enum Seg {
    Line(P),
    Quad(P, P),
    Cubic(P, P, P),
}

impl Seg {
    fn end(self) -> P {
        match self {
            Seg::Line(p) | Seg::Quad(_, p) | Seg::Cubic(_, _, p) => p,
        }
    }
}

fn push_seg(pb: &mut PathBuilder, seg: Seg) {
    match seg {
        Seg::Line(p) => pb.line_to(p.0, p.1),
        Seg::Quad(c, p) => pb.quad_to(c.0, c.1, p.0, p.1),
        Seg::Cubic(c1, c2, p) => pb.cubic_to(c1.0, c1.1, c2.0, c2.1, p.0, p.1),
    }
}

/// Builds a closed outline symmetric about the vertical line `x = axis`.
///
/// `start` and the last segment's end must lie on the axis; the segments
/// describe the right half, the left half is their mirror image traversed
/// backwards.
fn symmetric_outline(pb: &mut PathBuilder, axis: f32, start: P, right: &[Seg]) {
    let mirror = |p: P| (2.0 * axis - p.0, p.1);
    pb.move_to(start.0, start.1);
    for &seg in right {
        push_seg(pb, seg);
    }
    // Walk the right half backwards, mirrored: each segment now ends where it
    // used to start, with its control points in reverse order.
    for (i, &seg) in right.iter().enumerate().rev() {
        let from = if i == 0 { start } else { right[i - 1].end() };
        let m = mirror(from);
        let back = match seg {
            Seg::Line(_) => Seg::Line(m),
            Seg::Quad(c, _) => Seg::Quad(mirror(c), m),
            Seg::Cubic(c1, c2, _) => Seg::Cubic(mirror(c2), mirror(c1), m),
        };
        push_seg(pb, back);
    }
    pb.close();
}

/// A transparent pixmap of the given size.
fn pixmap(width: u32, height: u32) -> Res<Pixmap> {
    Pixmap::new(width, height).ok_or_else(|| format!("bad pixmap size {width}x{height}").into())
}

/// Opaque black anti-aliased paint.
fn black_paint() -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(0, 0, 0, 255);
    paint.anti_alias = true;
    paint
}

/// Converts the alpha of a pixmap (drawn in black on transparent) into an
/// 8-bit grayscale image, black shape on white.
fn alpha_to_gray(pixmap: &Pixmap) -> Vec<u8> {
    pixmap.pixels().iter().map(|p| 255 - p.alpha()).collect()
}

fn save_gray(path: &Path, width: u32, height: u32, gray: &[u8]) -> Res<()> {
    image::save_buffer(path, gray, width, height, ExtendedColorType::L8)?;
    println!("wrote {} ({width}x{height}, L8)", path.display());
    Ok(())
}

fn save_rgba(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Res<()> {
    image::save_buffer(path, rgba, width, height, ExtendedColorType::Rgba8)?;
    println!("wrote {} ({width}x{height}, RGBA8)", path.display());
    Ok(())
}

/// How big to draw a glyph.
#[derive(Clone, Copy)]
enum GlyphSize {
    /// Height of the glyph's own outline bounding box, in pixels.
    InkHeight(f32),
    /// Size of the em square, in pixels.
    Em(f32),
}

/// Renders one character with area coverage (0..=1) on a canvas that leaves
/// `margin` pixels around the glyph's pixel bounds.
fn render_glyph(
    font: &FontRef<'_>,
    ch: char,
    size: GlyphSize,
    margin: u32,
) -> Res<(u32, u32, Vec<f32>)> {
    let id = font.glyph_id(ch);
    // ab_glyph's PxScale is the pixel height of ascent - descent.
    let px = match size {
        GlyphSize::InkHeight(h) => {
            let outline = font
                .outline(id)
                .ok_or_else(|| format!("no outline for {ch:?}"))?;
            // Unscaled outline bounds store y_max in `min.y` and y_min in `max.y`.
            let ink = (outline.bounds.min.y - outline.bounds.max.y).abs();
            h * font.height_unscaled() / ink
        }
        GlyphSize::Em(em) => {
            let upem = font.units_per_em().ok_or("font has no units per em")?;
            em * font.height_unscaled() / upem
        }
    };
    let glyph = id.with_scale_and_position(PxScale::from(px), point(0.0, 0.0));
    let outlined = font
        .outline_glyph(glyph)
        .ok_or_else(|| format!("cannot outline {ch:?}"))?;
    let bounds = outlined.px_bounds();
    // px_bounds are whole pixels; the casts only drop the (zero) fraction.
    let gw = bounds.width().round() as u32;
    let gh = bounds.height().round() as u32;
    let (w, h) = (gw + 2 * margin, gh + 2 * margin);
    let mut cov = vec![0.0f32; (w * h) as usize];
    outlined.draw(|x, y, c| {
        let (x, y) = (x + margin, y + margin);
        if x < w && y < h {
            cov[(y * w + x) as usize] = c.clamp(0.0, 1.0);
        }
    });
    Ok((w, h, cov))
}

/// Coverage to black-on-white gray levels.
fn coverage_to_gray(cov: &[f32]) -> Vec<u8> {
    cov.iter()
        .map(|&c| (255.0 * (1.0 - c)).round() as u8)
        .collect()
}

fn glyph_samples(dir: &Path, font: &FontRef<'_>) -> Res<()> {
    for (ch, name) in [('s', "s.png"), ('e', "e.png")] {
        let (w, h, cov) = render_glyph(font, ch, GlyphSize::InkHeight(200.0), 24)?;
        save_gray(&dir.join(name), w, h, &coverage_to_gray(&cov))?;
    }

    let (w, h, cov) = render_glyph(font, 'A', GlyphSize::Em(64.0), 8)?;
    save_gray(&dir.join("glyph_aa.png"), w, h, &coverage_to_gray(&cov))?;

    let (w, h, cov) = render_glyph(font, 'R', GlyphSize::Em(128.0), 12)?;
    let bw: Vec<u8> = cov
        .iter()
        .map(|&c| if c >= 0.5 { 0 } else { 255 })
        .collect();
    save_gray(&dir.join("glyph_bw.png"), w, h, &bw)?;
    Ok(())
}

/// Top view of an aeroplane, nose up: rounded nose and tail cone, straight
/// swept wings and tail plane with sharp corners at the tips and roots.
fn aeroplane(dir: &Path) -> Res<()> {
    let (w, h) = (256, 256);
    let right = [
        // Nose: horizontal tangent on the axis, vertical where it meets the
        // straight fuselage side, so the whole nose is smooth.
        Seg::Cubic((136.0, 10.0), (141.0, 26.0), (141.0, 52.0)),
        Seg::Line((141.0, 92.0)),
        // Wing: swept leading edge, square tip, swept trailing edge.
        Seg::Line((243.0, 150.0)),
        Seg::Line((243.0, 163.0)),
        Seg::Line((141.0, 138.0)),
        // Rear fuselage tapers gently.
        Seg::Quad((141.0, 172.0), (137.0, 198.0)),
        // Tail plane.
        Seg::Line((180.0, 224.0)),
        Seg::Line((180.0, 234.0)),
        Seg::Line((135.0, 228.0)),
        // Tail cone, horizontal tangent on the axis.
        Seg::Cubic((135.0, 238.0), (132.0, 246.0), (128.0, 246.0)),
    ];
    let mut pb = PathBuilder::new();
    symmetric_outline(&mut pb, 128.0, (128.0, 10.0), &right);
    let path = pb.finish().ok_or("empty aeroplane path")?;
    let mut pm = pixmap(w, h)?;
    pm.fill_path(
        &path,
        &black_paint(),
        FillRule::Winding,
        Transform::identity(),
        None,
    );
    save_gray(&dir.join("aeroplane.png"), w, h, &alpha_to_gray(&pm))
}

/// A pear: round belly, narrower shoulders with a concave waist between,
/// and a short curved stalk; slightly tilted.
fn pear(dir: &Path) -> Res<()> {
    let (w, h) = (224, 288);
    let right = [
        Seg::Cubic((130.0, 62.0), (146.0, 76.0), (146.0, 98.0)),
        // Waist: leaves the shoulder going straight down, swings out to the belly.
        Seg::Cubic((146.0, 124.0), (184.0, 142.0), (184.0, 196.0)),
        Seg::Cubic((184.0, 240.0), (152.0, 268.0), (112.0, 268.0)),
    ];
    let mut pb = PathBuilder::new();
    symmetric_outline(&mut pb, 112.0, (112.0, 62.0), &right);
    let body = pb.finish().ok_or("empty pear path")?;

    let mut pb = PathBuilder::new();
    pb.move_to(112.0, 70.0);
    pb.cubic_to(112.0, 50.0, 116.0, 36.0, 126.0, 24.0);
    let stalk = pb.finish().ok_or("empty stalk path")?;
    let stroke = Stroke {
        width: 7.0,
        line_cap: LineCap::Round,
        ..Stroke::default()
    };

    let tilt = Transform::from_rotate_at(8.0, 112.0, 165.0);
    let mut pm = pixmap(w, h)?;
    let paint = black_paint();
    pm.fill_path(&body, &paint, FillRule::Winding, tilt, None);
    pm.stroke_path(&stalk, &paint, &stroke, tilt, None);
    save_gray(&dir.join("pear.png"), w, h, &alpha_to_gray(&pm))
}

/// Appends a rounded rectangle (circular corners approximated by cubics).
fn push_round_rect(pb: &mut PathBuilder, x0: f32, y0: f32, x1: f32, y1: f32, r: f32) {
    let k = 0.552_284_8 * r;
    pb.move_to(x0 + r, y0);
    pb.line_to(x1 - r, y0);
    pb.cubic_to(x1 - r + k, y0, x1, y0 + r - k, x1, y0 + r);
    pb.line_to(x1, y1 - r);
    pb.cubic_to(x1, y1 - r + k, x1 - r + k, y1, x1 - r, y1);
    pb.line_to(x0 + r, y1);
    pb.cubic_to(x0 + r - k, y1, x0, y1 - r + k, x0, y1 - r);
    pb.line_to(x0, y0 + r);
    pb.cubic_to(x0, y0 + r - k, x0 + r - k, y0, x0 + r, y0);
    pb.close();
}

/// RGBA logo on a transparent background: ring + inner disk (a hole with an
/// island) and a rounded square with two round holes. Even-odd filling makes
/// the nested contours holes/islands regardless of their direction.
fn logo(dir: &Path) -> Res<()> {
    let (w, h) = (300, 160);
    let colour = [28u8, 38, 78];

    let mut pb = PathBuilder::new();
    pb.push_circle(80.0, 80.0, 64.0);
    pb.push_circle(80.0, 80.0, 46.0);
    pb.push_circle(80.0, 80.0, 26.0);
    push_round_rect(&mut pb, 170.0, 22.0, 286.0, 138.0, 22.0);
    pb.push_circle(202.0, 80.0, 17.0);
    pb.push_circle(254.0, 80.0, 17.0);
    let path = pb.finish().ok_or("empty logo path")?;

    let mut pm = pixmap(w, h)?;
    pm.fill_path(
        &path,
        &black_paint(),
        FillRule::EvenOdd,
        Transform::identity(),
        None,
    );
    // Straight (non-premultiplied) alpha: constant colour, alpha = coverage.
    let rgba: Vec<u8> = pm
        .pixels()
        .iter()
        .flat_map(|p| [colour[0], colour[1], colour[2], p.alpha()])
        .collect();
    save_rgba(&dir.join("logo.png"), w, h, &rgba)
}

/// Line art for `--mode centerline`: a pen-drawn S-curve, a cross with a curved tail
/// (a "t"), a closed loop, and a brush stroke that tapers from 9 px to 2 px (drawn as
/// disks along its centre line, since a stroke of varying width is a union of disks).
fn sketch(dir: &Path) -> Res<()> {
    let (w, h) = (320, 170);
    let paint = black_paint();
    let pen = Stroke {
        width: 5.0,
        line_cap: LineCap::Round,
        line_join: resvg::tiny_skia::LineJoin::Round,
        ..Stroke::default()
    };
    let mut pm = pixmap(w, h)?;
    let mut pb = PathBuilder::new();
    pb.move_to(20.0, 130.0);
    pb.cubic_to(120.0, 150.0, -20.0, 20.0, 80.0, 35.0);
    // The "t": a stem with a curved foot, crossed by a bar.
    pb.move_to(130.0, 25.0);
    pb.line_to(130.0, 120.0);
    pb.cubic_to(130.0, 140.0, 145.0, 145.0, 160.0, 135.0);
    pb.move_to(110.0, 60.0);
    pb.line_to(155.0, 60.0);
    pb.push_circle(215.0, 60.0, 30.0);
    let path = pb.finish().ok_or("empty sketch path")?;
    pm.stroke_path(&path, &paint, &pen, Transform::identity(), None);
    // The brush stroke: disks every quarter pixel along a cubic, radius 4.5 → 1.
    let mut brush = PathBuilder::new();
    let (p0, p1, p2, p3) = (
        (190.0, 150.0),
        (230.0, 100.0),
        (270.0, 170.0),
        (305.0, 110.0),
    );
    let steps = 800;
    for k in 0..=steps {
        let t = k as f32 / steps as f32;
        let m = 1.0 - t;
        let x =
            m * m * m * p0.0 + 3.0 * m * m * t * p1.0 + 3.0 * m * t * t * p2.0 + t * t * t * p3.0;
        let y =
            m * m * m * p0.1 + 3.0 * m * m * t * p1.1 + 3.0 * m * t * t * p2.1 + t * t * t * p3.1;
        brush.push_circle(x, y, 4.5 - 3.5 * t);
    }
    let brush = brush.finish().ok_or("empty brush path")?;
    pm.fill_path(
        &brush,
        &paint,
        FillRule::Winding,
        Transform::identity(),
        None,
    );
    save_gray(&dir.join("sketch.png"), w, h, &alpha_to_gray(&pm))
}

fn main() -> Res<()> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    std::fs::create_dir_all(&dir)?;
    let font_path = dir.join("fonts").join("DejaVuSans.ttf");
    let font_data = std::fs::read(&font_path)
        .map_err(|e| format!("cannot read bundled font {}: {e}", font_path.display()))?;
    let font = FontRef::try_from_slice(&font_data)?;

    glyph_samples(&dir, &font)?;
    aeroplane(&dir)?;
    pear(&dir)?;
    logo(&dir)?;
    sketch(&dir)?;
    Ok(())
}
