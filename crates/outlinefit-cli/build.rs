//! Link options of the command-line program.
//!
//! On Linux the `outlinefit` binary is linked as a position-dependent executable
//! (`-no-pie`): the linker then resolves the ~18 000 pointers in its read-only data
//! itself, instead of the dynamic loader rewriting them at every start. That saves about
//! 80 page faults and 0.2–0.5 ms per process, which matters when a script calls `trace`
//! once per glyph. The price is that the program's own code is loaded at a fixed address
//! (shared libraries and the stack are still randomised). Build with `OUTLINEFIT_PIE=1`
//! to keep a position-independent executable.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=OUTLINEFIT_PIE");
    let linux = std::env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "linux");
    let keep_pie = std::env::var_os("OUTLINEFIT_PIE").is_some_and(|v| !v.is_empty() && v != "0");
    if linux && !keep_pie {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
}
