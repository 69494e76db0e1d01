//! Golden outputs: every bundled sample traced with the default options, its SVG, JSON
//! report and CSV report compared byte for byte with the files stored in `tests/golden/`.
//! Any change to any number the tracer writes shows up here, intended or not.
//!
//! After an intended change, regenerate the stored files and review their diff:
//!
//! ```sh
//! OUTLINEFIT_BLESS=1 cargo test --release --test golden
//! git diff --stat crates/outlinefit-cli/tests/golden
//! ```

mod common;

use std::path::{Path, PathBuf};

/// Where the stored outputs live.
fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("golden")
}

/// The first line where two texts differ, for the failure message.
fn first_difference(want: &str, got: &str) -> String {
    let (mut w, mut g) = (want.lines(), got.lines());
    for line in 1.. {
        match (w.next(), g.next()) {
            (None, None) => break,
            (a, b) if a == b => continue,
            (a, b) => {
                let cut = |s: Option<&str>| {
                    s.map_or("(none)".to_string(), |s| s.chars().take(300).collect())
                };
                return format!("line {line}:\n  stored: {}\n  now:    {}", cut(a), cut(b));
            }
        }
    }
    "the texts differ only in their final newline".to_string()
}

#[test]
fn samples_match_their_stored_outputs() {
    let bless = std::env::var_os("OUTLINEFIT_BLESS").is_some_and(|v| v != "0");
    // The repository root, two levels above this crate.
    let root = &Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = common::scratch("golden");
    let stored = golden_dir();
    if bless {
        std::fs::create_dir_all(&stored).unwrap();
    }
    let samples = common::sample_paths();
    assert!(samples.len() >= 7, "bundled samples missing");
    let mut mismatches = Vec::new();
    for sample in &samples {
        let stem = sample.file_stem().unwrap().to_string_lossy().to_string();
        // A path relative to the repository, so that the report names it the same everywhere.
        let input = sample.strip_prefix(root).unwrap();
        let files = ["svg", "json", "csv"].map(|ext| (ext, out.join(format!("{stem}.{ext}"))));
        let status = common::bin()
            .current_dir(root)
            .arg("trace")
            .arg(input)
            .arg("-o")
            .arg(&files[0].1)
            .arg("--report")
            .arg(&files[1].1)
            .arg("--csv")
            .arg(&files[2].1)
            .arg("--no-timings")
            .status()
            .unwrap();
        assert!(status.success(), "{stem}: trace failed");
        for (ext, path) in &files {
            let got = std::fs::read_to_string(path).unwrap();
            let golden = stored.join(format!("{stem}.{ext}"));
            if bless {
                std::fs::write(&golden, &got).unwrap();
                continue;
            }
            let want = std::fs::read_to_string(&golden).unwrap_or_else(|e| {
                panic!(
                    "{}: {e}; create it with OUTLINEFIT_BLESS=1 cargo test --release --test golden",
                    golden.display()
                )
            });
            if want != got {
                mismatches.push(format!(
                    "{stem}.{ext} differs from {} at {}",
                    golden.display(),
                    first_difference(&want, &got)
                ));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        mismatches.is_empty(),
        "{}\n\nIf the change is intended: OUTLINEFIT_BLESS=1 cargo test --release --test golden, \
         then review `git diff crates/outlinefit-cli/tests/golden`.",
        mismatches.join("\n")
    );
}
