//! Gauss–Legendre quadrature of any order, fixed and adaptive.
//!
//! Hand-written (Newton iteration on the Legendre recurrence, 20 lines) because the merging
//! and degree-reduction errors need rules of a chosen order, exact for polynomials of known
//! degree, and the rule is cheap to compute once per problem.

/// Gauss–Legendre nodes and weights of `order` points on `[0, 1]`. The rule integrates
/// polynomials of degree up to `2·order − 1` exactly (to rounding). `order == 0` gives an
/// empty rule.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    /// Nodes in `(0, 1)`, ascending.
    pub nodes: Vec<f64>,
    /// Positive weights summing to 1.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The rule with `order` nodes on `[0, 1]`.
    pub fn new(order: usize) -> Self {
        let (x, w) = legendre_rule(order);
        // Map [-1, 1] to [0, 1]; nodes come out descending, so reverse them.
        let nodes = x.iter().rev().map(|&z| 0.5 * (z + 1.0)).collect();
        let weights = w.iter().rev().map(|&v| 0.5 * v).collect();
        GaussLegendre { nodes, weights }
    }

    /// The smallest rule exact for polynomials of degree `degree`.
    pub fn exact_for_degree(degree: usize) -> Self {
        Self::new(degree / 2 + 1)
    }

    /// `∫_a^b f` by this rule.
    pub fn integrate(&self, f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
        let h = b - a;
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(&x, &w)| w * f(a + h * x))
            .sum::<f64>()
            * h
    }
}

/// Nodes (descending) and weights of the `n`-point rule on `[-1, 1]`.
fn legendre_rule(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

/// `∫_a^b f` to about 1e-14 relative to `max(|∫f|, scale)`, by recursive bisection of a
/// 16-point rule.
pub(crate) fn adaptive(f: &dyn Fn(f64) -> f64, a: f64, b: f64, scale: f64) -> f64 {
    let rule = GaussLegendre::new(16);
    let whole = rule.integrate(f, a, b);
    let tol = 1e-14 * whole.abs().max(scale).max(f64::MIN_POSITIVE);
    adapt(f, &rule, a, b, whole, tol, 0)
}

fn adapt(
    f: &dyn Fn(f64) -> f64,
    rule: &GaussLegendre,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let l = rule.integrate(f, a, m);
    let r = rule.integrate(f, m, b);
    if (l + r - whole).abs() <= tol || depth >= 20 {
        l + r
    } else {
        adapt(f, rule, a, m, l, 0.5 * tol, depth + 1)
            + adapt(f, rule, m, b, r, 0.5 * tol, depth + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_are_exact_for_their_degree() {
        for order in 1..=24 {
            let rule = GaussLegendre::new(order);
            assert!((rule.weights.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(rule.nodes.windows(2).all(|p| p[0] < p[1]));
            for k in 0..2 * order {
                // ∫_0^1 t^k = 1/(k+1)
                let got = rule.integrate(|t| t.powi(k as i32), 0.0, 1.0);
                let want = 1.0 / (k as f64 + 1.0);
                assert!(
                    (got - want).abs() < 1e-14,
                    "order {order}, t^{k}: {got} vs {want}"
                );
            }
            // and not for degree 2·order (the rule is the smallest one); the error shrinks
            // like 4^-order, so check where it is clearly above rounding.
            if order <= 10 {
                let k = 2 * order as i32;
                let got = rule.integrate(|t| (2.0 * t - 1.0).powi(k), 0.0, 1.0);
                assert!((got - 1.0 / (k as f64 + 1.0)).abs() > 1e-9, "order {order}");
            }
        }
    }

    #[test]
    fn exact_for_degree_picks_the_smallest_rule() {
        assert_eq!(GaussLegendre::exact_for_degree(0).nodes.len(), 1);
        assert_eq!(GaussLegendre::exact_for_degree(1).nodes.len(), 1);
        assert_eq!(GaussLegendre::exact_for_degree(2).nodes.len(), 2);
        assert_eq!(GaussLegendre::exact_for_degree(12).nodes.len(), 7);
        assert_eq!(GaussLegendre::exact_for_degree(13).nodes.len(), 7);
    }

    #[test]
    fn adaptive_integrates_a_kink() {
        let got = adaptive(&|t: f64| (t - 0.3).abs(), 0.0, 1.0, 1.0);
        assert!((got - (0.045 + 0.245)).abs() < 1e-12, "{got}");
    }
}
