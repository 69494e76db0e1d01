//! Small geometry of the extraction: unit vectors, turning angles, segment crossings,
//! total-least-squares lines and their crossings, and a walk along an outline by arc
//! length.

use crate::geom::{line_crossing, Point};

/// Euclidean length without `hypot` (which is several times slower and whose extra
/// range is not needed for pixel coordinates).
#[inline]
pub(super) fn norm(p: Point) -> f64 {
    p.length_squared().sqrt()
}

/// The vector scaled to unit length, or `None` if it is zero or not finite.
#[inline]
pub(super) fn unit(p: Point) -> Option<Point> {
    let length = norm(p);
    (length > 0.0 && length.is_finite()).then(|| p / length)
}

/// Angle in [0, π] between two vectors; 0 when either is zero.
#[inline]
pub(super) fn turn_angle(a: Point, b: Point) -> f64 {
    a.cross(b).abs().atan2(a.dot(b))
}

/// A line through `origin` along the unit vector `direction`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Line {
    pub(super) origin: Point,
    pub(super) direction: Point,
}

/// The crossing point of segments ab and cd when they properly intersect.
pub(super) fn segment_crossing(a: Point, b: Point, c: Point, d: Point) -> Option<Point> {
    let r = b - a;
    let q = d - c;
    let denom = r.cross(q);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (c - a).cross(q) / denom;
    let u = (c - a).cross(r) / denom;
    (t > 0.0 && t < 1.0 && u > 0.0 && u < 1.0).then(|| a + r * t)
}

/// Total least-squares line through at least two distinct points, with the largest
/// distance of a point from it.
pub(super) fn fit_line(points: impl Iterator<Item = Point> + Clone) -> Option<(Line, f64)> {
    let mut count = 0.0;
    let mut sum = Point::ZERO;
    for p in points.clone() {
        count += 1.0;
        sum += p;
    }
    if count < 2.0 {
        return None;
    }
    let mean = sum / count;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points.clone() {
        let d = p - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    if sxx + syy < 1e-12 {
        return None;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let direction = Point::new(angle.cos(), angle.sin());
    let residual = points
        .map(|p| (p - mean).cross(direction).abs())
        .fold(0.0, f64::max);
    Some((
        Line {
            origin: mean,
            direction,
        },
        residual,
    ))
}

/// Intersection of two lines that cross at more than 25°.
pub(super) fn intersect(a: Line, b: Line) -> Option<Point> {
    line_crossing(
        a.origin,
        a.direction,
        b.origin,
        b.direction,
        25f64.to_radians().sin(),
    )
}

/// `(k.rem_euclid(n), k.div_euclid(n))` for `n > 0`, without the division for an unrolled
/// index within a lap of [0, n), where the walks along a closed outline stay (a division
/// is tens of cycles, and they take several per point).
#[inline]
pub(super) fn lap(k: i64, n: i64) -> (i64, i64) {
    if (0..n).contains(&k) {
        (k, 0)
    } else if (n..2 * n).contains(&k) {
        (k - n, 1)
    } else if (-n..0).contains(&k) {
        (k + n, -1)
    } else {
        (k.rem_euclid(n), k.div_euclid(n))
    }
}

/// Arc length along a closed polyline at unrolled indices (index k + n is point k one lap
/// later).
pub(super) struct ArcWalk<'a> {
    /// Cumulative arc length: `cumulative[k]` at point k, the last entry the whole loop.
    pub(super) cumulative: &'a [f64],
}

impl ArcWalk<'_> {
    /// Arc length at unrolled index `k`.
    pub(super) fn arc(&self, k: i64) -> f64 {
        let n = self.cumulative.len() as i64 - 1;
        let total = self.cumulative[n as usize];
        let (index, laps) = lap(k, n);
        self.cumulative[index as usize] + total * laps as f64
    }

    /// The last index at least `length` of arc before `i` (at most one lap back).
    pub(super) fn back_by(&self, i: i64, length: f64) -> i64 {
        let n = self.cumulative.len() as i64 - 1;
        let mut k = i - 1;
        while k > i - n && self.arc(i) - self.arc(k) < length {
            k -= 1;
        }
        k
    }

    /// The first index at least `length` of arc after `i` (at most one lap ahead).
    pub(super) fn ahead_by(&self, i: i64, length: f64) -> i64 {
        let n = self.cumulative.len() as i64 - 1;
        let mut k = i + 1;
        while k < i + n && self.arc(k) - self.arc(i) < length {
            k += 1;
        }
        k
    }
}
