//! What every optimizer shares: the [`Problem`] it minimises, the [`Optimizer`] trait and
//! its [`Outcome`], the seeded generator, the [`Tracker`] that holds each run to its
//! budget, and the sampling helpers. The registry in the parent module names the
//! algorithms; they import only this.

use rand::RngExt;

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
pub trait Optimizer: Send + Sync {
    /// The command-line name, e.g. `hs`.
    fn name(&self) -> &'static str;
    /// Searches: evaluates points through `tracker` (which counts them against the budget
    /// and remembers the best) until it refuses one or the method ends. `tracker` is fresh
    /// from [`Tracker::new`], so [`Tracker::remaining`] is the whole budget.
    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng);

    /// Minimises `problem` with at most `budget` objective evaluations. With
    /// `record_history` the outcome lists the best value after every evaluation.
    fn minimize(
        &self,
        problem: &dyn Problem,
        budget: u64,
        rng: &mut SeededRng,
        record_history: bool,
    ) -> Outcome {
        let mut tracker = Tracker::new(problem, budget, record_history);
        self.search(&mut tracker, rng);
        tracker.into_outcome()
    }
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
pub(super) fn random_point(rng: &mut SeededRng, bounds: &[(f64, f64)], x: &mut [f64]) {
    for (v, &b) in x.iter_mut().zip(bounds) {
        *v = uniform(rng, b);
    }
}

/// Clamps every coordinate of `x` into its bounds (NaN goes to the lower bound).
pub(super) fn clamp_to(bounds: &[(f64, f64)], x: &mut [f64]) {
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
