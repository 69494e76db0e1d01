//! Centre-line tracing against strokes drawn from exact geometry: a tapered arc, a
//! constant-width S, an X, a T and a closed ring, anti-aliased (8 × 8 samples per pixel).
//! Each must come back as the right number of strokes, with every traced centre within
//! 0.25 px of the true centre line and every traced width within 0.3 px of the true one
//! (away from junctions, where two strokes' widths merge); a filled disk must be reported
//! as not stroke-like.

mod common;

use outlinefit::centerline::{trace_centerline, CenterlineResult, StrokeEnd, StrokeWidth};
use outlinefit::{Bitmap, Config, Point};

/// Coverage of the shape whose signed distance is `sdf` (negative inside): pixels far
/// from the edge are 0 or 1, the rest are supersampled 8 × 8.
fn coverage(w: usize, h: usize, sdf: &dyn Fn(Point) -> f64) -> Vec<f32> {
    let mut out = vec![0f32; w * h];
    for (k, c) in out.iter_mut().enumerate() {
        let (x, y) = ((k % w) as f64, (k / w) as f64);
        let d = sdf(Point::new(x + 0.5, y + 0.5));
        *c = if d > 1.0 {
            0.0
        } else if d < -1.0 {
            1.0
        } else {
            let mut hits = 0;
            for i in 0..8 {
                for j in 0..8 {
                    let p = Point::new(x + (j as f64 + 0.5) / 8.0, y + (i as f64 + 0.5) / 8.0);
                    hits += u32::from(sdf(p) < 0.0);
                }
            }
            hits as f32 / 64.0
        };
    }
    out
}

fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.dot(ab)).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// A stroke's true centre line as a dense polyline with the radius at each vertex.
struct Truth {
    centre: Vec<Point>,
    radius: Vec<f64>,
}

impl Truth {
    /// Distance from `p` to the centre line, and the true radius at the nearest point.
    fn nearest(&self, p: Point) -> (f64, f64) {
        let mut best = (f64::INFINITY, 0.0);
        for k in 0..self.centre.len() - 1 {
            let d = segment_distance(p, self.centre[k], self.centre[k + 1]);
            if d < best.0 {
                best = (d, self.radius[k]);
            }
        }
        best
    }

    /// Signed distance of the union of disks along the centre line (radius linear on each
    /// short edge, so the union is its vertices' disks and the hulls between them).
    fn sdf(&self, p: Point) -> f64 {
        let mut best = f64::INFINITY;
        for k in 0..self.centre.len() - 1 {
            let (a, b) = (self.centre[k], self.centre[k + 1]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.dot(ab)).clamp(0.0, 1.0);
            let r = self.radius[k] + t * (self.radius[k + 1] - self.radius[k]);
            best = best.min(p.distance(a + ab * t) - r);
        }
        best
    }
}

fn polyline(n: usize, f: impl Fn(f64) -> (Point, f64)) -> Truth {
    let (centre, radius) = (0..=n).map(|k| f(k as f64 / n as f64)).unzip();
    Truth { centre, radius }
}

fn trace(w: usize, h: usize, truths: &[Truth], width: StrokeWidth) -> CenterlineResult {
    let sdf = |p: Point| {
        truths
            .iter()
            .map(|t| t.sdf(p))
            .fold(f64::INFINITY, f64::min)
    };
    let cov = coverage(w, h, &sdf);
    let bitmap = Bitmap::from_coverage(w as u32, h as u32, cov, None).unwrap();
    // The fit keeps the centre within the tolerance of the measured centres; 0.2 px
    // leaves room for the measurement within the 0.25 px asked of the result.
    let config = Config {
        timings: false,
        tolerance: 0.2,
        ..Config::default()
    };
    trace_centerline(&bitmap, &config, width).unwrap()
}

/// The largest centre distance and width error over the traced strokes (sampled), the
/// truth being the nearest of `truths`; samples within `skip` px of any point of `away`
/// (junctions) are left out of the width error.
fn errors(
    result: &CenterlineResult,
    truths: &[Truth],
    away: &[Point],
    skip: f64,
) -> (f64, f64, f64) {
    let (mut centre_max, mut width_max, mut sum, mut n) = (0.0f64, 0.0f64, 0.0, 0.0);
    for stroke in &result.strokes {
        for seg in &stroke.segments {
            for k in 0..=50 {
                let d = seg.curve.eval(k as f64 / 50.0);
                let (dist, r) = truths
                    .iter()
                    .map(|t| t.nearest(d.center))
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap();
                centre_max = centre_max.max(dist);
                sum += dist;
                n += 1.0;
                if away.iter().all(|j| j.distance(d.center) > skip) {
                    width_max = width_max.max((2.0 * d.radius - 2.0 * r).abs());
                }
            }
        }
    }
    (centre_max, sum / n, width_max)
}

#[test]
fn a_tapered_arc_is_one_stroke_with_its_width() {
    // Centre on a circle of radius 60 about (80, 80), from 200° to 340°, width 8 → 3.
    let arc = polyline(400, |t| {
        let a = (200.0 + 140.0 * t).to_radians();
        (
            Point::new(80.0 + 60.0 * a.cos(), 80.0 + 60.0 * a.sin()),
            4.0 - 2.5 * t,
        )
    });
    let result = trace(160, 100, std::slice::from_ref(&arc), StrokeWidth::Variable);
    assert_eq!(result.strokes.len(), 1);
    assert!(result.junctions.is_empty());
    let (centre_max, centre_mean, width_max) = errors(&result, &[arc], &[], 0.0);
    assert!(
        centre_max <= 0.25 && centre_mean <= 0.1,
        "{centre_max} {centre_mean}"
    );
    assert!(width_max <= 0.3, "width off by {width_max}");
    let s = &result.strokes[0];
    assert!((s.width_range[1] - 8.0).abs() < 0.3 && (s.width_range[0] - 3.0).abs() < 0.3);
    assert!(result.check.held && !result.not_stroke_like);
}

#[test]
fn a_constant_width_s_is_one_stroke_of_one_width() {
    let bez = |t: f64| {
        let m = 1.0 - t;
        let (p0, p1, p2, p3) = ((20.0, 110.0), (160.0, 130.0), (-20.0, 10.0), (120.0, 30.0));
        Point::new(
            m * m * m * p0.0 + 3.0 * m * m * t * p1.0 + 3.0 * m * t * t * p2.0 + t * t * t * p3.0,
            m * m * m * p0.1 + 3.0 * m * m * t * p1.1 + 3.0 * m * t * t * p2.1 + t * t * t * p3.1,
        )
    };
    let s = polyline(600, |t| (bez(t), 3.0));
    for width in [StrokeWidth::Variable, StrokeWidth::Constant] {
        let result = trace(140, 140, std::slice::from_ref(&s), width);
        assert_eq!(result.strokes.len(), 1, "{width:?}");
        let (centre_max, centre_mean, width_max) =
            errors(&result, std::slice::from_ref(&s), &[], 0.0);
        assert!(
            centre_max <= 0.25 && centre_mean <= 0.1,
            "{width:?}: {centre_max} {centre_mean}"
        );
        assert!(width_max <= 0.3, "{width:?}: width off by {width_max}");
        let range = result.strokes[0].width_range;
        if width == StrokeWidth::Constant {
            assert!((range[0] - range[1]).abs() < 1e-9, "{range:?}");
        }
    }
}

#[test]
fn an_x_is_two_strokes_through_one_junction() {
    let a = polyline(200, |t| {
        (Point::new(20.0 + 100.0 * t, 20.0 + 80.0 * t), 2.5)
    });
    let b = polyline(200, |t| {
        (Point::new(20.0 + 100.0 * t, 100.0 - 80.0 * t), 2.5)
    });
    let result = trace(140, 120, &[a, b], StrokeWidth::Variable);
    assert_eq!(result.strokes.len(), 2);
    assert_eq!(result.junctions.len(), 1);
    assert_eq!(result.junctions[0].branches, 4);
    let centre = Point::new(70.0, 60.0);
    assert!(result.junctions[0].centre.distance(centre) < 1.0);
    // Both strokes pass through: their ends are free.
    for s in &result.strokes {
        assert_eq!(s.ends, [StrokeEnd::Free, StrokeEnd::Free]);
    }
    let a = polyline(200, |t| {
        (Point::new(20.0 + 100.0 * t, 20.0 + 80.0 * t), 2.5)
    });
    let b = polyline(200, |t| {
        (Point::new(20.0 + 100.0 * t, 100.0 - 80.0 * t), 2.5)
    });
    let (centre_max, centre_mean, width_max) = errors(&result, &[a, b], &[centre], 8.0);
    assert!(
        centre_max <= 0.25 && centre_mean <= 0.1,
        "{centre_max} {centre_mean}"
    );
    assert!(width_max <= 0.3, "width off by {width_max}");
}

#[test]
fn a_t_is_a_bar_and_a_stem_that_ends_at_it() {
    let bar = polyline(200, |t| (Point::new(20.0 + 100.0 * t, 30.0), 3.0));
    let stem = polyline(200, |t| (Point::new(70.0, 30.0 + 80.0 * t), 3.0));
    let result = trace(140, 130, &[bar, stem], StrokeWidth::Variable);
    assert_eq!(result.strokes.len(), 2);
    assert_eq!(result.junctions.len(), 1);
    let ends: Vec<[StrokeEnd; 2]> = result.strokes.iter().map(|s| s.ends).collect();
    assert!(
        ends.contains(&[StrokeEnd::Free, StrokeEnd::Free]),
        "{ends:?}"
    );
    assert!(
        ends.iter().any(|e| e.contains(&StrokeEnd::Junction(0))),
        "the stem ends at the junction: {ends:?}"
    );
    let bar = polyline(200, |t| (Point::new(20.0 + 100.0 * t, 30.0), 3.0));
    let stem = polyline(200, |t| (Point::new(70.0, 30.0 + 80.0 * t), 3.0));
    // Widths are checked two widths away from the junction and from the three free ends, where the
    // last few pixels' radii come out up to 0.3 px small (see the README).
    let away = [
        Point::new(70.0, 30.0),
        Point::new(20.0, 30.0),
        Point::new(120.0, 30.0),
        Point::new(70.0, 110.0),
    ];
    let (centre_max, centre_mean, width_max) = errors(&result, &[bar, stem], &away, 12.0);
    assert!(
        centre_max <= 0.25 && centre_mean <= 0.1,
        "{centre_max} {centre_mean}"
    );
    assert!(width_max <= 0.3, "width off by {width_max}");
}

#[test]
fn a_ring_is_one_closed_stroke() {
    let ring = polyline(720, |t| {
        let a = t * std::f64::consts::TAU;
        (
            Point::new(60.0 + 40.0 * a.cos(), 60.0 + 40.0 * a.sin()),
            2.0,
        )
    });
    let result = trace(120, 120, std::slice::from_ref(&ring), StrokeWidth::Variable);
    assert_eq!(result.strokes.len(), 1);
    assert!(result.strokes[0].closed);
    let (centre_max, centre_mean, width_max) = errors(&result, &[ring], &[], 0.0);
    assert!(
        centre_max <= 0.25 && centre_mean <= 0.1,
        "{centre_max} {centre_mean}"
    );
    assert!(width_max <= 0.3, "width off by {width_max}");
    // The ring closes on itself with a smooth joint: its first and last disks agree.
    let segs = &result.strokes[0].segments;
    let (first, last) = (
        segs[0].curve.eval(0.0),
        segs[segs.len() - 1].curve.eval(1.0),
    );
    assert!(first.center.distance(last.center) < 1e-9);
    assert!((first.radius - last.radius).abs() < 1e-9);
}

#[test]
fn a_filled_disk_is_reported_as_not_stroke_like() {
    let disk = Truth {
        centre: vec![Point::new(50.0, 50.0), Point::new(50.0, 50.000001)],
        radius: vec![30.0, 30.0],
    };
    let result = trace(100, 100, &[disk], StrokeWidth::Variable);
    assert!(result.not_stroke_like);
    assert!(!result.strokes.is_empty());
}
