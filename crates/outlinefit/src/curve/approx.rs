//! Polynomial cubics as a drawable stand-in for rational cubics.
//!
//! SVG (and most vector formats) can only draw polynomial cubics, while the fitter produces
//! rational ones. [`approximate_with_cubics`] converts one rational segment into a short run
//! of polynomial cubics:
//!
//! * a polynomial input (w1 = w2 = 1) is returned exactly, as one cubic with the same control
//!   points;
//! * otherwise one cubic is fitted with the same end points and the same end tangent
//!   *directions* as the rational curve, so that every G1 joint of the outline stays G1 in the
//!   drawing. Only the two tangent lengths are free. They start from a linear least-squares
//!   fit to 15 interior samples of the rational curve with two rounds of parameter
//!   correction (project each sample onto the current cubic, refit; Hoschek's intrinsic
//!   parameterization). Parameter correction alone converges slowly (after 30 rounds it still
//!   left errors up to 40× the optimum in our measurements), so the fit continues with the
//!   *tangent distance* (the residual along the cubic's normal at each foot point, which is
//!   linear in the two lengths), reweighted by Lawson's rule so that it heads for the
//!   smallest maximum distance rather than the smallest sum of squares;
//! * the geometric distance between the two curves is then measured both ways (each curve's
//!   samples projected onto the other, the larger of the two maxima). If it exceeds the
//!   bound, the rational curve is split at its parameter midpoint and both halves are
//!   approximated in turn, sharing the tangent direction of the split point so that the
//!   pieces meet G1 as well. (Choosing split points greedily, longest piece first, saved only
//!   2 % of the pieces on random curves for 2.6× the work, so bisection stays.)
//!
//! How many pieces are needed depends on how far the curve is from any polynomial cubic:
//! rational circular arcs up to a quarter circle of radius 70 px need one piece at 0.02 px;
//! random control polygons with random weights in [0.2, 2.5] on 50-px curves mostly need two
//! (see the `piece_counts_for_glyph_size_curves` test for the measured histogram).
//!
//! Limits, stated plainly: the distance is measured at 31 samples per direction (the fit
//! samples and the midpoints between them; a rational cubic's distance to a cubic with the
//! same ends and end tangents has a few broad extrema, and 63 samples drew 0.3 % fewer SVG
//! bytes for 12 % more time on a page of text), not bounded rigorously, so a narrow
//! excursion between samples could exceed the bound slightly;
//! subdivision stops at depth [`MAX_DEPTH`] (at most 2^8 pieces) and then keeps the best fit
//! of that depth even if it misses the bound. Curves with non-finite coordinates produce
//! non-finite cubics rather than an error; callers that write files check for that.

use super::cubic::{end_direction, start_direction, CubicBez};
use super::power::{PowerCubic, CONVERGED_STEP};
use super::RationalCubic;
use crate::geom::Point;
use crate::linalg::cramer2;

/// Subdivision depth after which [`approximate_with_cubics`] stops splitting.
pub(crate) const MAX_DEPTH: u32 = 8;

/// The fit uses the rational curve at u = k / FIT_INTERVALS, k = 1 … FIT_INTERVALS − 1 (the
/// ends are interpolated exactly); the distance check adds the midpoints between them.
const FIT_INTERVALS: usize = 16;

/// Rounds of parameter correction of the first, point-distance least-squares fit.
const CORRECTION_ROUNDS: usize = 2;

/// Most rounds of the minimax (Lawson) polish on the tangent distance.
const POLISH_ROUNDS: usize = 16;

/// The approximation bound used when no fitting tolerance chooses one (px).
pub(crate) const DEFAULT_DRAWING_BOUND: f64 = 0.02;

/// The approximation bound matched to a fitting tolerance: the drawing may add at most a
/// twentieth of it, `tolerance / 20` clamped to [0.005, 0.05] px (the default tolerance
/// 0.3 gives 0.015). A non-positive or non-finite tolerance gives
/// [`DEFAULT_DRAWING_BOUND`].
pub(crate) fn drawing_bound(tolerance: f64) -> f64 {
    if tolerance.is_finite() && tolerance > 0.0 {
        (tolerance / 20.0).clamp(0.005, 0.05)
    } else {
        DEFAULT_DRAWING_BOUND
    }
}

/// Approximates a rational cubic by polynomial cubics within `bound` pixels.
///
/// Guarantees: the pieces form one continuous chain from `curve.points[0]` to
/// `curve.points[3]` (exactly, bit for bit, at both ends and between pieces); the first piece
/// starts and the last piece ends in the rational curve's own tangent directions, and
/// consecutive pieces share their tangent direction, so G1 joints stay G1. A polynomial
/// input comes back unchanged as one cubic.
///
/// Not guaranteed: the distance is measured at samples (see the module docs), so it is a
/// close estimate rather than a proof; it is within `bound` unless subdivision reached
/// `MAX_DEPTH`. A NaN bound or non-finite coordinates never subdivide; a bound ≤ 0
/// subdivides to the cap.
///
/// Degenerate tangents (C1 = C0 or C2 = C3) fall back to the next control point, then the
/// chord, which is where the rational curve actually leaves its end point.
pub fn approximate_with_cubics(curve: &RationalCubic, bound: f64) -> Vec<CubicBez> {
    if curve.is_polynomial() {
        return vec![CubicBez {
            points: curve.points,
        }];
    }
    let start = start_direction(curve);
    let end = end_direction(curve);
    let mut out = Vec::new();
    approximate_into(curve, start, end, bound, 0, &mut out);
    out
}

fn approximate_into(
    curve: &RationalCubic,
    start: Point,
    end: Point,
    bound: f64,
    depth: u32,
    out: &mut Vec<CubicBez>,
) {
    let fit = fit_cubic(curve, start, end, bound);
    let done = depth >= MAX_DEPTH
        || !fit.worst.is_finite()
        || !(fit.worst > bound || check_distance(curve, &fit) > bound);
    if done {
        out.push(fit.cubic);
        return;
    }
    let (left, right) = curve.split(0.5);
    // One shared direction for both sides of the split makes the pieces G1 exactly.
    let mid = curve
        .jet(0.5)
        .d1
        .normalized()
        .unwrap_or_else(|| end_direction(&left));
    approximate_into(&left, start, mid, bound, depth + 1, out);
    approximate_into(&right, mid, end, bound, depth + 1, out);
}

/// A fitted cubic with what the distance check needs.
struct CubicFit {
    cubic: CubicBez,
    /// Foot-point parameter on `cubic` of each fit sample u = k / FIT_INTERVALS, with the
    /// ends: `params[0] = 0`, `params[FIT_INTERVALS] = 1`.
    params: Vec<f64>,
    /// Largest distance from a fit sample of the rational curve to the cubic.
    worst: f64,
}

/// The cubic family of one fit: fixed ends and tangent directions, free lengths a, b.
struct Family {
    c0: Point,
    c3: Point,
    t0: Point,
    t3: Point,
    /// Smallest tangent length allowed: a zero or negative length would make the tangent
    /// direction undefined or turn it around.
    min_length: f64,
}

impl Family {
    fn cubic(&self, (a, b): (f64, f64)) -> CubicBez {
        CubicBez::new(
            self.c0,
            self.c0 + self.t0 * a,
            self.c3 - self.t3 * b,
            self.c3,
        )
    }

    /// Least-squares (a, b) for fixed parameters, by the point distance when `normals` is
    /// `None`, else by the tangent distance Σ λ_i (n_i·(B(s_i) − Q_i))².
    ///
    /// B(s) = (b0 + b1) C0 + (b2 + b3) C3 + a b1 t0 − b b2 t3 is linear in (a, b), so either
    /// fit is a 2×2 normal system. For the point distance its determinant
    /// Σb1²·Σb2² − (Σb1b2)²(t0·t3)² is positive for distinct parameters (Cauchy–Schwarz);
    /// a singular system keeps `fallback`. Lengths below `min_length` are held at it and the
    /// other length re-solved (an active set of size one).
    fn solve(
        &self,
        samples: &[Point],
        params: &[f64],
        normals: Option<(&[Point], &[f64])>,
        fallback: (f64, f64),
    ) -> (f64, f64) {
        let (mut a11, mut a12, mut a22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (i, (&q, &s)) in samples.iter().zip(params).enumerate() {
            let b = super::bernstein(s);
            let r = q - self.c0 * (b[0] + b[1]) - self.c3 * (b[2] + b[3]);
            let g = self.t0 * b[1];
            let h = self.t3 * -b[2];
            // Project onto the normal for the tangent distance; weight by λ.
            let (g, h, r, l) = match normals {
                Some((n, lambda)) => (
                    Point::new(n[i].dot(g), 0.0),
                    Point::new(n[i].dot(h), 0.0),
                    Point::new(n[i].dot(r), 0.0),
                    lambda[i],
                ),
                None => (g, h, r, 1.0),
            };
            a11 += l * g.dot(g);
            a12 += l * g.dot(h);
            a22 += l * h.dot(h);
            r1 += l * g.dot(r);
            r2 += l * h.dot(r);
        }
        let (det, [a0, b0]) = cramer2([[a11, a12], [a12, a22]], [r1, r2]);
        let (mut a, mut b) = if det > 1e-12 * a11 * a22 && det.is_finite() {
            (a0, b0)
        } else {
            fallback
        };
        if a < self.min_length {
            a = self.min_length;
            if a22 > 0.0 {
                b = (r2 - a12 * a) / a22;
            }
        }
        if b < self.min_length {
            b = self.min_length;
            if a11 > 0.0 {
                a = (r1 - a12 * b) / a11;
            }
            a = a.max(self.min_length);
        }
        (a, b)
    }
}

/// One cubic with the end points of `curve`, P1 = C0 + a·start and P2 = C3 − b·end, a, b > 0.
///
/// First a point-distance least-squares fit against the samples with chord-length
/// parameters and [`CORRECTION_ROUNDS`] rounds of parameter correction; then up to
/// [`POLISH_ROUNDS`] rounds that re-project the samples and minimise the weighted tangent
/// distance, the weights updated by Lawson's rule (λ_i ∝ λ_i·d_i) so that the fit moves
/// towards the smallest maximum distance. The tangent distance converges much faster than
/// parameter correction (which stalled at several times the optimum in our measurements).
/// Stops early once the largest sample distance is below `0.75·bound`, or when the fit is
/// hopeless, since it will be split anyway: more than 4·bound after four rounds or
/// 1.5·bound after eight. On a page of text (26 000 fits) every fit that ended within the
/// bound was within 0.97·bound after eight rounds, while a fifth of all fits ran the full
/// sixteen rounds only to fail.
fn fit_cubic(curve: &RationalCubic, start: Point, end: Point, bound: f64) -> CubicFit {
    let c0 = curve.points[0];
    let c3 = curve.points[3];
    let samples: Vec<Point> = (1..FIT_INTERVALS)
        .map(|i| curve.eval(i as f64 / FIT_INTERVALS as f64))
        .collect();
    let scale = curve
        .points
        .iter()
        .map(|p| p.distance(c0))
        .fold(0.0, f64::max);
    let family = Family {
        c0,
        c3,
        t0: start,
        t3: end,
        min_length: 1e-3 * scale,
    };
    let chord_third = c0.distance(c3) / 3.0;
    let mut params = chord_length_params(c0, &samples, c3);
    let mut lengths = family.solve(&samples, &params, None, (chord_third, chord_third));
    // Projections go through the cubic's power form, made once per round (what
    // `CubicBez::refine_projection` makes at every call).
    let power = |cubic: &CubicBez| PowerCubic::polynomial(&cubic.points);
    for _ in 0..CORRECTION_ROUNDS {
        let cubic = power(&family.cubic(lengths));
        for (s, &q) in params.iter_mut().zip(&samples) {
            *s = cubic.refine_projection(q, *s, CONVERGED_STEP).0;
        }
        lengths = family.solve(&samples, &params, None, lengths);
    }
    let mut lambda = vec![1.0 / samples.len() as f64; samples.len()];
    let mut normals = vec![Point::ZERO; samples.len()];
    let mut best = (f64::INFINITY, lengths, params.clone());
    for round in 0..POLISH_ROUNDS {
        let cubic = family.cubic(lengths);
        let projected = power(&cubic);
        let mut worst: f64 = 0.0;
        let mut total = 0.0;
        for (i, &q) in samples.iter().enumerate() {
            let (t, d) = projected.refine_projection(q, params[i], CONVERGED_STEP);
            params[i] = t;
            if d.is_nan() {
                worst = f64::NAN;
            }
            worst = worst.max(d);
            normals[i] = cubic.deriv(t).perp().normalized().unwrap_or(Point::ZERO);
            lambda[i] *= d.max(1e-9 * (1.0 + scale));
            total += lambda[i];
        }
        if worst < best.0 {
            best = (worst, lengths, params.clone());
        }
        let hopeless = (round >= 3 && best.0 > 4.0 * bound) || (round >= 7 && best.0 > 1.5 * bound);
        let good_enough = best.0 <= 0.75 * bound;
        if good_enough || hopeless || total <= 0.0 || total.is_nan() {
            break;
        }
        for l in lambda.iter_mut() {
            *l /= total;
        }
        lengths = family.solve(&samples, &params, Some((&normals, &lambda)), lengths);
    }
    let (worst, lengths, inner) = best;
    let mut params = Vec::with_capacity(FIT_INTERVALS + 1);
    params.push(0.0);
    params.extend(inner);
    params.push(1.0);
    CubicFit {
        cubic: family.cubic(lengths),
        params,
        worst,
    }
}

/// The distance between the rational curve and the cubic, measured both ways (the larger
/// of the curve's distance to the cubic and the cubic's to the curve) at the fit samples
/// and the midpoints between them, with each projection started from the known correspondence of the fit
/// instead of a global scan. A projection that stalls in a local minimum can only report a
/// larger distance, so the shortcut errs towards splitting. Both projections stop at
/// Newton steps below [`CONVERGED_STEP`]: on a curve of 1000 px such a step moves the foot
/// by 1e-7 px, and the distance, stationary at the foot, by far less, against a bound of
/// at least 0.005 px. Running the rational one on to round-off ([`EXACT_STEP`]'s 1e-15)
/// took 7 % of the processor time of the 1600 px bicubic horse and drew the same bytes
/// (the horse series, the scan, the upscaled page, the 912 corpus SVGs).
///
/// [`EXACT_STEP`]: super::power::EXACT_STEP
fn check_distance(curve: &RationalCubic, fit: &CubicFit) -> f64 {
    let n = FIT_INTERVALS;
    // Both curves' power forms made once (each projection call would make its own).
    let cubic = PowerCubic::polynomial(&fit.cubic.points);
    let rational = curve.power_form();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let (u0, u1) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
        let (s0, s1) = (fit.params[k], fit.params[k + 1]);
        let (um, sm) = (0.5 * (u0 + u1), 0.5 * (s0 + s1));
        // The fit samples (k > 0) and the midpoints between them; the ends match exactly.
        let pairs = [(um, sm), (u0, s0)];
        for &(u, s) in &pairs[..if k > 0 { 2 } else { 1 }] {
            let d1 = cubic.refine_projection(curve.eval(u), s, CONVERGED_STEP).1;
            let d2 = rational
                .refine_projection(fit.cubic.eval(s), u, CONVERGED_STEP)
                .1;
            if d1.is_nan() || d2.is_nan() {
                return f64::NAN;
            }
            worst = worst.max(d1).max(d2);
        }
    }
    worst
}

/// Normalized cumulative chord lengths of `samples` between the fixed ends.
fn chord_length_params(c0: Point, samples: &[Point], c3: Point) -> Vec<f64> {
    let mut acc = Vec::with_capacity(samples.len());
    let mut total = 0.0;
    let mut prev = c0;
    for &q in samples {
        total += q.distance(prev);
        acc.push(total);
        prev = q;
    }
    total += c3.distance(prev);
    let n = samples.len() + 1;
    acc.iter()
        .enumerate()
        .map(|(i, &s)| {
            if total > 0.0 && total.is_finite() {
                s / total
            } else {
                (i + 1) as f64 / n as f64
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::angle_between;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random glyph-like rational segment spanning about `span` pixels.
    fn random_curve(rng: &mut ChaCha8Rng, span: f64, weights: (f64, f64)) -> RationalCubic {
        let k = span / 60.0;
        let p = |x: f64, y: f64| Point::new(x * k, y * k);
        RationalCubic::new(
            [
                p(0.0, 0.0),
                p(rng.random_range(5.0..25.0), rng.random_range(10.0..40.0)),
                p(rng.random_range(35.0..55.0), rng.random_range(10.0..40.0)),
                p(60.0, rng.random_range(-5.0..5.0)),
            ],
            [
                rng.random_range(weights.0..weights.1),
                rng.random_range(weights.0..weights.1),
            ],
        )
    }

    fn assert_chain(curve: &RationalCubic, pieces: &[CubicBez]) {
        assert_eq!(pieces[0].points[0], curve.points[0]);
        assert_eq!(pieces[pieces.len() - 1].points[3], curve.points[3]);
        for pair in pieces.windows(2) {
            assert_eq!(pair[0].points[3], pair[1].points[0]);
            let (Some(t_in), Some(t_out)) = (pair[0].end_tangent(), pair[1].start_tangent()) else {
                panic!("degenerate tangent at an inner joint");
            };
            assert!(angle_between(t_in, t_out) < 1e-9);
        }
    }

    #[test]
    fn polynomial_input_is_returned_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut c = random_curve(&mut rng, 50.0, (0.5, 2.0));
        c.weights = [1.0, 1.0];
        let pieces = approximate_with_cubics(&c, 1e-9);
        assert_eq!(pieces, vec![CubicBez { points: c.points }]);
    }

    #[test]
    fn random_rational_curves_are_within_bound_and_g1() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..60 {
            let c = random_curve(&mut rng, 50.0, (0.2, 2.5));
            for &bound in &[0.05, 0.02, 0.005] {
                let pieces = approximate_with_cubics(&c, bound);
                assert!(pieces.len() < 1 << MAX_DEPTH);
                assert_chain(&c, &pieces);
                // Ends keep the rational curve's own tangent directions.
                let t0 = c.start_tangent().unwrap();
                let t3 = c.end_tangent().unwrap();
                assert!(angle_between(pieces[0].start_tangent().unwrap(), t0) < 1e-9);
                assert!(angle_between(pieces[pieces.len() - 1].end_tangent().unwrap(), t3) < 1e-9);
                // Every piece is within the bound of the rational curve, measured densely
                // (4× the internal sampling) from both sides.
                for piece in &pieces {
                    for j in 0..=256 {
                        let s = j as f64 / 256.0;
                        assert!(c.nearest(piece.eval(s), 64).1 <= bound * 1.05);
                    }
                }
                let dense_max = (0..=256)
                    .map(|j| {
                        let q = c.eval(j as f64 / 256.0);
                        pieces
                            .iter()
                            .map(|p| p.nearest(q, 32).1)
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max);
                assert!(dense_max <= bound * 1.05, "{dense_max} > {bound}");
            }
        }
    }

    #[test]
    fn g1_joints_between_rational_segments_stay_g1() {
        // Two rational segments meeting G1 at (30, 10) with different handle lengths.
        let joint = Point::new(30.0, 10.0);
        let dir = Point::new(0.6, 0.8);
        let a = RationalCubic::new(
            [
                Point::new(0.0, 0.0),
                Point::new(8.0, 14.0),
                joint - dir * 9.0,
                joint,
            ],
            [0.35, 2.3],
        );
        let b = RationalCubic::new(
            [
                joint,
                joint + dir * 4.0,
                Point::new(55.0, 30.0),
                Point::new(60.0, 0.0),
            ],
            [2.1, 0.45],
        );
        let pa = approximate_with_cubics(&a, 0.02);
        let pb = approximate_with_cubics(&b, 0.02);
        let t_in = pa[pa.len() - 1].end_tangent().unwrap();
        let t_out = pb[0].start_tangent().unwrap();
        assert!(angle_between(t_in, t_out) < 1e-9);
        assert!(angle_between(t_in, dir) < 1e-9);
    }

    #[test]
    fn degenerate_tangents_fall_back_without_panicking() {
        let p0 = Point::new(1.0, 1.0);
        let p3 = Point::new(21.0, 1.0);
        // C1 = C0: the curve leaves towards C2.
        let c = RationalCubic::new([p0, p0, Point::new(15.0, 12.0), p3], [1.7, 0.6]);
        let pieces = approximate_with_cubics(&c, 0.02);
        assert_chain(&c, &pieces);
        let expected = (Point::new(15.0, 12.0) - p0).normalized().unwrap();
        assert!(angle_between(pieces[0].start_tangent().unwrap(), expected) < 1e-9);
        // C1 = C0 and C2 = C3: a straight segment, tangents along the chord.
        let line = RationalCubic::new([p0, p0, p3, p3], [0.4, 2.0]);
        let pieces = approximate_with_cubics(&line, 0.02);
        assert_chain(&line, &pieces);
        for piece in &pieces {
            for j in 0..=8 {
                assert!((piece.eval(j as f64 / 8.0).y - 1.0).abs() < 1e-12);
            }
        }
        // All points equal: a point, one piece, no NaN.
        let dot = RationalCubic::new([p0; 4], [0.5, 2.0]);
        let pieces = approximate_with_cubics(&dot, 0.02);
        assert_eq!(pieces, vec![CubicBez { points: [p0; 4] }]);
        // Non-finite input does not panic and does not subdivide.
        let bad = RationalCubic::new([p0, Point::new(f64::NAN, 0.0), p3, p3], [0.5, 2.0]);
        assert_eq!(approximate_with_cubics(&bad, 0.02).len(), 1);
    }

    /// Measured piece counts, the number the SVG benchmark pays for. Fixed seeds, so a
    /// change of the fit or of the sampling shows up here.
    ///
    /// Measured (200 random 50-px segments, the control polygons of `random_curve`):
    /// weights in [0.2, 2.5] at bound 0.02 px → 10 need one piece, 168 two, 16 three, 6 four
    /// (418 pieces, 2.09 per curve); weights in [0.3, 2.5] at 0.05 px → 23 / 172 / 5 / 0
    /// (382 pieces). Random weights on a random polygon are far from polynomial (a single
    /// cubic misses by 0.05–4 px), so one piece is the exception there. Rational circular
    /// arcs, the typical rational shape in glyphs, need one piece up to a quarter circle of
    /// radius 70 px at 0.02 px.
    #[test]
    fn piece_counts_for_glyph_size_curves() {
        let count = |span: f64, weights: (f64, f64), bound: f64| {
            let mut rng = ChaCha8Rng::seed_from_u64(5);
            let mut histogram = [0usize; 5];
            let mut total = 0;
            for _ in 0..200 {
                let c = random_curve(&mut rng, span, weights);
                let n = approximate_with_cubics(&c, bound).len();
                histogram[n.min(4)] += 1;
                total += n;
            }
            (histogram, total)
        };
        let (h, total) = count(50.0, (0.2, 2.5), 0.02);
        eprintln!("50 px, w in [0.2, 2.5], bound 0.02: pieces {h:?}, total {total}");
        assert!(total <= 425, "{h:?}");
        assert!(h[1] + h[2] >= 170, "{h:?}");
        let (h, total) = count(50.0, (0.3, 2.5), 0.05);
        eprintln!("50 px, w in [0.3, 2.5], bound 0.05: pieces {h:?}, total {total}");
        assert!(total <= 390, "{h:?}");
        // Quarter circles as degree-elevated conics: one piece up to r = 70 at 0.02 px.
        for &r in &[5.0, 25.0, 70.0] {
            let arc = quarter_arc(Point::new(100.0, 100.0), r, 0.3);
            assert_eq!(approximate_with_cubics(&arc, 0.02).len(), 1, "r = {r}");
        }
        let arc = quarter_arc(Point::new(100.0, 100.0), 200.0, 0.3);
        assert_eq!(approximate_with_cubics(&arc, 0.02).len(), 2);
    }

    /// A quarter circle of radius `r` around `center` starting at angle `phi`, exact as a
    /// rational cubic: the conic (w = cos 45°) degree-elevated, w1 = w2 = (1 + 2w) / 3.
    fn quarter_arc(center: Point, r: f64, phi: f64) -> RationalCubic {
        let at = |a: f64| center + Point::new(a.cos(), a.sin()) * r;
        let p1 = center
            + Point::new(
                (phi + std::f64::consts::FRAC_PI_4).cos(),
                (phi + std::f64::consts::FRAC_PI_4).sin(),
            ) * (r * std::f64::consts::SQRT_2);
        let p2 = at(phi + std::f64::consts::FRAC_PI_2);
        RationalCubic::from_conic(at(phi), p1, p2, std::f64::consts::FRAC_1_SQRT_2)
    }

    #[test]
    fn quarter_arc_is_a_circle() {
        let c = quarter_arc(Point::new(3.0, 4.0), 10.0, 0.7);
        for j in 0..=20 {
            let d = c.eval(j as f64 / 20.0).distance(Point::new(3.0, 4.0));
            assert!((d - 10.0).abs() < 1e-12, "{d}");
        }
    }
}
