//! Curve types. Rational cubic Bézier segments are the fitting primitive; polynomial
//! cubics are what SVG can draw.

pub mod approx;
pub mod basis;
pub mod cubic;
pub mod param_curve;
pub mod power;
pub mod rational;
pub mod wang_ball;

pub use approx::approximate_with_cubics;
pub use cubic::CubicBez;
pub use param_curve::{bezier_derivative, check_param_curve, ParamCurve};
pub use rational::{bernstein, rational_basis, RationalCubic};
