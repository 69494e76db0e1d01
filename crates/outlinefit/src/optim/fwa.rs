//! Fireworks algorithm (Tan & Zhu 2010), as used in §III of the curve-to-B-spline paper
//! (`shared/papers/fireworks-curve-to-bspline.txt`).
//!
//! A generation explodes each of n fireworks into sparks and then selects the next n
//! locations among fireworks and sparks:
//!
//! * Spark counts (Eq. 3): s_i = S · (E_max − E_i + ε) / (Σ_j (E_max − E_j) + ε), so better
//!   fireworks get more sparks; as in Tan & Zhu, s_i is bounded to [a·S, b·S] and rounded.
//! * Amplitudes (Eq. 4): A_i = Â · (E_i − E_min + ε) / (Σ_j (E_j − E_min) + ε), so better
//!   fireworks explode more closely. Â is a fraction of each variable's range (the paper
//!   searches parameters in [0, 1], where its amplitudes 0.01–0.03 are absolute values).
//! * An explosion spark picks z = round(d · U(0, 1)) of the d coordinates at random (at
//!   least one, so that no spark repeats its firework) and adds one common displacement
//!   h = A_i · U(−1, 1) · range to each of them (Tan & Zhu's Algorithm 1).
//! * m̂ Gaussian sparks (Tan & Zhu's Algorithm 2): a random firework, z random coordinates
//!   multiplied by one g ~ N(1, 1).
//! * Selection: the best of all fireworks and sparks is kept; the other n − 1 locations are
//!   drawn without replacement with probability proportional to R(x) = Σ_j ‖x − x_j‖, the
//!   summed Euclidean distance to all other candidates (Tan & Zhu's Eqs. 3–4).
//!
//! ε is the machine epsilon. A non-finite objective value gets the fewest sparks (a·S) and
//! the full amplitude Â and is left out of E_max, E_min and the sums.
//!
//! Defaults: the paper gives ranges found by test cases, "number of sparks and number of
//! fireworks … 3–5 and 2–10" and amplitude "0.01 to 0.03". The sparks figure is read as the
//! mean number of explosion sparks per firework, so S = 5 × n; n = 5 (Tan & Zhu's value, in
//! the paper's range); Â = 0.03 (the top of the range: the sum of all amplitudes is about
//! Â, so the mean explosion is only Â / n of the range). From Tan & Zhu, since the paper
//! does not state them: a = 0.04, b = 0.8, m̂ = 5.
//!
//! Known behaviour of the algorithm as published: with ε this small the best firework's
//! amplitude is ≈ 0, so its sparks (the most numerous) barely move; and the Gaussian
//! sparks x · g pull towards the coordinate origin, so origin-centred test problems are
//! solved almost exactly while shifted ones are not (see the tests' `shifted` figures).
//!
//! Bound handling: the modular mapping of Tan & Zhu, made shift-invariant: a coordinate
//! outside [lo, hi] is wrapped periodically, lo + (x − lo) mod (hi − lo). (Their literal
//! lo + |x| mod (hi − lo) depends on where the origin lies and pulls points towards it.)
//!
//! Budget: the initial n fireworks count, as does every spark; the selected fireworks are
//! not re-evaluated. The run stops at exactly the budget, mid-generation if need be.
//!
//! Written by hand: no maintained crate implements the fireworks algorithm over a
//! caller-seeded generator with an exact evaluation budget.

use super::problem::{random_point, standard_normal, uniform, Optimizer};
use super::problem::{SeededRng, Tracker};
use rand::RngExt;

/// Fireworks algorithm parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Fireworks {
    /// Number of fireworks n. Default: 5 (Tan & Zhu; the paper's range is 2–10).
    pub fireworks: usize,
    /// Total explosion sparks per generation, S of Eq. 3 (Tan & Zhu's m). Default: 25, i.e.
    /// 5 per firework (the top of the paper's 3–5 range).
    pub sparks: f64,
    /// Lower bound on a firework's spark count as a fraction of `sparks` (Tan & Zhu's a).
    /// Default: 0.04.
    pub min_sparks: f64,
    /// Upper bound on a firework's spark count as a fraction of `sparks` (Tan & Zhu's b).
    /// Default: 0.8.
    pub max_sparks: f64,
    /// Maximum explosion amplitude Â of Eq. 4, as a fraction of each variable's range.
    /// Default: 0.03 (the paper's range is 0.01–0.03).
    pub amplitude: f64,
    /// Gaussian sparks per generation (Tan & Zhu's m̂). Default: 5.
    pub gaussian_sparks: usize,
}

impl Default for Fireworks {
    fn default() -> Self {
        Fireworks {
            fireworks: 5,
            sparks: 25.0,
            min_sparks: 0.04,
            max_sparks: 0.8,
            amplitude: 0.03,
            gaussian_sparks: 5,
        }
    }
}

/// Wraps `x` periodically into `[lo, hi]` if it lies outside (NaN goes to `lo`).
fn wrap(x: f64, (lo, hi): (f64, f64)) -> f64 {
    if x.is_nan() || hi <= lo {
        return lo;
    }
    if (lo..=hi).contains(&x) {
        return x;
    }
    let y = lo + (x - lo).rem_euclid(hi - lo);
    if y.is_finite() {
        y.clamp(lo, hi)
    } else {
        lo
    }
}

/// Chooses `z` distinct coordinates: the first `z` entries of `dims` after a partial
/// Fisher–Yates shuffle.
fn choose_dims(rng: &mut SeededRng, dims: &mut [usize], z: usize) {
    for i in 0..z {
        let j = rng.random_range(i..dims.len());
        dims.swap(i, j);
    }
}

/// How many coordinates a spark changes: round(d · U(0, 1)), at least one.
fn spark_dims(rng: &mut SeededRng, dim: usize) -> usize {
    ((dim as f64 * rng.random::<f64>()).round() as usize).clamp(1, dim)
}

impl Optimizer for Fireworks {
    fn name(&self) -> &'static str {
        "fwa"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let n = self.fireworks.max(1);
        let s_total = self.sparks.max(0.0);
        let s_lo = (self.min_sparks * s_total).round().max(0.0) as usize;
        let s_hi = (self.max_sparks * s_total).round().max(s_lo as f64) as usize;
        let capacity = n + n * s_hi + self.gaussian_sparks;
        // Candidate pool: the fireworks first, then this generation's sparks.
        let mut pool = vec![0.0; capacity * dim];
        let mut values = vec![0.0; capacity];
        let mut distance = vec![0.0; capacity];
        let mut next = vec![0.0; n * dim];
        let mut next_values = vec![0.0; n];
        let mut counts = vec![0usize; n];
        let mut amplitudes = vec![0.0; n];
        let mut dims: Vec<usize> = (0..dim).collect();
        let mut spark = vec![0.0; dim];

        let mut live = 0; // fireworks evaluated so far
        for i in 0..n {
            let x = &mut pool[i * dim..(i + 1) * dim];
            random_point(rng, &bounds, x);
            match tracker.evaluate(x) {
                Some(v) => values[i] = v,
                None => break,
            }
            live += 1;
        }
        let n = live;
        'run: while !tracker.exhausted() {
            // Eqs. 3–4 over the finite values.
            let fin = || values[..n].iter().copied().filter(|v| v.is_finite());
            let e_max = fin().fold(f64::NEG_INFINITY, f64::max);
            let e_min = fin().fold(f64::INFINITY, f64::min);
            let sum_max: f64 = fin().map(|v| e_max - v).sum();
            let sum_min: f64 = fin().map(|v| v - e_min).sum();
            let eps = f64::EPSILON;
            for i in 0..n {
                let e = values[i];
                let (s, a) = if e.is_finite() {
                    (
                        s_total * (e_max - e + eps) / (sum_max + eps),
                        self.amplitude * (e - e_min + eps) / (sum_min + eps),
                    )
                } else {
                    (0.0, self.amplitude)
                };
                let s = s.clamp(self.min_sparks * s_total, self.max_sparks * s_total);
                counts[i] = (s.round() as usize).clamp(s_lo, s_hi);
                amplitudes[i] = a;
            }
            // Explosion sparks.
            let mut k = n;
            for i in 0..n {
                for _ in 0..counts[i] {
                    spark.copy_from_slice(&pool[i * dim..(i + 1) * dim]);
                    let z = spark_dims(rng, dim);
                    choose_dims(rng, &mut dims, z);
                    let h = amplitudes[i] * uniform(rng, (-1.0, 1.0));
                    for &j in &dims[..z] {
                        let (lo, hi) = bounds[j];
                        spark[j] = wrap(spark[j] + h * (hi - lo), bounds[j]);
                    }
                    let Some(v) = tracker.evaluate(&spark) else {
                        break 'run;
                    };
                    pool[k * dim..(k + 1) * dim].copy_from_slice(&spark);
                    values[k] = v;
                    k += 1;
                }
            }
            // Gaussian sparks.
            for _ in 0..self.gaussian_sparks {
                let i = rng.random_range(0..n);
                spark.copy_from_slice(&pool[i * dim..(i + 1) * dim]);
                let z = spark_dims(rng, dim);
                choose_dims(rng, &mut dims, z);
                let g = 1.0 + standard_normal(rng);
                for &j in &dims[..z] {
                    spark[j] = wrap(spark[j] * g, bounds[j]);
                }
                let Some(v) = tracker.evaluate(&spark) else {
                    break 'run;
                };
                pool[k * dim..(k + 1) * dim].copy_from_slice(&spark);
                values[k] = v;
                k += 1;
            }
            // Selection: the best candidate, then n − 1 more by summed distance.
            let best = (0..k)
                .min_by(|&a, &b| values[a].total_cmp(&values[b]))
                .unwrap_or(0);
            for a in 0..k {
                let xa = &pool[a * dim..(a + 1) * dim];
                distance[a] = (0..k)
                    .map(|b| {
                        let xb = &pool[b * dim..(b + 1) * dim];
                        xa.iter()
                            .zip(xb)
                            .map(|(p, q)| (p - q) * (p - q))
                            .sum::<f64>()
                            .sqrt()
                    })
                    .sum();
            }
            let mut take = |slot: usize, c: usize, distance: &mut [f64]| {
                next[slot * dim..(slot + 1) * dim].copy_from_slice(&pool[c * dim..(c + 1) * dim]);
                next_values[slot] = values[c];
                distance[c] = -1.0; // taken
            };
            take(0, best, &mut distance);
            for slot in 1..n.min(k) {
                let total: f64 = distance[..k].iter().filter(|&&d| d > 0.0).sum();
                let c = if total > 0.0 {
                    let mut r = uniform(rng, (0.0, total));
                    let mut chosen = None;
                    for c in 0..k {
                        if distance[c] > 0.0 {
                            chosen = Some(c);
                            r -= distance[c];
                            if r <= 0.0 {
                                break;
                            }
                        }
                    }
                    chosen.unwrap_or(best)
                } else {
                    // Every remaining candidate coincides with the others: take any.
                    (0..k).find(|&c| distance[c] >= 0.0).unwrap_or(best)
                };
                take(slot, c, &mut distance);
            }
            let kept = n.min(k);
            pool[..kept * dim].copy_from_slice(&next[..kept * dim]);
            values[..kept].copy_from_slice(&next_values[..kept]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::problem::Problem;
    use crate::optim::testfns::{run_checked, Rastrigin, Rosenbrock, Sphere};

    /// `inner` moved by `shift + 0.37 i` along coordinate i, bounds included, so that the
    /// optimum leaves the origin (which lies outside the box for shift ≥ 6 on `Sphere`).
    /// Catches algorithms whose operators pull towards the coordinate origin.
    struct Shifted<P>(P, f64);
    impl<P: Problem> Problem for Shifted<P> {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn bounds(&self, i: usize) -> (f64, f64) {
            let (lo, hi) = self.0.bounds(i);
            let s = self.1 + 0.37 * i as f64;
            (lo + s, hi + s)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            let mut y = [0.0; 16];
            for (i, v) in x.iter().enumerate() {
                y[i] = v - (self.1 + 0.37 * i as f64);
            }
            self.0.evaluate(&y[..x.len()])
        }
    }

    #[test]
    fn wraps_periodically() {
        let b = (2.0, 3.0);
        assert_eq!(wrap(2.5, b), 2.5);
        assert_eq!(wrap(3.0, b), 3.0);
        assert!((wrap(3.25, b) - 2.25).abs() < 1e-12);
        assert!((wrap(1.75, b) - 2.75).abs() < 1e-12);
        assert!((wrap(-7.5, b) - 2.5).abs() < 1e-12);
        assert_eq!(wrap(f64::NAN, b), 2.0);
        assert_eq!(wrap(f64::INFINITY, b), 2.0);
        assert_eq!(wrap(5.0, (1.0, 1.0)), 1.0);
    }

    #[test]
    fn budget_smaller_than_population() {
        let o = run_checked(&Fireworks::default(), &Sphere(3), 3, 4);
        assert!(o.value.is_finite());
        let o = run_checked(&Fireworks::default(), &Sphere(3), 12, 4);
        assert!(o.value.is_finite());
    }
    #[test]
    fn shifted() {
        let opt = Fireworks::default();
        let a = run_checked(&opt, &Shifted(Sphere(10), 7.0), 6000, 5);
        let b = run_checked(&opt, &Shifted(Rastrigin(5), 7.0), 6000, 5);
        let c = run_checked(&opt, &Shifted(Rosenbrock(5), 3.0), 6000, 5);
        assert!(a.value < 2.5, "sphere {}", a.value); // 1.20
        assert!(b.value < 8.0, "rastrigin {}", b.value); // 4.71
        assert!(c.value < 5.0, "rosenbrock {}", c.value); // 3.08
    }
}
