//! The search for the two inner weights with control points solved by least squares: the
//! problem an optimizer sees, and the deterministic compass search the `lsq` fit uses.

use super::model::EndCondition;
use super::model::LinearModel;
use super::model::WEIGHT_RANGE;
use crate::curve::rational::RationalCubic;
use crate::geom::Point;

/// The separable formulation as an optimisation problem: the variables stand for the two
/// inner weights (w1, w2) in [`WEIGHT_RANGE`]; for each candidate the control points are
/// solved by least squares under the end conditions, at fixed parameters, and the
/// objective is the resulting Eq. 4 error. Evaluation is allocation-free: one pass over
/// the data and a solve of at most 4 × 4.
///
/// The optimizer does not see w1, w2 themselves but x = (w1 + w2, w1 − w2): scaling both
/// weights together (how strongly the curve is pulled towards its control polygon) and
/// skewing them (how the parameter speed shifts along the curve) are the natural
/// directions of this problem. In (w1, w2) the error has a long, narrow valley along
/// w1 ≈ w2 (on one sample segment it rises 25-fold 0.4 across the valley and changes by
/// 10 % over 1.0 along it), which coordinate-wise searches such as harmony search cross
/// but cannot follow; in these coordinates it lies along the first axis. On the bundled
/// samples harmony search at 5 000 evaluations misses the optimum by more than 0.1 % on
/// 16 of 106 segments in (w1, w2), 29 in (ln w1, ln w2), and on none in these coordinates
/// (apart from two straight runs whose optimum is ~1e-6 px²). Points of the
/// diamond-shaped box outside the weight range are clamped into it
/// ([`WeightsProblem::weights`]).
pub struct WeightsProblem<'a> {
    model: LinearModel<'a>,
}

impl<'a> WeightsProblem<'a> {
    /// The problem for a run of at least 3 `points` at fixed `params`.
    pub fn new(
        points: &'a [Point],
        params: &[f64],
        start: EndCondition,
        end: EndCondition,
    ) -> Self {
        WeightsProblem {
            model: LinearModel::new(points, params, start, end),
        }
    }

    /// The weights a point of the search space stands for, clamped into [`WEIGHT_RANGE`].
    pub fn weights(x: &[f64]) -> [f64; 2] {
        let (lo, hi) = WEIGHT_RANGE;
        [
            (0.5 * (x[0] + x[1])).clamp(lo, hi),
            (0.5 * (x[0] - x[1])).clamp(lo, hi),
        ]
    }

    /// The point of the search space standing for weights `w` (inverse of
    /// [`WeightsProblem::weights`] inside the range).
    pub fn point_of(w: [f64; 2]) -> [f64; 2] {
        [w[0] + w[1], w[0] - w[1]]
    }

    /// The curve (least-squares control points) for the point `x`, with its Eq. 4 error.
    pub fn curve(&self, x: &[f64]) -> (RationalCubic, f64) {
        let w = Self::weights(x);
        let (z, e) = self.model.solve(w);
        (self.model.curve(&z, w), e)
    }

    /// True when a weight of the point `x` sits on a bound of [`WEIGHT_RANGE`].
    pub fn on_weight_bound(x: &[f64]) -> bool {
        let (lo, hi) = WEIGHT_RANGE;
        Self::weights(x)
            .iter()
            .any(|&w| w <= lo * (1.0 + 1e-9) || w >= hi * (1.0 - 1e-9))
    }
}

impl crate::optim::Problem for WeightsProblem<'_> {
    fn dim(&self) -> usize {
        2
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        let (lo, hi) = WEIGHT_RANGE;
        if i == 0 {
            (2.0 * lo, 2.0 * hi)
        } else {
            (lo - hi, hi - lo)
        }
    }

    fn evaluate(&self, x: &[f64]) -> f64 {
        self.model.solve(Self::weights(x)).1
    }
}

/// Compass search in (ln w1, ln w2) for the weights minimising the Eq. 4 error with control
/// points solved by least squares. Deterministic. Returns (weights, error, evaluations).
pub(super) fn search_weights(
    model: &LinearModel<'_>,
    range: (f64, f64),
    start: [f64; 2],
    step0: f64,
    min_step: f64,
) -> ([f64; 2], f64, u64) {
    let (lo, hi) = (range.0.ln(), range.1.ln());
    let mut x = [start[0].ln().clamp(lo, hi), start[1].ln().clamp(lo, hi)];
    let to_w = |x: [f64; 2]| [x[0].exp(), x[1].exp()];
    let mut best = model.solve(to_w(x)).1;
    let mut evals = 1;
    let mut step = step0;
    // The neighbour that the last move came from, as (dimension, direction): its error is
    // known to be higher than the current one, so it is not evaluated again (a tenth of
    // the search's evaluations on a page of text).
    let mut came_from: Option<(usize, f64)> = None;
    while step >= min_step && evals < 400 {
        let mut moved = false;
        for dim in 0..2 {
            for dir in [1.0, -1.0] {
                if came_from == Some((dim, dir)) {
                    continue;
                }
                let mut y = x;
                y[dim] = (y[dim] + dir * step).clamp(lo, hi);
                if y[dim] == x[dim] {
                    continue;
                }
                let e = model.solve(to_w(y)).1;
                evals += 1;
                if e < best {
                    best = e;
                    x = y;
                    moved = true;
                    came_from = Some((dim, -dir));
                    break;
                }
            }
        }
        if !moved {
            step *= 0.5;
            came_from = None;
        }
    }
    (to_w(x), best, evals)
}

/// Every `stride`-th item of `items`, and the last one.
pub(super) fn strided<T: Copy>(items: &[T], stride: usize) -> Vec<T> {
    every(items, stride).collect()
}

/// The items of [`strided`], in order.
pub(crate) fn every<T: Copy>(items: &[T], stride: usize) -> impl Iterator<Item = T> + '_ {
    let last = items.len() - 1;
    items[..last]
        .iter()
        .step_by(stride)
        .chain(std::iter::once(&items[last]))
        .copied()
}

/// Starting weights from a 4 × 4 grid of typical weights (0.1, 0.4, 1, 2, clamped into
/// `range`): the grid's local minima (4-neighbourhood), best first, at most `count` of them.
/// Returns the starts and the evaluations spent.
pub(super) fn grid_starts(
    model: &LinearModel<'_>,
    range: (f64, f64),
    count: usize,
) -> (Vec<[f64; 2]>, u64) {
    const N: usize = 4;
    const GRID: [f64; N] = [0.1, 0.4, 1.0, 2.0];
    let at = |i: usize| GRID[i].clamp(range.0, range.1);
    let mut e = [[0.0; N]; N];
    for (i, row) in e.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = model.solve([at(i), at(j)]).1;
        }
    }
    let mut found = [(0.0, [0.0; 2]); N * N];
    let mut minima_found = 0;
    for i in 0..N {
        for j in 0..N {
            let v = e[i][j];
            let lower = |a: usize, b: usize| e[a][b] < v;
            let is_min = !((i > 0 && lower(i - 1, j))
                || (i + 1 < N && lower(i + 1, j))
                || (j > 0 && lower(i, j - 1))
                || (j + 1 < N && lower(i, j + 1)));
            if is_min {
                found[minima_found] = (v, [at(i), at(j)]);
                minima_found += 1;
            }
        }
    }
    let minima = &mut found[..minima_found];
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut starts: Vec<[f64; 2]> = minima.iter().take(count).map(|m| m.1).collect();
    if starts.len() < count && !starts.contains(&[1.0, 1.0]) {
        starts.push([1.0, 1.0]);
    }
    (starts, (N * N) as u64)
}

/// Pattern search in (ln w1, ln w2) along the axes and both diagonals, from weights `w`
/// with error `e`, down to steps of 1e-7: it follows the narrow valley along w1 ≈ w2 that
/// an axis-only search leaves early (see [`WeightsProblem`]). Used for the reference
/// optimum, where a precise value matters more than time.
pub(super) fn follow_valley(model: &LinearModel<'_>, w: [f64; 2], e: f64) -> ([f64; 2], f64) {
    const DIRS: [[f64; 2]; 8] = [
        [1.0, 0.0],
        [-1.0, 0.0],
        [0.0, 1.0],
        [0.0, -1.0],
        [1.0, 1.0],
        [-1.0, -1.0],
        [1.0, -1.0],
        [-1.0, 1.0],
    ];
    let (lo, hi) = (WEIGHT_RANGE.0.ln(), WEIGHT_RANGE.1.ln());
    let mut x = [w[0].ln(), w[1].ln()];
    let mut best = e;
    let mut step = 0.05;
    let mut evals = 0;
    while step >= 1e-7 && evals < 20_000 {
        let mut moved = false;
        for d in DIRS {
            let y = [
                (x[0] + d[0] * step).clamp(lo, hi),
                (x[1] + d[1] * step).clamp(lo, hi),
            ];
            if y == x {
                continue;
            }
            let v = model.solve([y[0].exp(), y[1].exp()]).1;
            evals += 1;
            if v < best {
                best = v;
                x = y;
                moved = true;
                break;
            }
        }
        if moved {
            step *= 1.5;
        } else {
            step *= 0.5;
        }
    }
    ([x[0].exp(), x[1].exp()], best)
}
