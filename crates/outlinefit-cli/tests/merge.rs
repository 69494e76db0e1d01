//! `outlinefit merge` as a user meets it: the paper's Example 1 and 3 inputs, the JSON it
//! prints, the picture, and clean failures.

mod common;

use common::{bin, scratch};

use std::process::Output;

const EXAMPLE1: &str = r#"{"curves": [
  {"centers": [[0.3, 0.3], [0.8, 1.6], [1.6, 1.8], [2.5, 1.7]], "radii": [0.13, 0.15, 0.19, 0.17]},
  {"centers": [[2.5, 1.7], [3.4, 1.8], [3.8, 1.3], [3.4, 0.7], [2.2, 0.3]],
   "radii": [0.17, 0.12, 0.13, 0.1, 0.16]}]}"#;

const EXAMPLE3: &str = r#"{"curves": [
  {"centers": [[2, 7.2], [-1, 1], [2.5, 0.1], [5, 1.5]], "radii": [0.1, 0.3, 0.4, 0.2]},
  {"centers": [[5, 1.5], [7.5, 3], [7.3, 7.8], [3, 7], [2.5, 2.5]],
   "radii": [0.2, 0.4, 0.3, 0.2, 0.2]}]}"#;

fn merge(input: &str, args: &[&str]) -> (serde_json::Value, Output) {
    // One folder per call: tests run in parallel and may pass the same arguments.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = scratch(&format!("call{call}"));
    let path = dir.join("in.json");
    std::fs::write(&path, input).unwrap();
    let out = bin().arg("merge").arg(&path).args(args).output().unwrap();
    let value = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (value, out)
}

#[test]
fn exact_merges_reach_at_most_the_papers_best_errors() {
    // (input, degree, preserve, paper's best reported error (BEESO), our exact optimum)
    for (input, degree, preserve, paper, exact) in [
        (EXAMPLE1, "6", false, 7.256e-4, 4.4969e-4),
        (EXAMPLE1, "6", true, 5.777e-4, 5.4570e-4),
        (EXAMPLE3, "4", false, 8.957e-2, 8.9562e-2),
        (EXAMPLE3, "4", true, 1.467e-1, 1.46699e-1),
    ] {
        let mut args = vec!["--degree", degree];
        if preserve {
            args.push("--preserve-endpoints");
        }
        let (v, out) = merge(input, &args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let e = v["error"].as_f64().unwrap();
        assert!(e <= paper * (1.0 + 1e-4), "{e} > paper {paper}");
        assert!((e - exact).abs() < 1e-4 * exact, "{e} vs {exact}");
        let parts = v["center_error"].as_f64().unwrap() + v["radius_error"].as_f64().unwrap();
        assert!((parts - e).abs() <= 1e-15 * e.max(1.0));
        assert_eq!(v["method"], "exact");
        assert_eq!(
            v["degree"].as_u64().unwrap(),
            degree.parse::<u64>().unwrap()
        );
        let lambda = v["lambda"].as_f64().unwrap();
        assert!(lambda > 0.5 && lambda < 0.6, "{lambda}");
        let disks = v["disks"].as_array().unwrap();
        assert_eq!(disks.len(), degree.parse::<usize>().unwrap() + 1);
        assert!(disks
            .iter()
            .all(|d| d["r"].as_f64().unwrap() >= 0.001 - 1e-15));
    }
}

#[test]
fn metaheuristic_merge_is_seeded_and_draws_a_picture() {
    let dir = scratch("picture");
    let svg = dir.join("m.svg");
    let args = [
        "--degree", "6", "--method", "beeso", "--budget", "2000", "--seed", "4",
    ];
    let (a, out) = merge(
        EXAMPLE1,
        &[&args[..], &["--svg", svg.to_str().unwrap()]].concat(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (b, _) = merge(EXAMPLE1, &args);
    assert_eq!(a, b, "same seed, same answer");
    assert_eq!(a["method"], "beeso");
    assert_eq!(a["evaluations"], 2000);
    assert!(a["error"].as_f64().unwrap() >= 4.4969e-4 * (1.0 - 1e-4));
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let groups = doc.descendants().filter(|n| n.has_tag_name("g")).count();
    assert_eq!(groups, 3, "merged curve and both inputs");
}

#[test]
fn bad_inputs_fail_cleanly() {
    let not_adjacent = EXAMPLE1.replace("[[2.5, 1.7], [3.4", "[[2.6, 1.7], [3.4");
    for (input, args, expect) in [
        (EXAMPLE1, vec!["--degree", "3"], "--degree"),
        (EXAMPLE1, vec!["--degree", "21"], "--degree"),
        (
            EXAMPLE1,
            vec!["--degree", "6", "--min-radius=-1"],
            "--min-radius",
        ),
        (
            EXAMPLE1,
            vec!["--degree", "6", "--method", "beeso", "--budget", "0"],
            "--budget",
        ),
        ("{\"curves\": [", vec!["--degree", "6"], "not a merge input"),
        (not_adjacent.as_str(), vec!["--degree", "6"], "not adjacent"),
    ] {
        let (_, out) = merge(input, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.starts_with("error: ") && err.contains(expect),
            "{args:?}: {err}"
        );
    }
    let out = bin()
        .args(["merge", "/nonexistent/in.json", "--degree", "6"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
}
