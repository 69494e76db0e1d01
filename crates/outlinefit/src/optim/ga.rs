//! Real-coded genetic algorithm: binary tournament selection, simulated binary crossover
//! (SBX, Deb & Agrawal 1995), polynomial mutation (Deb & Goyal 1996) and elitism, one of
//! the two comparators of the HS paper (§7.1).
//!
//! The HS paper compares against "GA" but states neither its operators nor its parameters
//! (it cites Gálvez et al. for GA curve fitting and fixes the run time, not the number of
//! evaluations). So the defaults here are the standard textbook real-coded GA, with the
//! operator settings of Deb et al.'s NSGA-II paper (2002): crossover probability 0.9, SBX
//! distribution index η_c = 20, mutation probability 1/n per variable, polynomial
//! mutation index η_m = 20. Population 50 and two elites (the best two of each generation
//! survive unchanged, which keeps the pairs of children even) are common choices, not the
//! paper's.
//!
//! One generation: the elites are copied over; the rest of the new population is filled
//! pair by pair — two parents picked by binary tournament (the better of two random
//! members), crossed with probability `crossover_rate` (each variable with probability ½
//! undergoes SBX, and the two children swap it with probability ½, as in Deb's code),
//! then each child variable mutated with probability `mutation_rate` (default 1/n).
//! Every child is evaluated; the budget counts evaluations, the initial population
//! included, and may end in the middle of a generation.
//!
//! Bounds: polynomial mutation is the bounded form (its step never leaves the box); SBX
//! children that leave the box are clamped to it. Clamping puts some children exactly on
//! the boundary, which is where a boundary optimum is found.
//!
//! Written by hand: no maintained crate implements it over a caller-seeded generator with
//! an exact evaluation budget. All buffers are allocated before the main loop.

use super::problem::{clamp_to, random_point, Optimizer, SeededRng, Tracker};
use rand::RngExt;

/// Real-coded genetic algorithm parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct GeneticAlgorithm {
    /// Population size (at least 2 is used). Default: 50.
    pub population: usize,
    /// Probability that a pair of parents is crossed (otherwise the children are copies).
    /// Default: 0.9.
    pub crossover_rate: f64,
    /// SBX distribution index η_c: larger keeps children closer to their parents.
    /// Default: 20.
    pub eta_crossover: f64,
    /// Probability of mutating each variable of a child; `None` means 1/n for n
    /// variables. Default: `None`.
    pub mutation_rate: Option<f64>,
    /// Polynomial mutation distribution index η_m: larger gives smaller steps.
    /// Default: 20.
    pub eta_mutation: f64,
    /// Best members copied unchanged into each new generation (at most population − 1).
    /// Default: 2.
    pub elites: usize,
}

impl Default for GeneticAlgorithm {
    fn default() -> Self {
        GeneticAlgorithm {
            population: 50,
            crossover_rate: 0.9,
            eta_crossover: 20.0,
            mutation_rate: None,
            eta_mutation: 20.0,
            elites: 2,
        }
    }
}

/// Index of the better of two random members of a population of `n`.
fn tournament(rng: &mut SeededRng, values: &[f64]) -> usize {
    let n = values.len();
    let a = rng.random_range(0..n);
    let b = rng.random_range(0..n);
    if values[b] < values[a] {
        b
    } else {
        a
    }
}

/// Simulated binary crossover of `c1` and `c2` in place (they start as copies of the
/// parents): each variable with probability ½ gets the SBX spread, then the two children
/// swap it with probability ½.
fn sbx(rng: &mut SeededRng, eta: f64, c1: &mut [f64], c2: &mut [f64]) {
    let exponent = 1.0 / (eta + 1.0);
    for (a, b) in c1.iter_mut().zip(c2.iter_mut()) {
        if rng.random::<f64>() < 0.5 {
            let (p1, p2) = (*a, *b);
            if (p1 - p2).abs() > 1e-14 {
                let u: f64 = rng.random();
                let beta = if u <= 0.5 {
                    (2.0 * u).powf(exponent)
                } else {
                    (1.0 / (2.0 * (1.0 - u))).powf(exponent)
                };
                *a = 0.5 * ((1.0 + beta) * p1 + (1.0 - beta) * p2);
                *b = 0.5 * ((1.0 - beta) * p1 + (1.0 + beta) * p2);
            }
        }
        if rng.random::<f64>() < 0.5 {
            std::mem::swap(a, b);
        }
    }
}

/// Bounded polynomial mutation (Deb's NSGA-II form): each variable with probability
/// `rate` moves by a step whose distribution shrinks towards the nearer bound, so the
/// result stays in the box.
fn polynomial_mutation(
    rng: &mut SeededRng,
    eta: f64,
    rate: f64,
    bounds: &[(f64, f64)],
    x: &mut [f64],
) {
    let exponent = 1.0 / (eta + 1.0);
    for (y, &(lo, hi)) in x.iter_mut().zip(bounds) {
        if rng.random::<f64>() >= rate || hi <= lo {
            continue;
        }
        let range = hi - lo;
        let r: f64 = rng.random();
        let dq = if r < 0.5 {
            let xy = 1.0 - (*y - lo) / range;
            let val = 2.0 * r + (1.0 - 2.0 * r) * xy.powf(eta + 1.0);
            val.powf(exponent) - 1.0
        } else {
            let xy = 1.0 - (hi - *y) / range;
            let val = 2.0 * (1.0 - r) + 2.0 * (r - 0.5) * xy.powf(eta + 1.0);
            1.0 - val.powf(exponent)
        };
        *y = (*y + dq * range).clamp(lo, hi);
    }
}

impl Optimizer for GeneticAlgorithm {
    fn name(&self) -> &'static str {
        "ga"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let n = self.population.max(2);
        let elites = self.elites.min(n - 1);
        let mutation_rate = self.mutation_rate.unwrap_or(1.0 / dim.max(1) as f64);

        // Current and next generation, `n` rows of `dim` values each, with their values.
        let mut pop = vec![0.0; n * dim];
        let mut values = vec![f64::INFINITY; n];
        let mut next = vec![0.0; n * dim];
        let mut next_values = vec![f64::INFINITY; n];
        let mut spare = vec![0.0; dim];
        let mut order: Vec<usize> = (0..n).collect();

        for i in 0..n {
            let row = &mut pop[i * dim..(i + 1) * dim];
            random_point(rng, &bounds, row);
            match tracker.evaluate(row) {
                Some(v) => values[i] = v,
                None => return,
            }
        }

        'generations: while !tracker.exhausted() {
            // Elites: the best `elites` members, copied with their values.
            order.sort_unstable_by(|&a, &b| values[a].total_cmp(&values[b]));
            for (slot, &i) in order[..elites].iter().enumerate() {
                next[slot * dim..(slot + 1) * dim].copy_from_slice(&pop[i * dim..(i + 1) * dim]);
                next_values[slot] = values[i];
            }
            let mut slot = elites;
            while slot < n {
                let p1 = tournament(rng, &values);
                let p2 = tournament(rng, &values);
                // Children go straight into the next generation's rows; when the slots
                // run out, the second child of the last pair goes to `spare`, unevaluated.
                let pair = slot + 1 < n;
                let (c1, c2): (&mut [f64], &mut [f64]) = if pair {
                    let (head, tail) = next.split_at_mut((slot + 1) * dim);
                    (&mut head[slot * dim..], &mut tail[..dim])
                } else {
                    (&mut next[slot * dim..(slot + 1) * dim], &mut spare[..])
                };
                c1.copy_from_slice(&pop[p1 * dim..(p1 + 1) * dim]);
                c2.copy_from_slice(&pop[p2 * dim..(p2 + 1) * dim]);
                if rng.random::<f64>() < self.crossover_rate {
                    sbx(rng, self.eta_crossover, c1, c2);
                    clamp_to(&bounds, c1);
                    clamp_to(&bounds, c2);
                }
                polynomial_mutation(rng, self.eta_mutation, mutation_rate, &bounds, c1);
                match tracker.evaluate(c1) {
                    Some(v) => next_values[slot] = v,
                    None => break 'generations,
                }
                if pair {
                    polynomial_mutation(rng, self.eta_mutation, mutation_rate, &bounds, c2);
                    match tracker.evaluate(c2) {
                        Some(v) => next_values[slot + 1] = v,
                        None => break 'generations,
                    }
                }
                slot += 2;
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
        let ga = GeneticAlgorithm::default();
        let o = run_checked(&ga, &Sphere(4), 7, 5);
        assert!(o.value.is_finite());
        // One more than the population: a single child of the first generation.
        run_checked(&ga, &Sphere(4), ga.population as u64 + 1, 5);
    }
}
