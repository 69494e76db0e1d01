//! Parameterisation of data points along a segment.
//!
//! The centripetal method of Eq. 2–3 of the HS paper gives each data point a parameter
//! proportional to the running sum of square roots of the chord lengths; chordal and
//! uniform parameters are provided for comparison.

use crate::geom::Point;
use serde::{Deserialize, Serialize};

/// A rule that assigns parameters in [0, 1] to an ordered run of points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Parameterization {
    /// Equal steps.
    Uniform,
    /// Proportional to accumulated chord length.
    Chordal,
    /// Proportional to accumulated square roots of chord lengths (Eq. 2–3).
    #[default]
    Centripetal,
}

/// Writes parameters for `points` into `out` (resized to `points.len()`): 0 for the first
/// point, 1 for the last, non-decreasing in between. Coincident points share a parameter.
/// With fewer than two distinct points every parameter is spread uniformly.
pub(crate) fn parameters_into(points: &[Point], rule: Parameterization, out: &mut Vec<f64>) {
    let n = points.len();
    out.clear();
    if n == 0 {
        return;
    }
    out.push(0.0);
    let mut acc = 0.0;
    for w in points.windows(2) {
        let d = w[0].distance(w[1]);
        acc += match rule {
            Parameterization::Uniform => 1.0,
            Parameterization::Chordal => d,
            Parameterization::Centripetal => d.sqrt(),
        };
        out.push(acc);
    }
    if acc > 0.0 {
        for v in out.iter_mut() {
            *v /= acc;
        }
        if let Some(last) = out.last_mut() {
            *last = 1.0;
        }
    } else if n > 1 {
        for (i, v) in out.iter_mut().enumerate() {
            *v = i as f64 / (n - 1) as f64;
        }
    }
}

/// Centripetal parameters (Eq. 2–3) of `points`.
pub fn centripetal_parameters(points: &[Point]) -> Vec<f64> {
    let mut out = Vec::with_capacity(points.len());
    parameters_into(points, Parameterization::Centripetal, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centripetal_uses_square_roots_of_chords() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 1.0),
        ];
        let u = centripetal_parameters(&pts);
        // sqrt(4) = 2, sqrt(1) = 1 → 0, 2/3, 1.
        assert_eq!(u[0], 0.0);
        assert!((u[1] - 2.0 / 3.0).abs() < 1e-15);
        assert_eq!(u[2], 1.0);
        let mut c = Vec::new();
        parameters_into(&pts, Parameterization::Chordal, &mut c);
        assert!((c[1] - 0.8).abs() < 1e-15);
    }

    #[test]
    fn coincident_points_do_not_divide_by_zero() {
        let pts = [Point::new(1.0, 1.0); 3];
        let u = centripetal_parameters(&pts);
        assert_eq!(u, vec![0.0, 0.5, 1.0]);
    }
}
