//! Approximate merging of two adjacent disk Wang–Ball (DWB) curves into one DWB curve of
//! degree n (the BEESO merging paper, §2.2).
//!
//! The curves `W₁` (degree n₁) and `W₂` (degree n₂) meet at a shared disk. The merged
//! curve `D` of degree `n ≥ max(n₁, n₂)` is split at `λ` (the left curve's share of the
//! total center arc length) into `D_left(t) = D(λt)` and `D_right(t) = D(λ + (1 − λ)t)`,
//! and the merging error (Eq. 10) is
//!
//! ```text
//! ε = ∫₀¹ |C₁ − C_left|² + |C₂ − C_right|² dt  +  ∫₀¹ (R₁ − R_left)² + (R₂ − R_right)² dt
//! ```
//!
//! (center part + radius part, no square root). With end-point preservation (Eq. 11–12) the
//! merged curve's first and last disks are the first disk of `W₁` and the last of `W₂`.
//!
//! Every integrand is a polynomial of degree ≤ 2·max(n, n₁, n₂), so a Gauss–Legendre rule
//! of `max(n, n₁, n₂) + 1` nodes makes ε exact up to rounding.
//!
//! Two ways to minimise ε:
//! * [`MergeMethod::Exact`]: ε is quadratic in the control disks, and the center and radius parts
//!   do not share unknowns. The centers solve one linear least-squares system (same normal
//!   matrix for x and y); the radii solve the same system under `r_k ≥ min_radius`, a small
//!   bounded least-squares problem (`merge::bounded`). This is the global minimum.
//! * [`MergeMethod::Optimizer`]: any metaheuristic of [`crate::optim`] over the same variables
//!   (free centers and radii) within a box, as the paper does with BEESO (population 50,
//!   500 iterations = 25 000 evaluations). The box is centered on the input control
//!   centers' bounding box, `box_scale` times its larger side in every direction, radii in
//!   `[min_radius, min_radius + box_scale · 2 · max input radius]`; `exact`'s minimum lies
//!   in it on the paper's examples (checked by the tests), so a metaheuristic can reach it.
//!
//! `outline` applies merging to traced outlines (`trace --merge`).

mod bounded;
pub(crate) mod outline;

use crate::curve::wang_ball::{merge_lambda, wang_ball_basis, Disk, DiskWangBall};
use crate::error::{Error, Result};
use crate::geom::{Bounds, Point};
use crate::optim::{Optimizer, Problem, SeededRng};
use crate::quad::GaussLegendre;
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use serde::Serialize;

/// Highest merged degree accepted (the exact Wang–Ball ↔ Bézier conversion is exact far
/// beyond it; the bound keeps stack buffers fixed and problems well conditioned).
pub const MAX_DEGREE: usize = 20;

/// The paper's lower bound on radii (its reported radii stop at 0.001).
pub const DEFAULT_MIN_RADIUS: f64 = 0.001;

/// The paper's budget: population 50 × 500 iterations.
pub const DEFAULT_BUDGET: u64 = 25_000;

/// Default size of a metaheuristic's search box, in multiples of the input's extent.
pub const DEFAULT_BOX_SCALE: f64 = 3.0;

/// How the merged curve is found.
#[derive(Clone, Copy)]
pub enum MergeMethod<'a> {
    /// Linear least squares (centers) and bounded least squares (radii): the minimum.
    Exact,
    /// A metaheuristic over the free disks with an evaluation budget and a seed.
    Optimizer {
        /// The optimizer.
        optimizer: &'a dyn Optimizer,
        /// Objective evaluations.
        budget: u64,
        /// Seed of its random generator.
        seed: u64,
    },
}

/// Options of a merge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MergeOptions {
    /// Degree n of the merged curve, `max(n₁, n₂) ≤ n ≤` [`MAX_DEGREE`].
    pub degree: usize,
    /// Keep the outer end disks (Eq. 11–12).
    pub preserve_endpoints: bool,
    /// Lower bound of every free radius. Default 0.001.
    pub min_radius: f64,
    /// Half-width of a metaheuristic's search box in units of the input's extent. Default 3.
    pub box_scale: f64,
}

impl MergeOptions {
    /// Defaults for degree `degree`, without end-point preservation.
    pub fn new(degree: usize) -> Self {
        MergeOptions {
            degree,
            preserve_endpoints: false,
            min_radius: DEFAULT_MIN_RADIUS,
            box_scale: DEFAULT_BOX_SCALE,
        }
    }
}

/// A merged curve and its errors.
#[derive(Clone, Debug, Serialize)]
pub struct Merged {
    /// The merging error ε of Eq. 10 (= `center_error + radius_error`).
    pub error: f64,
    /// The center-curve part of ε.
    pub center_error: f64,
    /// The radius-function part of ε.
    pub radius_error: f64,
    /// The subdivision parameter λ.
    pub lambda: f64,
    /// The merged curve's degree.
    pub degree: usize,
    /// `exact` or the optimizer's name.
    pub method: String,
    /// Objective evaluations (0 for `exact`).
    pub evaluations: u64,
    /// The control disks of the merged curve.
    #[serde(skip)]
    pub curve: DiskWangBall,
    /// Metaheuristics: true when some variable of the best point is on the search box.
    pub on_search_boundary: bool,
}

/// The merging problem of two adjacent DWB curves: quadrature, basis values and the
/// original curves sampled at the nodes, ready for exact solves and fast evaluations.
pub struct MergeProblem {
    options: MergeOptions,
    lambda: f64,
    /// Quadrature weights, one per node (the same for both halves).
    weights: Vec<f64>,
    /// For each half and node: the original curve's disk there.
    targets: Vec<Disk>,
    /// For each half and node: the merged basis `W_{k,n}(τ)`, `n + 1` values.
    basis: Vec<f64>,
    /// The fixed end disks (end-point preservation).
    first: Disk,
    last: Disk,
    /// Search box of the metaheuristics: (x, y) ranges and the radius range.
    center_box: [(f64, f64); 2],
    radius_box: (f64, f64),
}

impl MergeProblem {
    /// Sets up the merge of `a` (left) and `b` (right).
    ///
    /// Errors: a degree outside `max(n₁, n₂)..=MAX_DEGREE`, curves that do not meet (the
    /// last disk of `a` must equal the first of `b` to 1e-9 of the curves' size),
    /// non-finite or negative data, a negative or non-finite `min_radius`.
    pub fn new(a: &DiskWangBall, b: &DiskWangBall, options: MergeOptions) -> Result<Self> {
        validate(a, b, &options)?;
        let n = options.degree;
        let top = n.max(a.degree()).max(b.degree());
        let rule = GaussLegendre::exact_for_degree(2 * top);
        let lambda = merge_lambda(a, b);
        let mut weights = Vec::new();
        let mut targets = Vec::new();
        let mut basis = Vec::new();
        let mut w = vec![0.0; n + 1];
        for (half, curve) in [a, b].into_iter().enumerate() {
            for (&t, &wt) in rule.nodes.iter().zip(&rule.weights) {
                let tau = if half == 0 {
                    lambda * t
                } else {
                    lambda + (1.0 - lambda) * t
                };
                wang_ball_basis(n, tau, &mut w);
                basis.extend_from_slice(&w);
                targets.push(curve.eval(t));
                weights.push(wt);
            }
        }
        let Bounds { min: lo, max: hi } =
            Bounds::of(a.disks.iter().chain(&b.disks).map(|d| d.center));
        let max_radius = a
            .disks
            .iter()
            .chain(&b.disks)
            .map(|d| d.radius)
            .fold(0.0, f64::max);
        let extent = (hi.x - lo.x).max(hi.y - lo.y).max(max_radius).max(1e-9);
        let mid = (lo + hi) * 0.5;
        let half_width = options.box_scale * extent;
        let center_box = [
            (mid.x - half_width, mid.x + half_width),
            (mid.y - half_width, mid.y + half_width),
        ];
        let radius_box = (
            options.min_radius,
            options.min_radius + options.box_scale * 2.0 * max_radius.max(1e-9),
        );
        Ok(MergeProblem {
            options,
            lambda,
            weights,
            targets,
            basis,
            first: a.disks[0],
            last: b.disks[b.disks.len() - 1], // validate: at least two disks
            center_box,
            radius_box,
        })
    }

    /// The subdivision parameter λ.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The options.
    pub fn options(&self) -> &MergeOptions {
        &self.options
    }

    /// `(center part, radius part)` of the merging error ε of `merged` (degree n).
    pub fn error_parts(&self, merged: &DiskWangBall) -> (f64, f64) {
        self.error_parts_of(&merged.disks)
    }

    /// ε's parts for the control disks `disks` (`degree + 1` of them).
    fn error_parts_of(&self, disks: &[Disk]) -> (f64, f64) {
        let m = self.options.degree + 1;
        let (mut ec, mut er) = (0.0, 0.0);
        for ((target, &w), phi) in self
            .targets
            .iter()
            .zip(&self.weights)
            .zip(self.basis.chunks_exact(m))
        {
            let (mut c, mut r) = (Point::ZERO, 0.0);
            for (d, &p) in disks.iter().zip(phi) {
                c += d.center * p;
                r += d.radius * p;
            }
            ec += w * (c - target.center).length_squared();
            er += w * (r - target.radius).powi(2);
        }
        (ec, er)
    }

    /// The indices of the disks that are unknowns (all, or all but the two ends).
    pub fn free_range(&self) -> std::ops::Range<usize> {
        let n = self.options.degree;
        if self.options.preserve_endpoints {
            1..n
        } else {
            0..n + 1
        }
    }

    /// The merged curve with the smallest ε (see [`MergeMethod::Exact`]).
    pub fn solve_exact(&self) -> Result<DiskWangBall> {
        let n = self.options.degree;
        let m = n + 1;
        let free = self.free_range();
        let k = free.len();
        let mut disks = vec![Disk::default(); m];
        if self.options.preserve_endpoints {
            disks[0] = self.first;
            disks[n] = self.last;
        }
        if k == 0 {
            return Ok(DiskWangBall::new(disks));
        }
        // Normal equations over the free disks; fixed disks move to the right-hand side.
        let mut g = DMatrix::zeros(k, k);
        let mut rhs = DMatrix::zeros(k, 3); // columns: x, y, r
        for ((target, &w), phi) in self
            .targets
            .iter()
            .zip(&self.weights)
            .zip(self.basis.chunks_exact(m))
        {
            let mut resid = Disk::new(target.center, target.radius);
            if self.options.preserve_endpoints {
                for &j in &[0, n] {
                    resid.center -= disks[j].center * phi[j];
                    resid.radius -= disks[j].radius * phi[j];
                }
            }
            for (a, i) in free.clone().enumerate() {
                let wi = w * phi[i];
                rhs[(a, 0)] += wi * resid.center.x;
                rhs[(a, 1)] += wi * resid.center.y;
                rhs[(a, 2)] += wi * resid.radius;
                for (c, j) in free.clone().enumerate() {
                    g[(a, c)] += wi * phi[j];
                }
            }
        }
        let singular = || Error::InvalidInput {
            what: "merge".to_string(),
            message: "the merging least-squares system is singular".to_string(),
        };
        let chol = g.clone().cholesky().ok_or_else(singular)?;
        let xy = chol.solve(&rhs.columns(0, 2).into_owned());
        let lower = vec![self.options.min_radius; k];
        let r = bounded::minimize_lower_bounded(&g, &DVector::from(rhs.column(2)), &lower)
            .map_err(|_| singular())?;
        for (a, i) in free.enumerate() {
            disks[i] = Disk::new(Point::new(xy[(a, 0)], xy[(a, 1)]), r[a]);
        }
        Ok(DiskWangBall::new(disks))
    }

    /// Merges by `method`.
    pub fn solve(&self, method: MergeMethod<'_>) -> Result<Merged> {
        let (curve, name, evaluations, on_boundary) = match method {
            MergeMethod::Exact => (self.solve_exact()?, "exact".to_string(), 0, false),
            MergeMethod::Optimizer {
                optimizer,
                budget,
                seed,
            } => {
                if budget == 0 {
                    return Err(Error::InvalidOption {
                        name: "budget",
                        message: "must be at least 1".to_string(),
                    });
                }
                if self.free_range().is_empty() {
                    (self.solve_exact()?, optimizer.name().to_string(), 0, false)
                } else {
                    let mut rng = SeededRng::seed_from_u64(seed);
                    let outcome = optimizer.minimize(self, budget, &mut rng, false);
                    let on_boundary = outcome.best.iter().enumerate().any(|(i, &v)| {
                        let (lo, hi) = self.bounds(i);
                        v <= lo || v >= hi
                    });
                    (
                        self.curve_of(&outcome.best),
                        optimizer.name().to_string(),
                        outcome.evaluations,
                        on_boundary,
                    )
                }
            }
        };
        let (center_error, radius_error) = self.error_parts(&curve);
        Ok(Merged {
            error: center_error + radius_error,
            center_error,
            radius_error,
            lambda: self.lambda,
            degree: self.options.degree,
            method: name,
            evaluations,
            curve,
            on_search_boundary: on_boundary,
        })
    }

    /// The disk of index `k` for the variable vector `x` (layout: x, y, r of each free disk).
    fn disk_of(&self, x: &[f64], k: usize) -> Disk {
        let n = self.options.degree;
        if self.options.preserve_endpoints {
            if k == 0 {
                return self.first;
            }
            if k == n {
                return self.last;
            }
        }
        let a = k - self.free_range().start;
        Disk::new(Point::new(x[3 * a], x[3 * a + 1]), x[3 * a + 2])
    }

    /// The merged curve for a variable vector.
    pub fn curve_of(&self, x: &[f64]) -> DiskWangBall {
        DiskWangBall::new(
            (0..=self.options.degree)
                .map(|k| self.disk_of(x, k))
                .collect(),
        )
    }
}

impl Problem for MergeProblem {
    fn dim(&self) -> usize {
        3 * self.free_range().len()
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        match i % 3 {
            0 => self.center_box[0],
            1 => self.center_box[1],
            _ => self.radius_box,
        }
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        // The disks once per evaluation (degree ≤ MAX_DEGREE), not once per node.
        let mut disks = [Disk::default(); MAX_DEGREE + 1];
        let n = self.options.degree;
        for (k, d) in disks[..=n].iter_mut().enumerate() {
            *d = self.disk_of(x, k);
        }
        let (c, r) = self.error_parts_of(&disks[..=n]);
        c + r
    }
}

fn validate(a: &DiskWangBall, b: &DiskWangBall, options: &MergeOptions) -> Result<()> {
    let bad_input = |message: String| {
        Err(Error::InvalidInput {
            what: "merge input".to_string(),
            message,
        })
    };
    for (name, c) in [("first", a), ("second", b)] {
        if c.disks.len() < 2 {
            return bad_input(format!("the {name} curve needs at least two disks"));
        }
        if c.disks.len() > MAX_DEGREE + 1 {
            return bad_input(format!(
                "the {name} curve has degree {}, more than {MAX_DEGREE}",
                c.disks.len() - 1
            ));
        }
        for d in &c.disks {
            if !(d.center.is_finite() && d.radius.is_finite()) {
                return bad_input(format!("the {name} curve has a non-finite value"));
            }
            if d.radius < 0.0 {
                return bad_input(format!("the {name} curve has a negative radius"));
            }
        }
    }
    let size = a
        .disks
        .iter()
        .chain(&b.disks)
        .map(|d| d.center.x.abs().max(d.center.y.abs()).max(d.radius))
        .fold(1.0, f64::max);
    let (end, start) = (a.disks[a.disks.len() - 1], b.disks[0]);
    if end.center.distance(start.center) > 1e-9 * size
        || (end.radius - start.radius).abs() > 1e-9 * size
    {
        return bad_input(format!(
            "the curves are not adjacent: the first one ends at ({}, {}) r {} but the second \
             starts at ({}, {}) r {}",
            end.center.x, end.center.y, end.radius, start.center.x, start.center.y, start.radius
        ));
    }
    let lowest = a.degree().max(b.degree());
    if options.degree < lowest || options.degree > MAX_DEGREE {
        return Err(Error::InvalidOption {
            name: "degree",
            message: format!(
                "must be between {lowest} (the higher input degree) and {MAX_DEGREE}, got {}",
                options.degree
            ),
        });
    }
    if !(options.min_radius.is_finite() && options.min_radius >= 0.0) {
        return Err(Error::InvalidOption {
            name: "min_radius",
            message: "must be a non-negative number".to_string(),
        });
    }
    if !(options.box_scale.is_finite() && options.box_scale > 0.0) {
        return Err(Error::InvalidOption {
            name: "box_scale",
            message: "must be a positive number".to_string(),
        });
    }
    Ok(())
}
