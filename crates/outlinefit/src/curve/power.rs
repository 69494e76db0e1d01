//! Cubic curves in power form, for evaluating one curve at many parameters.
//!
//! A Bézier coordinate p0…p3 is the polynomial a + b·u + c·u² + d·u³ with a = p0,
//! b = 3(p1 − p0), c = 3(p0 − 2p1 + p2), d = p3 − p0 + 3(p1 − p2). Converting once and
//! evaluating by Horner's rule costs about a third of the Bernstein sums for a position
//! with its first two derivatives, which is what Newton's projection evaluates at every
//! step. A rational cubic keeps its numerator in homogeneous coordinates (w·x, w·y) and
//! its denominator w as two more polynomials. On [0, 1] the conversion loses a few units
//! of round-off of the largest coordinate (1e-12 px at 10 000 px), far below anything
//! the fit measures.

use crate::geom::Point;

/// Newton steps on the parameter shorter than this end a projection: on a segment of
/// 1000 px they move the foot by 1e-7 px.
pub(crate) const CONVERGED_STEP: f64 = 1e-10;

/// Newton steps shorter than this end a projection that runs to round-off of the
/// parameter (`RationalCubic::refine_projection`).
pub(crate) const EXACT_STEP: f64 = 1e-15;

/// Position and derivatives of a curve at one parameter.
#[derive(Clone, Copy, Debug)]
pub struct CurveJet {
    /// P(u).
    pub point: Point,
    /// P'(u).
    pub d1: Point,
    /// P''(u).
    pub d2: Point,
}

/// Power-form coefficients [a, b, c, d] of the cubic with Bézier values `p`.
#[inline]
fn coefficients(p: [f64; 4]) -> [f64; 4] {
    [
        p[0],
        3.0 * (p[1] - p[0]),
        3.0 * (p[0] - 2.0 * p[1] + p[2]),
        p[3] - p[0] + 3.0 * (p[1] - p[2]),
    ]
}

/// Value, first and second derivative of a + b·u + c·u² + d·u³.
#[inline]
fn horner(k: &[f64; 4], u: f64) -> [f64; 3] {
    let [a, b, c, d] = *k;
    [
        ((d * u + c) * u + b) * u + a,
        (3.0 * d * u + 2.0 * c) * u + b,
        6.0 * d * u + 2.0 * c,
    ]
}

/// A rational (or polynomial) cubic converted for repeated evaluation.
#[derive(Clone, Copy, Debug)]
pub struct PowerCubic {
    x: [f64; 4],
    y: [f64; 4],
    /// The denominator's coefficients; `None` for a polynomial cubic (denominator 1).
    w: Option<[f64; 4]>,
}

impl PowerCubic {
    /// The power form of the rational cubic with control points `c` and weights `w`
    /// (all four).
    pub fn rational(c: &[Point; 4], w: [f64; 4]) -> Self {
        PowerCubic {
            x: coefficients([c[0].x, w[1] * c[1].x, w[2] * c[2].x, c[3].x]),
            y: coefficients([c[0].y, w[1] * c[1].y, w[2] * c[2].y, c[3].y]),
            w: Some(coefficients(w)),
        }
    }

    /// The power form of a polynomial cubic with control points `p`.
    pub fn polynomial(p: &[Point; 4]) -> Self {
        PowerCubic {
            x: coefficients([p[0].x, p[1].x, p[2].x, p[3].x]),
            y: coefficients([p[0].y, p[1].y, p[2].y, p[3].y]),
            w: None,
        }
    }

    /// P(u).
    #[inline]
    pub fn eval(&self, u: f64) -> Point {
        let value = |k: &[f64; 4]| ((k[3] * u + k[2]) * u + k[1]) * u + k[0];
        let p = Point::new(value(&self.x), value(&self.y));
        match &self.w {
            None => p,
            Some(w) => p * (1.0 / value(w)),
        }
    }

    /// P(u), P'(u) and P''(u).
    #[inline]
    pub fn jet(&self, u: f64) -> CurveJet {
        let [x, x1, x2] = horner(&self.x, u);
        let [y, y1, y2] = horner(&self.y, u);
        let (n, n1, n2) = (Point::new(x, y), Point::new(x1, y1), Point::new(x2, y2));
        match &self.w {
            None => CurveJet {
                point: n,
                d1: n1,
                d2: n2,
            },
            Some(w) => {
                let [d, d1, d2] = horner(w, u);
                let inv = 1.0 / d;
                let p = n * inv;
                let p1 = (n1 - p * d1) * inv;
                let p2 = (n2 - p1 * (2.0 * d1) - p * d2) * inv;
                CurveJet {
                    point: p,
                    d1: p1,
                    d2: p2,
                }
            }
        }
    }

    /// The Newton step on (P(u) − q)·P'(u) = 0 at a jet (a gradient-like step where the
    /// second derivative of the squared distance is not positive).
    #[inline]
    fn newton_step(jet: &CurveJet, q: Point) -> f64 {
        let r = jet.point - q;
        let g = r.dot(jet.d1);
        let h = jet.d1.length_squared() + r.dot(jet.d2);
        if h > 1e-12 {
            -g / h
        } else {
            -g / jet.d1.length_squared().max(1e-12)
        }
    }

    /// See [`RationalCubic::project_quick`](crate::curve::RationalCubic::project_quick).
    pub fn project_quick(&self, q: Point, u0: f64, iterations: usize) -> f64 {
        self.project_quick_distance(q, u0, iterations).0
    }

    /// [`PowerCubic::project_quick`], also returning the squared distance from `q` to the
    /// curve at the parameter found.
    #[inline]
    pub(crate) fn project_quick_distance(
        &self,
        q: Point,
        u0: f64,
        iterations: usize,
    ) -> (f64, f64) {
        let mut p = self.quick_start(q, u0);
        for _ in 0..iterations {
            if !p.going {
                break;
            }
            self.quick_step(&mut p, q);
        }
        (p.u, p.d2)
    }

    /// [`PowerCubic::project_quick_distance`] of two points at once, each exactly as alone:
    /// the two chains of Newton steps are independent, and interleaving them lets the
    /// processor work on one while the other waits on its divisions.
    #[inline]
    pub(crate) fn project_quick_distance_pair(
        &self,
        q: [Point; 2],
        u0: [f64; 2],
        iterations: usize,
    ) -> [(f64, f64); 2] {
        let mut p = [self.quick_start(q[0], u0[0]), self.quick_start(q[1], u0[1])];
        for _ in 0..iterations {
            if !p[0].going && !p[1].going {
                break;
            }
            for (p, &q) in p.iter_mut().zip(&q) {
                if p.going {
                    self.quick_step(p, q);
                }
            }
        }
        p.map(|p| (p.u, p.d2))
    }

    /// The state of [`PowerCubic::project_quick_distance`] before its first step.
    #[inline]
    fn quick_start(&self, q: Point, u0: f64) -> QuickProjection {
        let u = u0.clamp(0.0, 1.0);
        let jet = self.jet(u);
        QuickProjection {
            u,
            d2: (jet.point - q).length_squared(),
            jet,
            going: true,
        }
    }

    /// One Newton step of [`PowerCubic::project_quick_distance`]; it stops once a step
    /// is below [`CONVERGED_STEP`] (a further one moves the foot by less than round-off of
    /// pixel coordinates and would cost another evaluation) or would move away from `q`.
    #[inline]
    fn quick_step(&self, p: &mut QuickProjection, q: Point) {
        let un = (p.u + Self::newton_step(&p.jet, q)).clamp(0.0, 1.0);
        if (un - p.u).abs() <= CONVERGED_STEP {
            p.going = false;
            return;
        }
        let jn = self.jet(un);
        let dn = (jn.point - q).length_squared();
        if dn > p.d2 {
            p.going = false;
            return;
        }
        p.u = un;
        p.jet = jn;
        p.d2 = dn;
    }

    /// See [`RationalCubic::refine_projection`](crate::curve::RationalCubic::refine_projection); Newton stops at steps shorter than
    /// `min_step`.
    pub fn refine_projection(&self, q: Point, u0: f64, min_step: f64) -> (f64, f64) {
        let mut u = if u0.is_finite() {
            u0.clamp(0.0, 1.0)
        } else {
            0.0
        };
        let mut jet = self.jet(u);
        let mut dist2 = (jet.point - q).length_squared();
        for _ in 0..12 {
            let step = Self::newton_step(&jet, q);
            if !step.is_finite() || step.abs() < min_step {
                break;
            }
            let mut t = 1.0;
            let mut improved = false;
            for _ in 0..6 {
                let un = (u + t * step).clamp(0.0, 1.0);
                let jn = self.jet(un);
                let dn = (jn.point - q).length_squared();
                if dn <= dist2 {
                    improved = un != u;
                    u = un;
                    jet = jn;
                    dist2 = dn;
                    break;
                }
                t *= 0.5;
            }
            if !improved {
                break;
            }
        }
        (u, dist2.sqrt())
    }
}

/// Where [`PowerCubic::project_quick_distance`] stands between its Newton steps.
struct QuickProjection {
    u: f64,
    jet: CurveJet,
    d2: f64,
    going: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::RationalCubic;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn projecting_two_points_at_once_gives_each_its_own_foot_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for k in 0..300 {
            fn pt(rng: &mut ChaCha8Rng, r: f64) -> Point {
                Point::new(rng.random_range(-r..r), rng.random_range(-r..r))
            }
            let points = [0; 4].map(|_| pt(&mut rng, 50.0));
            let weights = if k % 2 == 0 {
                [1.0, 1.0]
            } else {
                [rng.random_range(0.2..2.5), rng.random_range(0.2..2.5)]
            };
            let power = RationalCubic::new(points, weights).power_form();
            for steps in [0, 1, 2, 5] {
                let q = [pt(&mut rng, 60.0), pt(&mut rng, 60.0)];
                // Starts outside [0, 1] too: both are clamped.
                let u = [rng.random_range(-0.2..1.2), rng.random_range(-0.2..1.2)];
                let pair = power.project_quick_distance_pair(q, u, steps);
                for j in 0..2 {
                    let alone = power.project_quick_distance(q[j], u[j], steps);
                    assert_eq!(pair[j].0.to_bits(), alone.0.to_bits(), "{k} {steps} {j}");
                    assert_eq!(pair[j].1.to_bits(), alone.1.to_bits(), "{k} {steps} {j}");
                }
            }
        }
    }

    #[test]
    fn power_form_matches_the_bernstein_form() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for k in 0..200 {
            let mut pt = || {
                Point::new(
                    rng.random_range(-500.0..5000.0),
                    rng.random_range(-500.0..5000.0),
                )
            };
            let points = [pt(), pt(), pt(), pt()];
            let weights = if k % 2 == 0 {
                [1.0, 1.0]
            } else {
                [rng.random_range(0.01..2.5), rng.random_range(0.01..2.5)]
            };
            let curve = RationalCubic::new(points, weights);
            let power = curve.power_form();
            for j in 0..=20 {
                let u = j as f64 / 20.0;
                let (a, b) = (curve.jet(u), power.jet(u));
                // Relative to the size of the coordinates and of each derivative.
                let scale = 5000.0;
                assert!(a.point.distance(b.point) < 1e-11 * scale, "{k} {u}");
                assert!(a.point.distance(power.eval(u)) < 1e-11 * scale);
                let d1 = a.d1.length().max(scale);
                assert!(a.d1.distance(b.d1) < 1e-10 * d1, "{k} {u} d1");
                let d2 = a.d2.length().max(scale);
                assert!(a.d2.distance(b.d2) < 1e-9 * d2, "{k} {u} d2");
            }
        }
    }
}
