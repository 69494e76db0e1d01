//! Parameterisation (placeholder).
