//! `--mode centerline` as a user meets it: every sample, with each stroke-width mode (and
//! the check on and off, alternately), gives an SVG whose two groups hold one path per reported stroke
//! and whose drawn strokes cover the line-art sample; options that centre lines cannot
//! honour are refused before any output; `batch` gives the same bytes on 1 and 2 threads.

mod common;

use common::{bin, scratch};
use std::path::Path;

fn run(args: &[&std::ffi::OsStr]) -> std::process::Output {
    bin().args(args).output().unwrap()
}

fn count_in_group(svg: &str, group: &str) -> usize {
    let start = svg.find(&format!("id=\"{group}\"")).unwrap();
    let end = start + svg[start..].find("</g>").unwrap();
    svg[start..end].matches("<path").count()
}

#[test]
fn every_sample_and_option_gives_matching_svg_and_reports() {
    let dir = scratch("centerline-all");
    // Each width mode once with the check and once without, on every sample (the four
    // combinations on alternate samples, to keep the test short).
    for (k, sample) in common::sample_paths().into_iter().enumerate() {
        for width in ["variable", "constant"] {
            {
                let check = (k % 2 == 0) == (width == "variable");
                let (svg, json, csv, overlay) = (
                    dir.join("o.svg"),
                    dir.join("o.json"),
                    dir.join("o.csv"),
                    dir.join("ov.svg"),
                );
                let mut args: Vec<&std::ffi::OsStr> = vec![
                    "trace".as_ref(),
                    sample.as_os_str(),
                    "-o".as_ref(),
                    svg.as_os_str(),
                    "--mode".as_ref(),
                    "centerline".as_ref(),
                    "--stroke-width".as_ref(),
                    width.as_ref(),
                    "--report".as_ref(),
                    json.as_os_str(),
                    "--csv".as_ref(),
                    csv.as_os_str(),
                    "--overlay".as_ref(),
                    overlay.as_os_str(),
                ];
                if !check {
                    args.push("--no-check".as_ref());
                }
                let out = run(&args);
                let stderr = String::from_utf8_lossy(&out.stderr);
                let what = format!("{} {width} check={check}: {stderr}", sample.display());
                assert!(out.status.success(), "{what}");
                assert!(!stderr.contains("panicked"), "{what}");
                let report: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
                assert_eq!(report["mode"], "centerline");
                let strokes = report["trace"]["strokes"].as_array().unwrap().len();
                assert!(strokes > 0, "{what}");
                let text = std::fs::read_to_string(&svg).unwrap();
                assert_eq!(count_in_group(&text, "strokes"), strokes, "{what}");
                assert_eq!(count_in_group(&text, "centerlines"), strokes, "{what}");
                let rows = std::fs::read_to_string(&csv).unwrap().lines().count();
                assert_eq!(rows, strokes + 1, "{what}");
                // Both pictures parse and render.
                let report_image = &report["trace"]["image"];
                let (w, h) = (
                    report_image["width"].as_u64().unwrap() as u32,
                    report_image["height"].as_u64().unwrap() as u32,
                );
                common::render_svg_coverage(&text, w, h);
                common::render_svg_coverage(&std::fs::read_to_string(&overlay).unwrap(), w, h);
            }
        }
    }
}

#[test]
fn the_line_art_sample_is_five_strokes_that_cover_it() {
    let dir = scratch("centerline-sketch");
    let input = common::samples_dir().join("sketch.png");
    for width in ["variable", "constant"] {
        let svg = dir.join(format!("{width}.svg"));
        let json = dir.join(format!("{width}.json"));
        let out = run(&[
            "trace".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            svg.as_os_str(),
            "--report".as_ref(),
            json.as_os_str(),
            "--mode".as_ref(),
            "centerline".as_ref(),
            "--stroke-width".as_ref(),
            width.as_ref(),
        ]);
        assert!(out.status.success());
        // Variable widths draw every stroke as it is, without a warning; one width per
        // stroke cannot draw the tapering brush stroke, and the warnings say so.
        let stderr = String::from_utf8_lossy(&out.stderr);
        if width == "variable" {
            assert!(stderr.is_empty(), "{stderr}");
        } else {
            assert!(stderr.contains("the width of 1 of 5 strokes"), "{stderr}");
            assert!(stderr.contains("do not match the input"), "{stderr}");
        }
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let strokes = report["trace"]["strokes"].as_array().unwrap();
        assert_eq!(strokes.len(), 5);
        assert_eq!(strokes.iter().filter(|s| s["closed"] == true).count(), 1);
        assert_eq!(report["trace"]["junctions"].as_array().unwrap().len(), 1);
        let (w, h, input_cov) = common::image_coverage(&input);
        let drawn = common::render_svg_coverage(&std::fs::read_to_string(&svg).unwrap(), w, h);
        let iou = common::coverage_iou(&drawn, &input_cov);
        let floor = if width == "variable" { 0.95 } else { 0.85 };
        assert!(iou >= floor, "{width}: IoU {iou}");
    }
}

fn assert_refused(extra: &[&str], out_name: &str, expect: &str) {
    let dir = scratch(&format!(
        "centerline-refused-{}",
        extra.join("").replace('-', "")
    ));
    let input = common::samples_dir().join("sketch.png");
    let out_path = dir.join(out_name);
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "trace".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out_path.as_os_str(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    let out = run(&args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{extra:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(expect),
        "{extra:?}: expected {expect:?} in {stderr}"
    );
    assert!(!out_path.exists());
}

#[test]
fn options_centre_lines_cannot_honour_are_refused() {
    assert_refused(&["--mode", "centerline"], "o.pdf", "SVG only");
    assert_refused(
        &["--stroke-width", "constant"],
        "o.svg",
        "--mode centerline",
    );
    assert_refused(
        &["--mode", "centerline", "--palette", "4"],
        "o.svg",
        "--palette",
    );
    assert_refused(
        &["--mode", "centerline", "--optimizer", "hs"],
        "o.svg",
        "--optimizer",
    );
    assert_refused(&["--mode", "centerline", "--merge"], "o.svg", "--merge");
    assert_refused(&["--mode", "centerline", "--params"], "o.svg", "--params");
}

#[test]
fn batch_gives_the_same_bytes_on_one_and_two_threads() {
    let dir = scratch("centerline-batch");
    let outs: Vec<_> = ["1", "2"]
        .iter()
        .map(|jobs| {
            let out_dir = dir.join(jobs);
            let status = bin()
                .args(["batch"])
                .arg(common::samples_dir())
                .arg("-o")
                .arg(&out_dir)
                .args(["--mode", "centerline", "--no-timings", "--jobs", jobs])
                .output()
                .unwrap();
            assert!(
                status.status.success(),
                "{}",
                String::from_utf8_lossy(&status.stderr)
            );
            out_dir
        })
        .collect();
    let names = |d: &Path| {
        let mut v: Vec<_> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&outs[0]), names(&outs[1]));
    for name in names(&outs[0]) {
        let a = std::fs::read(outs[0].join(&name)).unwrap();
        let b = std::fs::read(outs[1].join(&name)).unwrap();
        assert!(a == b, "{name:?} differs between 1 and 2 threads");
    }
    let summary = std::fs::read_to_string(outs[0].join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), common::sample_paths().len() + 1);
}
