//! The pieces the tracer cuts an outline into, against shapes whose pieces are known: a
//! polygon's sides between its exact corners, a circle (no corner; rational cubics draw
//! circular arcs exactly, so a few pieces), and a superellipse (no corner, curvature
//! varying smoothly, at most two pieces per quadrant).

mod common;

use outlinefit::{trace_bitmap, Bitmap, Config, JointKind, Point, TraceResult};

fn trace(w: usize, h: usize, inside: impl Fn(f64, f64) -> bool) -> TraceResult {
    let coverage = common::supersampled_coverage(w, h, 8, inside);
    let bitmap = Bitmap::from_coverage(w as u32, h as u32, coverage, None).unwrap();
    let config = Config {
        timings: false,
        ..Config::default()
    };
    trace_bitmap(&bitmap, &config).unwrap()
}

fn corners(r: &TraceResult) -> Vec<Point> {
    r.contours[0]
        .joints
        .iter()
        .filter(|j| j.kind == JointKind::Corner)
        .map(|j| j.position)
        .collect()
}

/// A rotated pentagon: five corners, each within 0.15 px of a true vertex, and one segment
/// per side (a straight side needs no more).
#[test]
fn a_polygon_is_cut_at_its_corners_into_one_piece_per_side() {
    let (cx, cy, r) = (100.0, 95.0, 70.0);
    let vertices: Vec<(f64, f64)> = (0..5)
        .map(|k| {
            let a = 0.3 + k as f64 * std::f64::consts::TAU / 5.0;
            (cx + r * a.cos(), cy + r * a.sin())
        })
        .collect();
    let inside = |x: f64, y: f64| {
        (0..5).all(|k| {
            let (a, b) = (vertices[k], vertices[(k + 1) % 5]);
            // The centre is on the inner side of every edge.
            let side = |px: f64, py: f64| (b.0 - a.0) * (py - a.1) - (b.1 - a.1) * (px - a.0);
            side(x, y) * side(cx, cy) >= 0.0
        })
    };
    let result = trace(200, 190, inside);
    assert_eq!(result.contours.len(), 1);
    assert!(result.fidelity.held);
    let found = corners(&result);
    assert_eq!(found.len(), 5, "corners {found:?}");
    for v in &vertices {
        let nearest = found
            .iter()
            .map(|p| p.distance(Point::new(v.0, v.1)))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 0.15,
            "vertex {v:?}: nearest corner {nearest} px away"
        );
    }
    assert_eq!(result.contours[0].segments.len(), 5);
    for s in &result.contours[0].segments {
        assert!(
            s.error.max_distance <= 0.3 + 1e-9,
            "{}",
            s.error.max_distance
        );
    }
}

/// A circle of radius 60 px: no corner, G1 everywhere, at most four pieces.
#[test]
fn a_circle_has_no_corner_and_few_pieces() {
    let result = trace(160, 160, |x, y| (x - 80.0).hypot(y - 80.0) < 60.0);
    assert_eq!(result.contours.len(), 1);
    assert!(result.fidelity.held);
    assert!(corners(&result).is_empty());
    let c = &result.contours[0];
    assert!(c.segments.len() <= 4, "{} pieces", c.segments.len());
    for j in &c.joints {
        assert!(j.angle < 1e-6, "joint angle {}", j.angle);
    }
}

/// The superellipse |x/80|⁴ + |y/50|⁴ = 1: no corner, and a few pieces per quadrant (9 in
/// all since a long piece is split into polynomial cubics before any weight search; 8
/// before).
#[test]
fn a_superellipse_has_no_corner_and_a_few_pieces_per_quadrant() {
    let result = trace(200, 140, |x, y| {
        ((x - 100.0) / 80.0).powi(4) + ((y - 70.0) / 50.0).powi(4) < 1.0
    });
    assert_eq!(result.contours.len(), 1);
    assert!(result.fidelity.held);
    assert!(
        corners(&result).is_empty(),
        "corners {:?}",
        corners(&result)
    );
    let c = &result.contours[0];
    assert!(c.segments.len() <= 10, "{} pieces", c.segments.len());
    for j in &c.joints {
        assert!(j.angle < 1e-6, "joint angle {}", j.angle);
    }
}
