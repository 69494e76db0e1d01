//! Cuckoo search with Lévy flights (Yang & Deb 2009), as described in §4 of the
//! surface-fitting paper (`shared/papers/cuckoo-search-levy-surface-fitting.txt`), and its
//! improved variant ICS (§7, after Valian et al.) in which the discovery probability p_a
//! falls over the run.
//!
//! N nests each hold one solution. A generation has two phases, each spending at most one
//! evaluation per nest:
//!
//! 1. Lévy flights (Eqs. 6–10): every nest x lays a cuckoo
//!    x′ = x + α · ς ⊙ (x − x_best) ⊙ Ψ, where ς is a Mantegna Lévy step per coordinate
//!    (ς = u / |v|^{1/β}, u ~ N(0, σ_u²) with σ_u from Eq. 8, v ~ N(0, 1)), α = 0.01
//!    (Eq. 10) and Ψ ~ N(0, 1) per coordinate. The cuckoo replaces its own nest if it is
//!    better ("compares it with the current one. In case of improvement, this new solution
//!    replaces the current one", §4.3). The best nest itself does not move (x − x_best = 0).
//! 2. Discovery: each coordinate of each nest is discovered with probability p_a; the
//!    discovered coordinates move by r · (x_p − x_q) for two random nests p, q and one
//!    uniform r ∈ [0, 1] per nest (the biased random walk of Yang & Deb's reference code,
//!    which §4.3 cites as "the original implementation"), and the new nest is kept if it is
//!    better. A nest with no discovered coordinate is not re-evaluated.
//!
//! Defaults (§4.3, §6.2): N = 100 nests, p_a = 0.25, β = 3/2, α = 0.01. ICS
//! ([`CuckooSearch::improved`]): p_a falls from p_a^max = 0.5 to p_a^min = 0.1 (§7). The
//! paper names only p_a as the varying parameter and gives no schedule; the schedule here
//! is Valian et al.'s linear one, p_a = p_a^max − progress · (p_a^max − p_a^min), with
//! progress = evaluations / budget. Valian et al. also shrink α exponentially; that is
//! available through [`CuckooSearch::alpha_end`] but off by default, following the paper.
//!
//! Reading of the reference code vs. the text: Yang & Deb's code marks a coordinate as
//! discovered when `rand > p_a` (i.e. with probability 1 − p_a); here it is `rand < p_a`,
//! so that p_a is the discovery probability the text defines and ICS's "high p_a explores"
//! holds.
//!
//! Bound handling: every coordinate of a new nest is clamped into its bounds (the reference
//! code's `simplebounds`).
//!
//! Written by hand: no maintained crate implements cuckoo search over a caller-seeded
//! generator with an exact evaluation budget.

use super::problem::{clamp_to, random_point, standard_normal, Optimizer, SeededRng};
use super::problem::{uniform, Tracker};
use rand::RngExt;

/// Cuckoo search parameters; the plain algorithm (`cs`) by default, ICS (`ics`) from
/// [`CuckooSearch::improved`] or whenever p_a or α vary over the run.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct CuckooSearch {
    /// Number of nests N. Default: 100 (§6.2).
    pub nests: usize,
    /// Discovery probability p_a at the start of the run. Default: 0.25 (§6.2); ICS: 0.5.
    pub pa: f64,
    /// Discovery probability when the budget is spent; p_a moves linearly from `pa` to
    /// `pa_end` with the fraction of the budget used. Default: 0.25 (constant); ICS: 0.1.
    pub pa_end: f64,
    /// Lévy step scale α at the start of the run. Default: 0.01 (Eq. 10).
    pub alpha: f64,
    /// Lévy step scale when the budget is spent; α moves geometrically (Valian et al.'s
    /// exponential schedule) from `alpha` to `alpha_end` (linearly if either is 0).
    /// Default: 0.01 (constant), also for ICS since the paper varies only p_a.
    pub alpha_end: f64,
    /// Lévy exponent β of Mantegna's algorithm. Default: 1.5 (§4.3).
    pub beta: f64,
}

impl Default for CuckooSearch {
    fn default() -> Self {
        CuckooSearch {
            nests: 100,
            pa: 0.25,
            pa_end: 0.25,
            alpha: 0.01,
            alpha_end: 0.01,
            beta: 1.5,
        }
    }
}

impl CuckooSearch {
    /// The improved cuckoo search (ICS) of §7: p_a falls linearly from 0.5 to 0.1 over the
    /// budget; everything else as the default.
    pub fn improved() -> Self {
        CuckooSearch {
            pa: 0.5,
            pa_end: 0.1,
            ..CuckooSearch::default()
        }
    }

    /// Whether a parameter varies over the run (the ICS variant).
    fn is_improved(&self) -> bool {
        self.pa != self.pa_end || self.alpha != self.alpha_end
    }
}

/// Mantegna's algorithm for symmetric Lévy-stable steps of exponent β.
#[derive(Clone, Copy, Debug)]
struct Mantegna {
    beta: f64,
    sigma_u: f64,
}

impl Mantegna {
    /// σ_u of Eq. 8 for exponent `beta` (σ_v = 1).
    fn new(beta: f64) -> Self {
        use statrs::function::gamma::gamma;
        let num = gamma(1.0 + beta) * (std::f64::consts::PI * beta / 2.0).sin();
        let den = gamma((1.0 + beta) / 2.0) * beta * 2f64.powf((beta - 1.0) / 2.0);
        Mantegna {
            beta,
            sigma_u: (num / den).powf(1.0 / beta),
        }
    }

    /// One step ς = u / |v|^{1/β} (Eq. 9).
    fn step(&self, rng: &mut SeededRng) -> f64 {
        let u = self.sigma_u * standard_normal(rng);
        let v = standard_normal(rng);
        u / v.abs().powf(1.0 / self.beta)
    }
}

impl Optimizer for CuckooSearch {
    fn name(&self) -> &'static str {
        if self.is_improved() {
            "ics"
        } else {
            "cs"
        }
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let budget = tracker.remaining();
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let n = self.nests.max(1);
        let levy = Mantegna::new(self.beta);
        let mut nests = vec![0.0; n * dim];
        let mut values = vec![f64::INFINITY; n];
        let mut best = vec![0.0; dim];
        let mut cuckoo = vec![0.0; dim];
        // Nests beyond the budget keep +∞ and are never chosen as the best.
        for (x, v) in nests.chunks_exact_mut(dim).zip(values.iter_mut()) {
            random_point(rng, &bounds, x);
            match tracker.evaluate(x) {
                Some(f) => *v = f,
                None => break,
            }
        }
        let progress = |t: &Tracker| t.evaluations() as f64 / budget as f64;
        'run: while !tracker.exhausted() {
            // Lévy flights around each nest, scaled by its distance to the best.
            best.copy_from_slice(tracker.best());
            let p = progress(tracker);
            let alpha = if self.alpha > 0.0 && self.alpha_end > 0.0 {
                self.alpha * (self.alpha_end / self.alpha).powf(p)
            } else {
                self.alpha + (self.alpha_end - self.alpha) * p
            };
            for (x, v) in nests.chunks_exact_mut(dim).zip(values.iter_mut()) {
                for k in 0..dim {
                    let step = alpha * levy.step(rng) * (x[k] - best[k]);
                    cuckoo[k] = x[k] + step * standard_normal(rng);
                }
                clamp_to(&bounds, &mut cuckoo);
                let Some(f) = tracker.evaluate(&cuckoo) else {
                    break 'run;
                };
                if f < *v {
                    *v = f;
                    x.copy_from_slice(&cuckoo);
                }
            }
            // Discovery: a fraction p_a of the coordinates take a biased random walk.
            let pa = self.pa + (self.pa_end - self.pa) * progress(tracker);
            for i in 0..n {
                let (a, b) = (rng.random_range(0..n), rng.random_range(0..n));
                let r = uniform(rng, (0.0, 1.0));
                let mut moved = false;
                for k in 0..dim {
                    let x = nests[i * dim + k];
                    cuckoo[k] = if rng.random::<f64>() < pa {
                        moved = true;
                        x + r * (nests[a * dim + k] - nests[b * dim + k])
                    } else {
                        x
                    };
                }
                if !moved {
                    continue;
                }
                clamp_to(&bounds, &mut cuckoo);
                let Some(f) = tracker.evaluate(&cuckoo) else {
                    break 'run;
                };
                if f < values[i] {
                    values[i] = f;
                    nests[i * dim..(i + 1) * dim].copy_from_slice(&cuckoo);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::testfns::{run_checked, Sphere};
    use rand::SeedableRng;

    fn both() -> [CuckooSearch; 2] {
        [CuckooSearch::default(), CuckooSearch::improved()]
    }

    #[test]
    fn names() {
        assert_eq!(CuckooSearch::default().name(), "cs");
        assert_eq!(CuckooSearch::improved().name(), "ics");
    }

    // 100 nests, 20,000 evaluations: about 100 generations. Values reached: cs, then ics.

    #[test]
    fn budget_smaller_than_population() {
        for cs in both() {
            let o = run_checked(&cs, &Sphere(3), 7, 4);
            assert!(o.value.is_finite());
        }
    }

    #[test]
    fn mantegna_sigma() {
        let m = Mantegna::new(1.5);
        assert!((m.sigma_u - 0.696_574_5).abs() < 1e-6, "{}", m.sigma_u);
    }

    /// P(|ς| ≤ s) for Mantegna's ς = u / |v|^{1/β}, by integrating over v:
    /// E_v[erf(s |v|^{1/β} / (σ_u √2))], independently of the sampler.
    fn mantegna_cdf(m: &Mantegna, s: f64) -> f64 {
        use statrs::function::erf::erf;
        let steps = 20_000;
        let h = 12.0 / steps as f64;
        (0..steps)
            .map(|i| {
                let v = (i as f64 + 0.5) * h;
                let density = 2.0 * (-v * v / 2.0).exp() / std::f64::consts::TAU.sqrt();
                density * erf(s * v.powf(1.0 / m.beta) / (m.sigma_u * 2f64.sqrt())) * h
            })
            .sum()
    }

    #[test]
    fn mantegna_step_distribution() {
        let m = Mantegna::new(1.5);
        // The median of |ς| from the integral (≈ 0.6310 for β = 1.5).
        let (mut lo, mut hi) = (0.01, 10.0);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if mantegna_cdf(&m, mid) < 0.5 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let median = 0.5 * (lo + hi);
        assert!((median - 0.631).abs() < 1e-3, "{median}");
        let mut rng = SeededRng::seed_from_u64(5);
        let n = 400_000;
        let mut steps: Vec<f64> = (0..n).map(|_| m.step(&mut rng).abs()).collect();
        steps.sort_by(f64::total_cmp);
        let sample_median = steps[n / 2];
        assert!(
            (sample_median - median).abs() < 0.01,
            "{sample_median} vs {median}"
        );
        // Heavy tail: P(|ς| > x) ≈ C x^{-β}; C = 2φ(0)·E|u|^β ≈ 0.399 for β = 1.5.
        for x in [10.0, 30.0] {
            let expected = 1.0 - mantegna_cdf(&m, x);
            let tail = steps.iter().filter(|&&s| s > x).count() as f64 / n as f64;
            assert!(
                (tail / expected - 1.0).abs() < 0.12,
                "P(|step| > {x}) = {tail}, expected {expected}"
            );
            assert!((expected * x.powf(1.5) - 0.399).abs() < 0.002);
        }
    }
}
