use super::bilevel::QuadraticFit;
use super::lines::{fit_line, Line};
use super::*;
use crate::geom::angle_between;

/// Coverage of a shape by `ss`×`ss` supersampling of each pixel.
fn supersample(w: u32, h: u32, ss: u32, inside: impl Fn(f64, f64) -> bool) -> Vec<f32> {
    let mut cov = Vec::with_capacity((w * h) as usize);
    for r in 0..h {
        for c in 0..w {
            let mut hits = 0;
            for j in 0..ss {
                for i in 0..ss {
                    let x = c as f64 + (i as f64 + 0.5) / ss as f64;
                    let y = r as f64 + (j as f64 + 0.5) / ss as f64;
                    hits += u32::from(inside(x, y));
                }
            }
            cov.push(hits as f32 / (ss * ss) as f32);
        }
    }
    cov
}

/// A 0/1 image of a shape sampled at pixel centres.
fn binary(w: u32, h: u32, inside: impl Fn(f64, f64) -> bool) -> Vec<f32> {
    supersample(w, h, 1, inside)
}

fn opts(min_area: f64) -> ContourOptions {
    ContourOptions {
        min_area,
        edge_spread: false,
    }
}

/// Distance from `p` to the closed polyline.
fn distance_to_polyline(p: Point, pts: &[Point]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
            p.distance(a + ab * t)
        })
        .fold(f64::INFINITY, f64::min)
}

fn disk_bitmap(ss: u32) -> (Bitmap, Point, f64) {
    let centre = Point::new(24.37, 25.81);
    let radius = 20.0;
    let cov = supersample(50, 52, ss, |x, y| {
        Point::new(x, y).distance(centre) < radius
    });
    (
        Bitmap::from_coverage(50, 52, cov, None).unwrap(),
        centre,
        radius,
    )
}

/// (max, mean) of |distance to centre − radius|.
fn circle_errors(pts: &[Point], centre: Point, radius: f64) -> (f64, f64) {
    let errs: Vec<f64> = pts
        .iter()
        .map(|p| (p.distance(centre) - radius).abs())
        .collect();
    let max = errs.iter().cloned().fold(0.0, f64::max);
    (max, errs.iter().sum::<f64>() / errs.len() as f64)
}

#[test]
fn antialiased_disk_is_refined_to_a_twentieth_of_a_pixel() {
    let (bm, centre, radius) = disk_bitmap(16);
    assert!(!bm.is_bilevel());
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    assert_eq!(cs.len(), 1);
    let c = &cs[0];
    assert!(!c.is_hole && c.parent.is_none());
    let (max, mean) = circle_errors(&c.points, centre, radius);
    eprintln!("integral: max {max:.4} mean {mean:.4} n {}", c.points.len());
    assert!(max < 0.05, "max |r − R| = {max}");
    assert!(mean < 0.02, "mean |r − R| = {mean}");
    // About one point per 0.8 px of the 125.7 px circumference.
    let n = c.points.len() as f64;
    assert!((140.0..180.0).contains(&n), "{n} points");
    let area = signed_area(&c.points);
    let true_area = std::f64::consts::PI * radius * radius;
    assert!((area - true_area).abs() < 0.01 * true_area, "{area}");
}

#[test]
fn coverage_integration_beats_the_threshold_crossing() {
    let (bm, centre, radius) = disk_bitmap(16);
    let integral = extract_with(&bm, &opts(2.0), EdgeEstimator::CoverageIntegral)
        .unwrap()
        .contours;
    let crossing = extract_with(&bm, &opts(2.0), EdgeEstimator::LevelCrossing)
        .unwrap()
        .contours;
    let (imax, imean) = circle_errors(&integral[0].points, centre, radius);
    let (cmax, cmean) = circle_errors(&crossing[0].points, centre, radius);
    eprintln!("integral {imax:.4}/{imean:.4}, crossing {cmax:.4}/{cmean:.4}");
    assert!(imax < cmax && imean < cmean);
}

/// Turning angle (degrees) at every point of a closed polyline.
fn turning_degrees(pts: &[Point]) -> Vec<f64> {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let p = pts[i];
            angle_between(p - pts[(i + n - 1) % n], pts[(i + 1) % n] - p).to_degrees()
        })
        .collect()
}

/// Corners of a square of side `side` centred at `centre`, rotated by `deg`.
fn square_corners(centre: Point, side: f64, deg: f64) -> [Point; 4] {
    let (s, c) = deg.to_radians().sin_cos();
    let u = Point::new(c, s) * (side / 2.0);
    let v = Point::new(-s, c) * (side / 2.0);
    [
        centre - u - v,
        centre + u - v,
        centre + u + v,
        centre - u + v,
    ]
}

/// Inside test for a convex polygon given clockwise on screen.
fn inside_convex(poly: &[Point], p: Point) -> bool {
    let n = poly.len();
    (0..n).all(|i| (poly[(i + 1) % n] - poly[i]).cross(p - poly[i]) > 0.0)
}

#[test]
fn antialiased_rotated_square_keeps_its_corners() {
    let corners = square_corners(Point::new(20.3, 19.6), 24.0, 30.0);
    let cov = supersample(40, 40, 16, |x, y| inside_convex(&corners, Point::new(x, y)));
    let bm = Bitmap::from_coverage(40, 40, cov, None).unwrap();
    assert!(!bm.is_bilevel());
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    assert_eq!(cs.len(), 1);
    let pts = &cs[0].points;
    for corner in corners {
        let d = distance_to_polyline(corner, pts);
        eprintln!("AA corner distance {d:.3}");
        assert!(d < 0.3, "corner {corner:?} is {d} px from the outline");
    }
    // Away from the corners the points lie on the sides.
    let mut worst: f64 = 0.0;
    for p in pts {
        if corners.iter().all(|c| c.distance(*p) > 1.5) {
            worst = worst.max(side_distance(*p, &corners));
        }
    }
    eprintln!("AA square side error {worst:.4}");
    assert!(worst < 0.05, "side error {worst}");
}

#[test]
fn bilevel_disk_is_smooth_and_close() {
    // Three sub-pixel centres: the first puts the top of the circle 0.4 px above the
    // first row of crack midpoints, where plain smoothing of the midpoints is 0.40 px
    // off.
    for centre in [
        Point::new(50.3, 49.6),
        Point::new(50.03, 50.0),
        Point::new(50.73, 50.59),
    ] {
        let radius = 40.0;
        let cov = binary(101, 100, |x, y| Point::new(x, y).distance(centre) < radius);
        let bm = Bitmap::from_coverage(101, 100, cov, None).unwrap();
        assert!(bm.is_bilevel());
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        assert_eq!(cs.len(), 1);
        let pts = &cs[0].points;
        let (max, mean) = circle_errors(pts, centre, radius);
        let turn = turning_degrees(pts).into_iter().fold(0.0, f64::max);
        eprintln!("bilevel disk {centre:?}: max {max:.3} mean {mean:.3} turn {turn:.1}°");
        // Measured: max 0.11–0.15 px, mean ≤ 0.053 px, turn ≤ 4°.
        assert!(max < 0.3, "max |r − R| = {max}");
        assert!(mean < 0.08, "mean |r − R| = {mean}");
        assert!(turn < 15.0, "turn {turn}°");
    }
}

#[test]
fn bilevel_square_stays_square() {
    // Pixels 5..=24 in both directions: the square [5, 25]².
    let cov = binary(30, 30, |x, y| {
        (5.0..25.0).contains(&x) && (5.0..25.0).contains(&y)
    });
    let bm = Bitmap::from_coverage(30, 30, cov, None).unwrap();
    assert!(bm.is_bilevel());
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    assert_eq!(cs.len(), 1);
    let pts = &cs[0].points;
    for corner in [(5.0, 5.0), (25.0, 5.0), (25.0, 25.0), (5.0, 25.0)] {
        let corner = Point::new(corner.0, corner.1);
        let d = pts
            .iter()
            .map(|p| p.distance(corner))
            .fold(f64::INFINITY, f64::min);
        assert!(d < 0.05, "corner {corner:?} at {d}");
    }
    // Every point on a side: the straight runs stay straight.
    for p in pts {
        let d = [p.x - 5.0, 25.0 - p.x, p.y - 5.0, 25.0 - p.y]
            .into_iter()
            .map(f64::abs)
            .fold(f64::INFINITY, f64::min);
        assert!(d < 1e-9, "{p:?}");
    }
    assert!((signed_area(pts) - 400.0).abs() < 1e-6);
    // 80 px of boundary at 0.8 px spacing.
    assert_eq!(pts.len(), 100);
}

#[test]
fn bilevel_rotated_square_has_sharp_corners() {
    let corners = square_corners(Point::new(30.3, 29.6), 36.0, 20.0);
    let cov = binary(60, 60, |x, y| inside_convex(&corners, Point::new(x, y)));
    let bm = Bitmap::from_coverage(60, 60, cov, None).unwrap();
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    let pts = &cs[0].points;
    for corner in corners {
        let d = distance_to_polyline(corner, pts);
        eprintln!("bilevel rotated corner {d:.3}");
        assert!(d < 0.7, "corner {corner:?} is {d} px away");
    }
}

/// Checks the invariants every result must satisfy: at least 3 finite points, outer
/// borders with positive area, holes negative, parents earlier in the list and of the
/// opposite kind.
fn check_invariants(cs: &[Contour]) {
    for (i, c) in cs.iter().enumerate() {
        assert!(
            c.points.len() >= 3,
            "contour {i} has {} points",
            c.points.len()
        );
        assert!(c.points.iter().all(|p| p.is_finite()));
        let area = signed_area(&c.points);
        assert_eq!(
            area < 0.0,
            c.is_hole,
            "contour {i}: area {area}, hole {}",
            c.is_hole
        );
        assert!(area != 0.0);
        match c.parent {
            Some(p) => {
                assert!(p < i, "contour {i} has parent {p}");
                assert_ne!(cs[p].is_hole, c.is_hole, "contour {i} and its parent {p}");
            }
            None => assert!(!c.is_hole, "hole {i} without parent"),
        }
    }
}

/// A disk of radius `outer` with a hole of radius `inner` and, if `island` > 0, a disk
/// of that radius in the hole.
fn rings(ss: u32, outer: f64, inner: f64, island: f64) -> Bitmap {
    let centre = Point::new(30.4, 29.7);
    let cov = supersample(61, 60, ss, |x, y| {
        let d = Point::new(x, y).distance(centre);
        (d < outer && d >= inner) || d < island
    });
    Bitmap::from_coverage(61, 60, cov, None).unwrap()
}

#[test]
fn ring_gives_an_outer_border_and_its_hole() {
    for ss in [16, 1] {
        let bm = rings(ss, 25.0, 12.0, 0.0);
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        check_invariants(&cs);
        assert_eq!(cs.len(), 2, "supersampling {ss}");
        assert!(!cs[0].is_hole && cs[0].parent.is_none());
        assert!(cs[1].is_hole);
        assert_eq!(cs[1].parent, Some(0));
        let pi = std::f64::consts::PI;
        let tolerance = if ss == 1 { 0.02 } else { 0.002 };
        let outer = signed_area(&cs[0].points);
        let hole = signed_area(&cs[1].points);
        assert!(
            (outer / (pi * 625.0) - 1.0).abs() < tolerance,
            "outer area {outer}"
        );
        assert!(
            (hole / (-pi * 144.0) - 1.0).abs() < tolerance,
            "hole area {hole}"
        );
    }
}

#[test]
fn island_in_a_hole_has_the_hole_as_parent() {
    for ss in [16, 1] {
        let bm = rings(ss, 25.0, 15.0, 7.0);
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        check_invariants(&cs);
        assert_eq!(cs.len(), 3, "supersampling {ss}");
        let hole = cs.iter().position(|c| c.is_hole).unwrap();
        let island = cs
            .iter()
            .position(|c| !c.is_hole && c.parent.is_some())
            .unwrap();
        assert_eq!(cs[hole].parent, Some(0));
        assert_eq!(cs[island].parent, Some(hole));
        let area = signed_area(&cs[island].points);
        let expected = std::f64::consts::PI * 49.0;
        assert!((area / expected - 1.0).abs() < 0.03, "island area {area}");
    }
}

#[test]
fn specks_and_everything_inside_them_are_dropped() {
    // A 20×20 square with a one-pixel hole, a one-pixel speck outside, and a 3×3 hole
    // holding a one-pixel island.
    let cov = binary(40, 30, |x, y| {
        let square = (5.0..25.0).contains(&x) && (5.0..25.0).contains(&y);
        let pinhole = (10.0..11.0).contains(&x) && (10.0..11.0).contains(&y);
        let big_hole = (15.0..18.0).contains(&x) && (15.0..18.0).contains(&y);
        let island = (16.0..17.0).contains(&x) && (16.0..17.0).contains(&y);
        let speck = (32.0..33.0).contains(&x) && (8.0..9.0).contains(&y);
        (square && !pinhole && !big_hole) || island || speck
    });
    let bm = Bitmap::from_coverage(40, 30, cov, Some(0.5)).unwrap();
    let all = extract_contours(&bm, &opts(0.0)).unwrap();
    check_invariants(&all);
    assert_eq!(all.len(), 5);
    // Speck area 0.5 (a diamond through the crack midpoints), pinhole 0.5, the big
    // hole about 8.5: min_area 2 keeps the square and the big hole; the island goes.
    let kept = extract_contours(&bm, &opts(2.0)).unwrap();
    check_invariants(&kept);
    assert_eq!(kept.len(), 2, "{kept:#?}");
    assert!(!kept[0].is_hole && kept[1].is_hole);
    assert_eq!(kept[1].parent, Some(0));
    assert!((signed_area(&kept[0].points) - 400.0).abs() < 1e-6);
    // Dropping the outer border drops its holes too.
    let none = extract_contours(&bm, &opts(500.0)).unwrap();
    assert!(none.is_empty());
}

#[test]
fn shapes_touching_the_edge_are_closed_along_it() {
    // A bar over the full width, rows 4..10 of a 30×14 image, and the same bar
    // anti-aliased (edges at y = 3.625 and 10.3125, exact under 16×16 supersampling).
    for ss in [1, 16] {
        let cov = supersample(30, 14, ss, |_, y| (3.625..10.3125).contains(&y));
        let bm = Bitmap::from_coverage(30, 14, cov, None).unwrap();
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        check_invariants(&cs);
        assert_eq!(cs.len(), 1);
        let pts = &cs[0].points;
        let min_x = pts.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
        let max_x = pts.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
        assert!(min_x.abs() < 1e-9, "min x {min_x}");
        assert!((max_x - 30.0).abs() < 1e-9, "max x {max_x}");
        assert!(pts.iter().filter(|p| p.x.abs() < 1e-9).count() >= 2);
        if ss == 16 {
            // The long sides are refined to the true edges.
            for p in pts.iter().filter(|p| (3.0..27.0).contains(&p.x)) {
                let d = (p.y - 3.625).abs().min((p.y - 10.3125).abs());
                assert!(d < 0.02, "{p:?}");
            }
        }
    }
}

#[test]
fn full_and_empty_images() {
    let full = Bitmap::from_coverage(30, 20, vec![1.0; 600], Some(0.5)).unwrap();
    let grey = Bitmap::from_coverage(30, 20, vec![0.9; 600], None).unwrap();
    for bm in [full, grey] {
        let cs = extract_contours(&bm, &opts(2.0)).unwrap();
        check_invariants(&cs);
        assert_eq!(cs.len(), 1);
        // One outer border along the image border, square corners kept.
        let area = signed_area(&cs[0].points);
        assert!((area - 600.0).abs() < 1e-9, "area {area}");
    }
    // Too small for corners (under 40 cracks of boundary): rounded, but traced.
    let small = Bitmap::from_coverage(7, 5, vec![1.0; 35], Some(0.5)).unwrap();
    let cs = extract_contours(&small, &opts(2.0)).unwrap();
    check_invariants(&cs);
    let area = signed_area(&cs[0].points);
    assert!(area > 33.0 && area < 35.0, "area {area}");
    let empty = Bitmap::from_coverage(7, 5, vec![0.0; 35], Some(0.5)).unwrap();
    assert!(extract_contours(&empty, &opts(0.0)).unwrap().is_empty());
}

#[test]
fn degenerate_shapes_do_not_break_anything() {
    let cases: Vec<(&str, u32, u32, Vec<f32>)> = vec![
        (
            "one pixel",
            5,
            5,
            binary(5, 5, |x, y| x > 2.0 && x < 3.0 && y > 2.0 && y < 3.0),
        ),
        (
            "one-pixel line",
            20,
            5,
            binary(20, 5, |x, y| x > 2.0 && y > 2.0 && y < 3.0),
        ),
        (
            "diagonal line",
            12,
            12,
            binary(12, 12, |x, y| (x - y).abs() < 0.5),
        ),
        (
            "checkerboard",
            9,
            8,
            binary(9, 8, |x, y| (x as i64 + y as i64) % 2 == 0),
        ),
        (
            "all four edges",
            9,
            9,
            binary(9, 9, |x, y| x < 1.0 || y < 1.0 || x > 8.0 || y > 8.0),
        ),
        (
            "thin grey line",
            20,
            6,
            (0..120)
                .map(|i| {
                    if i / 20 == 2 {
                        0.6
                    } else if i / 20 == 3 {
                        0.4
                    } else {
                        0.0
                    }
                })
                .collect(),
        ),
        (
            "noise",
            16,
            16,
            (0..256u32)
                .map(|i| ((i.wrapping_mul(2_654_435_761) >> 7) % 256) as f32 / 255.0)
                .collect(),
        ),
    ];
    for (name, w, h, cov) in cases {
        for threshold in [None, Some(0.5)] {
            let bm = Bitmap::from_coverage(w, h, cov.clone(), threshold).unwrap();
            for min_area in [0.0, 2.0] {
                let cs = extract_contours(&bm, &opts(min_area))
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                check_invariants(&cs);
                for c in &cs {
                    assert!(signed_area(&c.points).abs() >= min_area, "{name}");
                    for p in &c.points {
                        // Everything stays within a pixel of the image.
                        assert!(p.x >= -1.0 && p.y >= -1.0, "{name}: {p:?}");
                        assert!(p.x <= w as f64 + 1.0 && p.y <= h as f64 + 1.0, "{name}");
                    }
                }
            }
        }
    }
    // The single pixel survives only without a speck limit, as a small diamond.
    let bm = Bitmap::from_coverage(
        5,
        5,
        binary(5, 5, |x, y| x > 2.0 && x < 3.0 && y > 2.0 && y < 3.0),
        Some(0.5),
    )
    .unwrap();
    let cs = extract_contours(&bm, &opts(0.0)).unwrap();
    assert_eq!(cs.len(), 1);
    assert!((signed_area(&cs[0].points) - 0.5).abs() < 1e-9);
    assert!(extract_contours(&bm, &opts(2.0)).unwrap().is_empty());
}

#[test]
fn invalid_min_area_is_an_error() {
    let bm = Bitmap::from_coverage(2, 2, vec![1.0; 4], Some(0.5)).unwrap();
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            extract_contours(&bm, &opts(bad)),
            Err(Error::InvalidOption {
                name: "min_area",
                ..
            })
        ));
    }
}

#[test]
fn edge_placement_does_not_depend_on_the_threshold() {
    let (bm, centre, radius) = disk_bitmap(16);
    for t in [0.3, 0.7] {
        let moved =
            Bitmap::from_coverage(bm.width(), bm.height(), bm.to_coverage(), Some(t)).unwrap();
        let cs = extract_contours(&moved, &opts(2.0)).unwrap();
        let (max, _) = circle_errors(&cs[0].points, centre, radius);
        assert!(max < 0.05, "threshold {t}: {max}");
    }
}

#[test]
fn bilevel_shallow_straight_edges_stay_straight() {
    // A 60×40 rectangle rotated by 4°: its long sides are digital lines with long flat
    // runs; away from the corners the outline must follow the true sides.
    let corners = {
        let (s, c) = 4f64.to_radians().sin_cos();
        let centre = Point::new(40.3, 30.6);
        let u = Point::new(c, s) * 30.0;
        let v = Point::new(-s, c) * 20.0;
        [
            centre - u - v,
            centre + u - v,
            centre + u + v,
            centre - u + v,
        ]
    };
    let cov = binary(80, 62, |x, y| inside_convex(&corners, Point::new(x, y)));
    let bm = Bitmap::from_coverage(80, 62, cov, None).unwrap();
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    let pts = &cs[0].points;
    let mut worst: f64 = 0.0;
    for p in pts
        .iter()
        .filter(|p| corners.iter().all(|c| c.distance(**p) > 3.0))
    {
        worst = worst.max(side_distance(*p, &corners));
    }
    eprintln!("shallow sides: worst {worst:.3}");
    assert!(worst < 0.3, "worst side distance {worst}");
    let turn = turning_degrees(pts)
        .into_iter()
        .zip(pts)
        .filter(|(_, p)| corners.iter().all(|c| c.distance(**p) > 3.0))
        .map(|(t, _)| t)
        .fold(0.0, f64::max);
    assert!(turn < 10.0, "turn {turn}° on a straight side");
}

#[test]
fn quadratic_fit_recovers_a_parabola() {
    let mut fit = QuadraticFit::default();
    for k in -5..=5 {
        let u = k as f64 * 0.7;
        fit.add(u, 0.3 - 0.2 * u + 0.05 * u * u, 1.0 + (k * k) as f64);
    }
    let (a, b, c) = fit.solve().unwrap();
    assert!((a - 0.3).abs() < 1e-12 && (b + 0.2).abs() < 1e-12 && (c - 0.05).abs() < 1e-12);
    // Two points determine a line, one a constant.
    let mut line = QuadraticFit::default();
    line.add(0.0, 1.0, 1.0);
    line.add(2.0, 2.0, 1.0);
    let (a, b, c) = line.solve().unwrap();
    assert!((a - 1.0).abs() < 1e-12 && (b - 0.5).abs() < 1e-12 && c == 0.0);
}

#[test]
fn weighted_side_fit_follows_the_risers() {
    // The half-plane below y = 10.3 + tan(4°)·x, cut to a box: its top side is a
    // digital line with flat runs of about 14 px.
    let m = 4f64.to_radians().tan();
    let cov = binary(60, 30, |x, y| {
        y > 10.3 + m * x && x > 5.0 && x < 55.0 && y < 25.0
    });
    let bm = Bitmap::from_coverage(60, 30, cov, Some(0.5)).unwrap();
    let cracks = PaddedMask::new(&bm)
        .unwrap()
        .borders()
        .swap_remove(0)
        .cracks;
    let mut w = Workspace::default();
    w.raw.extend(cracks.iter().map(|c| c.mid()));
    w.normals.extend(cracks.iter().map(|c| c.normal()));
    w.run_weights();
    w.scratch = w.raw.clone();
    let top: Vec<usize> = (0..w.raw.len())
        .filter(|&j| (15.0..45.0).contains(&w.raw[j].x) && w.raw[j].y < 15.0)
        .collect();
    let weighted = w.fit_side(top.iter().copied()).unwrap();
    let (plain, _) = fit_line(top.iter().map(|&j| w.raw[j])).unwrap();
    let error = |l: Line| {
        let at = |x: f64| l.origin.y + (x - l.origin.x) / l.direction.x * l.direction.y;
        (at(20.0) - (10.3 + 20.0 * m))
            .abs()
            .max((at(40.0) - (10.3 + 40.0 * m)).abs())
    };
    let (we, pe) = (error(weighted), error(plain));
    // Measured: 0.041 px weighted, 0.071 px plain.
    assert!(we < 0.05, "weighted side line off by {we}");
    assert!(we < pe, "weighted {we} vs plain {pe}");
}

/// Bilevel diagonal strokes (a "V"): the outline keeps the shape's area.
#[test]
fn bilevel_diagonal_strokes_keep_their_area() {
    let poly = [
        Point::new(20.0, 10.0),
        Point::new(40.0, 10.0),
        Point::new(60.0, 70.0),
        Point::new(80.0, 10.0),
        Point::new(100.0, 10.0),
        Point::new(70.0, 100.0),
        Point::new(50.0, 100.0),
    ];
    let inside = |p: Point| {
        let mut c = false;
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                c = !c;
            }
        }
        c
    };
    let (w, h) = (120u32, 110u32);
    let cov: Vec<f32> = (0..h)
        .flat_map(|r| (0..w).map(move |c| (c, r)))
        .map(|(c, r)| {
            if inside(Point::new(c as f64 + 0.5, r as f64 + 0.5)) {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let pixels = cov.iter().filter(|&&v| v > 0.5).count() as f64;
    let bm = Bitmap::from_coverage(w, h, cov, Some(0.5)).unwrap();
    assert!(bm.is_bilevel());
    let cs = extract_contours(&bm, &opts(2.0)).unwrap();
    assert_eq!(cs.len(), 1);
    let area = signed_area(&cs[0].points);
    assert!(
        (area - pixels).abs() < 0.01 * pixels,
        "area {area} vs {pixels} pixels"
    );
}

/// The guard of the bilevel regression accepts outlines on the pixel boundary and
/// rejects ones that leave it (shifted, or cutting a corner off).
#[test]
fn crack_guard_rejects_outlines_off_the_pixels() {
    // Pixel-edge midpoints of a 10 × 10 square of pixels at (5, 5).
    let cov = binary(20, 20, |x, y| {
        (5.0..15.0).contains(&x) && (5.0..15.0).contains(&y)
    });
    let bm = Bitmap::from_coverage(20, 20, cov, Some(0.5)).unwrap();
    let cracks = PaddedMask::new(&bm)
        .unwrap()
        .borders()
        .swap_remove(0)
        .cracks;
    assert_eq!(cracks.len(), 40);
    let smooth = smoothed_cracks(&cracks);
    assert!(follows_cracks(&smooth, &cracks));
    let shifted: Vec<Point> = smooth.iter().map(|&p| p + Point::new(2.0, 0.0)).collect();
    assert!(!follows_cracks(&shifted, &cracks));
    // A chord across a quarter of the square keeps every point near a midpoint of
    // the far sides but loses a large area.
    let cut: Vec<Point> = cracks
        .iter()
        .map(|c| c.mid())
        .filter(|m| m.x + m.y > 15.0)
        .collect();
    assert!(!follows_cracks(&cut, &cracks));
}

/// Distance from `p` to the nearest of the lines through the sides of the quadrilateral
/// `corners`.
fn side_distance(p: Point, corners: &[Point; 4]) -> f64 {
    (0..4)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            ((p - a).cross(b - a) / (b - a).length()).abs()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Refining the borders while the scan still looks for more (as a large image is) gives
/// the same contours, borders and parents as scanning first: a page of rings and discs,
/// nested three deep, anti-aliased and large enough for many batches of borders.
#[test]
fn refining_while_scanning_gives_the_same_contours() {
    let (w, h) = (1200u32, 700u32);
    let cov = supersample(w, h, 2, |x, y| {
        // Cells of 40 px: a ring with an island, or a disc, by the cell's parity.
        let (cx, cy) = ((x / 40.0).floor(), (y / 40.0).floor());
        let centre = Point::new(cx * 40.0 + 20.3, cy * 40.0 + 19.8);
        let d = Point::new(x, y).distance(centre);
        if (cx + cy) as i64 % 2 == 0 {
            (9.0..17.0).contains(&d) || d < 4.5
        } else {
            d < 12.5 + 0.1 * cx
        }
    });
    let bm = Bitmap::from_coverage(w, h, cov, None).unwrap();
    let estimator = EdgeEstimator::CoverageIntegral;
    let plain = extract_scheduled(&bm, &opts(2.0), estimator, false).unwrap();
    let piped = extract_scheduled(&bm, &opts(2.0), estimator, true).unwrap();
    assert!(plain.contours.len() > 1000, "{}", plain.contours.len());
    assert_eq!(plain.contours.len(), piped.contours.len());
    for (a, b) in plain.contours.iter().zip(&piped.contours) {
        assert_eq!((a.is_hole, a.parent), (b.is_hole, b.parent));
        assert_eq!(a.points, b.points);
        assert_eq!(a.edge_spread, b.edge_spread);
    }
    assert_eq!(plain.border_of, piped.border_of);
    assert_eq!(plain.borders.len(), piped.borders.len());
    for (a, b) in plain.borders.iter().zip(&piped.borders) {
        assert_eq!((a.is_hole, a.parent), (b.is_hole, b.parent));
        assert_eq!(a.cracks.to_vec(), b.cracks.to_vec());
    }
    // Islands sit in holes, which sit in rings.
    let island = plain
        .contours
        .iter()
        .find(|c| !c.is_hole && c.parent.is_some())
        .unwrap();
    let hole = &plain.contours[island.parent.unwrap()];
    assert!(hole.is_hole && hole.parent.is_some());
}

/// [`lines::lap`] is `rem_euclid` and `div_euclid`, within a lap of the outline and far
/// outside it; [`crate::geom::wrap`] is the remainder within one lap past the end.
#[test]
fn a_lap_is_the_euclidean_remainder_and_quotient() {
    for n in [1i64, 2, 3, 7, 64, 1000] {
        for k in -3 * n - 2..=4 * n + 2 {
            assert_eq!(
                super::lines::lap(k, n),
                (k.rem_euclid(n), k.div_euclid(n)),
                "{k} of {n}"
            );
        }
        let m = n as usize;
        for x in 0..2 * m {
            assert_eq!(crate::geom::wrap(x, m), x % m, "{x} of {m}");
        }
    }
}
