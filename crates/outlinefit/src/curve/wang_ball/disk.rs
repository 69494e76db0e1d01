//! Wang–Ball curves, control disks, disk Wang–Ball curves and the merge ratio λ.

use super::basis::wang_ball_basis;
use super::basis::wang_ball_basis_derivative;
use super::convert::bezier_points_to_wang_ball;
use super::convert::check_degree;
use super::convert::wang_ball_points_to_bezier;
use crate::curve::basis::de_casteljau_split;
use crate::geom::Point;

/// A planar Wang–Ball curve `W(t) = Σ W_{i,n}(t) p_i`, `t ∈ [0, 1]`, of degree
/// `n = points.len() − 1 ≥ 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct WangBall {
    /// The control points `p_0 … p_n`.
    pub points: Vec<Point>,
}

impl WangBall {
    /// Creates a curve from its control points (at least two).
    pub fn new(points: Vec<Point>) -> Self {
        check_degree(points.len());
        WangBall { points }
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        check_degree(self.points.len())
    }

    /// The point at parameter `t`.
    pub fn eval(&self, t: f64) -> Point {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis(n, t, &mut w);
        self.points
            .iter()
            .zip(&w)
            .fold(Point::ZERO, |acc, (&p, &wi)| acc + p * wi)
    }

    /// The derivative `W'(t)`.
    pub fn derivative(&self, t: f64) -> Point {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis_derivative(n, t, &mut w);
        self.points
            .iter()
            .zip(&w)
            .fold(Point::ZERO, |acc, (&p, &wi)| acc + p * wi)
    }

    /// The Bézier control points of the same curve (same degree).
    pub fn to_bezier(&self) -> Vec<Point> {
        wang_ball_points_to_bezier(&self.points)
    }

    /// The Wang–Ball form of the Bézier curve with control points `bezier` (at least two).
    pub fn from_bezier(bezier: &[Point]) -> Self {
        WangBall {
            points: bezier_points_to_wang_ball(bezier),
        }
    }

    /// Splits the curve at `t`: the first part traces `W` on `[0, t]`, the second on
    /// `[t, 1]`, each reparametrised to `[0, 1]`. Done by de Casteljau on the Bézier form.
    pub fn split(&self, t: f64) -> (WangBall, WangBall) {
        let (l, r) = de_casteljau_split(&self.to_bezier(), t);
        (WangBall::from_bezier(&l), WangBall::from_bezier(&r))
    }
}

/// A disk: center and radius.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Disk {
    /// The center.
    pub center: Point,
    /// The radius (non-negative for a proper disk).
    pub radius: f64,
}

impl Disk {
    /// Creates a disk.
    pub const fn new(center: Point, radius: f64) -> Self {
        Disk { center, radius }
    }
}

/// A disk Wang–Ball curve (Eq. 1): `(W)(t) = Σ W_{i,n}(t) (p_i, r_i) = (C(t), R(t))` with
/// center curve `C` and radius function `R` (Eq. 3), degree `n = disks.len() − 1 ≥ 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct DiskWangBall {
    /// The control disks `(p_0, r_0) … (p_n, r_n)`.
    pub disks: Vec<Disk>,
}

impl DiskWangBall {
    /// Creates a DWB curve from its control disks (at least two).
    pub fn new(disks: Vec<Disk>) -> Self {
        check_degree(disks.len());
        DiskWangBall { disks }
    }

    /// The degree n.
    pub fn degree(&self) -> usize {
        check_degree(self.disks.len())
    }

    /// The center curve `C(t) = Σ W_{i,n}(t) p_i` as a Wang–Ball curve.
    pub fn center_curve(&self) -> WangBall {
        WangBall::new(self.disks.iter().map(|d| d.center).collect())
    }

    /// The disk `(C(t), R(t))` at parameter `t`.
    pub fn eval(&self, t: f64) -> Disk {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis(n, t, &mut w);
        self.disks
            .iter()
            .zip(&w)
            .fold(Disk::new(Point::ZERO, 0.0), |acc, (d, &wi)| {
                Disk::new(acc.center + d.center * wi, acc.radius + d.radius * wi)
            })
    }

    /// The center `C(t)`.
    pub fn center(&self, t: f64) -> Point {
        self.eval(t).center
    }

    /// The radius function `R(t) = Σ W_{i,n}(t) r_i`.
    pub fn radius(&self, t: f64) -> f64 {
        self.eval(t).radius
    }

    /// The derivative `C'(t)` of the center curve.
    pub fn center_derivative(&self, t: f64) -> Point {
        self.center_curve().derivative(t)
    }

    /// The derivative `R'(t)` of the radius function.
    pub fn radius_derivative(&self, t: f64) -> f64 {
        let n = self.degree();
        let mut w = vec![0.0; n + 1];
        wang_ball_basis_derivative(n, t, &mut w);
        self.disks
            .iter()
            .zip(&w)
            .map(|(d, &wi)| d.radius * wi)
            .sum()
    }

    /// The arc length `∫₀¹ |C'(t)| dt` of the center curve.
    ///
    /// Adaptive 16-point Gauss–Legendre quadrature: an interval is accepted when the rule on it
    /// and the sum of the rule on its two halves agree to `1e-14` times the total (the
    /// tolerance is shared among subintervals), otherwise it is bisected (depth ≤ 20). On
    /// smooth curves this is accurate to about 1e-13 relative; cusps (`C' = 0`) are resolved
    /// by the bisection.
    pub fn center_arc_length(&self) -> f64 {
        let c = self.center_curve();
        let f = |t: f64| c.derivative(t).length();
        // Rounding noise in C' scales with the control polygon, so the tolerance does too
        // (this keeps (near-)degenerate curves from bisecting to the depth limit).
        let p0 = c.points[0];
        let span = c.points.iter().map(|p| p.distance(p0)).fold(0.0, f64::max);
        crate::quad::adaptive(&f, 0.0, 1.0, 1e-2 * span)
    }
}

/// The subdivision parameter of §2.2.2 for merging the adjacent DWB curves `a` (left) and
/// `b` (right): `λ = ∫₀¹|C'_a| / (∫₀¹|C'_a| + ∫₀¹|C'_b|)`, the share of the left center
/// curve in the total arc length. Returns 0.5 if both center curves have zero length.
pub(crate) fn merge_lambda(a: &DiskWangBall, b: &DiskWangBall) -> f64 {
    let la = a.center_arc_length();
    let lb = b.center_arc_length();
    let total = la + lb;
    if total > 0.0 {
        la / total
    } else {
        0.5
    }
}
