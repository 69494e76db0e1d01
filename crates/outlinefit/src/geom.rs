//! Plane geometry primitives shared by every stage: a 2-D point/vector type and a few
//! helpers on polylines.
//!
//! Coordinates are in input-image pixel units with the SVG convention: x to the right,
//! y downwards, and pixel (c, r) covers the square [c, c+1] × [r, r+1], so its centre is
//! (c + 0.5, r + 0.5).

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// A point or a vector in the plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// Horizontal coordinate, pixels to the right.
    pub x: f64,
    /// Vertical coordinate, pixels downwards.
    pub y: f64,
}

impl Point {
    /// The origin.
    pub const ZERO: Point = Point { x: 0.0, y: 0.0 };

    /// Creates a point from its coordinates.
    #[inline]
    pub const fn new(x: f64, y: f64) -> Self {
        Point { x, y }
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: Point) -> f64 {
        self.x * o.x + self.y * o.y
    }

    /// z-component of the cross product (positive when `o` turns clockwise on screen,
    /// i.e. counter-clockwise in y-up axes).
    #[inline]
    pub fn cross(self, o: Point) -> f64 {
        self.x * o.y - self.y * o.x
    }

    /// Euclidean length.
    #[inline]
    pub fn length(self) -> f64 {
        // Not `hypot`: its overflow care costs several times a square root, and pixel
        // coordinates are nowhere near overflow.
        (self.x * self.x + self.y * self.y).sqrt()
    }

    /// Squared Euclidean length.
    #[inline]
    pub fn length_squared(self) -> f64 {
        self.x * self.x + self.y * self.y
    }

    /// Distance to another point.
    #[inline]
    pub fn distance(self, o: Point) -> f64 {
        (self - o).length()
    }

    /// The vector scaled to unit length, or `None` if its length is zero or not finite.
    #[inline]
    pub fn normalized(self) -> Option<Point> {
        let l = self.length();
        (l > 0.0 && l.is_finite()).then(|| self / l)
    }

    /// The vector rotated by +90° (from +x towards +y).
    #[inline]
    pub fn perp(self) -> Point {
        Point::new(-self.y, self.x)
    }

    /// Linear interpolation: `self` at t = 0, `o` at t = 1.
    #[inline]
    pub fn lerp(self, o: Point, t: f64) -> Point {
        self + (o - self) * t
    }

    /// True when both coordinates are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl Add for Point {
    type Output = Point;
    #[inline]
    fn add(self, o: Point) -> Point {
        Point::new(self.x + o.x, self.y + o.y)
    }
}
impl AddAssign for Point {
    #[inline]
    fn add_assign(&mut self, o: Point) {
        self.x += o.x;
        self.y += o.y;
    }
}
impl Sub for Point {
    type Output = Point;
    #[inline]
    fn sub(self, o: Point) -> Point {
        Point::new(self.x - o.x, self.y - o.y)
    }
}
impl SubAssign for Point {
    #[inline]
    fn sub_assign(&mut self, o: Point) {
        self.x -= o.x;
        self.y -= o.y;
    }
}
impl Mul<f64> for Point {
    type Output = Point;
    #[inline]
    fn mul(self, s: f64) -> Point {
        Point::new(self.x * s, self.y * s)
    }
}
impl Div<f64> for Point {
    type Output = Point;
    #[inline]
    fn div(self, s: f64) -> Point {
        Point::new(self.x / s, self.y / s)
    }
}
impl Neg for Point {
    type Output = Point;
    #[inline]
    fn neg(self) -> Point {
        Point::new(-self.x, -self.y)
    }
}

/// An axis-aligned box of points; empty until a finite point is added.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The smallest x and y seen.
    pub min: Point,
    /// The largest x and y seen.
    pub max: Point,
}

impl Bounds {
    /// The box of no point.
    pub const EMPTY: Bounds = Bounds {
        min: Point::new(f64::INFINITY, f64::INFINITY),
        max: Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    };

    /// The box of the finite points among `points`.
    pub fn of(points: impl IntoIterator<Item = Point>) -> Bounds {
        let mut b = Bounds::EMPTY;
        for p in points {
            b.add(p);
        }
        b
    }

    /// Grows the box to hold `p`; non-finite points are ignored.
    pub fn add(&mut self, p: Point) {
        if p.is_finite() {
            self.min = Point::new(self.min.x.min(p.x), self.min.y.min(p.y));
            self.max = Point::new(self.max.x.max(p.x), self.max.y.max(p.y));
        }
    }

    /// Grows the box to hold the disk of center `c` and radius `|r|`; ignored unless both
    /// are finite.
    pub fn add_disk(&mut self, c: Point, r: f64) {
        if c.is_finite() && r.is_finite() {
            let r = Point::new(r.abs(), r.abs());
            self.add(c - r);
            self.add(c + r);
        }
    }

    /// True when no point has been added.
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y)
    }

    /// The box itself, or the unit square [0, 1]² if it is empty.
    pub fn or_unit(self) -> Bounds {
        if self.is_empty() {
            Bounds {
                min: Point::ZERO,
                max: Point::new(1.0, 1.0),
            }
        } else {
            self
        }
    }

    /// Width (0 for a single point; meaningless when empty).
    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }

    /// Height (0 for a single point; meaningless when empty).
    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// The longer side.
    pub fn extent(&self) -> f64 {
        self.width().max(self.height())
    }
}

/// Signed area of a closed polygon by the shoelace formula, in the image frame
/// (y down): positive for loops that run clockwise on screen.
pub(crate) fn signed_area(points: &[Point]) -> f64 {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let mut acc = 0.0;
    for i in 0..n {
        let a = points[i];
        let b = points[(i + 1) % n];
        acc += a.cross(b);
    }
    0.5 * acc
}

/// Where the line through `a` along `da` meets the line through `b` along `db`:
/// a + da·s with s = ((b − a) × db) / (da × db). `None` when the sine of the angle between
/// them is below `min_sin` (|da × db| < min_sin·|da|·|db|: parallel, or nearly so) or
/// the crossing is not finite.
pub(crate) fn line_crossing(
    a: Point,
    da: Point,
    b: Point,
    db: Point,
    min_sin: f64,
) -> Option<Point> {
    let den = da.cross(db);
    if den.abs() < min_sin * da.length() * db.length() {
        return None;
    }
    let x = a + da * ((b - a).cross(db) / den);
    x.is_finite().then_some(x)
}

/// Distance from `p` to the segment from `a` to `b` (to `a` when they coincide).
pub(crate) fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Distance from `p` to a closed polyline (infinite for an empty one), whose vertices are
/// points or anything that converts to one.
pub(crate) fn distance_to_closed_polyline<T: Copy + Into<Point>>(p: Point, points: &[T]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|k| segment_distance(p, points[k].into(), points[(k + 1) % n].into()))
        .fold(f64::INFINITY, f64::min)
}

/// ⌊x⌋ as an integer, as `x.floor() as i64` gives it (saturating, 0 for NaN), without
/// the library call that `f64::floor` becomes on baseline x86-64 (no SSE4.1): truncation,
/// minus one below a negative non-integer.
#[inline]
pub(crate) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t.saturating_sub(i64::from((t as f64) > x))
}

/// `x % n` for `x < 2n`: an index at most one lap past the end of a closed outline of `n`
/// points, wrapped by a comparison instead of a division (tens of cycles, in loops that
/// take one or two per point).
#[inline]
pub(crate) fn wrap(x: usize, n: usize) -> usize {
    debug_assert!(x < 2 * n);
    if x >= n {
        x - n
    } else {
        x
    }
}

/// `x.rem_euclid(m)` (for m > 0), without the `fmod` library call when `x` is less than
/// one lap outside [0, m): there the wrap is one exact subtraction, or one addition that
/// rounds as `rem_euclid` rounds it.
#[inline]
pub(crate) fn wrap_once(x: f64, m: f64) -> f64 {
    if x >= 0.0 && x < m {
        x
    } else if x < 0.0 && x > -m {
        x + m
    } else if x >= m && x < 2.0 * m {
        x - m
    } else {
        x.rem_euclid(m)
    }
}

/// A floor on the angle between two vectors, tested without the angle's `atan2`: passes
/// that look for turns of at least some angle (corners) skip the arctangent of every
/// point that turns clearly less, which is most of them.
///
/// The test orders vectors by the "diamond angle" 1 − d / (|d| + |c|) of their dot
/// product d and the absolute value of their cross product c, which rises with the angle
/// from 0 (same direction) to 2 (opposite). A point counts as below the floor only when
/// that value is below the floor's by [`AngleFloor::MARGIN`], far beyond its round-off
/// (about 1e-16): the angle `atan2` would give it is then certainly below the floor too,
/// so a pass that replaces such angles by a value below every angle decides exactly as
/// with every angle computed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AngleFloor {
    diamond: f64,
}

impl AngleFloor {
    /// Margin of the diamond angle, about 1e-9 rad of angle.
    const MARGIN: f64 = 1e-9;

    /// The floor `theta` in radians, in [0, π].
    pub(crate) fn new(theta: f64) -> Self {
        let (s, c) = theta.sin_cos();
        AngleFloor {
            diamond: diamond(c, s.abs()),
        }
    }

    /// True when the angle between `a` and `b` is certainly below the floor. False for
    /// a zero vector (NaN compares false): the caller computes that angle itself.
    #[inline]
    pub(crate) fn certainly_below(self, a: Point, b: Point) -> bool {
        diamond(a.dot(b), a.cross(b).abs()) < self.diamond - Self::MARGIN
    }
}

/// 1 − d / (|d| + c) for c ≥ 0: rises with the angle atan2(c, d) from 0 to 2.
#[inline]
fn diamond(d: f64, c: f64) -> f64 {
    1.0 - d / (d.abs() + c)
}

/// Angle in radians, in [0, π], between two non-zero vectors; 0 for a zero vector.
pub(crate) fn angle_between(a: Point, b: Point) -> f64 {
    let la = a.length();
    let lb = b.length();
    if la == 0.0 || lb == 0.0 {
        return 0.0;
    }
    // atan2 of cross and dot is accurate for tiny angles, unlike acos of the dot.
    a.cross(b).abs().atan2(a.dot(b))
}

/// The points of the cyclic run from index `a` to index `b` (both included) into `out`.
pub(crate) fn cyclic_run(points: &[Point], a: usize, b: usize, out: &mut Vec<Point>) {
    out.clear();
    if b > a {
        out.extend_from_slice(&points[a..=b]);
    } else {
        out.extend_from_slice(&points[a..]);
        out.extend_from_slice(&points[..=b]);
    }
}

/// The 8-connected groups of `cells` (indices row × `w` + column on a `w × h` grid), in
/// the order of their smallest cell, each from its smallest cell outwards.
pub(crate) fn groups_8(
    cells: &std::collections::HashSet<usize>,
    w: usize,
    h: usize,
) -> Vec<Vec<usize>> {
    let mut seeds: Vec<usize> = cells.iter().copied().collect();
    seeds.sort_unstable();
    let mut seen: std::collections::HashSet<usize> = std::collections::HashSet::new();
    let mut groups = Vec::new();
    for seed in seeds {
        if !seen.insert(seed) {
            continue;
        }
        let mut group = vec![seed];
        let mut k = 0;
        while k < group.len() {
            let (col, row) = ((group[k] % w) as i64, (group[k] / w) as i64);
            for (c, r) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (col + dx, row + dy))) {
                if c < 0 || r < 0 || c >= w as i64 || r >= h as i64 {
                    continue;
                }
                let q = r as usize * w + c as usize;
                if cells.contains(&q) && seen.insert(q) {
                    group.push(q);
                }
            }
            k += 1;
        }
        groups.push(group);
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_and_wrap_match_the_library_functions() {
        let values = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.999,
            1e-300,
            -1e-300,
            4096.25,
            -4096.25,
            1e18,
            -1e18,
            1e30,
            -1e30,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in values {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
        let m = 7.3;
        for k in -8000..=8000 {
            let x = k as f64 * (m / 1999.7);
            assert_eq!(wrap_once(x, m).to_bits(), x.rem_euclid(m).to_bits(), "{x}");
        }
        for x in [
            -m,
            -1e-17,
            -0.0,
            0.0,
            m - 1e-15,
            m,
            2.0 * m - 1e-15,
            2.0 * m,
            f64::NAN,
        ] {
            let (a, b) = (wrap_once(x, m), x.rem_euclid(m));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x}"
            );
        }
    }

    #[test]
    fn shoelace_of_unit_square_is_one_clockwise_on_screen() {
        // (0,0) → (1,0) → (1,1) → (0,1) runs clockwise on a y-down screen.
        let sq = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        assert_eq!(signed_area(&sq), 1.0);
        let rev: Vec<Point> = sq.iter().rev().copied().collect();
        assert_eq!(signed_area(&rev), -1.0);
    }

    #[test]
    fn an_angle_floor_passes_only_angles_certainly_below_it() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for floor_deg in [10.0, 50.0, 90.0, 135.0, 179.0] {
            let theta: f64 = f64::to_radians(floor_deg);
            let floor = AngleFloor::new(theta);
            let (mut below, mut passed) = (0, 0);
            for _ in 0..20_000 {
                let a = Point::new(rng.random_range(-50.0..50.0), rng.random_range(-50.0..50.0));
                // Half the pairs turn by within 1e-6 rad of the floor.
                let turn = if rng.random_bool(0.5) {
                    theta + rng.random_range(-1e-6..1e-6)
                } else {
                    rng.random_range(0.0..std::f64::consts::PI)
                };
                let (s, c) = turn.sin_cos();
                let b =
                    Point::new(a.x * c - a.y * s, a.x * s + a.y * c) * rng.random_range(0.1..10.0);
                let angle = angle_between(a, b);
                if floor.certainly_below(a, b) {
                    below += 1;
                    assert!(angle < theta, "{floor_deg}: {angle} passed");
                } else if angle < theta - 1e-8 {
                    passed += 1;
                }
            }
            // Clearly smaller turns pass the cheap test (none is sent to the arctangent).
            assert_eq!(passed, 0, "{floor_deg}");
            assert!(below > 1_000, "{floor_deg}: {below}");
        }
        // A zero vector is never certainly below: its angle is the caller's to give.
        let floor = AngleFloor::new(0.5);
        assert!(!floor.certainly_below(Point::ZERO, Point::new(1.0, 0.0)));
    }

    #[test]
    fn tiny_angles_are_resolved() {
        let a = Point::new(1.0, 0.0);
        let b = Point::new(1.0, 1e-12);
        let ang = angle_between(a, b);
        assert!((ang - 1e-12).abs() < 1e-20, "{ang}");
        assert!((angle_between(a, -a) - std::f64::consts::PI).abs() < 1e-15);
    }
}
