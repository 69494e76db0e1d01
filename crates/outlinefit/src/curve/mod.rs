//! The curve kernel. Rational cubic Bézier segments are the fitting primitive; polynomial
//! cubics are what SVG can draw; (disk) Wang–Ball curves are what merging produces. Every
//! curve answers the [`ParamCurve`] trait; [`basis`] holds the Bernstein machinery they
//! share.

pub(crate) mod approx;
pub mod basis;
pub(crate) mod cubic;
pub(crate) mod param_curve;
pub(crate) mod power;
pub(crate) mod rational;
pub mod wang_ball;

pub use approx::approximate_with_cubics;
pub use cubic::CubicBez;
pub use param_curve::{bezier_derivative, check_param_curve, ParamCurve};
pub(crate) use rational::bernstein;
pub use rational::RationalCubic;
