//! File output helpers (placeholder: being written by a helper).
