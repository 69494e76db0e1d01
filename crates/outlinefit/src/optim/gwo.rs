//! Grey wolf optimizer (Mirjalili, Mirjalili & Lewis 2014), as described in §3 of the
//! SG-Bézier degree-reduction paper (`shared/papers/sg-bezier-degree-reduction-gwo.txt`).
//!
//! The pack is ranked into α, β, δ (the three best points) and ω (the rest). Every wolf X
//! moves towards the three leaders (Eqs. 10–12): for each leader L and each coordinate,
//! with r₁, r₂ uniform in [0, 1], A = 2a·r₁ − a and C = 2r₂, D = |C·L − X|, X_L = L − A·D;
//! the new position is (X_α + X_β + X_δ) / 3. The coefficient `a` falls linearly from 2 to
//! 0 (§3.1.2, a(t) = 2(1 − t/M)); here t/M is the fraction of the evaluation budget spent
//! (evaluations / budget), so the schedule completes exactly at the budget whatever the
//! population size.
//!
//! Defaults: population 20 (§5, "the population size of grey wolves as 20"); the paper's
//! 300 iterations correspond to a budget of 20 × 300 = 6,000 evaluations, which is the
//! caller's choice here.
//!
//! Choices the paper leaves open, taken from Mirjalili's reference implementation: the
//! leaders are the best three distinct points evaluated so far (not only those of the
//! current pack), updated after every evaluation with proper demotion (a new α pushes the
//! old α to β and β to δ); wolves always move (no greedy acceptance). With fewer than three
//! points evaluated the missing leaders repeat the best one.
//!
//! Known behaviour: GWO's update contracts towards the coordinate origin, so it lands
//! exactly on optima at the origin (Sphere, Rastrigin) and is far weaker on the same
//! problems shifted away from it (see the tests' `shifted` figures).
//!
//! Bound handling: every coordinate of a moved wolf is clamped into its bounds (as in the
//! reference implementation).
//!
//! Written by hand: no maintained crate implements GWO over a caller-seeded generator with
//! an exact evaluation budget.

use super::problem::{clamp_to, random_point, Optimizer, SeededRng, Tracker};
use rand::RngExt;

/// Grey wolf optimizer parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct GreyWolf {
    /// Number of wolves. Default: 20 (the paper's §5).
    pub population: usize,
    /// Value of the coefficient `a` at the start of the run. Default: 2 (§3.1.2).
    pub a_start: f64,
    /// Value of `a` when the budget is spent; `a` moves linearly between the two with the
    /// fraction of the budget used. Default: 0 (§3.1.2).
    pub a_end: f64,
}

impl Default for GreyWolf {
    fn default() -> Self {
        GreyWolf {
            population: 20,
            a_start: 2.0,
            a_end: 0.0,
        }
    }
}

/// The three best points so far: α, β, δ (each row `dim` values), best first.
struct Leaders {
    points: Vec<f64>,
    values: [f64; 3],
    dim: usize,
}

impl Leaders {
    fn new(dim: usize) -> Self {
        Leaders {
            points: vec![0.0; 3 * dim],
            values: [f64::INFINITY; 3],
            dim,
        }
    }

    /// Offers the evaluated point `x` with value `v`; it takes its rank among the leaders.
    fn offer(&mut self, x: &[f64], v: f64) {
        let d = self.dim;
        let Some(rank) = self.values.iter().position(|&w| v < w) else {
            return;
        };
        for r in (rank + 1..3).rev() {
            self.values[r] = self.values[r - 1];
            self.points.copy_within((r - 1) * d..r * d, r * d);
        }
        self.values[rank] = v;
        self.points[rank * d..(rank + 1) * d].copy_from_slice(x);
    }

    /// Leader `r` (0 = α, 1 = β, 2 = δ); a missing leader is the best point instead.
    fn get(&self, r: usize) -> &[f64] {
        let r = if self.values[r] == f64::INFINITY && self.values[0] < f64::INFINITY {
            0
        } else {
            r
        };
        &self.points[r * self.dim..(r + 1) * self.dim]
    }
}

impl Optimizer for GreyWolf {
    fn name(&self) -> &'static str {
        "gwo"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let budget = tracker.remaining();
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let pop = self.population.max(1);
        let mut wolves = vec![0.0; pop * dim];
        for w in wolves.chunks_exact_mut(dim) {
            random_point(rng, &bounds, w);
        }
        let mut leaders = Leaders::new(dim);
        let mut unranked_best = vec![0.0; dim];
        'run: loop {
            for w in wolves.chunks_exact(dim) {
                let Some(v) = tracker.evaluate(w) else {
                    break 'run;
                };
                leaders.offer(w, v);
            }
            // An infinite objective never enters the leaders; fall back to the best point.
            if leaders.values[0] == f64::INFINITY {
                unranked_best.copy_from_slice(tracker.best());
                leaders.offer(&unranked_best, f64::MAX);
            }
            let progress = tracker.evaluations() as f64 / budget as f64;
            let a = self.a_start + (self.a_end - self.a_start) * progress;
            for w in wolves.chunks_exact_mut(dim) {
                for k in 0..dim {
                    let mut sum = 0.0;
                    for r in 0..3 {
                        let l = leaders.get(r)[k];
                        let big_a = 2.0 * a * rng.random::<f64>() - a;
                        let c = 2.0 * rng.random::<f64>();
                        let d = (c * l - w[k]).abs();
                        sum += l - big_a * d;
                    }
                    w[k] = sum / 3.0;
                }
                clamp_to(&bounds, w);
            }
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
    fn budget_smaller_than_population() {
        let o = run_checked(&GreyWolf::default(), &Sphere(3), 7, 4);
        assert!(o.value.is_finite());
    }
    #[test]
    fn shifted() {
        let opt = GreyWolf::default();
        let a = run_checked(&opt, &Shifted(Sphere(10), 7.0), 6000, 5);
        let b = run_checked(&opt, &Shifted(Rastrigin(5), 7.0), 6000, 5);
        let c = run_checked(&opt, &Shifted(Rosenbrock(5), 3.0), 6000, 5);
        assert!(a.value < 1e-2, "sphere {}", a.value); // 1.9e-3
        assert!(b.value < 12.0, "rastrigin {}", b.value); // 8.47
        assert!(c.value < 2.0, "rosenbrock {}", c.value); // 1.02
    }
}
