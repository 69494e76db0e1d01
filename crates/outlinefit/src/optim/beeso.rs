//! BEESO, the snake optimizer boosted by bi-directional search, modified evolutionary
//! population dynamics and elite opposition-based learning (Hu et al. 2023), as described
//! in §3.1 of the disk Wang–Ball merging paper
//! (`shared/papers/disk-wang-ball-merging-beeso.txt`, Eqs. 13–39, steps in §3.2).
//!
//! BEESO keeps SO's phases, schedules and greedy selection (see [`super::SnakeOptimizer`],
//! whose code it reuses) and adds three strategies:
//!
//! - **bi-directional search** (Eqs. 21–22), in the exploration phase: besides SO's random
//!   search each snake also tries x_i + r1·(x_best − x_i) − r2·(x_worst − x_i) with the best
//!   and worst snakes of its sex; both are evaluated and the better one goes on (Eqs. 19–20);
//! - **modified evolutionary population dynamics** (MEPD, Eqs. 32–36), replacing SO's egg
//!   step when the eggs hatch after mating: the candidates are ranked; each of the worse
//!   half tries an offspring around the best snake or around itself,
//!   base ± ((ub − lb)·r + lb), kept if better and otherwise replaced by a random point of the
//!   box (Eq. 33); each of the better half tries a differential mutant
//!   x_p1 + F·(x_p2 − x_p3) (p1, p2, p3, i distinct), kept if better, with the sinusoidal
//!   scale F = ½(sin(2π·freq·k)·k/K + 1) (Eq. 36);
//! - **elite opposition-based learning** (Eqs. 37–39), every iteration: with EA_j, EB_j
//!   the least and greatest coordinate j of the EN = 0.1·N best candidates, each candidate
//!   tries its elite opposite S·(EA_j + EB_j) − x_j (S uniform in [0, 1], one per snake);
//!   a coordinate outside the bounds is redrawn uniformly in [EA_j, EB_j]; the opposite
//!   replaces the candidate if better.
//!
//! Defaults: SO's c1 = 0.5, c2 = 0.05, c3 = 2 and thresholds 0.25, 0.6, 0.6 (the paper's
//! s1, s2, s3; see the SO module), EN = 0.1·N (Eq. 39's "EN = 0.1 × N"), population 50 and
//! 500 iterations (§3.3: every experiment). The paper does not give freq; the default
//! (`None`) is 1/D, as in a public MATLAB implementation of BEESO.
//!
//! **Iterations and budget.** The schedules' k/K is the fraction of the evaluation budget
//! spent, read at the start of each iteration, so they complete at the budget whatever the
//! population; the k in F's sine is the iteration number. Every strategy's evaluations are
//! counted: an iteration costs 2N (candidates and their opposites), 3N in the exploration
//! phase (random and bi-directional candidates), and in an iteration where the eggs hatch
//! another ⌈N/2⌉ mutants plus ⌊N/2⌋ offspring and one random point per offspring that fails.
//! The paper's 50 × 500 thus needs about 55,000 to 60,000 evaluations.
//!
//! **Restored from the garbled text.** Besides SO's restorations (signs of the schedules,
//! the abilities, Q and "+" in fight and mating): Eqs. 19–20 are printed as copies of
//! Eqs. 17–18, but the text after them ("Fit represents the fitness value") and §3.2 step
//! four say they select the better of the random and the bi-directional candidate, which is
//! what is done. Eq. 32's "UB − LB × r + LB" is (UB − LB)·r + LB, a random point of the box
//! as in SO's exploration. Eq. 36 prints "(k + K)", which would give F in the hundreds; it
//! is k/K, the sinusoidal increasing scale of LSHADE-EpSin that keeps F in [0, 1]. Eq. 37's
//! EA_j (printed only in the prose) is the least elite coordinate, mirroring Eq. 38.
//!
//! **Details the paper leaves open.** The random numbers of Eqs. 21–22 and 32 are drawn per
//! coordinate (both the choice between the best snake and the snake itself as base, and the
//! sign); the elites are the best candidates of the whole population (both sexes); the
//! mutation is skipped when N < 4 (it needs four distinct snakes). The population is at
//! least 2.
//!
//! **Bounds.** Every candidate, offspring and mutant is clamped into the box before it is
//! evaluated; elite opposites follow Eq. 39 instead (always within bounds, since the elites
//! are), so every evaluated coordinate lies within its bounds.
//!
//! Written by hand: no maintained crate implements BEESO over a caller-seeded generator
//! with an exact evaluation budget.

use super::problem::{clamp_to, random_point, uniform, Optimizer, SeededRng, Tracker};
use super::so::{random_sign, Phase, SnakeOptimizer, Swarm};
use rand::RngExt;

/// BEESO parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Beeso {
    /// Number of snakes, half male and half female (at least 2 are used). Default: 50.
    pub population: usize,
    /// c1 (s1), scale of the food quantity Q = c1·exp(k/K − 1). Default: 0.5.
    pub c1: f64,
    /// c2 (s2), step scale of the random search. Default: 0.05.
    pub c2: f64,
    /// c3 (s3), step scale of exploitation (hot phase, fight and mating). Default: 2.
    pub c3: f64,
    /// Exploration while Q is below this. Default: 0.25.
    pub food_threshold: f64,
    /// Move towards the food while Temp = exp(−k/K) is above this. Default: 0.6.
    pub temp_threshold: f64,
    /// In the cold phase, fight when a uniform draw exceeds this, mate otherwise. Default: 0.6.
    pub fight_threshold: f64,
    /// Probability that the eggs hatch after mating, triggering MEPD. Default: 0.5.
    pub egg_probability: f64,
    /// Fraction of the population that are elites for opposition-based learning (at least
    /// one elite). Default: 0.1.
    pub elite_fraction: f64,
    /// Frequency of the sine in the mutation scale F; `None` means 1/D. Default: `None`.
    pub freq: Option<f64>,
}

impl Default for Beeso {
    fn default() -> Self {
        let so = SnakeOptimizer::default();
        Beeso {
            population: 50,
            c1: so.c1,
            c2: so.c2,
            c3: so.c3,
            food_threshold: so.food_threshold,
            temp_threshold: so.temp_threshold,
            fight_threshold: so.fight_threshold,
            egg_probability: so.egg_probability,
            elite_fraction: 0.1,
            freq: None,
        }
    }
}

impl Beeso {
    /// The SO parameters BEESO runs on.
    fn base(&self) -> SnakeOptimizer {
        SnakeOptimizer {
            population: self.population,
            c1: self.c1,
            c2: self.c2,
            c3: self.c3,
            food_threshold: self.food_threshold,
            temp_threshold: self.temp_threshold,
            fight_threshold: self.fight_threshold,
            egg_probability: self.egg_probability,
        }
    }

    fn run(&self, tracker: &mut Tracker, budget: u64, rng: &mut SeededRng) -> Option<()> {
        let so = self.base();
        let mut s = Swarm::new(so.population, tracker, rng)?;
        let (n, dim) = (s.n, s.dim);
        let freq = self.freq.unwrap_or(1.0 / dim.max(1) as f64);
        let elites = ((self.elite_fraction * n as f64).ceil() as usize).clamp(1, n);
        // Buffers for the whole run.
        let mut alt = vec![0.0; n * dim];
        let mut order: Vec<usize> = (0..n).collect();
        let mut trial = vec![0.0; dim];
        let mut ea = vec![0.0; dim];
        let mut eb = vec![0.0; dim];
        let mut k = 0u64;
        loop {
            k += 1;
            let progress = tracker.evaluations() as f64 / budget as f64;
            match so.phase(progress, rng) {
                Phase::Explore => {
                    s.explore(so.c2, rng);
                    bidirectional(&s, &mut alt, rng);
                    s.evaluate_candidates(tracker)?;
                    for i in 0..n {
                        let r = i * dim..(i + 1) * dim;
                        clamp_to(&s.bounds, &mut alt[r.clone()]);
                        let v = tracker.evaluate(&alt[r.clone()])?;
                        if v < s.cand_fit[i] {
                            s.cand_fit[i] = v;
                            s.cand[r.clone()].copy_from_slice(&alt[r]);
                        }
                    }
                }
                Phase::Hot { temp } => {
                    s.hot(so.c3, temp, rng);
                    s.evaluate_candidates(tracker)?;
                }
                Phase::Fight { q } => {
                    s.fight(so.c3, q, rng);
                    s.evaluate_candidates(tracker)?;
                }
                Phase::Mate { q, hatch } => {
                    s.mate(so.c3, q, rng);
                    s.evaluate_candidates(tracker)?;
                    if hatch {
                        let f = mutation_scale(freq, k, progress);
                        mepd(&mut s, f, &mut order, &mut trial, tracker, rng)?;
                    }
                }
            }
            rank_candidates(&s, &mut order);
            elite_bounds(&s, &order[..elites], &mut ea, &mut eb);
            for i in 0..n {
                let r = i * dim..(i + 1) * dim;
                let scale = rng.random::<f64>();
                elite_opposite(
                    &s.cand[r.clone()],
                    scale,
                    &ea,
                    &eb,
                    &s.bounds,
                    rng,
                    &mut trial,
                );
                let v = tracker.evaluate(&trial)?;
                if v < s.cand_fit[i] {
                    s.cand_fit[i] = v;
                    s.cand[r].copy_from_slice(&trial);
                }
            }
            s.select();
        }
    }
}

impl Optimizer for Beeso {
    fn name(&self) -> &'static str {
        "beeso"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let budget = tracker.remaining();
        // `None` only says the budget is spent; the tracker holds the result.
        let _ = self.run(tracker, budget, rng);
    }
}

/// Bi-directional search (Eqs. 21–22) into `alt`: towards the best and away from the worst
/// current snake of the same sex.
fn bidirectional(s: &Swarm, alt: &mut [f64], rng: &mut SeededRng) {
    let dim = s.dim;
    for i in 0..s.n {
        let best = s.best_in(s.group(i));
        let worst = s.worst_in(s.group(i));
        for j in 0..dim {
            let x = s.pos[i * dim + j];
            let b = s.pos[best * dim + j];
            let w = s.pos[worst * dim + j];
            alt[i * dim + j] = x + rng.random::<f64>() * (b - x) - rng.random::<f64>() * (w - x);
        }
    }
}

/// The sinusoidal mutation scale F = ½(sin(2π·freq·k)·k/K + 1) of Eq. 36, with `k` the
/// iteration number and `progress` = k/K.
fn mutation_scale(freq: f64, k: u64, progress: f64) -> f64 {
    0.5 * ((std::f64::consts::TAU * freq * k as f64).sin() * progress + 1.0)
}

/// Sorts `order` by candidate value, best first.
fn rank_candidates(s: &Swarm, order: &mut [usize]) {
    order.sort_unstable_by(|&a, &b| s.cand_fit[a].total_cmp(&s.cand_fit[b]).then(a.cmp(&b)));
}

/// Modified evolutionary population dynamics (Eqs. 32–35) on the evaluated candidates.
fn mepd(
    s: &mut Swarm,
    f: f64,
    order: &mut [usize],
    trial: &mut [f64],
    tracker: &mut Tracker,
    rng: &mut SeededRng,
) -> Option<()> {
    let (n, dim) = (s.n, s.dim);
    let food = s.food();
    rank_candidates(s, order);
    let top = n.div_ceil(2);
    // The worse half: offspring around the best snake or around itself (Eq. 32), else a
    // random point (Eq. 33).
    for &i in &order[top..] {
        for j in 0..dim {
            let (lo, hi) = s.bounds[j];
            let base = if rng.random::<f64>() < 0.5 {
                s.pos[food * dim + j]
            } else {
                s.cand[i * dim + j]
            };
            trial[j] = base + random_sign(rng) * ((hi - lo) * rng.random::<f64>() + lo);
        }
        clamp_to(&s.bounds, trial);
        let mut v = tracker.evaluate(trial)?;
        if v >= s.cand_fit[i] {
            random_point(rng, &s.bounds, trial);
            v = tracker.evaluate(trial)?;
        }
        s.cand_fit[i] = v;
        s.cand[i * dim..(i + 1) * dim].copy_from_slice(trial);
    }
    // The better half: differential mutation (Eqs. 34–35).
    if n < 4 {
        return Some(());
    }
    for &i in &order[..top] {
        let p1 = distinct(rng, n, [i, i, i]);
        let p2 = distinct(rng, n, [i, p1, p1]);
        let p3 = distinct(rng, n, [i, p1, p2]);
        for j in 0..dim {
            trial[j] = s.cand[p1 * dim + j] + f * (s.cand[p2 * dim + j] - s.cand[p3 * dim + j]);
        }
        clamp_to(&s.bounds, trial);
        let v = tracker.evaluate(trial)?;
        if v < s.cand_fit[i] {
            s.cand_fit[i] = v;
            s.cand[i * dim..(i + 1) * dim].copy_from_slice(trial);
        }
    }
    Some(())
}

/// A uniform index in `0..n` other than those of `taken` (n must exceed their number).
fn distinct(rng: &mut SeededRng, n: usize, taken: [usize; 3]) -> usize {
    loop {
        let p = rng.random_range(0..n);
        if !taken.contains(&p) {
            return p;
        }
    }
}

/// The least (EA, Eq. 37) and greatest (EB, Eq. 38) coordinates of the elite candidates.
fn elite_bounds(s: &Swarm, elites: &[usize], ea: &mut [f64], eb: &mut [f64]) {
    ea.fill(f64::INFINITY);
    eb.fill(f64::NEG_INFINITY);
    for &e in elites {
        for j in 0..s.dim {
            let v = s.cand[e * s.dim + j];
            ea[j] = ea[j].min(v);
            eb[j] = eb[j].max(v);
        }
    }
}

/// The elite opposite of `x` (Eqs. 37–39): S·(EA_j + EB_j) − x_j, a coordinate outside its
/// bounds redrawn uniformly in [EA_j, EB_j].
fn elite_opposite(
    x: &[f64],
    scale: f64,
    ea: &[f64],
    eb: &[f64],
    bounds: &[(f64, f64)],
    rng: &mut SeededRng,
    out: &mut [f64],
) {
    for j in 0..x.len() {
        let (lo, hi) = bounds[j];
        let o = scale * (ea[j] + eb[j]) - x[j];
        // `!(lo..=hi).contains` also catches NaN.
        out[j] = if (lo..=hi).contains(&o) {
            o
        } else {
            uniform(rng, (ea[j], eb[j]))
        };
    }
    // A no-op (elites lie in the box), kept so evaluated points are within bounds by
    // construction.
    clamp_to(bounds, out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::problem::Problem;
    use crate::optim::testfns::{run_checked, Sphere};
    use rand::SeedableRng;

    #[test]
    fn budget_smaller_than_the_population() {
        let b = Beeso::default();
        let a = run_checked(&b, &Sphere(3), 7, 2);
        assert!(a.value.is_finite());
        let c = run_checked(&b, &Sphere(3), 1, 2);
        assert!(c.value.is_finite());
    }

    #[test]
    fn odd_and_tiny_populations() {
        for population in [1, 2, 3, 5, 7] {
            let b = Beeso {
                population,
                ..Beeso::default()
            };
            let a = run_checked(&b, &Sphere(2), 2000, 4);
            assert!(a.value < 1e-2, "population {population}: {}", a.value);
        }
    }

    #[test]
    fn elite_opposite_reflects_through_the_elite_box() {
        let mut rng = SeededRng::seed_from_u64(0);
        let bounds = [(-5.0, 5.0), (0.0, 10.0), (-1.0, 1.0)];
        let ea = [-1.0, 2.0, -0.5];
        let eb = [3.0, 4.0, 0.5];
        let x = [0.5, 3.5, 0.25];
        let mut out = [0.0; 3];
        // S = 1: the plain opposite EA + EB − x.
        elite_opposite(&x, 1.0, &ea, &eb, &bounds, &mut rng, &mut out);
        assert_eq!(out, [1.5, 2.5, -0.25]);
        // With the elites spanning the box and S = 1 it is the classical lb + ub − x.
        let (lo, hi) = ([-5.0, 0.0, -1.0], [5.0, 10.0, 1.0]);
        elite_opposite(&x, 1.0, &lo, &hi, &bounds, &mut rng, &mut out);
        assert_eq!(out, [-0.5, 6.5, -0.25]);
        // S = 0.5: (EA + EB)/2 − x; a coordinate leaving its bounds is redrawn uniformly in
        // [EA, EB], the others are kept.
        let mut tally = [0usize; 2];
        for _ in 0..200 {
            elite_opposite(&[4.0, 9.0, 0.9], 0.5, &ea, &eb, &bounds, &mut rng, &mut out);
            // 0.5·2 − 4 = −3 (inside), 0.5·6 − 9 = −6 (outside [0, 10]), 0 − 0.9 (inside).
            assert_eq!(out[0], -3.0);
            assert!((2.0..=4.0).contains(&out[1]), "{}", out[1]);
            tally[(out[1] > 3.0) as usize] += 1;
            assert_eq!(out[2], -0.9);
        }
        assert!(tally[0] > 50 && tally[1] > 50, "{tally:?}");
    }

    #[test]
    fn elite_bounds_are_the_extremes_of_the_elites() {
        let mut tracker = Tracker::new(&Sphere(2), 100, false);
        let mut rng = SeededRng::seed_from_u64(1);
        let mut s = Swarm::new(4, &mut tracker, &mut rng).unwrap();
        s.cand = vec![1.0, 2.0, -3.0, 0.5, 4.0, 4.0, 0.0, 0.0];
        s.cand_fit = vec![3.0, 1.0, 9.0, 2.0];
        let mut order = [0; 4];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i;
        }
        rank_candidates(&s, &mut order);
        assert_eq!(order, [1, 3, 0, 2]);
        let (mut ea, mut eb) = ([0.0; 2], [0.0; 2]);
        elite_bounds(&s, &order[..2], &mut ea, &mut eb);
        assert_eq!((ea, eb), ([-3.0, 0.0], [0.0, 0.5]));
    }

    #[test]
    fn mepd_renews_the_worse_half_and_improves_the_better_half() {
        let problem = Sphere(3);
        let mut tracker = Tracker::new(&problem, 1000, false);
        let mut rng = SeededRng::seed_from_u64(2);
        let mut s = Swarm::new(8, &mut tracker, &mut rng).unwrap();
        s.evaluate_candidates(&mut tracker).unwrap();
        let (before, before_fit) = (s.cand.clone(), s.cand_fit.clone());
        let mut order: Vec<usize> = (0..8).collect();
        rank_candidates(&s, &mut order);
        let (better, worse) = (order[..4].to_vec(), order[4..].to_vec());
        let used = tracker.evaluations();
        let mut trial = vec![0.0; 3];
        mepd(&mut s, 0.5, &mut order, &mut trial, &mut tracker, &mut rng).unwrap();
        // 4 mutants, 4 offspring and a random point for each offspring that failed.
        let spent = tracker.evaluations() - used;
        assert!((8..=12).contains(&spent), "{spent}");
        for i in 0..8 {
            let x = &s.cand[i * 3..(i + 1) * 3];
            assert_eq!(problem.evaluate(x), s.cand_fit[i]);
            assert!(x.iter().all(|v| (-5.0..=5.0).contains(v)));
            if better.contains(&i) {
                assert!(s.cand_fit[i] <= before_fit[i]);
            } else {
                assert!(worse.contains(&i));
                assert_ne!(x, &before[i * 3..(i + 1) * 3], "candidate {i} not renewed");
            }
        }
    }

    #[test]
    fn mutation_scale_stays_in_the_unit_interval() {
        for k in 1..=500 {
            let f = mutation_scale(0.1, k, k as f64 / 500.0);
            assert!((0.0..=1.0).contains(&f), "{k}: {f}");
        }
        // Early on the sine's amplitude is small: F ≈ ½.
        assert!((mutation_scale(0.1, 1, 0.002) - 0.5).abs() < 1e-3);
        assert!((mutation_scale(0.25, 1, 1.0) - 1.0).abs() < 1e-12);
    }
}
