//! Differential evolution, the classic DE/rand/1/bin of Storn & Price (1997): a strong,
//! well-known reference that none of the papers compares against.
//!
//! For each member x_i of the population a mutant v = x_r1 + F·(x_r2 − x_r3) is built
//! from three other distinct random members; the trial vector takes each coordinate from
//! v with probability CR (binomial crossover), and from v at one random coordinate
//! always, the rest from x_i. The trial replaces x_i in the next generation if it is no
//! worse (generational, "synchronous" replacement as in Storn & Price). The budget counts
//! evaluations, the initial population included, and may end in the middle of a
//! generation.
//!
//! Defaults: F = 0.5 and CR = 0.9, Storn & Price's usual first choice. Population NP =
//! 10·n for n variables, Storn & Price's rule of thumb, clamped to [40, 50]. The lower
//! clamp is measured, not inherited: with F = 0.5, NP = 20 stalls for good (the whole
//! population collapses onto one value of a coordinate) in 23 of 100 runs on the 2-D
//! Rosenbrock function and in some runs on the 10-D sphere, NP = 40 in 1 of 100 — Storn &
//! Price's own remedy for premature convergence is a larger F or NP. The upper clamp keeps
//! ~100 generations within the few-thousand-evaluation budgets of curve fitting. A
//! population below 4 is raised to 4, the least rand/1 needs.
//!
//! Bounds: a trial coordinate below its lower bound is set halfway between the bound and
//! the target's coordinate, (lo + x_i,j)/2, likewise above (the rule of JADE, Zhang &
//! Sanderson 2009). Unlike clamping it does not pile trials up on the boundary, yet a
//! boundary optimum is approached geometrically.
//!
//! Written by hand: no maintained crate implements it over a caller-seeded generator with
//! an exact evaluation budget. All buffers are allocated before the main loop.

use super::problem::{random_point, Optimizer, SeededRng, Tracker};
use rand::RngExt;

/// Differential evolution (DE/rand/1/bin) parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct DifferentialEvolution {
    /// Population size NP (at least 4 is used); `None` means 10 × the number of variables,
    /// clamped to [40, 50]. Default: `None`.
    pub population: Option<usize>,
    /// Differential weight F scaling the difference vector. Default: 0.5.
    pub f: f64,
    /// Crossover rate CR: probability of taking each coordinate from the mutant.
    /// Default: 0.9.
    pub cr: f64,
}

impl Default for DifferentialEvolution {
    fn default() -> Self {
        DifferentialEvolution {
            population: None,
            f: 0.5,
            cr: 0.9,
        }
    }
}

impl DifferentialEvolution {
    /// The population size used for a problem of `dim` variables.
    pub fn population_for(&self, dim: usize) -> usize {
        self.population
            .unwrap_or_else(|| (10 * dim).clamp(40, 50))
            .max(4)
    }
}

impl Optimizer for DifferentialEvolution {
    fn name(&self) -> &'static str {
        "de"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let n = self.population_for(dim);

        // Current and next generation, `n` rows of `dim` values each, with their values.
        let mut pop = vec![0.0; n * dim];
        let mut values = vec![f64::INFINITY; n];
        let mut next = vec![0.0; n * dim];
        let mut next_values = vec![f64::INFINITY; n];
        let mut trial = vec![0.0; dim];

        for i in 0..n {
            let row = &mut pop[i * dim..(i + 1) * dim];
            random_point(rng, &bounds, row);
            match tracker.evaluate(row) {
                Some(v) => values[i] = v,
                None => return,
            }
        }

        'generations: while !tracker.exhausted() {
            next.copy_from_slice(&pop);
            next_values.copy_from_slice(&values);
            for i in 0..n {
                // Three distinct members, all different from i.
                let r1 = loop {
                    let r = rng.random_range(0..n);
                    if r != i {
                        break r;
                    }
                };
                let r2 = loop {
                    let r = rng.random_range(0..n);
                    if r != i && r != r1 {
                        break r;
                    }
                };
                let r3 = loop {
                    let r = rng.random_range(0..n);
                    if r != i && r != r1 && r != r2 {
                        break r;
                    }
                };
                let jrand = if dim > 0 { rng.random_range(0..dim) } else { 0 };
                for j in 0..dim {
                    let target = pop[i * dim + j];
                    trial[j] = if j == jrand || rng.random::<f64>() < self.cr {
                        let (lo, hi) = bounds[j];
                        let v =
                            pop[r1 * dim + j] + self.f * (pop[r2 * dim + j] - pop[r3 * dim + j]);
                        if v < lo {
                            0.5 * (lo + target)
                        } else if v > hi {
                            0.5 * (hi + target)
                        } else if v.is_nan() {
                            target
                        } else {
                            v
                        }
                    } else {
                        target
                    };
                }
                let Some(v) = tracker.evaluate(&trial) else {
                    break 'generations;
                };
                if v <= values[i] {
                    next[i * dim..(i + 1) * dim].copy_from_slice(&trial);
                    next_values[i] = v;
                }
            }
            std::mem::swap(&mut pop, &mut next);
            std::mem::swap(&mut values, &mut next_values);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::testfns::{run_checked, Sphere};

    #[test]
    fn budget_smaller_than_the_population() {
        let de = DifferentialEvolution::default();
        assert_eq!(de.population_for(4), 40);
        let o = run_checked(&de, &Sphere(4), 7, 5);
        assert!(o.value.is_finite());
        run_checked(&de, &Sphere(4), 41, 5);
        // Below the four members rand/1 needs, the population is raised to four.
        let tiny = DifferentialEvolution {
            population: Some(2),
            ..de
        };
        assert_eq!(tiny.population_for(4), 4);
        run_checked(&tiny, &Sphere(4), 200, 5);
    }
}
