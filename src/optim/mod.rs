//! Bounded continuous minimisation by metaheuristics.
//!
//! One trait, [`Optimizer`], every algorithm behind it: a [`Problem`] has box bounds and an
//! objective; an optimizer spends at most a budget of objective evaluations and returns an
//! [`Outcome`] with the best point, its value, the evaluations used and the best-so-far
//! history. Every random choice comes from the seeded generator passed in, so a run is
//! reproducible from its seed.
//!
//! [`Algorithm`] names each of them and builds it with the papers' default parameters;
//! [`by_name`] does the same from its command-line name ([`NAMES`]). Each algorithm lives in its own file; the module docs of each say where
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
mod problem;
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

pub use problem::{
    clamp_to, random_point, standard_normal, uniform, Optimizer, Outcome, Problem, SeededRng,
    Tracker,
};

/// The seed every command and options type starts from unless told otherwise (the same
/// seed gives the same output on any number of threads).
pub const DEFAULT_SEED: u64 = 1;

/// The metaheuristics of the papers, as a closed set: what a caller names instead of a
/// string. [`Algorithm::name`] is the command-line and report name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Algorithm {
    /// Harmony search ([`HarmonySearch`]).
    Hs,
    /// Genetic algorithm ([`GeneticAlgorithm`]).
    Ga,
    /// Particle swarm ([`ParticleSwarm`]).
    Pso,
    /// Grey wolf optimizer ([`GreyWolf`]).
    Gwo,
    /// Cuckoo search ([`CuckooSearch::default`]).
    Cs,
    /// Improved cuckoo search ([`CuckooSearch::improved`]).
    Ics,
    /// Fireworks algorithm ([`Fireworks`]).
    Fwa,
    /// Snake optimizer ([`SnakeOptimizer`]).
    So,
    /// Enhanced snake optimizer ([`Beeso`]).
    Beeso,
    /// Differential evolution ([`DifferentialEvolution`]).
    De,
}

impl Algorithm {
    /// Every algorithm, in the order reports list them.
    pub const ALL: [Algorithm; 10] = [
        Algorithm::Hs,
        Algorithm::Ga,
        Algorithm::Pso,
        Algorithm::Gwo,
        Algorithm::Cs,
        Algorithm::Ics,
        Algorithm::Fwa,
        Algorithm::So,
        Algorithm::Beeso,
        Algorithm::De,
    ];

    /// The command-line name, e.g. `hs`.
    pub const fn name(self) -> &'static str {
        match self {
            Algorithm::Hs => "hs",
            Algorithm::Ga => "ga",
            Algorithm::Pso => "pso",
            Algorithm::Gwo => "gwo",
            Algorithm::Cs => "cs",
            Algorithm::Ics => "ics",
            Algorithm::Fwa => "fwa",
            Algorithm::So => "so",
            Algorithm::Beeso => "beeso",
            Algorithm::De => "de",
        }
    }

    /// The algorithm with command-line name `name`.
    pub fn from_name(name: &str) -> Option<Algorithm> {
        Algorithm::ALL.into_iter().find(|a| a.name() == name)
    }

    /// The optimizer with the papers' default parameters.
    pub fn build(self) -> Box<dyn Optimizer> {
        match self {
            Algorithm::Hs => Box::new(HarmonySearch::default()),
            Algorithm::Ga => Box::new(GeneticAlgorithm::default()),
            Algorithm::Pso => Box::new(ParticleSwarm::default()),
            Algorithm::Gwo => Box::new(GreyWolf::default()),
            Algorithm::Cs => Box::new(CuckooSearch::default()),
            Algorithm::Ics => Box::new(CuckooSearch::improved()),
            Algorithm::Fwa => Box::new(Fireworks::default()),
            Algorithm::So => Box::new(SnakeOptimizer::default()),
            Algorithm::Beeso => Box::new(Beeso::default()),
            Algorithm::De => Box::new(DifferentialEvolution::default()),
        }
    }
}

impl std::fmt::Display for Algorithm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for Algorithm {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Command-line names of every optimizer, in the order reports list them
/// ([`Algorithm::ALL`]'s names).
pub const NAMES: &[&str] = &ALL_NAMES;

const ALL_NAMES: [&str; Algorithm::ALL.len()] = {
    let mut names = [""; Algorithm::ALL.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = Algorithm::ALL[i].name();
        i += 1;
    }
    names
};

/// The optimizer with command-line name `name`, with its default parameters.
pub fn by_name(name: &str) -> Option<Box<dyn Optimizer>> {
    Algorithm::from_name(name).map(Algorithm::build)
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

#[cfg(test)]
mod tests {
    use super::{Algorithm, NAMES};

    #[test]
    fn every_algorithm_builds_the_optimizer_of_its_name() {
        assert_eq!(NAMES.len(), Algorithm::ALL.len());
        for (a, name) in Algorithm::ALL.into_iter().zip(NAMES) {
            assert_eq!(a.name(), *name);
            assert_eq!(a.build().name(), *name, "{a:?}");
            assert_eq!(Algorithm::from_name(name), Some(a));
        }
        assert_eq!(Algorithm::from_name("lsq"), None);
    }
}
