//! Harmony search (Geem et al.), with the parameters of the HS paper (§6): harmony memory
//! size 5, memory considering rate 0.9, pitch adjusting rate 0.3, bandwidth 0.03.
//!
//! The bandwidth has no unit in the paper; here it is a fraction of each variable's range
//! (bw × (upper − lower)), which works far better than an absolute step (see
//! `shared/papers/NOTES.md`).
//!
//! Each improvisation builds a new vector variable by variable: with probability HMCR the
//! value is taken from a random harmony of the memory and then, with probability PAR,
//! moved by a uniform step of at most bw × range; otherwise it is drawn uniformly from the
//! bounds. The new harmony replaces the worst one in memory if it is better. The budget
//! counts objective evaluations, the HMS initial harmonies included.

use super::problem::{random_point, uniform, Optimizer, SeededRng, Tracker};
use rand::RngExt;

/// Harmony search parameters.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct HarmonySearch {
    /// Harmony memory size. Default: 5.
    pub hms: usize,
    /// Harmony memory considering rate. Default: 0.9.
    pub hmcr: f64,
    /// Pitch adjusting rate. Default: 0.3.
    pub par: f64,
    /// Bandwidth as a fraction of each variable's range. Default: 0.03.
    pub bw: f64,
}

impl Default for HarmonySearch {
    fn default() -> Self {
        HarmonySearch {
            hms: 5,
            hmcr: 0.9,
            par: 0.3,
            bw: 0.03,
        }
    }
}

impl Optimizer for HarmonySearch {
    fn name(&self) -> &'static str {
        "hs"
    }

    fn search(&self, tracker: &mut Tracker<'_>, rng: &mut SeededRng) {
        let dim = tracker.dim();
        let bounds = tracker.bounds().to_vec();
        let hms = self.hms.max(1);
        // Harmony memory: rows of `dim` values, with their objective values.
        let mut memory: Vec<f64> = Vec::with_capacity(hms * dim);
        let mut values: Vec<f64> = Vec::with_capacity(hms);
        let mut candidate = vec![0.0; dim];
        for _ in 0..hms {
            random_point(rng, &bounds, &mut candidate);
            let Some(v) = tracker.evaluate(&candidate) else {
                break;
            };
            memory.extend_from_slice(&candidate);
            values.push(v);
        }
        let rows = values.len();
        while !tracker.exhausted() {
            for (i, &(lo, hi)) in bounds.iter().enumerate() {
                let x = if rng.random::<f64>() < self.hmcr {
                    let r = rng.random_range(0..rows);
                    let mut x = memory[r * dim + i];
                    if rng.random::<f64>() < self.par {
                        x += self.bw * (hi - lo) * rng.random_range(-1.0..=1.0);
                    }
                    x.clamp(lo, hi)
                } else {
                    uniform(rng, (lo, hi))
                };
                candidate[i] = x;
            }
            let Some(v) = tracker.evaluate(&candidate) else {
                break;
            };
            let worst = (0..rows)
                .max_by(|&a, &b| values[a].total_cmp(&values[b]))
                .unwrap_or(0);
            if v < values[worst] {
                values[worst] = v;
                memory[worst * dim..(worst + 1) * dim].copy_from_slice(&candidate);
            }
        }
    }
}
