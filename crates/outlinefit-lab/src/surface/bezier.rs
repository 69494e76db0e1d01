//! Tensor-product Bézier surfaces of degree (η, σ) in 3-D: evaluation, partial derivatives
//! and the mesh of a surface (the Bernstein basis is [`outlinefit::curve::basis`]).

use outlinefit::curve::basis::{bernstein, bernstein_jet};
use serde::Serialize;

/// A point or vector in 3-D.
pub type P3 = [f64; 3];

/// `a + s·b`, coordinate-wise, into `a`.
#[inline]
pub(crate) fn axpy(a: &mut P3, s: f64, b: &P3) {
    a[0] += s * b[0];
    a[1] += s * b[1];
    a[2] += s * b[2];
}

/// Dot product.
#[inline]
pub(crate) fn dot(a: &P3, b: &P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a − b`.
#[inline]
pub(crate) fn sub(a: &P3, b: &P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// A polynomial tensor-product Bézier surface (Eq. 2): poles Λ_{i,j}, i = 0..=η along u
/// (τ), j = 0..=σ along v (ζ), stored row by row (`poles[i * (σ + 1) + j]`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BezierSurface {
    /// Degree η in u.
    pub degree_u: usize,
    /// Degree σ in v.
    pub degree_v: usize,
    /// The (η + 1)(σ + 1) poles, row i = 0..=η, column j = 0..=σ.
    pub poles: Vec<P3>,
}

/// A surface point with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, Default)]
pub struct Jet {
    /// S(u, v).
    pub s: P3,
    /// ∂S/∂u.
    pub su: P3,
    /// ∂S/∂v.
    pub sv: P3,
    /// ∂²S/∂u².
    pub suu: P3,
    /// ∂²S/∂u∂v.
    pub suv: P3,
    /// ∂²S/∂v².
    pub svv: P3,
}

impl BezierSurface {
    /// The pole Λ_{i,j}.
    pub fn pole(&self, i: usize, j: usize) -> P3 {
        self.poles[i * (self.degree_v + 1) + j]
    }

    /// S(u, v).
    pub fn eval(&self, u: f64, v: f64) -> P3 {
        let (ku, kv) = (self.degree_u + 1, self.degree_v + 1);
        let mut bu = [0.0; 32];
        let mut bv = [0.0; 32];
        bernstein(self.degree_u, u, &mut bu);
        bernstein(self.degree_v, v, &mut bv);
        let mut s = [0.0; 3];
        for i in 0..ku {
            let mut row = [0.0; 3];
            for j in 0..kv {
                axpy(&mut row, bv[j], &self.poles[i * kv + j]);
            }
            axpy(&mut s, bu[i], &row);
        }
        s
    }

    /// S(u, v) with its first and second partial derivatives.
    pub fn jet(&self, u: f64, v: f64) -> Jet {
        let (ku, kv) = (self.degree_u + 1, self.degree_v + 1);
        let (mut bu, mut du, mut ddu) = ([0.0; 32], [0.0; 32], [0.0; 32]);
        let (mut bv, mut dv, mut ddv) = ([0.0; 32], [0.0; 32], [0.0; 32]);
        bernstein_jet(self.degree_u, u, &mut bu, &mut du, &mut ddu);
        bernstein_jet(self.degree_v, v, &mut bv, &mut dv, &mut ddv);
        let mut jet = Jet::default();
        for i in 0..ku {
            // The row curve's value, v-derivative and second v-derivative at v.
            let (mut r, mut rv, mut rvv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            for j in 0..kv {
                let p = &self.poles[i * kv + j];
                axpy(&mut r, bv[j], p);
                axpy(&mut rv, dv[j], p);
                axpy(&mut rvv, ddv[j], p);
            }
            axpy(&mut jet.s, bu[i], &r);
            axpy(&mut jet.su, du[i], &r);
            axpy(&mut jet.suu, ddu[i], &r);
            axpy(&mut jet.sv, bu[i], &rv);
            axpy(&mut jet.suv, du[i], &rv);
            axpy(&mut jet.svv, bu[i], &rvv);
        }
        jet
    }

    /// The surface sampled on a `res` × `res` grid of parameters (`res` ≥ 2), row by row
    /// in u: `points[a * res + b] = S(a / (res − 1), b / (res − 1))`.
    pub fn mesh(&self, res: usize) -> Vec<P3> {
        let res = res.max(2);
        let step = 1.0 / (res - 1) as f64;
        let mut points = Vec::with_capacity(res * res);
        for a in 0..res {
            for b in 0..res {
                points.push(self.eval(a as f64 * step, b as f64 * step));
            }
        }
        points
    }
}

/// The highest degree a surface may have in either parameter (the stack buffers of
/// [`BezierSurface::jet`] hold 32 basis values).
pub const MAX_DEGREE: usize = 30;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jet_derivatives_match_differences() {
        let poles: Vec<P3> = (0..4 * 3)
            .map(|k| {
                let k = k as f64;
                [k.sin(), (1.3 * k).cos(), 0.1 * k * k]
            })
            .collect();
        let s = BezierSurface {
            degree_u: 3,
            degree_v: 2,
            poles,
        };
        let (u, v, h) = (0.31, 0.64, 1e-5);
        let j = s.jet(u, v);
        let e = s.eval(u, v);
        for c in 0..3 {
            assert!((j.s[c] - e[c]).abs() < 1e-14);
            let su = (s.eval(u + h, v)[c] - s.eval(u - h, v)[c]) / (2.0 * h);
            let sv = (s.eval(u, v + h)[c] - s.eval(u, v - h)[c]) / (2.0 * h);
            let suv = (s.eval(u + h, v + h)[c] - s.eval(u + h, v - h)[c] - s.eval(u - h, v + h)[c]
                + s.eval(u - h, v - h)[c])
                / (4.0 * h * h);
            assert!((j.su[c] - su).abs() < 1e-8);
            assert!((j.sv[c] - sv).abs() < 1e-8);
            assert!((j.suv[c] - suv).abs() < 1e-4);
        }
    }
}
