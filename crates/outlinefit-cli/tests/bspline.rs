//! `outlinefit bspline` as a user meets it: the documented JSON on stdout, the paper's
//! Example 1 below its reported error, clean one-line failures, a parseable SVG picture.

mod common;

use common::scratch;

use std::process::{Command, Output};

const EX1_X: &str = "-26*u^4+64*u^3-52*u^2+16*u-1";
const EX1_Y: &str = "-112/3*u^4+224/3*u^3-48*u^2+32/3*u";

fn bspline(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_outlinefit"))
        .arg("bspline")
        .args(args)
        .output()
        .unwrap()
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn assert_clean_failure(args: &[&str], expect: &str) {
    let out = bspline(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line expected: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(expect), "expected {expect:?} in: {stderr}");
    assert!(out.stdout.is_empty(), "stdout: {:?}", out.stdout);
}

#[test]
fn example_1_prints_the_documented_fields_and_beats_the_papers_error() {
    let out = bspline(&[
        "--x",
        EX1_X,
        "--y",
        EX1_Y,
        "--range",
        "0,1",
        "--samples",
        "20",
        "--control-points",
        "6",
    ]);
    let v = json(&out);
    for field in [
        "rmse",
        "rmse_dense",
        "max_error_dense",
        "knots",
        "control_points",
        "samples",
        "feature_points",
    ] {
        assert!(v.get(field).is_some(), "missing {field}: {v}");
    }
    // Defaults: fwa, 3000 evaluations, control points fitted to the curve; the floor of
    // the spline space is 0.0069492 (unit test in src/bspline/mod.rs).
    assert_eq!(v["fit"], "curve");
    let dense = v["rmse_dense"].as_f64().unwrap();
    assert!(
        (0.006949..0.00696).contains(&dense),
        "rmse_dense {dense} (paper: 0.007 on its samples)"
    );
    assert!(v["rmse"].as_f64().unwrap() < 0.0095);
    assert!(v["max_error_dense"].as_f64().unwrap() >= dense);
    assert_eq!(v["samples"].as_array().unwrap().len(), 20);
    assert_eq!(v["control_points"].as_array().unwrap().len(), 6);
    assert_eq!(v["control_points"][0].as_array().unwrap().len(), 2);
    assert_eq!(v["knots"].as_array().unwrap().len(), 10);
    let features = v["feature_points"].as_array().unwrap();
    assert!(!features.is_empty());
    for f in features {
        assert!(f["u"].is_f64() && f["kind"].is_string() && f["curvature"].is_f64());
    }
}

#[test]
fn fit_samples_is_the_papers_least_squares_and_stays_above_the_floor() {
    let out = bspline(&[
        "--x", EX1_X, "--y", EX1_Y, "--range", "0,1", "--fit", "samples",
    ]);
    let v = json(&out);
    assert_eq!(v["fit"], "samples");
    let dense = v["rmse_dense"].as_f64().unwrap();
    assert!((0.00696..0.0085).contains(&dense), "rmse_dense {dense}");
    assert!(v["rmse"].as_f64().unwrap() < 0.0085);
    assert_eq!(v["evaluations"], 3000);
    let bad = bspline(&["--x", "u", "--y", "u", "--range", "0,1", "--fit", "nope"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(bad.stdout.is_empty());
}

#[test]
fn same_seed_gives_identical_json() {
    let args = [
        "--x",
        "u^2 - 1",
        "--y",
        "u^3 - u",
        "--range",
        "0,1",
        "--control-points",
        "5",
        "--budget",
        "300",
        "--seed",
        "7",
    ];
    let one = bspline(&args);
    let two = bspline(&args);
    assert!(one.status.success());
    assert_eq!(one.stdout, two.stdout);
    let v = json(&one);
    assert!(v["max_error_dense"].as_f64().unwrap() < 1e-9, "{v}");
}

#[test]
fn bad_expressions_ranges_and_options_fail_cleanly() {
    let base = |x: &'static str, range: &'static str| vec!["--x", x, "--y", "u", "--range", range];
    assert_clean_failure(&base("u + v", "0,1"), "unknown variable 'v'");
    assert_clean_failure(&base("foo(u)", "0,1"), "unknown function 'foo'");
    assert_clean_failure(&base("2*(u", "0,1"), "missing ')'");
    assert_clean_failure(&base("u", "1,0"), "--range");
    assert_clean_failure(&base("u", "0;1"), "--range");
    assert_clean_failure(&base("u", "0,inf"), "--range");
    assert_clean_failure(&base("1/u", "0,1"), "not defined");
    let mut a = base("u", "0,1");
    a.extend(["--samples", "4"]);
    assert_clean_failure(&a, "--samples");
    let mut a = base("u", "0,1");
    a.extend(["--method", "nope"]);
    assert_clean_failure(&a, "--method");
    let mut a = base("u", "0,1");
    a.extend(["--order", "1"]);
    assert_clean_failure(&a, "--order");
}

#[test]
fn svg_picture_is_written_and_parses() {
    let dir = scratch("svg");
    let path = dir.join("ex1.svg");
    let out = bspline(&[
        "--x",
        EX1_X,
        "--y",
        EX1_Y,
        "--range",
        "0,1",
        "--budget",
        "300",
        "--svg",
        path.to_str().unwrap(),
    ]);
    let v = json(&out);
    let text = std::fs::read_to_string(&path).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert!(root.attribute("viewBox").is_some());
    let ids: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .collect();
    for id in ["curve", "spline", "control-polygon"] {
        assert!(ids.contains(&id), "{id} missing");
    }
    let features = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("feature"))
        .count();
    let samples = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("sample"))
        .count();
    assert_eq!(features, v["feature_points"].as_array().unwrap().len());
    assert_eq!(features + samples, 20);
    // No temporary file is left behind.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    // A missing output folder is one clean error.
    let missing = dir.join("no-such-dir").join("x.svg");
    assert_clean_failure(
        &[
            "--x",
            "u",
            "--y",
            "u^2",
            "--range",
            "0,1",
            "--svg",
            missing.to_str().unwrap(),
        ],
        "cannot write",
    );
}
