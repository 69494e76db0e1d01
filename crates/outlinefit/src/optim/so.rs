//! Snake optimizer (SO; Hashim & Hussien, *Knowledge-Based Systems* 242, 2022), the base
//! algorithm of BEESO, as described in §3.1 of the disk Wang–Ball merging paper
//! (`shared/papers/disk-wang-ball-merging-beeso.txt`, Eqs. 13–31) and in the SO paper.
//!
//! The population is split into males (the first ⌈N/2⌉ rows) and females (the rest,
//! Eq. 14). Two schedules steer every iteration: the temperature Temp = exp(−t/T) (Eq. 15)
//! and the food quantity Q = c1·exp((t − T)/T) (Eq. 16). Each iteration builds one
//! candidate per snake, evaluates it and keeps it if it beats the snake's current position
//! (greedy selection, as in the SO reference code):
//!
//! - **exploration** (Q < 0.25, no food): around a random snake r of the same sex,
//!   x = x_r ± c2·A·((ub − lb)·rand + lb) with the foraging ability A = exp(−f_r / f_i)
//!   (Eqs. 17–18);
//! - **exploitation, hot** (Temp > 0.6): towards the food (the best snake),
//!   x = x_food ± c3·Temp·rand·(x_food − x_i) (Eq. 23);
//! - **exploitation, cold**, with probability 0.4 (a uniform draw above 0.6) **fight**:
//!   x_i + c3·FM·rand·(Q·x_best of the other sex − x_i), FM = exp(−f_best,other / f_i)
//!   (Eqs. 24–27); otherwise **mating**: x_i + c3·MM·rand·(Q·x_partner − x_i),
//!   MM = exp(−f_partner / f_i) (Eqs. 28–31); after mating the eggs hatch with probability
//!   ½, replacing the worst male's and the worst female's candidates by random points.
//!
//! Defaults: c1 = 0.5, c2 = 0.05, c3 = 2 and the thresholds 0.25 (Q), 0.6 (Temp) and 0.6
//! (fight or mate) are those of the SO paper and its reference code, which the BEESO paper
//! keeps (it calls them s1, s2, s3; Eq. 16 and Step four/five of §3.2). The egg-hatching
//! probability ½ is the reference code's ±1 coin. The population of 50 is the setting of
//! every experiment of the BEESO paper (§3.3), so SO and BEESO compare like for like.
//!
//! **Iterations and budget.** The paper's t/T (current over maximum iteration) is here the
//! fraction of the evaluation budget spent, `evaluations / budget`, read at the start of each
//! iteration, so the schedules complete at the budget whatever the population. One SO
//! iteration evaluates the whole population once; the paper's 50 snakes × 500 iterations
//! correspond to a budget of about 25,050 evaluations.
//!
//! **Restored from the garbled text.** The extraction lost signs and symbols; the standard
//! SO definition was used instead where they disagree: Temp = exp(−t/T) and
//! Q = c1·exp((t − T)/T) with the minus signs restored; the exploration step uses the
//! foraging abilities AM = exp(−f_rand,m / f_i,m), AF likewise (the text defines neither);
//! the fight step carries the food quantity Q in front of the opposite sex's best and a
//! plus sign (the text prints "± s3·FM·r·(y_best,f − y_i,m)"), as the SO paper and its
//! reference code do; mating likewise uses "+". A ± means a random sign: drawn per
//! coordinate in exploration and per snake in the hot phase (as in the reference code). The
//! random snake of the exploration step is one per snake (the equations' x_rand), and
//! `rand` is drawn afresh per coordinate. The reference code's egg replacement draws one
//! scalar for all coordinates (a point on the box's diagonal); here every coordinate is
//! drawn independently.
//!
//! **Details the papers leave open.** A male i mates with female i (and female i with male
//! i), wrapping around the smaller group when N is odd (the reference code would index past
//! the females). The abilities A, FM, FF, MM, MF are clamped to [0, 1] (a NaN counts as 0):
//! for nonnegative objectives, such as every fitting error of this crate, they already lie
//! there; for objectives of mixed sign the paper's ratio can overflow. The population is at
//! least 2 (one of each sex). Note that fight and mating pull towards Q·x (Q ≤ ½), i.e.
//! towards the origin, a bias of SO itself that favours test functions with their optimum
//! at 0; the greedy selection keeps it from doing harm elsewhere.
//!
//! **Bounds.** Every candidate is clamped into the box before it is evaluated (as the
//! reference code does), so every evaluated coordinate lies within its bounds.
//!
//! Written by hand: no maintained crate implements SO over a caller-seeded generator with
//! an exact evaluation budget. BEESO (`beeso.rs`) reuses the phases defined here.

use super::problem::{clamp_to, random_point, Optimizer, SeededRng, Tracker};
use rand::RngExt;
use std::ops::Range;

/// Snake optimizer parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct SnakeOptimizer {
    /// Number of snakes, half male and half female (at least 2 are used). Default: 50.
    pub population: usize,
    /// c1, scale of the food quantity Q = c1·exp(t/T − 1). Default: 0.5.
    pub c1: f64,
    /// c2, step scale of exploration. Default: 0.05.
    pub c2: f64,
    /// c3, step scale of exploitation (hot phase, fight and mating). Default: 2.
    pub c3: f64,
    /// Exploration while Q is below this. Default: 0.25.
    pub food_threshold: f64,
    /// Move towards the food while Temp = exp(−t/T) is above this. Default: 0.6.
    pub temp_threshold: f64,
    /// In the cold phase, fight when a uniform draw exceeds this, mate otherwise. Default: 0.6.
    pub fight_threshold: f64,
    /// Probability that the eggs hatch after mating. Default: 0.5.
    pub egg_probability: f64,
}

impl Default for SnakeOptimizer {
    fn default() -> Self {
        SnakeOptimizer {
            population: 50,
            c1: 0.5,
            c2: 0.05,
            c3: 2.0,
            food_threshold: 0.25,
            temp_threshold: 0.6,
            fight_threshold: 0.6,
            egg_probability: 0.5,
        }
    }
}

/// What one iteration does, from the schedules at the current progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Phase {
    /// No food: random search around snakes of the same sex.
    Explore,
    /// Food and heat: move around the food.
    Hot { temp: f64 },
    /// Cold: fight for the best of the other sex.
    Fight { q: f64 },
    /// Cold: mate with a partner; `hatch` says whether eggs hatch afterwards.
    Mate { q: f64, hatch: bool },
}

impl SnakeOptimizer {
    /// The phase of an iteration at `progress` = t/T ∈ [0, 1] (Eqs. 15–16 and the
    /// thresholds); draws the fight-or-mate and egg coins in the cold phase.
    pub(super) fn phase(&self, progress: f64, rng: &mut SeededRng) -> Phase {
        let temp = (-progress).exp();
        let q = (self.c1 * (progress - 1.0).exp()).min(1.0);
        if q < self.food_threshold {
            Phase::Explore
        } else if temp > self.temp_threshold {
            Phase::Hot { temp }
        } else if rng.random::<f64>() > self.fight_threshold {
            Phase::Fight { q }
        } else {
            let hatch = rng.random::<f64>() < self.egg_probability;
            Phase::Mate { q, hatch }
        }
    }

    fn run(&self, tracker: &mut Tracker, budget: u64, rng: &mut SeededRng) -> Option<()> {
        let mut s = Swarm::new(self.population, tracker, rng)?;
        loop {
            let progress = tracker.evaluations() as f64 / budget as f64;
            match self.phase(progress, rng) {
                Phase::Explore => s.explore(self.c2, rng),
                Phase::Hot { temp } => s.hot(self.c3, temp, rng),
                Phase::Fight { q } => s.fight(self.c3, q, rng),
                Phase::Mate { q, hatch } => {
                    s.mate(self.c3, q, rng);
                    if hatch {
                        s.hatch_eggs(rng);
                    }
                }
            }
            s.evaluate_candidates(tracker)?;
            s.select();
        }
    }
}

impl Optimizer for SnakeOptimizer {
    fn name(&self) -> &'static str {
        "so"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let budget = tracker.remaining();
        // `None` only says the budget is spent; the tracker holds the result.
        let _ = self.run(tracker, budget, rng);
    }
}

/// A snake's ability exp(−a / (b + ε)) (Eqs. 26–27, 30–31 and SO's A), clamped to [0, 1].
pub(super) fn ability(a: f64, b: f64) -> f64 {
    let v = (-a / (b + f64::EPSILON)).exp();
    if v.is_nan() {
        0.0
    } else {
        v.min(1.0)
    }
}

/// A random sign, +1 or −1 with equal probability.
pub(super) fn random_sign(rng: &mut SeededRng) -> f64 {
    if rng.random::<bool>() {
        1.0
    } else {
        -1.0
    }
}

/// The snakes: positions and values, one candidate per snake, males first.
pub(super) struct Swarm {
    /// Number of variables.
    pub(super) dim: usize,
    /// Number of snakes.
    pub(super) n: usize,
    /// Number of males: rows `0..males` are male, `males..n` female.
    pub(super) males: usize,
    /// The box.
    pub(super) bounds: Vec<(f64, f64)>,
    /// Current positions, `n` rows of `dim`.
    pub(super) pos: Vec<f64>,
    /// Objective at each position.
    pub(super) fit: Vec<f64>,
    /// This iteration's candidates, `n` rows of `dim`.
    pub(super) cand: Vec<f64>,
    /// Objective at each candidate (after `evaluate_candidates`).
    pub(super) cand_fit: Vec<f64>,
}

impl Swarm {
    /// Draws and evaluates the initial population (Eq. 13); `None` if the budget ran out.
    pub(super) fn new(
        population: usize,
        tracker: &mut Tracker,
        rng: &mut SeededRng,
    ) -> Option<Self> {
        let dim = tracker.dim();
        let n = population.max(2);
        let bounds = tracker.bounds().to_vec();
        let mut pos = vec![0.0; n * dim];
        let mut fit = vec![f64::INFINITY; n];
        for (x, f) in pos.chunks_exact_mut(dim.max(1)).zip(&mut fit) {
            random_point(rng, &bounds, x);
            *f = tracker.evaluate(x)?;
        }
        if dim == 0 {
            // No variables: the single point was evaluated above as often as the budget allows.
            for f in &mut fit {
                *f = tracker.evaluate(&[])?;
            }
        }
        Some(Swarm {
            dim,
            n,
            males: n.div_ceil(2),
            bounds,
            cand: pos.clone(),
            cand_fit: fit.clone(),
            pos,
            fit,
        })
    }

    /// Row `i` of a population matrix.
    pub(super) fn row(&self, m: &[f64], i: usize) -> Range<usize> {
        debug_assert_eq!(m.len(), self.n * self.dim);
        i * self.dim..(i + 1) * self.dim
    }

    /// The snakes of the same sex as snake `i`.
    pub(super) fn group(&self, i: usize) -> Range<usize> {
        if i < self.males {
            0..self.males
        } else {
            self.males..self.n
        }
    }

    /// The snakes of the other sex.
    pub(super) fn other_group(&self, i: usize) -> Range<usize> {
        if i < self.males {
            self.males..self.n
        } else {
            0..self.males
        }
    }

    /// The best current snake of `range`.
    pub(super) fn best_in(&self, range: Range<usize>) -> usize {
        range
            .min_by(|&a, &b| self.fit[a].total_cmp(&self.fit[b]))
            .unwrap_or(0)
    }

    /// The worst current snake of `range`.
    pub(super) fn worst_in(&self, range: Range<usize>) -> usize {
        range
            .max_by(|&a, &b| self.fit[a].total_cmp(&self.fit[b]))
            .unwrap_or(0)
    }

    /// The food: the best current snake.
    pub(super) fn food(&self) -> usize {
        self.best_in(0..self.n)
    }

    /// Exploration (Eqs. 17–18): around a random snake of the same sex.
    pub(super) fn explore(&mut self, c2: f64, rng: &mut SeededRng) {
        let dim = self.dim;
        for i in 0..self.n {
            let r = rng.random_range(self.group(i));
            let a = ability(self.fit[r], self.fit[i]);
            for j in 0..dim {
                let (lo, hi) = self.bounds[j];
                let step = c2 * a * ((hi - lo) * rng.random::<f64>() + lo);
                self.cand[i * dim + j] = self.pos[r * dim + j] + random_sign(rng) * step;
            }
        }
    }

    /// Hot exploitation (Eq. 23): around the food.
    pub(super) fn hot(&mut self, c3: f64, temp: f64, rng: &mut SeededRng) {
        let dim = self.dim;
        let food = self.food();
        for i in 0..self.n {
            let flag = random_sign(rng);
            for j in 0..dim {
                let f = self.pos[food * dim + j];
                let x = self.pos[i * dim + j];
                self.cand[i * dim + j] = f + flag * c3 * temp * rng.random::<f64>() * (f - x);
            }
        }
    }

    /// Fight mode (Eqs. 24–27): towards Q times the best snake of the other sex.
    pub(super) fn fight(&mut self, c3: f64, q: f64, rng: &mut SeededRng) {
        let dim = self.dim;
        let best_m = self.best_in(0..self.males);
        let best_f = self.best_in(self.males..self.n);
        for i in 0..self.n {
            let rival = if i < self.males { best_f } else { best_m };
            let a = ability(self.fit[rival], self.fit[i]);
            for j in 0..dim {
                let x = self.pos[i * dim + j];
                let y = self.pos[rival * dim + j];
                self.cand[i * dim + j] = x + c3 * a * rng.random::<f64>() * (q * y - x);
            }
        }
    }

    /// The mating partner of snake `i`: the snake of the other sex with the same rank in
    /// its group, wrapping around the smaller group.
    pub(super) fn partner(&self, i: usize) -> usize {
        let other = self.other_group(i);
        let k = i - self.group(i).start;
        other.start + k % other.len()
    }

    /// Mating mode (Eqs. 28–31): towards Q times the partner.
    pub(super) fn mate(&mut self, c3: f64, q: f64, rng: &mut SeededRng) {
        let dim = self.dim;
        for i in 0..self.n {
            let p = self.partner(i);
            let a = ability(self.fit[p], self.fit[i]);
            for j in 0..dim {
                let x = self.pos[i * dim + j];
                let y = self.pos[p * dim + j];
                self.cand[i * dim + j] = x + c3 * rng.random::<f64>() * a * (q * y - x);
            }
        }
    }

    /// SO's egg hatching: the worst male's and the worst female's candidates become random
    /// points of the box.
    fn hatch_eggs(&mut self, rng: &mut SeededRng) {
        for worst in [
            self.worst_in(0..self.males),
            self.worst_in(self.males..self.n),
        ] {
            let r = self.row(&self.cand, worst);
            random_point(rng, &self.bounds, &mut self.cand[r]);
        }
    }

    /// Clamps every candidate into the box and evaluates it; `None` when the budget is spent.
    pub(super) fn evaluate_candidates(&mut self, tracker: &mut Tracker) -> Option<()> {
        for i in 0..self.n {
            let r = self.row(&self.cand, i);
            clamp_to(&self.bounds, &mut self.cand[r.clone()]);
            self.cand_fit[i] = tracker.evaluate(&self.cand[r])?;
        }
        Some(())
    }

    /// Greedy selection: each snake moves to its candidate if the candidate is better.
    pub(super) fn select(&mut self) {
        for i in 0..self.n {
            if self.cand_fit[i] < self.fit[i] {
                self.fit[i] = self.cand_fit[i];
                let r = self.row(&self.pos, i);
                self.pos[r.clone()].copy_from_slice(&self.cand[r]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::testfns::{run_checked, Sphere};
    use rand::SeedableRng;

    #[test]
    fn budget_smaller_than_the_population() {
        let so = SnakeOptimizer::default();
        let a = run_checked(&so, &Sphere(3), 7, 2);
        assert!(a.value.is_finite());
        let b = run_checked(&so, &Sphere(3), 1, 2);
        assert!(b.value.is_finite());
    }

    #[test]
    fn odd_and_tiny_populations() {
        for population in [1, 2, 3, 7] {
            let so = SnakeOptimizer {
                population,
                ..SnakeOptimizer::default()
            };
            let a = run_checked(&so, &Sphere(2), 2000, 4);
            assert!(a.value < 1e-2, "population {population}: {}", a.value);
        }
    }

    #[test]
    fn schedule_switches_at_the_paper_thresholds() {
        let so = SnakeOptimizer::default();
        let mut rng = SeededRng::seed_from_u64(0);
        // Q < 0.25 until t/T = 1 − ln 2 ≈ 0.307; Temp > 0.6 until t/T = −ln 0.6 ≈ 0.511.
        assert_eq!(so.phase(0.0, &mut rng), Phase::Explore);
        assert_eq!(so.phase(0.30, &mut rng), Phase::Explore);
        assert!(matches!(so.phase(0.31, &mut rng), Phase::Hot { .. }));
        assert!(matches!(so.phase(0.51, &mut rng), Phase::Hot { .. }));
        let (mut fights, mut matings) = (0, 0);
        for _ in 0..1000 {
            match so.phase(0.52, &mut rng) {
                Phase::Fight { q } => {
                    assert!((q - 0.5 * (0.52f64 - 1.0).exp()).abs() < 1e-15);
                    fights += 1;
                }
                Phase::Mate { .. } => matings += 1,
                p => panic!("{p:?}"),
            }
        }
        // Fight with probability 0.4.
        assert!(
            (350..450).contains(&fights),
            "{fights} fights, {matings} matings"
        );
    }

    #[test]
    fn partners_wrap_around_the_smaller_group() {
        let so = SnakeOptimizer {
            population: 5,
            ..SnakeOptimizer::default()
        };
        let mut tracker = Tracker::new(&Sphere(2), 100, false);
        let mut rng = SeededRng::seed_from_u64(0);
        let s = Swarm::new(so.population, &mut tracker, &mut rng).unwrap();
        assert_eq!(s.males, 3);
        let partners: Vec<usize> = (0..5).map(|i| s.partner(i)).collect();
        assert_eq!(partners, [3, 4, 3, 0, 1]);
    }
}
