//! Bounded continuous minimisation by metaheuristics.
//!
//! One trait, [`Optimizer`], every algorithm behind it: a [`Problem`] has box bounds and an
//! objective; an optimizer spends at most a budget of objective evaluations and returns an
//! [`Outcome`] with the best point, its value, the evaluations used and the best-so-far
//! history. Every random choice comes from the seeded generator passed in, so a run is
//! reproducible from its seed.
//!
//! Harmony search ([`HarmonySearch`]) is written by hand: no maintained crate implements it
//! with a seedable generator.

mod hs;

pub use hs::HarmonySearch;

/// The random generator every optimizer draws from: ChaCha8, seeded by the caller.
pub type SeededRng = rand_chacha::ChaCha8Rng;

/// A bounded minimisation problem.
pub trait Problem {
    /// Number of variables.
    fn dim(&self) -> usize;
    /// Lower and upper bound of variable `i` (lower ≤ upper).
    fn bounds(&self, i: usize) -> (f64, f64);
    /// The objective at `x` (`x.len() == dim()`, every coordinate within its bounds).
    fn evaluate(&self, x: &[f64]) -> f64;
}

/// What a run of an optimizer found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Outcome {
    /// The best point found.
    pub best: Vec<f64>,
    /// The objective at `best`.
    pub value: f64,
    /// Objective evaluations used.
    pub evaluations: u64,
    /// Best value so far after each evaluation (empty unless requested).
    pub history: Vec<f64>,
}

/// A bounded minimiser with an evaluation budget.
pub trait Optimizer {
    /// The command-line name, e.g. `hs`.
    fn name(&self) -> &'static str;
    /// Minimises `problem` with at most `budget` objective evaluations. With
    /// `record_history` the outcome lists the best value after every evaluation.
    fn minimize(
        &self,
        problem: &dyn Problem,
        budget: u64,
        rng: &mut SeededRng,
        record_history: bool,
    ) -> Outcome;
}

/// Standard test functions, for checking optimizers before trusting them on curves.
#[cfg(test)]
pub(crate) mod testfns {
    use super::Problem;

    /// Sphere: Σ x², minimum 0 at the origin, in [-5, 5]^n.
    pub(crate) struct Sphere(pub usize);
    impl Problem for Sphere {
        fn dim(&self) -> usize {
            self.0
        }
        fn bounds(&self, _i: usize) -> (f64, f64) {
            (-5.0, 5.0)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            x.iter().map(|v| v * v).sum()
        }
    }

    /// Rosenbrock: minimum 0 at (1, …, 1), in [-2, 2]^n.
    pub(crate) struct Rosenbrock(pub usize);
    impl Problem for Rosenbrock {
        fn dim(&self) -> usize {
            self.0
        }
        fn bounds(&self, _i: usize) -> (f64, f64) {
            (-2.0, 2.0)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            x.windows(2)
                .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
                .sum()
        }
    }

    /// Rastrigin: minimum 0 at the origin, many local minima, in [-5.12, 5.12]^n.
    pub(crate) struct Rastrigin(pub usize);
    impl Problem for Rastrigin {
        fn dim(&self) -> usize {
            self.0
        }
        fn bounds(&self, _i: usize) -> (f64, f64) {
            (-5.12, 5.12)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            10.0 * x.len() as f64
                + x.iter()
                    .map(|v| v * v - 10.0 * (std::f64::consts::TAU * v).cos())
                    .sum::<f64>()
        }
    }
}
