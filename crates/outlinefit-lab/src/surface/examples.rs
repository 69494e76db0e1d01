//! The paper's three test clouds (Table 1), regenerated.
//!
//! The paper does not publish its surfaces, only their kind, sizes, degrees and noise
//! levels; these generators match those and are seeded, so every run can draw new noise
//! (and, for Example III, new sample positions) reproducibly.
//!
//! | | points | layout | degree | SNR (dB) | shape |
//! |---|---|---|---|---|---|
//! | I | 841 | 29 × 29 grid | (5, 5) | 20.75 | height map, two hills and a valley |
//! | II | 1681 | 41 × 41 grid | (9, 9) | 12.5 | height map, a 3 × 2.5 wave under a bump |
//! | III | 628 | unorganized | (5, 5) | 18 | self-intersecting, four corners at one cusp |
//!
//! **Irregular sampling** (§6.1: "the data points are affected by noise and irregular
//! sampling"): the grid lines of I and II sit at smoothly warped abscissae
//! x = w(s), s evenly spaced, so the uniform rule is wrong by design; Example III samples
//! its parameter square uniformly at random.
//!
//! **Example III**: S(u, v) = (sin πv · cos 2πu, ½ sin πv · sin 4πu, 0.6 sin 2πv). Each
//! v-section is a lemniscate (a figure eight) scaled by sin πv, so the surface crosses
//! itself along the line where the eights cross (u = ¼ and u = ¾ meet), and all four
//! corners of the parameter square map to the origin, where the sections shrink to a
//! point: a cusp.
//!
//! **How the SNR is read**: as a power ratio in decibels, SNR = 10 log₁₀(P_signal /
//! P_noise), with P_signal the mean squared deviation of the clean coordinates from their
//! centroid (per coordinate) and P_noise = σ², the variance of the isotropic Gaussian
//! noise added to each coordinate of each point — MATLAB's `awgn(…, 'measured')`, the
//! paper's likely tool, measured about the centroid so that moving the surface does not
//! change the noise.

use super::{PointCloud, P3};
use outlinefit::optim::{standard_normal, SeededRng};
use rand::{RngExt, SeedableRng};
use serde::Serialize;
use std::f64::consts::PI;

/// One of the paper's examples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Example {
    /// 29 × 29 grid, degree (5, 5), SNR 20.75.
    I,
    /// 41 × 41 grid, degree (9, 9), SNR 12.5.
    II,
    /// 628 unorganized points, degree (5, 5), SNR 18.
    III,
}

impl Example {
    /// All three, in the paper's order.
    pub const ALL: [Example; 3] = [Example::I, Example::II, Example::III];

    /// The name, `I`, `II` or `III`.
    pub fn name(self) -> &'static str {
        match self {
            Example::I => "I",
            Example::II => "II",
            Example::III => "III",
        }
    }

    /// The example named `I`, `II` or `III` (or 1, 2, 3).
    pub fn from_name(name: &str) -> Option<Example> {
        match name {
            "I" | "i" | "1" => Some(Example::I),
            "II" | "ii" | "2" => Some(Example::II),
            "III" | "iii" | "3" => Some(Example::III),
            _ => None,
        }
    }

    /// The degree of the approximating surface (Table 1).
    pub fn degree(self) -> (usize, usize) {
        match self {
            Example::I | Example::III => (5, 5),
            Example::II => (9, 9),
        }
    }

    /// The signal-to-noise ratio in decibels (Table 1).
    pub fn snr(self) -> f64 {
        match self {
            Example::I => 20.75,
            Example::II => 12.5,
            Example::III => 18.0,
        }
    }

    /// The clean points (no noise); Example III's sample positions come from `seed`.
    pub fn clean(self, seed: u64) -> PointCloud {
        let mut rng = SeededRng::seed_from_u64(seed);
        self.clean_with(&mut rng)
    }

    fn clean_with(self, rng: &mut SeededRng) -> PointCloud {
        match self {
            Example::I => height_map(
                29,
                |s| s + 0.07 * (2.0 * PI * s).sin(),
                |s| s - 0.05 * (2.0 * PI * s).sin() + 0.03 * (4.0 * PI * s).sin(),
                height_i,
            ),
            Example::II => height_map(
                41,
                |s| s + 0.05 * (2.0 * PI * s).sin() + 0.02 * (6.0 * PI * s).sin(),
                |s| s - 0.06 * (2.0 * PI * s).sin(),
                height_ii,
            ),
            Example::III => {
                let points = (0..628)
                    .map(|_| {
                        let u: f64 = rng.random();
                        let v: f64 = rng.random();
                        lemniscate_pinch(u, v)
                    })
                    .collect();
                PointCloud { points, grid: None }
            }
        }
    }

    /// The example's points with noise at its SNR, all drawn from `seed`.
    pub fn generate(self, seed: u64) -> PointCloud {
        let mut rng = SeededRng::seed_from_u64(seed);
        let mut cloud = self.clean_with(&mut rng);
        add_noise(&mut cloud.points, self.snr(), &mut rng);
        cloud
    }
}

/// An n × n grid of a height map over warped abscissae x = wx(s), y = wy(t).
fn height_map(
    n: usize,
    wx: impl Fn(f64) -> f64,
    wy: impl Fn(f64) -> f64,
    h: impl Fn(f64, f64) -> f64,
) -> PointCloud {
    let mut points = Vec::with_capacity(n * n);
    for p in 0..n {
        let x = wx(p as f64 / (n - 1) as f64);
        for q in 0..n {
            let y = wy(q as f64 / (n - 1) as f64);
            points.push([x, y, h(x, y)]);
        }
    }
    PointCloud {
        points,
        grid: Some((n, n)),
    }
}

fn bump(x: f64, y: f64, cx: f64, cy: f64, w: f64) -> f64 {
    (-((x - cx).powi(2) + (y - cy).powi(2)) / w).exp()
}

/// Example I: two hills and a valley on a gentle wave.
fn height_i(x: f64, y: f64) -> f64 {
    0.30 * bump(x, y, 0.28, 0.30, 0.045) - 0.25 * bump(x, y, 0.70, 0.62, 0.035)
        + 0.12 * bump(x, y, 0.25, 0.78, 0.03)
        + 0.06 * (2.0 * PI * x).sin()
}

/// Example II: a wave of 1.5 × 1.25 periods with a bump in the middle.
fn height_ii(x: f64, y: f64) -> f64 {
    0.2 * (3.0 * PI * x + 0.3).sin() * (2.5 * PI * y).sin()
        + 0.1 * (2.0 * PI * (x + 2.0 * y)).cos() * bump(x, y, 0.5, 0.5, 0.5)
}

/// Example III's surface (see the module docs).
pub fn lemniscate_pinch(u: f64, v: f64) -> P3 {
    let r = (PI * v).sin();
    [
        r * (2.0 * PI * u).cos(),
        0.5 * r * (4.0 * PI * u).sin(),
        0.6 * (2.0 * PI * v).sin(),
    ]
}

/// Adds isotropic Gaussian noise at `snr` decibels (see the module docs).
pub fn add_noise(points: &mut [P3], snr: f64, rng: &mut SeededRng) {
    let sigma = noise_sigma(points, snr);
    for p in points.iter_mut() {
        for c in p.iter_mut() {
            *c += sigma * standard_normal(rng);
        }
    }
}

/// The noise deviation σ for `snr` decibels on these clean points.
pub fn noise_sigma(points: &[P3], snr: f64) -> f64 {
    let n = points.len() as f64;
    let mut c = [0.0; 3];
    for p in points {
        for k in 0..3 {
            c[k] += p[k] / n;
        }
    }
    let power = points
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - c[k]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / (3.0 * n);
    (power / 10f64.powf(snr / 10.0)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn examples_match_table_1_and_their_snr() {
        for ex in Example::ALL {
            let clean = ex.clean(7);
            let noisy = ex.generate(7);
            let expected = [841, 1681, 628][ex as usize];
            assert_eq!(noisy.points.len(), expected);
            assert_eq!(clean.points, {
                // Same seed, same positions: the noise is the only difference.
                let mut rng = SeededRng::seed_from_u64(7);
                ex.clean_with(&mut rng).points
            });
            let sigma = noise_sigma(&clean.points, ex.snr());
            let diffs: Vec<f64> = clean
                .points
                .iter()
                .zip(&noisy.points)
                .flat_map(|(a, b)| (0..3).map(move |k| b[k] - a[k]))
                .collect();
            let var = diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64;
            // The sample variance of ~2000–5000 normal deviates is within 10 % of σ².
            assert!(
                (var / (sigma * sigma) - 1.0).abs() < 0.1,
                "{ex:?} {var} {sigma}"
            );
        }
    }

    #[test]
    fn example_iii_corners_meet_and_the_surface_crosses_itself() {
        let o = lemniscate_pinch(0.0, 0.0);
        for (u, v) in [(1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let p = lemniscate_pinch(u, v);
            assert!((0..3).all(|k| (p[k] - o[k]).abs() < 1e-15));
        }
        for v in [0.2, 0.5, 0.9] {
            let (a, b) = (lemniscate_pinch(0.25, v), lemniscate_pinch(0.75, v));
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-15));
        }
    }
}
