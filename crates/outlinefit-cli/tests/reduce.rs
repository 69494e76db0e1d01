//! `outlinefit reduce` as a user meets it: the documented JSON on stdout with the right
//! error, one `error:` line and exit status 1 (and nothing on stdout) for bad input, a
//! parseable SVG picture, the same output for the same seed.

mod common;

use common::{bin, scratch};

use std::path::{Path, PathBuf};
use std::process::Output;

/// The paper's Example 1 (degree 6, plain Bézier) as a curve file.
const EXAMPLE1: &str = r#"{"control_points": [[0.1, 0], [0, 0.1], [0.05, 0.2], [0.3, 0.3],
    [0.55, 0.2], [0.6, 0.1], [0.5, 0]], "omega": 0, "lambda": [3, 3, 3], "mu": [3, 3, 3]}"#;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn run(args: &[&str]) -> Output {
    bin().arg("reduce").args(args).output().unwrap()
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn assert_clean_failure(out: &Output, expect: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line expected: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(expect), "expected {expect:?} in: {stderr}");
    assert!(
        out.stdout.is_empty(),
        "stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn prints_the_documented_fields() {
    let dir = scratch("fields");
    let input = write(&dir, "ex1.json", EXAMPLE1);
    let input = input.to_str().unwrap();
    // C1 at ω = 0.2, λ = μ = 3: the paper's Table 2 gives 9.1890e-3.
    let v = json(&run(&[
        input,
        "--degree",
        "4",
        "--constraint",
        "c1",
        "--omega",
        "0.2",
        "--lambda",
        "3,3",
        "--mu",
        "3,3",
    ]));
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    let mut want = vec![
        "error",
        "degree",
        "constraint",
        "method",
        "omega",
        "lambda",
        "mu",
        "control_points",
        "evaluations",
    ];
    let mut got = keys.clone();
    got.sort();
    want.sort();
    assert_eq!(got, want);
    assert!((v["error"].as_f64().unwrap() / 9.1890e-3 - 1.0).abs() < 1e-4);
    assert_eq!(v["degree"], 4);
    assert_eq!(v["constraint"], "c1");
    assert_eq!(v["method"], "exact");
    assert_eq!(v["omega"], 0.2);
    assert_eq!(v["lambda"], serde_json::json!([3.0, 3.0]));
    assert_eq!(v["evaluations"], 1);
    let q = v["control_points"].as_array().unwrap();
    assert_eq!(q.len(), 5);
    assert_eq!(q[0], serde_json::json!([0.1, 0.0]));
    assert_eq!(q[4], serde_json::json!([0.5, 0.0]));

    // Default method: plain Bézier, ω = 0, unconstrained optimum 1.83050e-3.
    let v = json(&run(&[input, "--degree", "4"]));
    assert!((v["error"].as_f64().unwrap() / 1.83050e-3 - 1.0).abs() < 1e-5);
    assert_eq!(v["omega"], 0.0);
    assert_eq!(v["constraint"], "none");

    // GWO with a small budget: never worse than exact, deterministic for a seed.
    let args = [
        input, "--degree", "4", "--method", "gwo", "--budget", "400", "--seed", "7",
    ];
    let a = run(&args);
    let v = json(&a);
    assert_eq!(v["method"], "gwo");
    assert_eq!(v["evaluations"], 400);
    assert!(v["error"].as_f64().unwrap() <= 1.83050e-3);
    assert_eq!(run(&args).stdout, a.stdout);
}

#[test]
fn bad_input_fails_cleanly() {
    let dir = scratch("bad");
    let good = write(&dir, "ex1.json", EXAMPLE1);
    let good = good.to_str().unwrap();
    let missing = dir.join("missing.json");
    assert_clean_failure(
        &run(&[missing.to_str().unwrap(), "--degree", "3"]),
        "cannot read",
    );
    let broken = write(&dir, "broken.json", "{\"control_points\": [[0, 0], ");
    assert_clean_failure(
        &run(&[broken.to_str().unwrap(), "--degree", "3"]),
        "not a valid curve file",
    );
    let typo = write(
        &dir,
        "typo.json",
        r#"{"control_points": [[0,0],[1,1],[2,0]], "lamda": [1]}"#,
    );
    assert_clean_failure(
        &run(&[typo.to_str().unwrap(), "--degree", "1"]),
        "unknown field",
    );
    let lengths = write(
        &dir,
        "lengths.json",
        r#"{"control_points": [[0,0],[1,1],[2,0]], "omega": 0.5, "lambda": [1, 2]}"#,
    );
    assert_clean_failure(&run(&[lengths.to_str().unwrap(), "--degree", "1"]), "λ");
    for degree in ["0", "6", "7"] {
        assert_clean_failure(&run(&[good, "--degree", degree]), "--degree");
    }
    assert_clean_failure(
        &run(&[good, "--degree", "2", "--constraint", "c1"]),
        "C1 needs at least 3",
    );
    assert_clean_failure(
        &run(&[good, "--degree", "4", "--method", "gwo", "--omega", "0.5"]),
        "exact only",
    );
    assert_clean_failure(&run(&[good, "--degree", "4", "--lambda", "1,2,3"]), "λ");
    // A picture into a missing folder: nothing is computed or printed.
    let nowhere = dir.join("no-such-folder").join("p.svg");
    assert_clean_failure(
        &run(&[good, "--degree", "4", "--svg", nowhere.to_str().unwrap()]),
        "does not exist",
    );
}

#[test]
fn svg_picture_parses() {
    let dir = scratch("svg");
    let input = write(&dir, "ex1.json", EXAMPLE1);
    let picture = dir.join("reduced.svg");
    let out = run(&[
        input.to_str().unwrap(),
        "--degree",
        "4",
        "--constraint",
        "c0",
        "--svg",
        picture.to_str().unwrap(),
    ]);
    json(&out);
    let text = std::fs::read_to_string(&picture).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let view: Vec<f64> = root
        .attribute("viewBox")
        .unwrap()
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(view.len(), 4);
    assert!(view[2] > 0.5 && view[3] > 0.3, "{view:?}");
    let polylines: Vec<_> = root
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .collect();
    assert_eq!(polylines.len(), 4);
    // Every drawn point lies inside the view box.
    for p in &polylines {
        for pair in p.attribute("points").unwrap().split_whitespace() {
            let (x, y) = pair.split_once(',').unwrap();
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!(x >= view[0] && x <= view[0] + view[2]);
            assert!(y >= view[1] && y <= view[1] + view[3]);
        }
    }
    // Only the picture was written (no temporary files left).
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}
