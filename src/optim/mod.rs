//! Bounded continuous minimisation by metaheuristics.
//!
//! One trait, [`Optimizer`], every algorithm behind it: a [`Problem`] has box bounds and an
//! objective; an optimizer spends at most a budget of objective evaluations and returns an
//! [`Outcome`] with the best point, its value, the evaluations used and the best-so-far
//! history. Every random choice comes from the seeded generator passed in, so a run is
//! reproducible from its seed.
//!
//! [`by_name`] builds any of them with the papers' default parameters from its command-line
//! name ([`NAMES`]). Each algorithm lives in its own file; the module docs of each say where
//! its parameters come from. All of them are written by hand: no maintained crate
//! implements these algorithms over a caller-seeded generator with an exact evaluation
//! budget.
//!
//! Shared machinery: [`Tracker`] counts evaluations against the budget, keeps the best
//! point and the history, so every algorithm stops at exactly its budget.

mod beeso;
mod cs;
mod de;
mod fwa;
mod ga;
mod gwo;
mod hs;
mod pso;
mod so;

pub use beeso::Beeso;
pub use cs::CuckooSearch;
pub use de::DifferentialEvolution;
pub use fwa::Fireworks;
pub use ga::GeneticAlgorithm;
pub use gwo::GreyWolf;
pub use hs::HarmonySearch;
pub use pso::ParticleSwarm;
pub use so::SnakeOptimizer;

use rand::RngExt;

/// The random generator every optimizer draws from: ChaCha8, seeded by the caller.
pub type SeededRng = rand_chacha::ChaCha8Rng;

/// Command-line names of every optimizer, in the order reports list them.
pub const NAMES: &[&str] = &[
    "hs", "ga", "pso", "gwo", "cs", "ics", "fwa", "so", "beeso", "de",
];

/// The optimizer with command-line name `name`, with its default parameters.
pub fn by_name(name: &str) -> Option<Box<dyn Optimizer>> {
    Some(match name {
        "hs" => Box::new(HarmonySearch::default()),
        "ga" => Box::new(GeneticAlgorithm::default()),
        "pso" => Box::new(ParticleSwarm::default()),
        "gwo" => Box::new(GreyWolf::default()),
        "cs" => Box::new(CuckooSearch::default()),
        "ics" => Box::new(CuckooSearch::improved()),
        "fwa" => Box::new(Fireworks::default()),
        "so" => Box::new(SnakeOptimizer::default()),
        "beeso" => Box::new(Beeso::default()),
        "de" => Box::new(DifferentialEvolution::default()),
        _ => return None,
    })
}

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
pub trait Optimizer: Send + Sync {
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

/// Counts objective evaluations against a budget and remembers the best point.
///
/// Every optimizer evaluates through a tracker: [`Tracker::evaluate`] returns `None` once
/// the budget is spent, so an algorithm stops at exactly its budget even in the middle of
/// a generation, and the outcome's best point is the best ever evaluated (not merely the
/// best of the final population).
pub struct Tracker<'a> {
    problem: &'a dyn Problem,
    bounds: Vec<(f64, f64)>,
    budget: u64,
    evaluations: u64,
    best: Vec<f64>,
    best_value: f64,
    history: Option<Vec<f64>>,
}

impl<'a> Tracker<'a> {
    /// A tracker for `problem` with `budget` evaluations; with `record_history` it keeps
    /// the best value after every evaluation.
    pub fn new(problem: &'a dyn Problem, budget: u64, record_history: bool) -> Self {
        let dim = problem.dim();
        let bounds = (0..dim).map(|i| problem.bounds(i)).collect();
        Tracker {
            problem,
            bounds,
            budget,
            evaluations: 0,
            best: Vec::with_capacity(dim),
            best_value: f64::INFINITY,
            history: record_history.then(|| Vec::with_capacity(budget.min(1 << 20) as usize)),
        }
    }

    /// Number of variables.
    pub fn dim(&self) -> usize {
        self.bounds.len()
    }

    /// The bounds of every variable.
    pub fn bounds(&self) -> &[(f64, f64)] {
        &self.bounds
    }

    /// Whether the budget is spent.
    pub fn exhausted(&self) -> bool {
        self.evaluations >= self.budget
    }

    /// Evaluations left.
    pub fn remaining(&self) -> u64 {
        self.budget.saturating_sub(self.evaluations)
    }

    /// Evaluations used so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations
    }

    /// The best value so far (infinity before the first evaluation).
    pub fn best_value(&self) -> f64 {
        self.best_value
    }

    /// The best point so far (empty before the first evaluation).
    pub fn best(&self) -> &[f64] {
        &self.best
    }

    /// Evaluates `x` (which must lie within the bounds) if budget remains. A NaN objective
    /// counts as +infinity, so it never becomes the best point.
    pub fn evaluate(&mut self, x: &[f64]) -> Option<f64> {
        if self.exhausted() {
            return None;
        }
        debug_assert!(
            x.iter()
                .zip(&self.bounds)
                .all(|(v, &(lo, hi))| *v >= lo && *v <= hi),
            "point outside the bounds: {x:?}"
        );
        let mut v = self.problem.evaluate(x);
        if v.is_nan() {
            v = f64::INFINITY;
        }
        self.evaluations += 1;
        if v < self.best_value || self.best.is_empty() {
            self.best_value = v;
            self.best.clear();
            self.best.extend_from_slice(x);
        }
        if let Some(h) = &mut self.history {
            h.push(self.best_value);
        }
        Some(v)
    }

    /// The outcome: best point, its value, evaluations used and the history.
    pub fn into_outcome(self) -> Outcome {
        Outcome {
            best: self.best,
            value: self.best_value,
            evaluations: self.evaluations,
            history: self.history.unwrap_or_default(),
        }
    }
}

/// A uniform random value in `[lo, hi]` (`lo` when the range is empty).
pub fn uniform(rng: &mut SeededRng, (lo, hi): (f64, f64)) -> f64 {
    if hi > lo {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

/// Fills `x` with a uniform random point of the box.
pub fn random_point(rng: &mut SeededRng, bounds: &[(f64, f64)], x: &mut [f64]) {
    for (v, &b) in x.iter_mut().zip(bounds) {
        *v = uniform(rng, b);
    }
}

/// Clamps every coordinate of `x` into its bounds (NaN goes to the lower bound).
pub fn clamp_to(bounds: &[(f64, f64)], x: &mut [f64]) {
    for (v, &(lo, hi)) in x.iter_mut().zip(bounds) {
        *v = if v.is_nan() { lo } else { v.clamp(lo, hi) };
    }
}

/// A standard normal deviate (Box–Muller; one of the pair is discarded so the stream of
/// draws does not depend on hidden state).
pub fn standard_normal(rng: &mut SeededRng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
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

    /// Wraps a problem and panics if any evaluated point leaves the bounds.
    pub(crate) struct Checked<'a>(pub &'a dyn Problem);
    impl Problem for Checked<'_> {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn bounds(&self, i: usize) -> (f64, f64) {
            self.0.bounds(i)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            assert_eq!(x.len(), self.dim());
            for (i, v) in x.iter().enumerate() {
                let (lo, hi) = self.bounds(i);
                assert!(
                    *v >= lo && *v <= hi,
                    "coordinate {i} = {v} outside [{lo}, {hi}]"
                );
            }
            self.0.evaluate(x)
        }
    }

    /// Shifted bounds with the optimum in a corner: minimise −Σx over [i, i+1]. The best is
    /// −Σ(i+1); an optimizer that clamps badly or escapes the box fails here.
    pub(crate) struct Corner(pub usize);
    impl Problem for Corner {
        fn dim(&self) -> usize {
            self.0
        }
        fn bounds(&self, i: usize) -> (f64, f64) {
            (i as f64, i as f64 + 1.0)
        }
        fn evaluate(&self, x: &[f64]) -> f64 {
            -x.iter().sum::<f64>()
        }
    }

    /// Runs `opt` on `problem` (bounds checked) with a budget and seed, and checks what
    /// every optimizer must do: use exactly the budget, record a monotone history ending
    /// at the reported value, report a best point whose value is the reported value, and
    /// give the same result for the same seed.
    pub(crate) fn run_checked(
        opt: &dyn super::Optimizer,
        problem: &dyn Problem,
        budget: u64,
        seed: u64,
    ) -> super::Outcome {
        use rand::SeedableRng;
        let checked = Checked(problem);
        let mut rng = super::SeededRng::seed_from_u64(seed);
        let o = opt.minimize(&checked, budget, &mut rng, true);
        assert_eq!(
            o.evaluations,
            budget,
            "{} used {} of {budget}",
            opt.name(),
            o.evaluations
        );
        assert_eq!(o.history.len() as u64, budget);
        assert!(
            o.history.windows(2).all(|w| w[1] <= w[0]),
            "history not monotone"
        );
        assert_eq!(*o.history.last().unwrap(), o.value);
        assert_eq!(
            problem.evaluate(&o.best),
            o.value,
            "best point does not give the value"
        );
        let mut rng = super::SeededRng::seed_from_u64(seed);
        let again = opt.minimize(&checked, budget, &mut rng, false);
        assert_eq!(again.best, o.best, "{} is not deterministic", opt.name());
        assert!(again.history.is_empty());
        o
    }
}
