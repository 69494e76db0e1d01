//! The check of drawn strokes against the input: the union of every piece's disks is
//! rasterised (pixel centres, disks sampled at most half a pixel apart along each piece)
//! and compared with the thresholded mask. A pixel is lost when it is ink and lies more
//! than `tolerance + 0.5` px outside the drawn strokes, invented when it is paper and
//! lies that far inside them (the half pixel is the mask's own uncertainty). Regions of
//! such pixels (8-connected) of at least `region` pixels fail the check.

use super::result::{Stroke, StrokeCheck};
use super::skeleton::Grid;

/// Signed distance (px) of every pixel centre from the drawn strokes' edge, negative
/// inside; `+∞` far outside.
fn drawn_distance(strokes: &[Stroke], width: usize, height: usize) -> Vec<f32> {
    let mut field = vec![f32::INFINITY; width * height];
    let mut stamp = |cx: f64, cy: f64, r: f64| {
        let reach = r.max(0.0) + 2.0;
        let x0 = ((cx - reach).floor().max(0.0)) as usize;
        let y0 = ((cy - reach).floor().max(0.0)) as usize;
        let x1 = ((cx + reach).ceil().max(0.0) as usize).min(width);
        let y1 = ((cy + reach).ceil().max(0.0) as usize).min(height);
        for y in y0..y1 {
            for x in x0..x1 {
                let d = ((x as f64 + 0.5 - cx).hypot(y as f64 + 0.5 - cy) - r) as f32;
                let f = &mut field[y * width + x];
                if d < *f {
                    *f = d;
                }
            }
        }
    };
    for stroke in strokes {
        for seg in &stroke.segments {
            let length = seg.chord_length();
            let steps = (2.0 * length).ceil().max(1.0) as usize;
            for i in 0..=steps {
                let d = seg.curve.eval(i as f64 / steps as f64);
                stamp(d.center.x, d.center.y, d.radius);
            }
        }
    }
    field
}

/// Checks `strokes` against the mask `ink`.
pub(crate) fn check(strokes: &[Stroke], ink: &Grid, tolerance: f64, region: f64) -> StrokeCheck {
    let (w, h) = (ink.width, ink.height);
    let field = drawn_distance(strokes, w, h);
    let margin = (tolerance + 0.5) as f32;
    let (mut both, mut either) = (0usize, 0usize);
    // 1 = lost, 2 = invented.
    let mut flag = vec![0u8; w * h];
    for i in 0..w * h {
        let drawn = field[i] <= 0.0;
        both += usize::from(drawn && ink.cells[i]);
        either += usize::from(drawn || ink.cells[i]);
        if ink.cells[i] && field[i] > margin {
            flag[i] = 1;
        } else if !ink.cells[i] && field[i] < -margin {
            flag[i] = 2;
        }
    }
    let mut result = StrokeCheck {
        iou: if either == 0 {
            1.0
        } else {
            both as f64 / either as f64
        },
        ..StrokeCheck::default()
    };
    let mut seen = vec![false; w * h];
    let mut stack = Vec::new();
    for start in 0..w * h {
        if flag[start] == 0 || seen[start] {
            continue;
        }
        let kind = flag[start];
        let mut size = 0usize;
        seen[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            for (dx, dy) in super::skeleton::RING {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx as usize >= w || ny as usize >= h {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if flag[j] == kind && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if kind == 1 {
            result.lost_pixels += size;
        } else {
            result.invented_pixels += size;
        }
        if size as f64 >= region {
            if kind == 1 {
                result.lost_regions += 1;
            } else {
                result.invented_regions += 1;
            }
        }
        result.largest_region = result.largest_region.max(size);
    }
    result.held = result.lost_regions == 0 && result.invented_regions == 0;
    result
}
