//! Helpers of the program's end-to-end tests: the `outlinefit` binary, and the library
//! tests' rendering and sample helpers (their file, included here).

// Each test binary uses only some of these helpers, and `pub` items of a
// private module are unreachable by construction.
#![allow(dead_code, unreachable_pub)]

#[path = "../../../outlinefit/tests/common/mod.rs"]
mod library;

pub use library::*;

use std::process::Command;

/// The `outlinefit` binary built for these tests.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_outlinefit"))
}
