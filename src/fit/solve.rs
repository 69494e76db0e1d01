//! Linear solves (placeholder).
