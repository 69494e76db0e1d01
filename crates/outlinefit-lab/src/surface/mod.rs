//! Bézier surfaces fitted to clouds of 3-D points: the system of the fifth paper
//! (`shared/papers/cuckoo-search-levy-surface-fitting.txt`, Iglesias et al. 2018).
//!
//! Given points Δ — an organized m × n grid (a height map, a scanned sheet) or κ
//! unorganized points — and a degree (η, σ), find the polynomial tensor-product Bézier
//! surface (Eq. 2) that minimises the sum of squared distances Y between each point and the
//! surface at that point's parameters (Eq. 4 for grids, Eq. 5 for unorganized points). The
//! unknowns split in two: the data parameters (τ, ζ) — one τ per row and one ζ per column
//! of a grid, one (τ, ζ) per unorganized point — enter nonlinearly; for fixed parameters
//! the poles are a linear least-squares problem (the `solve` module, Eqs. 16–17).
//!
//! The parameters come from one of [`ParamMethod`]:
//! - the classical rules of §5.2, uniform, chordal and centripetal (`params` module);
//! - cuckoo search with Lévy flights over the parameter vector, the paper's method (CSA,
//!   [`outlinefit::optim::CuckooSearch`], N = 100 nests, p_a = 0.25), or its improved variant
//!   (ICSA, p_a from 0.5 to 0.1); each evaluation solves the poles by least squares;
//! - parameter correction from the centripetal parameters (`correct` module), which the
//!   paper does not try: alternating least squares and Newton foot points, then, on grids,
//!   a Levenberg–Marquardt polish. It reaches a lower Y than the searches in a fraction of a
//!   second.
//!
//! [`examples`] generates the paper's three test clouds; [`experiment`] reruns its Tables
//! 3–5. [`obj`] writes a fitted surface as a Wavefront mesh and [`picture`] draws the points
//! with the surface's wireframe.
//!
//! The surface code (Bernstein basis, evaluation, least squares by structure) is written by
//! hand: no maintained crate fits tensor-product Bézier surfaces; the dense linear algebra
//! is nalgebra's.

pub mod bezier;
mod correct;
mod data;
pub mod examples;
pub mod experiment;
pub mod obj;
mod params;
pub mod picture;
pub mod points;
mod solve;

pub use bezier::{BezierSurface, P3};
pub use data::{Params, PointCloud};
pub use params::{classical, Rule};

use crate::Error;
use outlinefit::optim::{CuckooSearch, Optimizer, Problem, SeededRng};
use rand::SeedableRng;
use serde::Serialize;
use solve::Fitter;
use std::time::Instant;

/// How the data parameters are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ParamMethod {
    /// Equal steps (Eq. 11).
    Uniform,
    /// Accumulated chord lengths (Eq. 12).
    Chordal,
    /// Accumulated square roots of chord lengths (Eq. 13).
    Centripetal,
    /// Cuckoo search with Lévy flights (the paper's CSA).
    Cs,
    /// The improved cuckoo search (ICSA): p_a falls from 0.5 to 0.1.
    Ics,
    /// Parameter correction from the centripetal parameters.
    Correct,
}

impl ParamMethod {
    /// Every method, in the order the paper's Table 4 lists them, then `correct`.
    pub const ALL: [ParamMethod; 6] = [
        ParamMethod::Uniform,
        ParamMethod::Chordal,
        ParamMethod::Centripetal,
        ParamMethod::Cs,
        ParamMethod::Ics,
        ParamMethod::Correct,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ParamMethod::Uniform => "uniform",
            ParamMethod::Chordal => "chordal",
            ParamMethod::Centripetal => "centripetal",
            ParamMethod::Cs => "cs",
            ParamMethod::Ics => "ics",
            ParamMethod::Correct => "correct",
        }
    }

    /// Whether the method draws random numbers (and spends a budget).
    pub fn is_search(self) -> bool {
        matches!(self, ParamMethod::Cs | ParamMethod::Ics)
    }
}

/// Default objective evaluations of the searches: 2000 generations of 100 nests, each
/// generation evaluating every nest twice (Lévy flight, then discovery). The paper runs a
/// fixed number of iterations without stating it; its convergence diagrams flatten by
/// about 1400 and it says the method "converges in less than 2000 iterations" (§6.1).
pub const DEFAULT_BUDGET: u64 = 400_000;

/// Highest degree accepted in either direction.
pub const MAX_DEGREE: usize = 20;

/// Options of [`fit`].
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SurfaceOptions {
    /// Degree (η, σ) of the surface: η along τ (grid rows), σ along ζ (grid columns).
    pub degree: (usize, usize),
    /// How the data parameters are chosen.
    pub method: ParamMethod,
    /// Objective evaluations of a search (`cs`, `ics`).
    pub budget: u64,
    /// Seed of a search's random choices.
    pub seed: u64,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions {
            degree: (5, 5),
            method: ParamMethod::Correct,
            budget: DEFAULT_BUDGET,
            seed: outlinefit::optim::DEFAULT_SEED,
        }
    }
}

/// A fitted surface and its errors.
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceFit {
    /// The method that chose the parameters.
    pub method: ParamMethod,
    /// The least-squares surface for `params`.
    pub surface: BezierSurface,
    /// The data parameters.
    pub params: Params,
    /// Y, the sum of squared distances between each point and its surface point (Eq. 4/5).
    pub error: f64,
    /// √(Y / number of points) (Eq. 14/15).
    pub rmse: f64,
    /// Largest distance between a point and its surface point.
    pub max_distance: f64,
    /// Objective evaluations of a search (0 for the other methods).
    pub evaluations: u64,
    /// Correction rounds that lowered Y (0 for the other methods).
    pub rounds: usize,
    /// Wall-clock seconds of the fit.
    pub seconds: f64,
}

/// Checks that `cloud` can be fitted with `options`: a degree from 1 to [`MAX_DEGREE`],
/// enough points (a grid needs at least η + 1 rows and σ + 1 columns, unorganized points
/// at least (η + 1)(σ + 1)), every coordinate finite, and a budget for a search.
pub fn validate(cloud: &PointCloud, options: &SurfaceOptions) -> Result<(), Error> {
    let (eta, sigma) = options.degree;
    if !(1..=MAX_DEGREE).contains(&eta) || !(1..=MAX_DEGREE).contains(&sigma) {
        return Err(Error::InvalidOption {
            name: "degree",
            message: format!("each degree must be from 1 to {MAX_DEGREE}, got ({eta}, {sigma})"),
        });
    }
    if options.method.is_search() && options.budget == 0 {
        return Err(Error::InvalidOption {
            name: "budget",
            message: "a search needs at least one evaluation".into(),
        });
    }
    let invalid = |message: String| Error::InvalidInput {
        what: "the points".into(),
        message,
    };
    if let Some(k) = cloud
        .points
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return Err(invalid(format!(
            "point {} has a coordinate that is not a finite number",
            k + 1
        )));
    }
    match cloud.grid {
        Some((m, n)) => {
            if m * n != cloud.points.len() {
                return Err(invalid(format!(
                    "a {m}×{n} grid needs {} points, got {}",
                    m * n,
                    cloud.points.len()
                )));
            }
            if m < eta + 1 || n < sigma + 1 {
                return Err(invalid(format!(
                    "a {m}×{n} grid is too small for degree ({eta}, {sigma}): it needs at least {} rows and {} columns",
                    eta + 1,
                    sigma + 1
                )));
            }
        }
        None => {
            let need = (eta + 1) * (sigma + 1);
            if cloud.points.len() < need {
                return Err(invalid(format!(
                    "{} points are too few for degree ({eta}, {sigma}), which has {need} poles",
                    cloud.points.len()
                )));
            }
        }
    }
    Ok(())
}

/// The search problem: parameters in [0, 1], objective Y at the least-squares poles.
struct ParamSearch<'a> {
    fitter: &'a Fitter<'a>,
    /// Number of τ values (rows, or points); the ζ values follow.
    split: usize,
    /// Number of τ and ζ values.
    dim: usize,
}

impl Problem for ParamSearch<'_> {
    fn dim(&self) -> usize {
        self.dim
    }

    fn bounds(&self, _: usize) -> (f64, f64) {
        (0.0, 1.0)
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        self.fitter.objective(&self.unpack(x))
    }
}

impl ParamSearch<'_> {
    fn unpack(&self, x: &[f64]) -> Params {
        Params {
            tau: x[..self.split].to_vec(),
            zeta: x[self.split..].to_vec(),
        }
    }
}

/// Fits a Bézier surface to `cloud` (see the module docs).
pub fn fit(cloud: &PointCloud, options: &SurfaceOptions) -> Result<SurfaceFit, Error> {
    validate(cloud, options)?;
    let start = Instant::now();
    let fitter = Fitter::new(cloud, options.degree);
    let (mut evaluations, mut rounds) = (0, 0);
    let params = match options.method {
        ParamMethod::Uniform => classical(cloud, Rule::Uniform),
        ParamMethod::Chordal => classical(cloud, Rule::Chordal),
        ParamMethod::Centripetal => classical(cloud, Rule::Centripetal),
        ParamMethod::Correct => {
            let c = correct::correct(&fitter, cloud, classical(cloud, Rule::Centripetal));
            rounds = c.rounds;
            c.params
        }
        ParamMethod::Cs | ParamMethod::Ics => {
            let optimizer = if options.method == ParamMethod::Cs {
                CuckooSearch::default()
            } else {
                CuckooSearch::improved()
            };
            let (split, dim) = match cloud.grid {
                Some((m, n)) => (m, m + n),
                None => (cloud.points.len(), 2 * cloud.points.len()),
            };
            let problem = ParamSearch {
                fitter: &fitter,
                split,
                dim,
            };
            let mut rng = SeededRng::seed_from_u64(options.seed);
            let outcome = optimizer.minimize(&problem, options.budget, &mut rng, false);
            evaluations = outcome.evaluations;
            problem.unpack(&outcome.best)
        }
    };
    let surface = fitter.surface(&params);
    let residuals = fitter.residuals(&surface, &params);
    let error: f64 = residuals.iter().map(|r| bezier::dot(r, r)).sum();
    let max_distance = residuals
        .iter()
        .map(|r| bezier::dot(r, r).sqrt())
        .fold(0.0, f64::max);
    Ok(SurfaceFit {
        method: options.method,
        rmse: (error / cloud.points.len() as f64).sqrt(),
        surface,
        params,
        error,
        max_distance,
        evaluations,
        rounds,
        seconds: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests;
