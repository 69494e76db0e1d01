//! Particle swarm optimisation (Kennedy & Eberhart 1995) with a linearly decreasing
//! inertia weight (Shi & Eberhart 1998, 1999), one of the two comparators of the HS paper
//! (§7.1).
//!
//! The HS paper takes "the procedure of PSO" from Das, Abraham & Konar (2008), its ref.
//! [2], a survey that presents this inertia-weight global-best PSO, but it states no
//! parameter values (and it fixes the run time, not the number of evaluations). So the
//! defaults are the textbook ones of Shi & Eberhart: inertia weight falling linearly from
//! 0.9 to 0.4 over the run and acceleration coefficients c1 = c2 = 2, with a swarm of 30
//! (the usual 20–50). Each velocity component is clamped to ±20 % of its variable's range
//! (V_max): Shi & Eberhart let V_max be the whole range. Among 0.1, 0.2, 0.5 and 1 none
//! was best everywhere on the test functions (30 seeds each); 0.2 had the best worst case
//! on 5-D and 10-D Rastrigin and converged as fast as any on the sphere.
//!
//! Each particle moves by v ← w·v + c1·r1·(p − x) + c2·r2·(g − x), x ← x + v, with fresh
//! uniform r1, r2 per component, p its own best point and g the swarm's best (global-best
//! topology). Updates are asynchronous: g improves as soon as any particle finds a better
//! point, within the sweep over the swarm. Velocities start at zero (Engelbrecht 2012
//! found this no worse than random starts, and it needs no extra parameter). The inertia
//! schedule runs on the fraction of the evaluation budget spent, so it reaches its end
//! value exactly at the budget.
//!
//! Bounds: a component that would leave the box is put on the bound and its velocity set
//! to zero (the "absorbing wall" of Robinson & Rahmat-Samii 2004), so the particle can
//! settle on a boundary optimum rather than bounce off it.
//!
//! Written by hand: no maintained crate implements it over a caller-seeded generator with
//! an exact evaluation budget. All buffers are allocated before the main loop.

use super::problem::{random_point, Optimizer, SeededRng, Tracker};
use rand::RngExt;

/// Particle swarm optimisation parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ParticleSwarm {
    /// Number of particles (at least 1 is used). Default: 30.
    pub swarm: usize,
    /// Inertia weight at the start of the run. Default: 0.9.
    pub inertia_start: f64,
    /// Inertia weight at the end of the budget (linear in between). Default: 0.4.
    pub inertia_end: f64,
    /// Cognitive coefficient c1 (pull towards the particle's own best). Default: 2.
    pub c1: f64,
    /// Social coefficient c2 (pull towards the swarm's best). Default: 2.
    pub c2: f64,
    /// Velocity limit per component as a fraction of the variable's range (V_max);
    /// infinity disables it. Default: 0.2.
    pub vmax: f64,
}

impl Default for ParticleSwarm {
    fn default() -> Self {
        ParticleSwarm {
            swarm: 30,
            inertia_start: 0.9,
            inertia_end: 0.4,
            c1: 2.0,
            c2: 2.0,
            vmax: 0.2,
        }
    }
}

impl Optimizer for ParticleSwarm {
    fn name(&self) -> &'static str {
        "pso"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let budget = tracker.remaining();
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let n = self.swarm.max(1);
        // Velocity limits; a fixed variable (empty range) gets none to move by, and NaN or
        // negative fractions count as zero.
        let vlimit: Vec<f64> = bounds
            .iter()
            .map(|&(lo, hi)| {
                if hi > lo {
                    (self.vmax.abs() * (hi - lo)).max(0.0)
                } else {
                    0.0
                }
            })
            .collect();

        // Positions, velocities and personal bests: `n` rows of `dim` values each.
        let mut x = vec![0.0; n * dim];
        let mut v = vec![0.0; n * dim];
        let mut pbest = vec![0.0; n * dim];
        let mut pbest_values = vec![f64::INFINITY; n];
        let mut g = 0; // index of the particle whose personal best is the swarm's best

        for i in 0..n {
            let row = &mut x[i * dim..(i + 1) * dim];
            random_point(rng, &bounds, row);
            let Some(f) = tracker.evaluate(row) else {
                return;
            };
            pbest[i * dim..(i + 1) * dim].copy_from_slice(row);
            pbest_values[i] = f;
            if f < pbest_values[g] {
                g = i;
            }
        }

        'sweeps: loop {
            for i in 0..n {
                if tracker.exhausted() {
                    break 'sweeps;
                }
                let progress = tracker.evaluations() as f64 / budget as f64;
                let w = self.inertia_start + (self.inertia_end - self.inertia_start) * progress;
                for j in 0..dim {
                    let k = i * dim + j;
                    let (lo, hi) = bounds[j];
                    let r1: f64 = rng.random();
                    let r2: f64 = rng.random();
                    let mut vj = w * v[k]
                        + self.c1 * r1 * (pbest[k] - x[k])
                        + self.c2 * r2 * (pbest[g * dim + j] - x[k]);
                    vj = vj.clamp(-vlimit[j], vlimit[j]);
                    let xj = x[k] + vj;
                    if xj < lo || xj.is_nan() {
                        x[k] = lo;
                        v[k] = 0.0;
                    } else if xj > hi {
                        x[k] = hi;
                        v[k] = 0.0;
                    } else {
                        x[k] = xj;
                        v[k] = vj;
                    }
                }
                let row = &x[i * dim..(i + 1) * dim];
                let Some(f) = tracker.evaluate(row) else {
                    break 'sweeps;
                };
                if f < pbest_values[i] {
                    pbest_values[i] = f;
                    pbest[i * dim..(i + 1) * dim].copy_from_slice(row);
                    if f < pbest_values[g] {
                        g = i;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::testfns::{run_checked, Sphere};

    #[test]
    fn budget_smaller_than_the_population() {
        let pso = ParticleSwarm::default();
        let o = run_checked(&pso, &Sphere(4), 7, 5);
        assert!(o.value.is_finite());
        run_checked(&pso, &Sphere(4), pso.swarm as u64 + 1, 5);
    }
}
