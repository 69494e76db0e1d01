//! Link options of the command-line program: what a process pays before `main` matters
//! when a script calls `trace` once per glyph.
//!
//! On Linux the `outlinefit` binary is linked as a position-dependent executable
//! (`-no-pie`): the linker then resolves the ~18 000 pointers in its read-only data
//! itself, instead of the dynamic loader rewriting them at every start. That saves about
//! 80 page faults and 0.2–0.5 ms per process. The price is that the program's own code
//! is loaded at a fixed address (shared libraries and the stack are still randomised).
//! Build with `OUTLINEFIT_PIE=1` to keep a position-independent executable.
//!
//! With the GNU C library, Rust's standard library also asks for the shared unwinder
//! `libgcc_s.so.1`, which every start then loads, relocates and initialises (its
//! constructor reads the processor's features, slow in a virtual machine): about 0.3 ms
//! of a 64 px glyph's 3.4 ms here. Where the C compiler has GCC's static unwinder
//! (`libgcc_eh.a`, part of every GCC installation), a linker script named `libgcc_s.so`
//! in the build's output folder, found before the system's, links that instead: the
//! same unwinder inside the program. Build with `OUTLINEFIT_SHARED_LIBGCC=1` to link the
//! shared one.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=OUTLINEFIT_PIE");
    println!("cargo:rerun-if-env-changed=OUTLINEFIT_SHARED_LIBGCC");
    let linux = std::env::var("CARGO_CFG_TARGET_OS").is_ok_and(|os| os == "linux");
    let gnu = std::env::var("CARGO_CFG_TARGET_ENV").is_ok_and(|env| env == "gnu");
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty() && v != "0");
    if linux && !set("OUTLINEFIT_PIE") {
        println!("cargo:rustc-link-arg-bins=-no-pie");
    }
    if linux && gnu && !set("OUTLINEFIT_SHARED_LIBGCC") && has_static_unwinder() {
        let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
        std::fs::write(out.join("libgcc_s.so"), "INPUT(-lgcc_eh -lgcc)\n")
            .expect("writing to OUT_DIR");
        println!("cargo:rustc-link-search=native={}", out.display());
    }
}

/// True when the C compiler that links the program finds `libgcc_eh.a` (it prints the
/// bare name back when it does not).
fn has_static_unwinder() -> bool {
    let cc = std::env::var("RUSTC_LINKER").unwrap_or_else(|_| "cc".into());
    Command::new(cc)
        .arg("-print-file-name=libgcc_eh.a")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .is_some_and(|path| Path::new(path.trim()).is_absolute() && Path::new(path.trim()).exists())
}
